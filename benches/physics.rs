//! The physics scenes: one rollout of each shipped physics scene (one
//! command per world and many copies per world, and a batch of 8 on a
//! world of 32 copies), a first pass of 256
//! commands on a world that keeps prefix states, the reset alone, and a
//! 5000-trial E3D session on each scene's outcome table; and a trial of
//! continuous commands on arm7_continuous (one Gaussian E3D trial on live
//! physics); 32 sessions of continuous commands on a puck, in lockstep
//! and a world each; and the loader on a scene of 10,000 bodies (the most it
//! takes), whose names are checked in linear time.
//!
//! `cargo bench --bench physics`; criterion prints each rate (elements/s
//! are rollouts/s or trials/s). The figures are in docs/benchmarks.md.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use e3d::learner::LearnerSetup;
use e3d::world::TABLE_COPIES;
use e3d::{run_session, LearnerKind, OutcomeTable, Scene, SessionConfig, World};
use std::hint::black_box;

const SCENES: [&str; 4] = ["puck_rooms", "maze3", "pendulum3", "arm7"];

fn physics(c: &mut Criterion) {
    for name in SCENES {
        let scene = Scene::builtin(name).unwrap();
        let physics = scene.as_physics().expect("a physics scene");
        let space = scene.command_space();
        let n = space.num_commands().unwrap();
        // commands spread over the space, cycled through
        let cmds: Vec<_> = (0..256u64)
            .map(|k| {
                let mut c = space.first();
                space.write_command_at(k * 7919 % n, &mut c);
                c
            })
            .collect();
        let mut g = c.benchmark_group(name);
        g.sample_size(10);
        g.throughput(Throughput::Elements(1));
        // every step simulated: no prefix state kept
        let mut world = physics.world(1);
        world.set_prefix_states(0);
        let mut i = 0;
        g.bench_function("rollout (one copy)", |b| {
            b.iter(|| {
                i = (i + 1) % cmds.len();
                black_box(world.execute(&cmds[i]).unwrap().effect)
            })
        });
        // the same 256 commands on a new world that keeps prefix states:
        // what a first pass over new commands costs
        if physics.world(1).prefix_depth() > 0 {
            g.throughput(Throughput::Elements(cmds.len() as u64));
            g.bench_function("256 commands on a new world (prefix states)", |b| {
                b.iter(|| {
                    let mut w = physics.world(1);
                    let e: usize = cmds.iter().map(|c| w.execute(c).unwrap().effect).sum();
                    black_box(e)
                })
            });
            g.throughput(Throughput::Elements(1));
        }
        let mut fresh = physics.world(1);
        g.bench_function("reset (restore the pristine sets)", |b| {
            b.iter(|| {
                fresh.reset();
                black_box(&fresh);
            })
        });
        g.throughput(Throughput::Elements(TABLE_COPIES as u64));
        let mut multi = physics.world(TABLE_COPIES);
        let mut out = Vec::with_capacity(TABLE_COPIES);
        let mut k = 0;
        g.bench_function(format!("rollouts ({TABLE_COPIES} copies per world)"), |b| {
            b.iter(|| {
                k = (k + TABLE_COPIES) % cmds.len();
                out.clear();
                multi.execute_batch(&cmds[k..(k + TABLE_COPIES).min(cmds.len())], &mut out);
                black_box(out.len())
            })
        });
        // a batch of 8 on the same world: its other copies are switched off
        g.throughput(Throughput::Elements(8));
        g.bench_function(
            format!("8 rollouts on a world of {TABLE_COPIES} copies"),
            |b| {
                b.iter(|| {
                    k = (k + 8) % cmds.len();
                    out.clear();
                    multi.execute_batch(&cmds[k..(k + 8).min(cmds.len())], &mut out);
                    black_box(out.len())
                })
            },
        );
        let table = OutcomeTable::build_scene(&scene).unwrap();
        g.throughput(Throughput::Elements(5000));
        g.bench_function("e3d session of 5000 trials (outcome table)", |b| {
            let mut seed = 0;
            b.iter(|| {
                seed += 1;
                let mut l = LearnerSetup::new(LearnerKind::E3d)
                    .symbols(&space, table.num_effects())
                    .unwrap();
                let cfg = SessionConfig {
                    trials: 5000,
                    seed,
                    use_reward: true,
                };
                black_box(
                    run_session(&mut &table, &mut l, &cfg)
                        .unwrap()
                        .effects
                        .len(),
                )
            })
        });
        g.finish();
    }
}

/// A trial of continuous commands: the Gaussian E3D proposes, arm7 runs
/// the values live, the learner learns (what `e3d run arm7_continuous`
/// repeats on every core).
fn continuous(c: &mut Criterion) {
    use e3d::{ContinuousLearner, SessionRng};
    use rand::SeedableRng;
    let scene = Scene::builtin("arm7_continuous").unwrap();
    let space = scene.value_space().unwrap();
    let mut world = scene.physics_world().unwrap();
    let mut l = LearnerSetup::new(LearnerKind::E3d)
        .values(&space, scene.num_effects())
        .unwrap();
    let mut rng = SessionRng::seed_from_u64(0);
    let mut v = Vec::new();
    let mut g = c.benchmark_group("arm7_continuous");
    g.sample_size(10);
    g.throughput(Throughput::Elements(1));
    g.bench_function("gaussian e3d trial (live rollout)", |b| {
        b.iter(|| {
            l.propose(&mut rng, &mut v);
            let o = world.execute_values(&v).unwrap();
            l.learn(&v, &o);
            black_box(o.effect)
        })
    });
    g.finish();
}

