//! The physics scenes: one rollout of each shipped physics scene (one
//! command per world and many copies per world), the reset alone, and a
//! 5000-trial E3D session on each scene's outcome table; and a trial of
//! continuous commands on arm7_continuous (one Gaussian E3D trial on live
//! physics).
//!
//! `cargo bench --bench physics`; criterion prints each rate (elements/s
//! are rollouts/s or trials/s). The figures are in docs/benchmarks.md.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use e3d::scene::WorldSpec;
use e3d::world::TABLE_COPIES;
use e3d::{
    run_session, LearnerKind, OutcomeTable, Params, PhysicsWorld, Scene, SessionConfig, Target,
    World,
};
use std::hint::black_box;

const SCENES: [&str; 4] = ["puck_rooms", "maze3", "pendulum3", "arm7"];

fn physics(c: &mut Criterion) {
    for name in SCENES {
        let scene = Scene::builtin(name).unwrap();
        let WorldSpec::Physics(spec) = &scene.world else {
            unreachable!("a physics scene")
        };
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
        let mut world = PhysicsWorld::from_scene(&scene, spec);
        let mut i = 0;
        g.bench_function("rollout (one copy)", |b| {
            b.iter(|| {
                i = (i + 1) % cmds.len();
                black_box(world.execute(&cmds[i]).unwrap().effect)
            })
        });
        let mut fresh = PhysicsWorld::from_scene(&scene, spec);
        g.bench_function("reset (restore the pristine sets)", |b| {
            b.iter(|| {
                fresh.reset();
                black_box(&fresh);
            })
        });
        g.throughput(Throughput::Elements(TABLE_COPIES as u64));
        let mut multi = PhysicsWorld::with_copies(&scene, spec, TABLE_COPIES);
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
        let table = OutcomeTable::build_scene(&scene).unwrap();
        g.throughput(Throughput::Elements(5000));
        g.bench_function("e3d session of 5000 trials (outcome table)", |b| {
            let mut seed = 0;
            b.iter(|| {
                seed += 1;
                let mut l = LearnerKind::E3d
                    .make(
                        &Params::TASK1,
                        &space,
                        table.num_effects(),
                        &Target::Uniform,
                    )
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
    let mut l = LearnerKind::E3d
        .make_continuous(
            &Params::TASK1,
            &space,
            scene.num_effects(),
            &Target::Uniform,
        )
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

criterion_group!(benches, physics, continuous);
criterion_main!(benches);
