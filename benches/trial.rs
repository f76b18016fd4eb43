//! One trial of each learner on two_rooms, and its parts.
//!
//! `cargo bench --bench trial`; the figures and the targets are in
//! docs/benchmarks.md.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use e3d::learner::E3d;
use e3d::learner::LearnerSetup;
use e3d::{
    run_session, Learner, LearnerKind, OutcomeTable, Params, Scene, SessionConfig, SessionRng,
    Target, World,
};
use rand::SeedableRng;
use std::hint::black_box;

fn trial(c: &mut Criterion) {
    let scene = Scene::builtin("two_rooms").unwrap();
    let table = OutcomeTable::build(&mut scene.build()).unwrap();
    let space = scene.command_space();
    let mut g = c.benchmark_group("two_rooms");
    g.throughput(Throughput::Elements(1));
    for kind in LearnerKind::ALL {
        let mut learner = LearnerSetup::new(kind)
            .params(Params::TASK2)
            .symbols(&space, 18)
            .unwrap();
        let mut rng = SessionRng::seed_from_u64(1);
        let mut cmd = space.first();
        g.bench_function(format!("{kind} trial (propose, table, learn)"), |b| {
            b.iter(|| {
                learner.propose(&mut rng, &mut cmd);
                let o = *table.lookup(&cmd).unwrap();
                learner.learn(&cmd, &o);
                black_box(o.effect)
            })
        });
    }
    // the concrete type, as a library user holds it (no dyn dispatch)
    let mut learner = E3d::new(&space, 18, &Params::TASK2, &Target::Uniform).unwrap();
    let mut rng = SessionRng::seed_from_u64(1);
    let mut cmd = space.first();
    g.bench_function("e3d trial, concrete E3d (propose, table, learn)", |b| {
        b.iter(|| {
            learner.propose(&mut rng, &mut cmd);
            let o = *table.lookup(&cmd).unwrap();
            learner.learn(&cmd, &o);
            black_box(o.effect)
        })
    });
    let mut world = scene.build();
    let cmd = space.parse("SEEEEES").unwrap();
    g.bench_function("grid execute", |b| {
        b.iter(|| black_box(world.execute(black_box(&cmd)).unwrap().effect))
    });
    g.bench_function("table lookup", |b| {
        b.iter(|| black_box(table.lookup(black_box(&cmd)).unwrap().effect))
    });
    g.finish();

    let mut g = c.benchmark_group("two_rooms session");
    g.throughput(Throughput::Elements(5000));
    g.sample_size(20);
    g.bench_function("e3d 5000 trials", |b| {
        b.iter(|| {
            let mut l = LearnerSetup::new(LearnerKind::E3d)
                .symbols(&space, 18)
                .unwrap();
            let cfg = SessionConfig {
                trials: 5000,
                seed: 3,
                use_reward: false,
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

criterion_group!(benches, trial);
criterion_main!(benches);
