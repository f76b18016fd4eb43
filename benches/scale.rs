//! Research-scale command spaces: what the outcome memo costs per trial,
//! and sessions in lockstep on a space no table fits (`puck_rooms` with 14
//! slots, 4^14 commands); and the refusal of a sweep too large to plan
//! (10^8 cells), which costs its size check.
//!
//! `cargo bench --bench scale`; criterion prints each rate (elements/s are
//! trials/s, summed over sessions). The end-to-end targets (a whole sweep,
//! `e3d run` against `e3d scene table`, against pymunk) are measured by
//! `scripts/bench-scale.sh`; the figures are in docs/benchmarks.md.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use e3d::learner::LearnerSetup;
use e3d::session::{run_group, RunningMetrics};
use e3d::world::{ExecOptions, Executor, Memoized, OutcomeMemo, Strategy, Workload};
use e3d::World;
use e3d::{Control, LearnerKind, Scene, SessionConfig};
use std::hint::black_box;

fn puck14() -> Scene {
    let (_, text) = e3d::scene::BUILTIN
        .iter()
        .find(|(n, _)| *n == "puck_rooms")
        .unwrap();
    let text = text
        .replace("slots: 7", "slots: 14")
        .replace("name: \"puck_rooms\"", "name: \"puck_rooms14\"");
    Scene::parse(&text, "puck_rooms14").unwrap()
}

fn scale(c: &mut Criterion) {
    let mut g = c.benchmark_group("scale");
    g.sample_size(10);
    // a memo hit: the look-up a repeated command costs instead of a rollout
    let scene = Scene::builtin("puck_rooms").unwrap();
    let space = scene.command_space();
    let memo = OutcomeMemo::new(&space, scene.num_effects(), 1 << 20).unwrap();
    let mut world = Memoized::new(scene.build(), &memo);
    let cmds: Vec<_> = (0..64u64)
        .map(|k| space.command_at(k * 7919 % 16384))
        .collect();
    for c in &cmds {
        world.execute(c).unwrap();
    }
    let mut i = 0;
    g.throughput(Throughput::Elements(1));
    g.bench_function("memo hit (puck_rooms)", |b| {
        b.iter(|| {
            i = (i + 1) % cmds.len();
            black_box(world.execute(&cmds[i]).unwrap().effect)
        })
    });
    // 25 E3D sessions in lockstep on puck_rooms14, 20 trials each, a fresh
    // memo each time: nearly every command new, 25 per world step
    let scene = puck14();
    let space = scene.command_space();
    let work = Workload {
        trials: 500,
        sessions: 25,
        threads: 1,
    };
    let options = ExecOptions {
        force: Some(Strategy::Memo),
        ..ExecOptions::default()
    };
    g.throughput(Throughput::Elements(500));
    let mut seed = 0;
    g.bench_function(
        "25 e3d sessions x 20 trials in lockstep (puck_rooms14, memo)",
        |b| {
            b.iter(|| {
                seed += 1;
                let exec = Executor::new(&scene, &work, &options).unwrap();
                let mut world = exec.world(25);
                let mut learners: Vec<_> = (0..25)
                    .map(|_| {
                        LearnerSetup::new(LearnerKind::E3d)
                            .symbols(&space, scene.num_effects())
                            .unwrap()
                    })
                    .collect();
                let configs: Vec<SessionConfig> = (0..25)
                    .map(|k| SessionConfig {
                        trials: 20,
                        seed: seed * 100 + k,
                        use_reward: false,
                    })
                    .collect();
                let mut rec: Vec<RunningMetrics> = (0..25)
                    .map(|_| RunningMetrics::new(scene.num_effects()))
                    .collect();
                black_box(run_group(
                    &mut *world,
                    &mut learners,
                    &configs,
                    &mut rec,
                    &Control::default(),
                ))
            })
        },
    );
    g.finish();
}

/// `Sweep::parse` of a sweep of 100000 x 1000 values (10^8 cells, over
/// the 10^7 sessions a plan may hold): refused from the counts of values,
/// before the ranges are expanded (tests/library/outcomes.rs checks the
/// message).
fn sweep_refusal(c: &mut Criterion) {
    let text = r#"Sweep(scenes: ["two_rooms"], learners: [e3d], use_reward: [false],
        params: (beta: (scale: Log, from: 1, to: 1000, steps: 100000),
                 eta: (scale: Linear, from: 0.001, to: 0.1, steps: 1000)),
        sessions: 1, trials: 10, seed: 1)"#;
    let mut g = c.benchmark_group("sweep_parse");
    g.bench_function("refused_1e8_cells", |b| {
        b.iter(|| black_box(e3d::sweep::Sweep::parse(text, "huge.ron", None).unwrap_err()))
    });
    g.finish();
}

/// What the bounds of a file's declared counts cost (docs/robustness.md):
/// 10^5 grid contexts refused by the bound, 1024 loaded, 1000 physics
/// contexts loaded and checked, a summary.csv of 30,000 columns refused.
/// These were quadratic (over 30 s) before the bounds and the linear
/// checks; `cargo bench --bench scale -- bounds`.
fn bounds(c: &mut Criterion) {
    let two_rooms = std::fs::read_to_string("scenes/two_rooms_contexts.ron").unwrap();
    let grid = |n: usize| {
        let list: Vec<String> = (0..n)
            .map(|k| format!(r#"(name: "c{k}", cell: ({}, {}))"#, k % 3, k % 6))
            .collect();
        two_rooms.replace(
            r#"contexts: [(name: "room_a", cell: (0, 0)), (name: "room_b", cell: (2, 5))],"#,
            &format!("contexts: [{}],", list.join(", ")),
        )
    };
    let (refused, loaded) = (grid(100_000), grid(1024));
    let puck = std::fs::read_to_string("scenes/puck_contexts.ron").unwrap();
    let list: Vec<String> = (0..1000)
        .map(|k| {
            format!(
                r#"(name: "c{k}", bodies: [(body: "puck", position: ({}, {}))])"#,
                0.5 + (k % 5) as f64 * 0.5,
                0.5 + (k % 4) as f64 * 0.5
            )
        })
        .collect();
    let two = r#"contexts: [
            (name: "room_a", bodies: [(body: "puck", position: (0.5, 2.5))]),
            (name: "room_b", bodies: [(body: "puck", position: (5.5, 0.5))]),
        ],"#;
    assert!(puck.contains(two));
    let physics = puck.replace(two, &format!("contexts: [{}],", list.join(", ")));
    let head = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,sessions";
    let wide: Vec<String> = (0..30_000).map(|k| format!("m{k}_mean")).collect();
    let summary = format!(
        "{head},{}\ntwo_rooms,e3d,false,0.3,1,0.03,0.01,,3{}\n",
        wide.join(","),
        ",1".repeat(30_000)
    );
    let mut g = c.benchmark_group("bounds");
    g.sample_size(10);
    g.bench_function("10^5 grid contexts refused", |b| {
        b.iter(|| assert!(Scene::parse(black_box(&refused), "many.ron").is_err()))
    });
    g.bench_function("1024 grid contexts loaded", |b| {
        b.iter(|| Scene::parse(black_box(&loaded), "ok.ron").unwrap())
    });
    g.bench_function("1000 physics contexts loaded", |b| {
        b.iter(|| Scene::parse(black_box(&physics), "puck.ron").unwrap())
    });
    g.bench_function("summary.csv of 30000 columns refused", |b| {
        b.iter(|| assert!(e3d::csv::Summary::parse(black_box(&summary)).is_err()))
    });
    g.finish();
}

criterion_group!(benches, scale, sweep_refusal, bounds);
criterion_main!(benches);
