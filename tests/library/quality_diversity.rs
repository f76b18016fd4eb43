//! Quality-diversity: MAP-Elites, the two archives (chosen and reached
//! counts) and the QD-score (docs/algorithms.md, "MAP-Elites",
//! "QD-score"). Fixed seeds; numbers a wrong implementation would change.

use e3d::command::{CommandSpace, ValueSpace};
use e3d::learner::{
    Archive, ArchiveReached, Effort, LearnerSetup, MapElites, MapElitesValues, MAP_ELITES_INITIAL,
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
    // arm7: '0' is every joint's idle symbol; MAP-Elites' elite of a cell
    // is the best quality among the commands that reached it, and the
    // elites improve as the session goes on
    let (scene, table) = table("arm7");
    let space = scene.command_space();
    let effort = Effort::of_symbols(&space);
    let mut me = MapElites::new(&space, scene.num_effects(), &Params::TASK1);
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
    // the mean elite quality over the filled cells rises (seed 4: 0.462
    // after 100 trials, 0.557 after 3000, with more cells filled)
    assert!(mean_at[1] > mean_at[0] + 0.05, "{mean_at:?}");
}

#[test]
fn qd_score_by_hand() {
    // 3 slots of '-', '0', '+': quality 1 - (non-'0' slots) / 3
    let space = CommandSpace::repeat(3, &['-', '0', '+']).unwrap();
    let mut m = RunningMetrics::new(4).with_effort(Effort::of_symbols(&space));
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
    // values: |v| / max(|min|, |max|) summed, ranges (-2, 1) and (0, 4)
    let vs = ValueSpace::new(vec![(-2.0, 1.0), (0.0, 4.0)]).unwrap();
    let mut m = RunningMetrics::new(2).with_effort(Effort::of_values(&vs));
    m.record(&vec![-1.0, 2.0], &outcome(1)); // effort 0.5 + 0.5: quality 0.5
    m.record(&vec![1.0, 4.0], &outcome(1)); // effort 2: quality 0
    assert_eq!(m.metrics(&Target::Uniform).qd_score, Some(0.5));
    // a command of the wrong kind or length has no effort
    assert_eq!(Effort::of_values(&vs).of(&[0u8, 1][..]), None);
    assert_eq!(Effort::of_symbols(&space).of(&[0u8][..]), None);
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
    let mut reached = ArchiveReached::new(&space, 2, &p);
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
    // two_rooms has no '0' symbol: every command spends full effort
    assert!(one.iter().all(|r| r.ends_with(",0,")), "{one:?}");
}

#[test]
fn map_elites_on_values_keeps_the_least_effort_values() {
    let space = ValueSpace::new(vec![(-1.0, 1.0); 2]).unwrap();
    let mut me = MapElitesValues::new(&space, 2, &Params::TASK1);
    use e3d::ContinuousLearner;
    me.learn(&[0.5, 0.5], &outcome(0));
    me.learn(&[0.1, -0.2], &outcome(0));
    me.learn(&[0.9, 0.0], &outcome(0));
    assert_eq!(me.command_of(0), Some(&[0.1, -0.2][..]));
    assert!((me.elite_quality(0).unwrap() - 0.85).abs() < 1e-12);
}
