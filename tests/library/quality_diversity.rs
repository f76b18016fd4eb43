//! Quality-diversity: MAP-Elites, the two archives (chosen and reached
//! counts) and the QD-score (docs/algorithms.md, "MAP-Elites",
//! "QD-score"). Fixed seeds; numbers a wrong implementation would change.

use e3d::command::{CommandSpace, ValueSpace};
use e3d::learner::{
    Archive, ArchiveReached, Effort, LearnerSetup, MapElites, MapElitesValues, ValueEffort,
    MAP_ELITES_INITIAL, REACHED_BATCH,
};
use e3d::rand::SeedableRng;
use e3d::report::mean_ci95;
use e3d::session::RunningMetrics;
use e3d::sweep::{Sweep, SweepSpec};
use e3d::{
    run_session, Command, Learner, LearnerKind, Outcome, OutcomeTable, Params, Recorder, Scene,
    SessionConfig, SessionRng, Target, World,
};

fn table(name: &str) -> (Scene, OutcomeTable) {
    let scene = Scene::builtin(name).unwrap();
    let table = OutcomeTable::build(&mut *scene.build()).unwrap();
    (scene, table)
}

fn outcome(effect: usize) -> Outcome {
    Outcome {
        effect,
        reward: 0.0,
        point: [0.0; 2],
    }
}

/// The distinct cells each of 100 sessions of `kind` reaches in `trials`
/// trials on `table`, task 1.
fn distinct(kind: LearnerKind, scene: &Scene, table: &OutcomeTable, trials: usize) -> Vec<f64> {
    (0..100)
        .map(|seed| {
            let mut l = LearnerSetup::new(kind)
                .symbols(&scene.command_space(), scene.num_effects())
                .unwrap();
            let cfg = SessionConfig {
                trials,
                seed,
                use_reward: false,
            };
            let rec = run_session(&mut &*table, &mut l, &cfg).unwrap();
            rec.metrics(&Target::Uniform).distinct_effects as f64
        })
        .collect()
}

#[test]
fn map_elites_fills_more_cells_than_uniform() {
    // three_rooms' table (262144 commands) is slow to build: two_rooms,
    // 300 trials, 100 seeds; the paired difference's 95% interval is
    // above 0 (measured: map_elites 15.9 of 18 cells, uniform 14.7)
    let (scene, table) = table("two_rooms");
    let me = distinct(LearnerKind::MapElites, &scene, &table, 300);
    let uni = distinct(LearnerKind::Uniform, &scene, &table, 300);
    let diff: Vec<f64> = me.iter().zip(&uni).map(|(a, b)| a - b).collect();
    let ci = mean_ci95(&diff).unwrap();
    let (m, u) = (mean_ci95(&me).unwrap().mean, mean_ci95(&uni).unwrap().mean);
    assert!(
        ci.lo() > 0.0,
        "map_elites {m}, uniform {u}: {} ± {}",
        ci.mean,
        ci.half
    );
}

#[test]
fn map_elites_keeps_the_least_effort_command_of_each_cell() {
    // arm7: effort the sum of |torque| (4.62 N·m at most); MAP-Elites'
    // elite of a cell is the best quality among the commands that reached
    // it, and the elites improve as the session goes on
    let (scene, table) = table("arm7");
    let space = scene.command_space();
    let effort = Effort::of_scene(&scene);
    let mut me = MapElites::new(&space, scene.num_effects(), &Params::TASK1)
        .with_effort(Some(effort.clone()));
    let mut best = vec![f64::NEG_INFINITY; scene.num_effects()];
    let mut rng = SessionRng::seed_from_u64(4);
    let mut c = space.first();
    let mut world = &table;
    let mut mean_at = Vec::new();
    for t in 1..=3000 {
        me.propose(&mut rng, &mut c);
        assert_eq!(
            me.last_cell().is_none(),
            t <= MAP_ELITES_INITIAL as usize,
            "{t}"
        );
        let o = world.execute(&c).unwrap();
        me.learn(&c, &o);
        let q = effort.quality(&c).unwrap();
        best[o.effect] = best[o.effect].max(q);
        if t == 100 || t == 3000 {
            let qs: Vec<f64> = me
                .reached()
                .iter()
                .map(|&e| me.elite_quality(e).unwrap())
                .collect();
            mean_at.push(qs.iter().sum::<f64>() / qs.len() as f64);
        }
    }
    for (e, &b) in best.iter().enumerate() {
        assert_eq!(me.elite_quality(e), b.is_finite().then_some(b), "cell {e}");
        if let Some(cmd) = me.command_of(e) {
            assert_eq!(effort.quality(cmd), Some(b));
            assert_eq!(
                world.execute(&Command::new(cmd.to_vec())).unwrap().effect,
                e
            );
        }
    }
    // the mean elite quality over the filled cells rises, with more cells
    // filled
    assert!(mean_at[1] > mean_at[0] + 0.05, "{mean_at:?}");
}

