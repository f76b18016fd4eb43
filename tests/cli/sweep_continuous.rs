//! `e3d sweep` on scenes of continuous commands: live sessions, in
//! lockstep where the scene's copies are exact, each the bytes of the
//! session run alone, whatever the threads and the shards.

use crate::common::{e3d, ok, temp_dir, PUCK_HEADINGS};
use crate::sweep::{assert_same_files, FINAL_FILES};
use e3d::learner::LearnerSetup;
use e3d::session::run_value_session;
use e3d::{LearnerKind, Scene, SessionConfig, Target};

/// A puck of continuous commands (exact copies: its sessions step
/// together) and arm7_continuous (a world per session), 2 learners, 2
/// values of eta, 3 sessions of 40 trials.
const SWEEP: &str = r#"Sweep(
    scenes: ["puck_headings.ron", "arm7_continuous"],
    learners: [e3d, uniform],
    params: (eta: [0.01, 0.1]),
    sessions: 3,
    trials: 40,
    seed: 5,
    metrics: [normalized_entropy, kl_to_target, distinct_effects, cumulative_reward(40), first_reward_trial],
)
"#;

#[test]
fn a_continuous_sweep_gives_each_session_alone_whatever_the_threads_and_shards() {
    let d = temp_dir("sweep-continuous");
    std::fs::write(d.join("puck_headings.ron"), PUCK_HEADINGS).unwrap();
    let file = d.join("values.ron");
    std::fs::write(&file, SWEEP).unwrap();
    let f = file.to_str().unwrap();
    let out = |name: &str| d.join(name).to_str().unwrap().to_string();
    let one = ok(e3d(&["sweep", f, "--out", &out("one"), "--threads", "1"]));
    let told = String::from_utf8_lossy(&one.stderr);
    // one thread: the puck's 18 sessions step together on worlds of 9
    // copies; each arm session has a world of its own
    assert!(
        told.contains("puck_headings: live: every proposal executed (continuous commands; sessions in lockstep, 1 group(s), up to 9 commands per world)"),
        "{told}"
    );
    assert!(
        told.contains("arm7_continuous: live: every proposal executed (continuous commands; 9 group(s) of sessions, one command per world"),
        "{told}"
    );
    ok(e3d(&["sweep", f, "--out", &out("two"), "--threads", "2"]));
    assert_same_files(&d.join("one"), &d.join("two"), &FINAL_FILES);
    for k in 1..=2 {
        let shard = out(&format!("shard{k}"));
        ok(e3d(&[
            "sweep",
            f,
            "--shard",
            &format!("{k}/2"),
            "--out",
            &shard,
            "--threads",
            "2",
        ]));
    }
    ok(e3d(&[
        "merge",
        &out("shard2"),
        &out("shard1"),
        "--out",
        &out("merged"),
    ]));
    assert_same_files(&d.join("one"), &d.join("merged"), &FINAL_FILES);

    // every row holds the metrics of the session run alone, on a world of
    // one copy, with its seed and its cell's parameters
    let sweep = e3d::Sweep::load(&file).unwrap();
    let results = std::fs::read_to_string(d.join("one/results.csv")).unwrap();
    let rows: Vec<Vec<&str>> = results
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let sessions = sweep.sessions();
    assert_eq!(rows.len(), 2 * 3 * 3);
    assert_eq!(sessions.len(), rows.len());
    let puck = Scene::load(d.join("puck_headings.ron")).unwrap();
    let arm = Scene::builtin("arm7_continuous").unwrap();
    let mut distinct = Vec::new();
    for (s, row) in sessions.iter().zip(&rows) {
        let cell = &sweep.cells()[s.cell];
        let scene = if cell.scene == 0 { &puck } else { &arm };
        assert_eq!(row[0], scene.spec().name);
        assert_eq!(row[9], s.seed.to_string());
        let space = scene.value_space().unwrap();
        let kind: LearnerKind = cell.learner.parse().unwrap();
        let mut learner = LearnerSetup::new(kind)
            .params(cell.params)
            .values(&space, scene.num_effects())
            .unwrap();
        let mut world = scene.as_continuous().unwrap().world(1);
        let config = SessionConfig {
            trials: 40,
            seed: s.seed,
            use_reward: true,
        };
        let rec = run_value_session(&mut world, &mut learner, &config).unwrap();
        let m = rec.metrics(&Target::Uniform);
        let num = |i: usize| row[i].parse::<f64>().unwrap();
        assert_eq!(num(10).to_bits(), m.normalized_entropy.to_bits(), "{row:?}");
        assert_eq!(num(11).to_bits(), m.kl_to_target.to_bits(), "{row:?}");
        assert_eq!(row[12], m.distinct_effects.to_string(), "{row:?}");
        assert_eq!(num(13), m.cumulative_reward, "{row:?}");
        assert_eq!(row[15], "", "no failure: {row:?}");
        distinct.push(m.distinct_effects);
    }
    // the sessions differ from each other (their seeds and learners count)
    distinct.sort_unstable();
    distinct.dedup();
    assert!(distinct.len() >= 3, "{distinct:?}");
}

#[test]
fn a_continuous_scene_with_a_learner_of_symbols_or_in_episodes_is_refused_with_its_place() {
    let d = temp_dir("sweep-continuous-bad");
    let cases = [
        (
            "Sweep(\n    scenes: [\"arm7_continuous\"],\n    learners: [e3d, egreedy],\n    sessions: 2,\n    trials: 10,\n)\n",
            "learners.ron:3:5: field `learners`: expected learners that take continuous commands on scene `arm7_continuous`, found `egreedy`: learner `egreedy` takes symbols",
        ),
        (
            "Sweep(\n    scenes: [\"two_rooms\", \"arm7_continuous\"],\n    learners: [e3d],\n    sessions: 2,\n    trials: 10,\n    commands: 2,\n)\n",
            "episodes.ron:2:27: field `scenes`: expected scenes of symbols in a sweep of episodes (commands, observe or closed_loop set), found `arm7_continuous`, whose slots take values (`Continuous`)",
        ),
    ];
    for (name, (text, says)) in ["learners.ron", "episodes.ron"].iter().zip(cases) {
        let file = d.join(name);
        std::fs::write(&file, text).unwrap();
        let r = e3d(&[
            "sweep",
            file.to_str().unwrap(),
            "--out",
            d.join("out").to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
        assert!(!d.join("out").exists(), "{name}: nothing runs");
    }
}

#[test]
fn a_table_or_memo_forced_on_a_continuous_sweep_is_refused_before_its_folder_exists() {
    let d = temp_dir("sweep-continuous-forced");
    let file = d.join("arm.ron");
    std::fs::write(
        &file,
        "Sweep(scenes: [\"two_rooms\", \"arm7_continuous\"], learners: [e3d], sessions: 2, trials: 10)\n",
    )
    .unwrap();
    for forced in ["table", "memo"] {
        let out = d.join(format!("out-{forced}"));
        let r = e3d(&[
            "sweep",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--outcomes",
            forced,
        ]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{forced}: {err}");
        assert!(
            err.contains(&format!("--outcomes: scene `arm7_continuous` takes continuous commands, which run live only (no table, no memo), but the sweep forces {forced}")),
            "{forced}: {err}"
        );
        assert!(!out.exists(), "{forced}: no folder made");
    }
    // live is what such a scene runs anyway
    let out = d.join("out-live");
    ok(e3d(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--outcomes",
        "live",
    ]));
    assert!(out.join("summary.csv").is_file());
}
