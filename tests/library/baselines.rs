//! The baselines that keep commands and mutate them (goal babbling, the
//! archive of reached cells; docs/algorithms.md) and the coverage
//! measures. Fixed seeds; every check compares numbers or contents that a
//! wrong implementation would change.

use e3d::command::ValueSpace;
use e3d::learner::mutation::{mutate_symbols, mutate_values};
use e3d::learner::LearnerSetup;
use e3d::learner::{Archive, GoalBabbling};
use e3d::rand::SeedableRng;
use e3d::session::{run_value_session, RunningMetrics};
use e3d::{
    run_session, Command, Learner, LearnerKind, Outcome, OutcomeTable, Params, Recorder, Scene,
    SessionConfig, SessionRng, Sweep, Target, World,
};
use std::collections::HashMap;

fn two_rooms() -> (Scene, OutcomeTable) {
    let scene = Scene::builtin("two_rooms").unwrap();
    let table = OutcomeTable::build(&mut *scene.build()).unwrap();
    (scene, table)
}

fn differing(a: &[u8], b: &[u8]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count()
}

#[test]
fn mutation_changes_exactly_k_slots() {
    // slot 2 has one symbol: it can never change, so at most 4 slots can
    let sizes = [4, 3, 1, 2, 5];
    let mut scratch = Vec::new();
    let mut picked = [0u32; 5];
    for k in 1..=6 {
        for seed in 0..200u64 {
            let mut rng = SessionRng::seed_from_u64(seed);
            let before: Vec<u8> = vec![1, 2, 0, 1, 4];
            let mut after = before.clone();
            mutate_symbols(&sizes, k, &mut rng, &mut after, &mut scratch);
            assert_eq!(differing(&before, &after), k.min(4), "k {k}, seed {seed}");
            assert_eq!(after[2], 0);
            for (slot, (&s, &n)) in after.iter().zip(&sizes).enumerate() {
                assert!((s as usize) < n, "slot {slot}: symbol {s} of {n}");
                if k == 1 && s != before[slot] {
                    picked[slot] += 1;
                }
            }
        }
    }
    // k = 1: each of the 4 mutable slots about 50 times in 200
    assert_eq!(picked.iter().sum::<u32>(), 200);
    assert_eq!(picked[2], 0);
    for slot in [0, 1, 3, 4] {
        assert!((30..=70).contains(&picked[slot]), "{picked:?}");
    }
}

#[test]
fn gaussian_mutation_has_the_spread_of_sigma() {
    let space = ValueSpace::new(vec![(0.0, 4.0); 2]).unwrap();
    let mut rng = SessionRng::seed_from_u64(7);
    let (mut sum, mut sq, n) = (0.0, 0.0, 4000);
    for _ in 0..n {
        let mut v = vec![2.0, 2.0];
        mutate_values(&space, 0.1, &mut rng, &mut v);
        // in unit coordinates, the half-range is 2
        let d = (v[0] - 2.0) / 2.0;
        sum += d;
        sq += d * d;
        assert!((0.0..=4.0).contains(&v[1]));
    }
    let mean = sum / n as f64;
    let sd = (sq / n as f64 - mean * mean).sqrt();
    assert!(mean.abs() < 0.01, "{mean}");
    assert!((sd - 0.1).abs() < 0.01, "{sd}");
    // a value at the end of its range is clamped, never past it
    let mut v = vec![4.0, 0.0];
    for _ in 0..100 {
        mutate_values(&space, 0.5, &mut rng, &mut v);
        assert!(v.iter().all(|x| (0.0..=4.0).contains(x)));
    }
}

#[test]
fn the_archive_keeps_exactly_one_command_per_reached_cell() {
    let (scene, table) = two_rooms();
    let space = scene.command_space();
    let params = Params {
        k: 2,
        ..Params::TASK1
    };
    let mut archive = Archive::new(&space, scene.num_effects(), &params);
    let mut rng = SessionRng::seed_from_u64(11);
    let mut world = &table;
    let mut first: HashMap<usize, Vec<u8>> = HashMap::new();
    let mut order = Vec::new();
    let mut c = space.first();
    for t in 0..3000 {
        archive.propose(&mut rng, &mut c);
        if let Some(cell) = archive.last_cell() {
            // the proposal is the kept command of the cell picked, k slots changed
            let kept = archive.command_of(cell).unwrap();
            assert_eq!(differing(kept, &c.symbols), 2, "trial {t}");
        } else {
            assert_eq!(t, 0, "only the first proposal is uniform");
        }
        let o = world.execute(&c).unwrap();
        archive.learn(&c, &Outcome { reward: 0.0, ..o });
        first.entry(o.effect).or_insert_with(|| {
            order.push(o.effect);
            c.symbols.clone()
        });
    }
    // one command per reached cell: the first that reached it (no reward
    // to replace it), and it reaches that cell
    assert_eq!(archive.reached(), order.as_slice());
    assert!(order.len() >= 16, "{} cells", order.len());
    for e in 0..scene.num_effects() {
        match first.get(&e) {
            Some(cmd) => {
                assert_eq!(archive.command_of(e), Some(cmd.as_slice()));
                let o = world.execute(&Command::new(cmd.clone())).unwrap();
                assert_eq!(o.effect, e);
            }
            None => assert_eq!(archive.command_of(e), None),
        }
    }
    // every pick was counted: 2999 proposals from the archive
    let picks: u64 = order.iter().map(|&e| archive.times_chosen(e)).sum();
    assert_eq!(picks, 2999);
}