/// The effort of `command` on built-in scene `name`, and its largest.
fn effort_on(name: &str, command: &str) -> (f64, f64) {
    let scene = Scene::builtin(name).unwrap();
    let e = Effort::of_scene(&scene);
    let c = scene.command_space().parse(command).unwrap();
    (e.of(&c).unwrap(), e.max())
}

#[test]
fn the_effort_of_a_command_is_the_size_of_its_actions() {
    let close = |(a, b): (f64, f64), (x, y): (f64, f64)| {
        assert!((a - x).abs() < 1e-12 && (b - y).abs() < 1e-12, "{a} {b}")
    };
    // arm7: |torque| summed, 1.8 + 1.2 + ... + 0.06 = 4.62 N·m at most
    close(effort_on("arm7", "+0-0000"), (1.8 + 0.75, 4.62));
    close(effort_on("arm7", "0000000"), (0.0, 4.62));
    close(effort_on("arm7", "------+"), (4.62, 4.62));
    // pendulum3: |angle| of the set points, 'c' the idle symbol
    close(effort_on("pendulum3", "ccc"), (0.0, 4.5));
    close(effort_on("pendulum3", "adc"), (1.5 + 0.75, 4.5));
    // puck_rooms: 7 impulses of 1.6 N·s whatever their directions
    close(effort_on("puck_rooms", "ESWNESW"), (7.0 * 1.6, 7.0 * 1.6));
    // a grid scene: 7 moves of one cell
    close(effort_on("two_rooms", "EEEEESS"), (7.0, 7.0));
    // continuous arm7: |v| summed over the torques' ranges
    let arm = Scene::builtin("arm7_continuous").unwrap();
    let e = Effort::of_scene(&arm);
    let v = [1.0, -0.5, 0.0, 0.0, 0.0, 0.0, 0.25];
    assert!((e.of(&v[..]).unwrap() - 1.75).abs() < 1e-12);
    // only where commands differ does the quality (and the qd_score) mean anything
    let varies = |n| Effort::of_scene(&Scene::builtin(n).unwrap()).varies();
    assert!(varies("arm7") && varies("pendulum3") && varies("arm7_continuous"));
    assert!(!varies("puck_rooms") && !varies("three_rooms") && !varies("two_rooms"));
}

#[test]
fn qd_score_by_hand() {
    // 3 slots of '-', '0', '+' of sizes 1, 0, 1: quality 1 - effort / 3
    let space = CommandSpace::repeat(3, &['-', '0', '+']).unwrap();
    let sizes = Effort::Symbols(vec![vec![1.0, 0.0, 1.0]; 3]);
    let mut m = RunningMetrics::new(4).with_effort(sizes.clone());
    for (c, e) in [("+++", 0), ("0+0", 0), ("-++", 1), ("000", 3), ("+0+", 3)] {
        m.record(&space.parse(c).unwrap(), &outcome(e));
    }
    // cell 0: "0+0" 2/3; cell 1: "-++" 0; cell 3: "000" 1
    let got = m.metrics(&Target::Uniform);
    assert_eq!(got.qd_score, Some((1.0 - 1.0 / 3.0) + 0.0 + 1.0));
    assert_eq!(got.coverage, 0.75);
    assert_eq!(
        RunningMetrics::new(4).metrics(&Target::Uniform).qd_score,
        None
    );
    // values: |v| summed, |v| <= 2 and 4: at most 6
    let slot = |bound| ValueEffort {
        scale: 1.0,
        fixed: 0.0,
        bound,
    };
    let values = Effort::Values(vec![slot(2.0), slot(4.0)]);
    let mut m = RunningMetrics::new(2).with_effort(values.clone());
    m.record(&vec![-1.0, 2.0], &outcome(1)); // effort 3: quality 0.5
    m.record(&vec![2.0, 4.0], &outcome(1)); // effort 6: quality 0
    assert_eq!(m.metrics(&Target::Uniform).qd_score, Some(0.5));
    // a command of the wrong kind or length has no effort
    assert_eq!(values.of(&[0u8, 1][..]), None);
    assert_eq!(sizes.of(&[0u8][..]), None);
    // every command the same effort: no qd_score
    let flat = Effort::Symbols(vec![vec![1.6; 4]; 7]);
    let mut m = RunningMetrics::new(2).with_effort(flat);
    m.record(&space.parse("+0+").unwrap(), &outcome(1));
    assert_eq!(m.metrics(&Target::Uniform).qd_score, None);
}

