//! Multi-copy physics: K commands at once in one Rapier world give the
//! outcomes of one command per world, bit for bit; a command that blows
//! up fails alone.

use e3d::scene::WorldSpec;
use e3d::world::PhysicsWorld;
use e3d::{Command, Outcome, OutcomeTable, Scene, World, WorldError};

fn world(scene: &Scene, copies: usize) -> PhysicsWorld {
    scene.as_physics().expect("a physics scene").world(copies)
}

/// `n` commands spread over the command space (a fixed stride).
fn commands(scene: &Scene, n: u64) -> Vec<Command> {
    let space = scene.command_space();
    let total = space.num_commands().unwrap();
    let stride = (total / n).max(1) | 1;
    (0..n)
        .map(|k| {
            let mut c = space.first();
            space.write_command_at((k * stride + k / 3) % total, &mut c);
            c
        })
        .collect()
}

fn same_bits(a: &Outcome, b: &Outcome) -> bool {
    a.effect == b.effect
        && a.reward.to_bits() == b.reward.to_bits()
        && a.point[0].to_bits() == b.point[0].to_bits()
        && a.point[1].to_bits() == b.point[1].to_bits()
}

/// Asserts that each of `out` has the bits `single` gives its command.
fn assert_as_single(
    what: &str,
    scene: &Scene,
    single: &mut PhysicsWorld,
    cmds: &[Command],
    out: &[Result<Outcome, WorldError>],
) {
    assert_eq!(out.len(), cmds.len());
    for (c, got) in cmds.iter().zip(out) {
        let want = single.execute(c).unwrap();
        let got = got.as_ref().unwrap();
        assert!(
            same_bits(&want, got),
            "{what}: {} single {want:?} batched {got:?}",
            scene.command_space().format(c)
        );
    }
}

fn check_identical(name: &str, n: u64, copies: usize) {
    let scene = Scene::load(format!("scenes/{name}.ron")).unwrap();
    let cmds = commands(&scene, n);
    let mut single = world(&scene, 1);
    let mut multi = world(&scene, copies);
    assert_eq!(multi.num_copies(), copies);
    let mut out = Vec::new();
    multi.execute_batch(&cmds, &mut out);
    assert_as_single(name, &scene, &mut single, &cmds, &out);
}

#[test]
fn puck_rooms_copies_are_bit_identical_to_one_world_per_command() {
    // 300 commands: 9 full batches of 32 and a partial one
    check_identical("puck_rooms", 300, 32);
}

#[test]
fn copies_are_exact_only_with_one_moving_body_with_contacts() {
    // arm7's links touch each other: in one world with other copies,
    // Rapier orders the contacts differently and the last bits of some
    // terminal points differ (for example `--+++--`, by about 1e-5 m), so
    // its table is built one command per world
    let exact = |name: &str| match &Scene::builtin(name).unwrap().spec().world {
        WorldSpec::Physics(p) => p.copies_are_exact(),
        _ => unreachable!(),
    };
    assert!(exact("puck_rooms") && exact("maze3"));
    assert!(!exact("arm7") && !exact("pendulum3"));
}

#[test]
fn puck_rooms_table_built_batched_is_the_table_built_one_by_one() {
    let scene = Scene::builtin("puck_rooms").unwrap();
    let batched = OutcomeTable::build_scene(&scene).unwrap();
    let single = OutcomeTable::build_parallel(|| scene.build()).unwrap();
    assert_eq!(batched.len(), 16384);
    let key = OutcomeTable::key(&scene);
    assert_eq!(batched.to_bytes(key), single.to_bytes(key));
}

#[test]
fn pendulum3_and_maze3_copies_are_bit_identical() {
    check_identical("pendulum3", 60, 16);
    check_identical("maze3", 60, 16);
}

/// A batch smaller than the world leaves copies without a command; they
/// are switched off for the run (not simulated) and on again for the next.
/// Batches of every size class, partial ones before and after full ones,
/// give each command the bits of a world of its own.
#[test]
fn batches_smaller_than_the_world_give_the_same_bits() {
    for (name, copies) in [("puck_rooms", 32), ("maze3", 16), ("pendulum3", 16)] {
        let scene = Scene::load(format!("scenes/{name}.ron")).unwrap();
        let cmds = commands(&scene, 90);
        let mut single = world(&scene, 1);
        let mut multi = world(&scene, copies);
        let mut k = 0;
        for size in [1, 5, copies, copies / 2 + 1, copies - 1, 2, copies] {
            let batch: Vec<Command> = (0..size)
                .map(|i| cmds[(k + i) % cmds.len()].clone())
                .collect();
            k += size;
            let mut out = Vec::new();
            multi.execute_batch(&batch, &mut out);
            let what = format!("{name}, batch of {size}");
            assert_as_single(&what, &scene, &mut single, &batch, &out);
        }
    }
}

#[test]
fn a_blown_up_copy_fails_alone() {
    let text = include_str!("../scenes/blowup.ron");
    let scene = Scene::parse(text, "blowup.ron").unwrap();
    let space = scene.command_space();
    let cmds: Vec<Command> = ["T0", "0K", "00", "TK", "T0"]
        .iter()
        .map(|s| space.parse(s).unwrap())
        .collect();
    let mut single = world(&scene, 1);
    let mut multi = world(&scene, 4);
    let mut out = Vec::new();
    multi.execute_batch(&cmds, &mut out);
    for (c, got) in cmds.iter().zip(&out) {
        let want = single.execute(c);
        match (&want, got) {
            (Ok(a), Ok(b)) => assert!(same_bits(a, b), "{a:?} {b:?}"),
            (Err(a), Err(b)) => assert_eq!(a, b),
            _ => panic!("{want:?} vs {got:?}"),
        }
    }
    assert!(matches!(out[1], Err(WorldError::Diverged { ref command, .. }) if command == "0K"));
    assert!(out[0].is_ok() && out[2].is_ok() && out[4].is_ok());
    // a bad command is reported for itself
    let bad = Command {
        symbols: vec![0, 5],
    };
    out.clear();
    multi.execute_batch(&[cmds[0].clone(), bad], &mut out);
    assert!(out[0].is_ok());
    assert!(matches!(out[1], Err(WorldError::BadCommand { .. })));
}

/// arm7 in copies is not bit-identical; how many effects still agree
/// (docs/benchmarks.md). Slow in a debug build:
/// `cargo test --release --test physics copies:: -- --ignored --nocapture`.
#[test]
#[ignore]
fn arm7_copies_effects_agree_with_one_world_per_command() {
    let scene = Scene::builtin("arm7").unwrap();
    let cmds = commands(&scene, 2187);
    let mut single = world(&scene, 1);
    let mut multi = world(&scene, 32);
    let mut out = Vec::new();
    multi.execute_batch(&cmds, &mut out);
    let (mut effects, mut bits) = (0, 0);
    for (c, got) in cmds.iter().zip(&out) {
        let want = single.execute(c).unwrap();
        let got = got.as_ref().unwrap();
        effects += usize::from(want.effect == got.effect);
        bits += usize::from(same_bits(&want, got));
    }
    println!("arm7, 32 copies: {effects} of 2187 effects equal, {bits} bit-identical");
    assert!(effects * 100 >= 99 * 2187);
}