#[test]
fn a_rewarded_command_replaces_the_kept_one() {
    let space = e3d::command::CommandSpace::repeat(2, &['a', 'b']).unwrap();
    let mut a = Archive::new(&space, 3, &Params::TASK1);
    let o = |reward| Outcome {
        effect: 1,
        reward,
        point: [0.0; 2],
    };
    a.learn(&Command::new(vec![0, 0]), &o(0.0));
    a.learn(&Command::new(vec![1, 0]), &o(0.0));
    assert_eq!(a.command_of(1), Some(&[0u8, 0][..]));
    a.learn(&Command::new(vec![1, 1]), &o(1.0));
    assert_eq!(a.command_of(1), Some(&[1u8, 1][..]));
    a.learn(&Command::new(vec![0, 1]), &o(1.0));
    assert_eq!(a.command_of(1), Some(&[1u8, 1][..]));
    assert_eq!(a.reached(), [1]);
}

#[test]
fn the_archive_favours_rarely_chosen_cells() {
    // cell 0 is picked 200 times alone, then cell 1 joins: over the next
    // 200 picks, cell 0's chance is (1 + n0)^-r / ((1 + n0)^-r + (1 + n1)^-r):
    // picks of cell 0 about 100 (r = 0, sd 7.2), 67 (r = 0.5, sd 5.6) and
    // 50 (r = 1, sd 4.9) (4000 simulated runs)
    let space = e3d::command::CommandSpace::repeat(3, &['a', 'b', 'c']).unwrap();
    let o = |e| Outcome {
        effect: e,
        reward: 0.0,
        point: [0.0; 2],
    };
    let mut picks = Vec::new();
    for rarity in [0.0, 0.5, 1.0] {
        let params = Params {
            rarity,
            ..Params::TASK1
        };
        let mut a = Archive::new(&space, 3, &params);
        let mut rng = SessionRng::seed_from_u64(5);
        let mut c = space.first();
        a.learn(&Command::new(vec![0, 0, 0]), &o(0));
        for _ in 0..200 {
            a.propose(&mut rng, &mut c);
        }
        assert_eq!(a.times_chosen(0), 200);
        a.learn(&Command::new(vec![1, 1, 1]), &o(1));
        for _ in 0..200 {
            a.propose(&mut rng, &mut c);
        }
        assert_eq!(a.times_chosen(0) + a.times_chosen(1), 400);
        picks.push(a.times_chosen(0) - 200);
    }
    // within 3 sd
    assert!((79..=121).contains(&picks[0]), "{picks:?}");
    assert!((50..=84).contains(&picks[1]), "{picks:?}");
    assert!((36..=64).contains(&picks[2]), "{picks:?}");
    assert!(picks[0] > picks[2], "{picks:?}");
}

#[test]
fn goal_babbling_mutates_the_nearest_known_command() {
    let (scene, table) = two_rooms();
    let space = scene.command_space();
    for k in [1, 3] {
        let params = Params { k, ..Params::TASK1 };
        let mut gb = GoalBabbling::new(&space, scene.num_effects(), &params);
        let mut rng = SessionRng::seed_from_u64(21);
        let mut world = &table;
        // the test's own inverse model: per cell, its outcome and the last command
        let mut known: Vec<(usize, [f64; 2], Vec<u8>)> = Vec::new();
        let mut c = space.first();
        let mut checked = 0;
        for t in 0..1500 {
            gb.propose(&mut rng, &mut c);
            match gb.last_goal() {
                None => assert_eq!(t, 0),
                Some(g) => {
                    let d = |p: [f64; 2]| (p[0] - g[0]).powi(2) + (p[1] - g[1]).powi(2);
                    // nearest, ties to the first reached
                    let mut best = 0;
                    for i in 1..known.len() {
                        if d(known[i].1) < d(known[best].1) {
                            best = i;
                        }
                    }
                    assert_eq!(gb.last_parent(), Some(known[best].0), "trial {t}");
                    assert_eq!(gb.nearest(g), Some(known[best].0));
                    assert_eq!(differing(&known[best].2, &c.symbols), k, "trial {t}");
                    checked += 1;
                }
            }
            let o = world.execute(&c).unwrap();
            gb.learn(&c, &o);
            match known.iter_mut().find(|(e, _, _)| *e == o.effect) {
                Some(entry) => {
                    entry.1 = o.point;
                    entry.2 = c.symbols.clone();
                }
                None => known.push((o.effect, o.point, c.symbols.clone())),
            }
        }
        assert_eq!(checked, 1499);
        assert_eq!(gb.known().len(), known.len());
        // two_rooms has 18 cells, all reachable: goal babbling finds them all
        assert_eq!(known.len(), 18, "k {k}");
    }
}