#[test]
fn the_reached_archive_counts_reaches_not_picks() {
    // cell 0 reached 3 times, cell 1 once; the reached archive weights
    // them (1 + 3)^-0.5 = 0.5 and (1 + 1)^-0.5 = 0.707: cell 1 is picked
    // with probability 0.586 and proposals change nothing (sd of 2000
    // picks: 22); the chosen archive counts the picks instead, and
    // splits them about evenly
    let space = CommandSpace::repeat(3, &['a', 'b', 'c']).unwrap();
    let p = Params::TASK1;
    // batches of one trial: every pick sees the counts as they are
    let mut reached = ArchiveReached::new(&space, 2, &p).with_batch(1);
    let mut chosen = Archive::new(&space, 2, &p);
    for e in [0, 0, 1, 0] {
        reached.learn(&Command::new(vec![e as u8; 3]), &outcome(e));
        chosen.learn(&Command::new(vec![e as u8; 3]), &outcome(e));
    }
    assert_eq!((reached.times_chosen(0), reached.times_chosen(1)), (3, 1));
    assert_eq!((chosen.times_chosen(0), chosen.times_chosen(1)), (0, 0));
    let (mut rng, mut c) = (SessionRng::seed_from_u64(9), space.first());
    let mut ones = [0, 0];
    for _ in 0..2000 {
        reached.propose(&mut rng, &mut c);
        ones[0] += (reached.last_cell() == Some(1)) as i32;
        chosen.propose(&mut rng, &mut c);
        ones[1] += (chosen.last_cell() == Some(1)) as i32;
    }
    assert_eq!((reached.times_chosen(0), reached.times_chosen(1)), (3, 1));
    assert!((1106..=1238).contains(&ones[0]), "{ones:?}");
    assert!((960..=1040).contains(&ones[1]), "{ones:?}");
    assert_eq!(chosen.times_chosen(0) + chosen.times_chosen(1), 2000);
}

#[test]
fn the_reached_archive_picks_in_batches_of_64() {
    // a batch's picks are among the cells of its start: none during the
    // first 64 trials (uniform commands), then cells 0 and 1 only, though
    // cell 2 was reached at trial 65, until trial 128 adds it
    let space = CommandSpace::repeat(3, &['a', 'b', 'c']).unwrap();
    let mut a = ArchiveReached::new(&space, 3, &Params::TASK1);
    let (mut rng, mut c) = (SessionRng::seed_from_u64(2), space.first());
    let mut picked = vec![[0u32; 4]; 3]; // per batch: uniform, cell 0, 1, 2
    for t in 0..192 {
        a.propose(&mut rng, &mut c);
        let k = a.last_cell().map_or(0, |e| e + 1);
        picked[t / REACHED_BATCH][k] += 1;
        let e = if t < 64 { t % 2 } else { 2 };
        a.learn(&c, &outcome(e));
    }
    assert_eq!(picked[0], [64, 0, 0, 0]);
    assert_eq!(picked[1][0] + picked[1][3], 0, "{picked:?}");
    assert!(picked[2][3] > 0, "{picked:?}");
    assert_eq!(a.times_chosen(2), 128);
}

#[test]
fn quality_diversity_sweeps_repeat_whatever_the_threads() {
    let spec = SweepSpec::new(["two_rooms"], ["map_elites", "archive_reached"], 3, 400);
    let sweep = Sweep::new(spec).unwrap();
    let rows = |threads| -> Vec<String> {
        let mut r: Vec<String> = (sweep.run(threads).unwrap().iter())
            .map(|r| sweep.result_row(r))
            .collect();
        r.sort();
        r
    };
    let one = rows(1);
    assert_eq!(one, rows(2));
    assert!(
        sweep.results_header().ends_with(",qd_score,failure"),
        "{}",
        sweep.results_header()
    );
    // two_rooms' commands are all 7 moves: the same effort, no qd_score
    assert!(one.iter().all(|r| r.ends_with(",,")), "{one:?}");
}

#[test]
fn map_elites_on_values_keeps_the_least_effort_values() {
    let space = ValueSpace::new(vec![(-1.0, 1.0); 2]).unwrap();
    let unit = ValueEffort {
        scale: 1.0,
        fixed: 0.0,
        bound: 1.0,
    };
    let effort = Effort::Values(vec![unit; 2]);
    let mut me = MapElitesValues::new(&space, 2, &Params::TASK1).with_effort(Some(effort));
    use e3d::ContinuousLearner;
    me.learn(&[0.5, 0.5], &outcome(0));
    me.learn(&[0.1, -0.2], &outcome(0));
    me.learn(&[0.9, 0.0], &outcome(0));
    assert_eq!(me.command_of(0), Some(&[0.1, -0.2][..]));
    assert!((me.elite_quality(0).unwrap() - 0.85).abs() < 1e-12);
}