/// puck_rooms's rooms and puck with 3 continuous slots, each an impulse
/// of 1.6 N*s in any heading (tests/scenes/puck_headings.ron, the tests' too):
/// one moving body, so its copies in one world are exact.
const PUCK_HEADINGS: &str = include_str!("../tests/scenes/puck_headings.ron");

/// 32 sessions of 8 Gaussian E3D trials of continuous commands on one
/// thread: in lockstep on one world of 32 copies (`run_sessions`,
/// what `e3d run --sessions 32` does), and one world per session.
fn continuous_lockstep(c: &mut Criterion) {
    use e3d::session::{run_value_session, ValueSessionRecord};
    use e3d::world::{Executor, Workload};
    use e3d::{run_sessions, Control};
    let scene = Scene::parse(PUCK_HEADINGS, "puck_headings.ron").unwrap();
    let space = scene.value_space().unwrap();
    let configs: Vec<SessionConfig> = (0..32)
        .map(|seed| SessionConfig {
            trials: 8,
            seed,
            use_reward: false,
        })
        .collect();
    let learner = || {
        LearnerSetup::new(LearnerKind::E3d)
            .values(&space, scene.num_effects())
            .unwrap()
    };
    let work = Workload {
        trials: 32 * 8,
        sessions: 32,
        threads: 1,
    };
    let exec = Executor::for_values(&scene, &work).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut g = c.benchmark_group("continuous_lockstep");
    g.sample_size(10);
    g.throughput(Throughput::Elements(32 * 8));
    g.bench_function("32 sessions in lockstep, 32 copies", |b| {
        b.iter(|| {
            pool.install(|| {
                let mut learners: Vec<_> = configs.iter().map(|_| learner()).collect();
                let mut recs: Vec<ValueSessionRecord> = configs
                    .iter()
                    .map(|c| {
                        ValueSessionRecord::new(space.num_slots(), scene.num_effects(), c.trials)
                    })
                    .collect();
                run_sessions(
                    &exec,
                    &mut learners,
                    &configs,
                    &mut recs,
                    &Control::default(),
                );
                recs
            })
        })
    });
    g.bench_function("32 sessions, a world each", |b| {
        b.iter(|| {
            configs
                .iter()
                .map(|cfg| {
                    let mut world = scene.as_continuous().unwrap().world(1);
                    run_value_session(&mut world, &mut learner(), cfg).unwrap()
                })
                .collect::<Vec<_>>()
        })
    });
    g.finish();
}

/// A two-link arm's scene with `n` more fixed balls, in `bodies` (the
/// scene of tests/physics/scene_errors.rs's body cap).
fn many_bodies(n: usize) -> String {
    const BASE: &str = r#"Scene(
    name: "base",
    world: Physics(
        bodies: [
            (name: "wall", kind: Fixed, shape: Cuboid(width: 4.0, height: 0.1), position: (0.0, -1.0)),
            (name: "upper", shape: Cuboid(width: 0.5, height: 0.05), mass: 0.2, position: (0.25, 0.0)),
            (name: "lower", shape: Cuboid(width: 0.5, height: 0.05), mass: 0.2, position: (0.75, 0.0)),
        ],
        joints: [
            (name: "shoulder", parent: "ground", child: "upper", child_anchor: (-0.25, 0.0)),
            (name: "elbow", parent: "upper", child: "lower",
             parent_anchor: (0.25, 0.0), child_anchor: (-0.25, 0.0), motor: (stiffness: 5.0)),
        ],
        schedule: Simultaneous(push: 0.25, settle: 0.5),
        effect: (body: "lower", point: (0.25, 0.0),
                 grid: (rows: 4, cols: 4, min: (-1.0, -1.0), max: (1.0, 1.0))),
    ),
    command: Slots([
        (alphabet: [(symbol: '-', action: Torque(joint: "shoulder", torque: -1.0)),
                    (symbol: '+', action: Torque(joint: "shoulder", torque: 1.0))]),
        (alphabet: [(symbol: '0', action: Idle),
                    (symbol: 't', action: Target(joint: "elbow", angle: 0.5))]),
    ]),
)"#;
    let bodies: String = (0..n)
        .map(|i| {
            format!(
                "(name: \"b{i}\", kind: Fixed, shape: Ball(radius: 0.1), position: ({}.0, 5.0)),\n",
                i % 1000
            )
        })
        .collect();
    BASE.replacen(
        "        bodies: [\n",
        &format!("        bodies: [\n{bodies}"),
        1,
    )
}

/// Loading (parsing and validating) a scene of 10,000 bodies, the most a
/// scene may hold.
fn scene_parse(c: &mut Criterion) {
    let text = many_bodies(10_000 - 3);
    let mut g = c.benchmark_group("scene_parse");
    g.sample_size(10);
    g.bench_function("10000_bodies", |b| {
        b.iter(|| black_box(Scene::parse(&text, "s.ron").unwrap()))
    });
    g.finish();
}

criterion_group!(
    benches,
    physics,
    continuous,
    continuous_lockstep,
    scene_parse
);
criterion_main!(benches);
