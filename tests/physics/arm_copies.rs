//! Why arm copies in one Rapier world are not bit-identical to one world
//! per command (docs/benchmarks.md, "Multi-copy worlds"): Rapier solves the
//! contacts of every multibody link from one list in insertion-history
//! order, so one copy's contacts starting and ending reorder another's.
//! With the other copies idle (no contacts of theirs), a copy's outcome is
//! the one-copy world's, bit for bit (120 of 120 commands); with every
//! copy busy, some are not (117 of 120). The test asserts both, and prints
//! the counts:
//! `cargo test --release --test physics arm_copies:: -- --nocapture`.

use e3d::scene::WorldSpec;
use e3d::world::PhysicsWorld;
use e3d::{Command, Outcome, Scene, World};

fn world(scene: &Scene, copies: usize) -> PhysicsWorld {
    scene.as_physics().expect("a physics scene").world(copies)
}

fn same_bits(a: &Outcome, b: &Outcome) -> bool {
    a.point[0].to_bits() == b.point[0].to_bits() && a.point[1].to_bits() == b.point[1].to_bits()
}

/// arm7 without its mirror symmetry: every command simulated as given.
fn arm7() -> Scene {
    let mut spec = Scene::builtin("arm7").unwrap().into_spec();
    if let WorldSpec::Physics(p) = &mut spec.world {
        p.symmetry = None;
    }
    spec.validate().unwrap()
}

/// `n` arm7 commands spread over the space (a fixed odd stride).
fn commands(scene: &Scene, n: u64) -> Vec<Command> {
    let space = scene.command_space();
    (0..n)
        .map(|k| {
            let mut c = space.first();
            space.write_command_at(k * 73 % 2187, &mut c);
            c
        })
        .collect()
}

#[test]
fn an_arm_copy_beside_idle_copies_is_bit_identical_and_beside_busy_ones_is_not() {
    let scene = arm7();
    let cmds = commands(&scene, 120);
    let mut single = world(&scene, 1);
    let want: Vec<Outcome> = cmds.iter().map(|c| single.execute(c).unwrap()).collect();

    // one command per run of an 8-copy world: copies 1..8 stay idle
    let mut lonely = world(&scene, 8);
    let mut alone = 0;
    for (c, w) in cmds.iter().zip(&want) {
        let mut out = Vec::new();
        lonely.execute_batch(std::slice::from_ref(c), &mut out);
        alone += usize::from(same_bits(out[0].as_ref().unwrap(), w));
    }

    // 8 commands per run: every copy busy
    let mut busy = world(&scene, 8);
    let mut out = Vec::new();
    busy.execute_batch(&cmds, &mut out);
    let together = out
        .iter()
        .zip(&want)
        .filter(|(o, w)| same_bits(o.as_ref().unwrap(), w))
        .count();
    println!(
        "arm7, 120 commands: beside 7 idle copies {alone} bit-identical, beside 7 busy copies {together}"
    );
    assert_eq!(alone, cmds.len(), "idle copies changed a copy's bits");
    assert!(
        together < cmds.len(),
        "busy copies are bit-identical: Rapier may now order multibody contacts per copy (update \
         PhysicsSpec::copies_are_exact and docs/benchmarks.md)"
    );
}
