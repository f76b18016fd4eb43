//! Continuous commands on arm7: the Gaussian E3D against the uniform
//! sampler, the table and figure of docs/reproducing.md ("Continuous
//! commands on arm7").
//!
//! ```sh
//! cargo run --release --example continuous_arm7                       # 4 sessions x 2000 trials
//! cargo run --release --example continuous_arm7 -- 10 5000 docs/figures/arm7_continuous.svg
//! ```
//!
//! Every trial is simulated (live physics; about 300 arm7 rollouts a
//! second per core): 10 x 5000 trials for both learners take about 6
//! minutes on 2 cores.

use e3d::learner::LearnerSetup;
use e3d::report::paper::effect_panels_svg;
use e3d::session::ValueSessionRecord;
use e3d::world::GridSpec;
use e3d::{effect::entropy, run_sessions, Control, LearnerKind, Scene, SessionConfig, Target};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let sessions: u64 = args.first().map_or(Ok(4), |a| a.parse())?;
    let trials: usize = args.get(1).map_or(Ok(2000), |a| a.parse())?;
    let out = args.get(2);
    let scene = Scene::builtin("arm7_continuous").expect("shipped");
    let space = scene.value_space().expect("continuous");
    let n = scene.num_effects();
    let configs: Vec<SessionConfig> = (0..sessions)
        .map(|seed| SessionConfig {
            trials,
            seed,
            use_reward: false,
        })
        .collect();
    let run = |kind: LearnerKind| -> Result<Vec<ValueSessionRecord>, Box<dyn std::error::Error>> {
        eprintln!("{kind}: {sessions} sessions x {trials} trials, live physics ...");
        let work = e3d::world::Workload {
            trials: trials as u64 * sessions,
            sessions: configs.len(),
            threads: rayon::current_num_threads(),
        };
        let exec = e3d::Executor::for_values(&scene, &work)?;
        let mut learners = configs
            .iter()
            .map(|_| LearnerSetup::new(kind).values(&space, n))
            .collect::<Result<Vec<_>, e3d::learner::LearnerError>>()?;
        let mut records: Vec<ValueSessionRecord> = configs
            .iter()
            .map(|c| ValueSessionRecord::new(space.num_slots(), n, c.trials))
            .collect();
        let status = run_sessions(
            &exec,
            &mut learners,
            &configs,
            &mut records,
            &Control::default(),
        );
        for s in status {
            s?;
        }
        Ok(records)
    };
    let mut panels = Vec::new();
    println!("| {sessions} sessions x {trials} trials | normalised entropy (mean ± sd, min-max) | cells reached (mean, min-max) | pooled entropy |");
    println!("|---|---|---|---|");
    for (kind, label) in [
        (LearnerKind::Uniform, "uniform sampler"),
        (LearnerKind::E3d, "Gaussian E3D"),
    ] {
        let records = run(kind)?;
        let ms: Vec<_> = records
            .iter()
            .map(|r| r.metrics(&Target::Uniform))
            .collect();
        let h = e3d::report::describe(&ms.iter().map(|m| m.normalized_entropy).collect::<Vec<_>>());
        let cells: Vec<f64> = ms.iter().map(|m| m.distinct_effects as f64).collect();
        let c = e3d::report::describe(&cells);
        let mut pooled = vec![0.0; n];
        for r in &records {
            for (p, k) in pooled.iter_mut().zip(r.effect_counts(0..r.trials())) {
                *p += k;
            }
        }
        let total: f64 = pooled.iter().sum();
        let shares: Vec<f64> = pooled.iter().map(|k| k / total).collect();
        let hp = entropy(&shares) / (n as f64).ln();
        println!(
            "| {label} | {:.4} ± {:.4} ({:.4}-{:.4}) | {:.1} ({}-{}) | {hp:.4} over {} cells |",
            h.mean,
            h.sd,
            h.min,
            h.max,
            c.mean,
            c.min,
            c.max,
            shares.iter().filter(|&&s| s > 0.0).count()
        );
        panels.push((format!("{label}: H/log {n} = {hp:.3} (pooled)"), shares));
    }
    if let Some(path) = out {
        let peak = panels
            .iter()
            .flat_map(|(_, s)| s.iter().copied())
            .fold(1e-12, f64::max);
        // the arm's rest tip, (1.75, 0), is in cell (7, 14)
        let spec = GridSpec {
            rows: 15,
            cols: 15,
            start: (7, 14),
            walls: vec![],
            contexts: vec![],
        };
        let lines = [
            format!(
                "Each cell: its share of all {} trials of the {sessions} sessions per learner (tip cells of 0.25 m over [-1.875, 1.875]^2),",
                sessions as usize * trials
            ),
            "on one colour scale for both panels. Torques: any value in [-t_k, t_k] per joint, drawn independently per slot:".to_string(),
            "uniformly (left) or from E3D's Gaussian policy, updated by the intrinsic reward (right).".to_string(),
        ];
        let svg = effect_panels_svg(
            &format!("arm7_continuous, task 1: where the tip ends, {sessions} sessions x {trials} trials pooled"),
            &lines,
            &spec,
            &panels,
            peak,
            1.0 / n as f64,
        )?;
        std::fs::write(path, svg)?;
        eprintln!("wrote {path}");
    }
    Ok(())
}
