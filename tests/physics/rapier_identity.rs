//! The patched Rapier (vendor/rapier2d: a leaner multibody mass matrix,
//! see vendor/README.md) computes what crates.io's rapier2d 0.36.1
//! computes, bit for bit. The constants below were recorded with the
//! unpatched crates.io build, before the patch: every outcome table of the
//! arm scenes (all their commands, from every start context), and arm7_continuous
//! on 500 random continuous commands, in the library and through
//! `e3d scene exec`. A patch that changes one bit of one tip fails here.
//!
//! A hash is FNV-1a 64 over each outcome in order: the effect (u64), then
//! the bits of the reward and of the tip's x and y (little-endian), so a
//! change of any of them, or of their order, changes it.

use crate::common::{e3d_command, ok};
use e3d::world::ContextTables;
use e3d::{Outcome, OutcomeTable, Scene};
use std::io::Write;
use std::process::Stdio;

/// The FNV-1a 64 hash of `outcomes` (see the module's doc).
fn hash_outcomes<'a>(outcomes: impl IntoIterator<Item = &'a Outcome>) -> u64 {
    let mut bytes = Vec::new();
    for o in outcomes {
        bytes.extend_from_slice(&(o.effect as u64).to_le_bytes());
        bytes.extend_from_slice(&o.reward.to_bits().to_le_bytes());
        bytes.extend_from_slice(&o.point[0].to_bits().to_le_bytes());
        bytes.extend_from_slice(&o.point[1].to_bits().to_le_bytes());
    }
    e3d::hash::fnv1a64(&bytes)
}

/// The outcome table of the built-in scene `name`, as `e3d scene table`
/// computes it: its number of commands and its hash.
fn table(name: &str) -> (usize, u64) {
    let scene = Scene::builtin(name).unwrap();
    let t = OutcomeTable::build_scene(&scene).unwrap();
    (t.len(), hash_outcomes(t.outcomes()))
}

#[test]
fn arm7s_table_is_the_unpatched_one() {
    assert_eq!(table("arm7"), (2187, 10588360652013978684));
}

#[test]
fn arm4_gravitys_table_is_the_unpatched_one() {
    assert_eq!(table("arm4_gravity"), (81, 9617682461544999108));
}

#[test]
fn pendulum3s_table_is_the_unpatched_one() {
    assert_eq!(table("pendulum3"), (125, 2551703429816101108));
}

#[test]
fn arm_pushs_table_is_the_unpatched_one() {
    assert_eq!(table("arm_push"), (729, 18206221529133631675));
}

#[test]
fn arm7_poses_tables_are_the_unpatched_ones() {
    // every command of arm7 from each of three poses, without symmetry:
    // the straight context is arm7's every command, simulated
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/arm7_poses.ron");
    let scene = Scene::load(path).unwrap();
    let tables = ContextTables::build(&scene).unwrap();
    assert_eq!(tables.names(), ["straight", "raised", "curled"]);
    let got: Vec<(usize, u64)> = tables
        .tables()
        .iter()
        .map(|t| (t.len(), hash_outcomes(t.outcomes())))
        .collect();
    assert_eq!(
        got,
        [
            (2187, 5983385882423772421),
            (2187, 11069233876893459947),
            (2187, 5203232582299817726),
        ]
    );
}

/// The torque bounds of arm7_continuous's joints, as its scene file gives
/// them.
const T: [f64; 7] = [1.8, 1.2, 0.75, 0.45, 0.24, 0.12, 0.06];

/// `n` random continuous commands of arm7_continuous, each value uniform in
/// its slot's range (SplitMix64 from seed 47: a fixed, portable rule).
fn random_commands(n: usize) -> Vec<Vec<f64>> {
    let mut state = 47u64;
    let mut next = || {
        state = e3d::hash::splitmix64(state);
        // 53 random bits, uniform in [0, 1)
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| T.iter().map(|&t| t * (2.0 * next() - 1.0)).collect())
        .collect()
}

#[test]
fn arm7_continuous_on_500_random_commands_is_the_unpatched_one() {
    let commands = random_commands(500);
    let mut world = Scene::builtin("arm7_continuous")
        .unwrap()
        .physics_world()
        .unwrap();
    let outcomes: Vec<Outcome> = commands
        .iter()
        .map(|v| world.execute_values(v).unwrap())
        .collect();
    assert_eq!(hash_outcomes(&outcomes), 16367679150428510309);
    // one command's bits written out, in case the hash differs
    assert_eq!(
        outcomes[0].point.map(f64::to_bits),
        [4609963055789375488, 13807422932713996288],
        "{:?}",
        outcomes[0]
    );
}

#[test]
fn scene_exec_of_random_continuous_commands_prints_the_unpatched_bits() {
    // 100 of the commands above through the command line (its parallel,
    // batched path): the hash of its CSV (command,effect,reward,x,y, with
    // every float written in full)
    let input: String = random_commands(100)
        .iter()
        .map(|v| {
            let v: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
            v.join(",") + "\n"
        })
        .collect();
    let mut child = e3d_command()
        .args(["scene", "exec", "arm7_continuous", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let out = ok(child.wait_with_output().unwrap());
    let csv = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        csv.lines().count(),
        101,
        "a header and one line per command"
    );
    assert_eq!(
        e3d::hash::fnv1a64(csv.as_bytes()),
        6930194151253599839,
        "{csv}"
    );
}