#[test]
fn goals_beyond_the_known_box_pull_outwards() {
    // two known cells on a line; goals are drawn within 10% beyond them
    let space = e3d::command::CommandSpace::repeat(2, &['a', 'b', 'c']).unwrap();
    let mut gb = GoalBabbling::new(&space, 4, &Params::TASK1);
    let o = |e, x| Outcome {
        effect: e,
        reward: 0.0,
        point: [x, 1.0],
    };
    gb.learn(&Command::new(vec![0, 0]), &o(0, 0.0));
    gb.learn(&Command::new(vec![2, 2]), &o(3, 10.0));
    let mut rng = SessionRng::seed_from_u64(2);
    let mut c = space.first();
    let (mut below, mut above, mut picks0) = (0, 0, 0);
    for _ in 0..1000 {
        gb.propose(&mut rng, &mut c);
        let g = gb.last_goal().unwrap();
        assert!((-1.0..=11.0).contains(&g[0]) && g[1] == 1.0, "{g:?}");
        below += usize::from(g[0] < 0.0);
        above += usize::from(g[0] > 10.0);
        picks0 += usize::from(gb.last_parent() == Some(0));
    }
    // 1/12 of the goals on each side, half of them nearer to cell 0
    assert!((50..=120).contains(&below) && (50..=120).contains(&above));
    assert!((430..=570).contains(&picks0), "{picks0}");
}

#[test]
fn learning_progress_goals_run_and_differ_from_uniform_goals() {
    let (scene, table) = two_rooms();
    let run = |goal_progress: f64| {
        let params = Params {
            goal_progress,
            ..Params::TASK1
        };
        let mut l = LearnerSetup::new(LearnerKind::GoalBabbling)
            .params(params)
            .symbols(&scene.command_space(), 18)
            .unwrap();
        let cfg = SessionConfig {
            trials: 2000,
            seed: 4,
            use_reward: false,
        };
        run_session(&mut &table, &mut l, &cfg).unwrap()
    };
    let (plain, lp) = (run(0.0), run(0.8));
    assert_ne!(plain.effects, lp.effects);
    assert_eq!(lp.metrics(&Target::Uniform).distinct_effects, 18);
    // the same seed, the same session
    assert_eq!(run(0.8), lp);
}

