//! Prefix states (`PhysicsWorld::set_prefix_states`): a command that starts
//! from the phase-end state an earlier command with the same prefix left
//! ends on the same bits as its whole rollout, on every shipped scene, in
//! any order, and whatever ran from another start in between.

use e3d::scene::BUILTIN;
use e3d::world::{Episodic, PhysicsWorld};
use e3d::{Command, Outcome, Scene, World, WorldError};
use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};

/// `n` commands of `scene` in groups of four that share prefixes of every
/// length (each group a random command and three that differ from it from
/// a random slot on), shuffled.
fn sharing_commands(scene: &Scene, n: usize, seed: u64) -> Vec<Command> {
    let space = scene.command_space();
    let total = space.num_commands().expect("a countable space");
    let sizes: Vec<usize> = space.sizes().collect();
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let mut out = Vec::new();
    while out.len() < n {
        let base = space.command_at(rng.random_range(0..total));
        out.push(base.clone());
        for _ in 0..3 {
            let mut c = base.clone();
            let from = rng.random_range(0..sizes.len());
            for (slot, &k) in sizes.iter().enumerate().skip(from) {
                c.symbols[slot] = rng.random_range(0..k) as u8;
            }
            out.push(c);
        }
    }
    out.shuffle(&mut rng);
    out
}

/// The outcome's bits, or the error's text.
fn bits(r: Result<Outcome, WorldError>) -> Result<(usize, u64, [u64; 2]), String> {
    r.map(|o| (o.effect, o.reward.to_bits(), o.point.map(f64::to_bits)))
        .map_err(|e| e.to_string())
}

fn plain(scene: &Scene) -> PhysicsWorld {
    let mut w = scene.physics_world().unwrap();
    w.set_prefix_states(0);
    w
}

#[test]
fn prefix_states_change_no_bit_on_any_shipped_scene() {
    let mut sequential = 0;
    for &(name, _) in BUILTIN {
        let scene = Scene::builtin(name).unwrap();
        if scene.spec().is_continuous() || scene.physics_world().is_none() {
            continue;
        }
        let mut reusing = scene.physics_world().unwrap();
        let mut fresh = plain(&scene);
        let depth = reusing.prefix_depth();
        let commands = sharing_commands(&scene, 48, 7);
        for (k, c) in commands.iter().enumerate() {
            let a = bits(reusing.execute(c));
            let b = bits(fresh.execute(c));
            assert_eq!(a, b, "{name}: command {k} {c:?}");
        }
        if depth > 0 {
            sequential += 1;
            assert!(
                reusing.prefix_states_kept() > 10,
                "{name}: {} states kept",
                reusing.prefix_states_kept()
            );
        } else {
            assert_eq!(reusing.prefix_states_kept(), 0, "{name}");
        }
        // batches on a world of one copy run command by command: the same
        let mut out = Vec::new();
        reusing.execute_batch(&commands[..8], &mut out);
        for (c, r) in commands.iter().zip(out) {
            assert_eq!(bits(r), bits(fresh.execute(c)), "{name}: batch {c:?}");
        }
    }
    // puck_rooms, maze3, three_rooms, swimmer, arm_push, cart_pole, ...
    assert!(sequential >= 6, "only {sequential} sequential scenes");
}

#[test]
fn runs_from_another_start_leave_the_scene_starts_states_alone() {
    let scene = Scene::load("scenes/puck_contexts.ron").unwrap();
    let mut world = scene.physics_world().unwrap();
    assert!(world.prefix_depth() > 0);
    let mut fresh = plain(&scene);
    let commands = sharing_commands(&scene, 24, 3);
    let mut rng = e3d::rng::SessionRng::seed_from_u64(0);
    let from = world.draw_start(1, &mut rng).unwrap();
    for c in &commands {
        // from another start, by both doors into the world
        let (o, _) = world.execute_from(&from, c).unwrap();
        let (p, _) = fresh.execute_from(&from, c).unwrap();
        assert_eq!(bits(Ok(o)), bits(Ok(p)));
        let o = world.from_start(&from, |w| w.execute(c)).unwrap();
        assert_eq!(bits(o), bits(Ok(p)));
        // then from the scene's own start
        assert_eq!(bits(world.execute(c)), bits(fresh.execute(c)));
    }
}