#[test]
fn both_learners_run_by_name_on_symbols_values_and_in_sweeps() {
    let (scene, table) = two_rooms();
    for kind in [LearnerKind::GoalBabbling, LearnerKind::Archive] {
        let name = kind.as_str();
        assert_eq!(name.parse::<LearnerKind>().unwrap(), kind);
        let mut l = LearnerSetup::new(kind)
            .symbols(&scene.command_space(), 18)
            .unwrap();
        assert_eq!(l.name(), name);
        let cfg = SessionConfig {
            trials: 3000,
            seed: 1,
            use_reward: false,
        };
        let rec = run_session(&mut &table, &mut l, &cfg).unwrap();
        let m = rec.metrics(&Target::Uniform);
        // more even than the uniform policy's 0.80 on two_rooms
        assert!(
            m.normalized_entropy > 0.84,
            "{name}: {}",
            m.normalized_entropy
        );
        assert!(m.distinct_effects >= 16, "{name}: {}", m.distinct_effects);
        assert!(l.slot_policy(0).is_none());
    }
    // continuous commands: the arm with a value per joint
    let arm = Scene::builtin("arm7_continuous").unwrap();
    let space = arm.value_space().unwrap();
    for kind in [LearnerKind::GoalBabbling, LearnerKind::Archive] {
        let mut l = LearnerSetup::new(kind)
            .values(&space, arm.num_effects())
            .unwrap();
        assert_eq!(l.name(), kind.as_str());
        let cfg = SessionConfig {
            trials: 40,
            seed: 3,
            use_reward: false,
        };
        let rec =
            run_value_session(&mut arm.as_continuous().unwrap().world(1), &mut l, &cfg).unwrap();
        assert_eq!(rec.commands.len(), 40 * 7);
        assert!(space.check(rec.values_of(39)).is_ok());
        // after the first, every command is a mutation of a kept one:
        // within 5 sigma (in unit coordinates) of some earlier command
        let unit = |v: &[f64]| -> Vec<f64> {
            v.iter()
                .enumerate()
                .map(|(i, &x)| {
                    let (lo, hi) = space.range(i);
                    2.0 * (x - lo) / (hi - lo) - 1.0
                })
                .collect()
        };
        for t in 1..40 {
            let now = unit(rec.values_of(t));
            let near = (0..t).any(|s| {
                unit(rec.values_of(s))
                    .iter()
                    .zip(&now)
                    .all(|(a, b)| (a - b).abs() <= 0.5)
            });
            assert!(near, "{}: trial {t}", kind.as_str());
        }
    }
    // a sweep file: both by name, k fixed for the sweep, coverage columns
    let text = r#"Sweep(
        scenes: ["two_rooms"], learners: [goal_babbling, archive], use_reward: [false],
        params: (k: 2, sigma: 0.2), sessions: 2, trials: 400, seed: 3,
    )"#;
    let sweep = Sweep::parse(text, "baselines.ron", None).unwrap();
    assert_eq!(sweep.cells().len(), 2);
    assert!(sweep
        .cells()
        .iter()
        .all(|c| c.params.k == 2 && c.params.sigma == 0.2));
    assert!(sweep.spec.to_ron().contains("k: 2,\n        sigma: 0.2,"));
    let cols = sweep.metric_columns();
    assert_eq!(
        cols[cols.len() - 4..],
        [
            "coverage",
            "trials_to_50_percent",
            "trials_to_90_percent",
            "qd_score"
        ]
    );
    let results = sweep.run(1).unwrap();
    assert_eq!(results.len(), 4);
    for r in &results {
        let cov = r.values[cols.len() - 4].unwrap();
        assert!(cov > 0.5 && cov <= 1.0, "{cov}");
    }
    let bad = Sweep::parse(
        r#"Sweep(scenes: ["two_rooms"], learners: [archive], params: (k: 0), sessions: 1, trials: 10)"#,
        "bad.ron",
        None,
    )
    .unwrap_err()
    .to_string();
    assert!(
        bad.contains("`k`: expected a whole number >= 1, found 0"),
        "{bad}"
    );
}

#[test]
fn coverage_measures_of_a_hand_made_sequence() {
    // 10 effects, 8 of them reachable; first visits at trials 1, 2, 4, 7, 8, 12, 13, 20
    let effects = [
        0, 1, 1, 2, 0, 2, 3, 4, 4, 0, 1, 5, 6, 6, 0, 1, 2, 3, 4, 7, 7,
    ];
    let mut running = RunningMetrics::new(10);
    let mut record = e3d::SessionRecord {
        num_slots: 1,
        num_effects: 10,
        commands: Vec::new(),
        effects: Vec::new(),
        rewards: Vec::new(),
        points: Vec::new(),
        final_policy: Vec::new(),
    };
    for (t, &e) in effects.iter().enumerate() {
        let o = Outcome {
            effect: e,
            // rewards at trials 9 and 15
            reward: if t == 8 || t == 14 { 1.0 } else { 0.0 },
            point: [0.0; 2],
        };
        let c = Command::new(vec![0]);
        running.record(&c, &o);
        record.record(&c, &o);
    }
    let m = running.metrics_over_reachable(&Target::Uniform, 8);
    assert_eq!(m, record.metrics_over_reachable(&Target::Uniform, 8));
    assert_eq!(m.discovery_trials, [1, 2, 4, 7, 8, 12, 13, 20]);
    assert_eq!(m.coverage_cells, 8);
    assert_eq!(m.coverage, 1.0);
    // 50% of 8 = 4 cells: trial 7; 90% of 8 = ceil(7.2) = 8 cells: trial 20
    assert_eq!(m.trials_to_50_percent, Some(7));
    assert_eq!(m.trials_to_90_percent, Some(20));
    assert_eq!(m.coverage_at(0), 0.0);
    assert_eq!(m.coverage_at(6), 3.0 / 8.0);
    assert_eq!(m.coverage_at(12), 6.0 / 8.0);
    assert_eq!(m.first_reward_trial, Some(9));
    assert_eq!(m.cumulative_reward, 2.0);
    // against all 10 effects: 8 of 10, 50% = 5 cells at trial 8, 90% = 9 never
    let all = running.metrics(&Target::Uniform);
    assert_eq!(all.coverage_cells, 10);
    assert_eq!(all.coverage, 0.8);
    assert_eq!(all.trials_to_50_percent, Some(8));
    assert_eq!(all.trials_to_90_percent, None);
    assert_eq!(all, record.metrics(&Target::Uniform));
}
