//! Continuous commands: the scene format, the values, their execution on
//! live physics, the Gaussian E3D against the uniform sampler, and the CLI.

use crate::common::{e3d, e3d_command, temp_path, PUCK_HEADINGS};
use e3d::command::ValueSpace;
use e3d::learner::LearnerSetup;
use e3d::learner::{GaussianE3d, UniformValues};
use e3d::scene::{Symmetry, WorldSpec};
use e3d::session::run_value_session;
use e3d::world::{Executor, Workload};
use e3d::{
    ContinuousLearner, LearnerKind, Outcome, Params, Scene, SessionConfig, SessionRng, Target,
    World,
};
use rand::SeedableRng;
use std::path::Path;

fn continuous() -> Scene {
    Scene::builtin("arm7_continuous").unwrap()
}

/// The workload of `configs` on the current rayon pool.
fn work(configs: &[SessionConfig]) -> Workload {
    Workload {
        trials: configs.iter().map(|c| c.trials as u64).sum(),
        sessions: configs.len(),
        threads: rayon::current_num_threads(),
    }
}

/// The torque bounds of arm7's joints, as its scene file gives them.
const T: [f64; 7] = [1.8, 1.2, 0.75, 0.45, 0.24, 0.12, 0.06];

#[test]
fn the_values_minus_t_zero_plus_t_give_arm7s_outcomes_bit_for_bit() {
    // arm7 without its symmetry: Rapier's own outcome of every command
    let mut arm = Scene::builtin("arm7").unwrap().to_spec();
    if let WorldSpec::Physics(p) = &mut arm.world {
        assert_eq!(p.symmetry, Some(Symmetry::FlipY));
        p.symmetry = None;
    }
    let arm = arm.validate().unwrap();
    let mut symbols = arm.build();
    let space = arm.command_space();
    let mut values = continuous().physics_world().unwrap();
    for i in (0..2187).step_by(97) {
        let c = space.command_at(i);
        let v: Vec<f64> = c
            .symbols
            .iter()
            .zip(T)
            .map(|(&s, t)| [-t, 0.0, t][s as usize])
            .collect();
        let a = symbols.execute(&c).unwrap();
        let b = values.execute_values(&v).unwrap();
        assert_eq!(
            a.point.map(f64::to_bits),
            b.point.map(f64::to_bits),
            "{}",
            space.format(&c)
        );
        assert_eq!(a.effect, b.effect);
    }
}

#[test]
fn values_are_parsed_checked_and_written_back() {
    let scene = continuous();
    let space = scene.value_space().unwrap();
    assert_eq!(space.num_slots(), 7);
    assert_eq!(space.range(0), (-1.8, 1.8));
    assert_eq!(space.range(6), (-0.06, 0.06));
    let v = space.parse(" 1.8, -1.2 ,0.75,0,0,0,-0.06").unwrap();
    assert_eq!(v, [1.8, -1.2, 0.75, 0.0, 0.0, 0.0, -0.06]);
    assert_eq!(space.format(&v), "1.8,-1.2,0.75,0,0,0,-0.06");
    assert_eq!(space.parse(&space.format(&v)).unwrap(), v);
    let e = |t: &str| space.parse(t).unwrap_err().to_string();
    assert_eq!(
        e("1,2"),
        "command `1,2` has 2 values, expected 7 (one per slot)"
    );
    assert_eq!(
        e("0,0,x,0,0,0,0"),
        "command `0,0,x,0,0,0,0`: `x` at slot 2 is not a number"
    );
    assert_eq!(
        e("0,0,0,0,0,0,0.07"),
        "command `0,0,0,0,0,0,0.07`: value 0.07 at slot 6 is outside its range [-0.06, 0.06]"
    );
    assert!(e("0,0,0,NaN,0,0,0").contains("value NaN at slot 3 is outside"));
    // the world refuses what the space refuses, and a command of symbols
    let mut w = scene.physics_world().unwrap();
    let bad = w.execute_values(&[0.0; 6]).unwrap_err().to_string();
    assert!(bad.contains("has 6 values, expected 7"), "{bad}");
    let c = e3d::Command::new(vec![0; 7]);
    let bad = w.execute(&c).unwrap_err().to_string();
    assert!(bad.contains("takes values, not symbols"), "{bad}");
    // and the unit cube maps onto the ranges, ends included
    assert_eq!(space.from_unit(0, -1.0), -1.8);
    assert_eq!(space.from_unit(0, 1.0), 1.8);
    assert_eq!(space.from_unit(0, 7.0), 1.8);
    assert_eq!(space.from_unit(1, 0.0), 0.0);
    assert!(ValueSpace::new(vec![(1.0, 1.0)]).is_err());
    assert!(ValueSpace::new(vec![(0.0, f64::INFINITY)]).is_err());
}

#[test]
fn bad_continuous_scenes_name_the_place_and_what_was_expected() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs/continuous");
    let cases: &[(&str, &str)] = &[
        ("grid.ron", "grid.ron:4:14: field `Continuous`: expected symbols in a Grid world (one-cell moves); continuous slots need a Physics world"),
        ("inverted_range.ron", "inverted_range.ron:73:22: field `range`: expected slot 2: a range (min, max) of finite numbers with min < max, found (0.75, -0.75)"),
        ("unknown_joint.ron", "unknown_joint.ron:75:44: field `action`: expected slot 4 (j5): a known joint, but there is no joint `j55` (did you mean `j5`?)"),
        ("target_no_motor.ron", "target_no_motor.ron:72:42: field `action`: expected slot 1 (j2): a Target on a joint with a `motor: (stiffness: ..., damping: ...)`, but joint `j2` has none"),
        ("huge_torque.ron", "huge_torque.ron:77:22: field `range`: expected slot 6 (j7) at 1e9: a torque that adds at most 1e6 rad/s to a body in one step"),
        ("symmetry.ron", "symmetry.ron:64:9: field `symmetry`: expected no symmetry with continuous slots"),
    ];
    for (file, expected) in cases {
        let e = Scene::load(dir.join(file)).unwrap_err().to_string();
        assert!(
            e.contains(expected),
            "{file}:\n  got      {e}\n  expected {expected}"
        );
    }
}

#[test]
fn tools_of_symbols_refuse_a_continuous_scene_by_name() {
    let scene = continuous();
    let e = scene
        .spec()
        .require_symbols("a world of symbols")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("but this scene's slots take values (`Continuous`)"),
        "{e}"
    );
    let e = e3d::Executor::new(
        &scene,
        &e3d::world::Workload {
            trials: 10,
            sessions: 1,
            threads: 1,
        },
        &e3d::world::ExecOptions::default(),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.contains("for an executor (table, memo or lockstep)"),
        "{e}"
    );
    assert!(scene.spec().to_ron().contains("Continuous(["));
    assert_eq!(
        Scene::parse(&scene.spec().to_ron(), "back.ron").unwrap(),
        scene
    );
}

/// Sessions of `kind` on arm7_continuous, seeds 0 and 1, 1500 trials.
fn sessions(kind: LearnerKind) -> Vec<e3d::session::ValueSessionRecord> {
    let scene = continuous();
    let space = scene.value_space().unwrap();
    let configs: Vec<SessionConfig> = (0..2)
        .map(|seed| SessionConfig {
            trials: 1500,
            seed,
            use_reward: false,
        })
        .collect();
    let exec = Executor::for_values(&scene, &work(&configs)).unwrap();
    let learner = || {
        LearnerSetup::new(kind)
            .values(&space, scene.num_effects())
            .unwrap()
    };
    crate::common::value_sessions(&exec, &configs, configs.iter().map(|_| learner()).collect())
}

#[test]
fn e3d_spreads_the_tip_over_more_cells_than_the_uniform_sampler() {
    // measured (1500 trials, seeds 0..4): E3D 0.722-0.730 over 63-71
    // cells, the uniform sampler 0.646-0.653 over 52-55
    let e3d: Vec<_> = sessions(LearnerKind::E3d)
        .iter()
        .map(|r| r.metrics(&Target::Uniform))
        .collect();
    let uniform: Vec<_> = sessions(LearnerKind::Uniform)
        .iter()
        .map(|r| r.metrics(&Target::Uniform))
        .collect();
    for m in &e3d {
        assert!(m.normalized_entropy > 0.70, "E3D {m:?}");
    }
    for m in &uniform {
        assert!(m.normalized_entropy < 0.67, "uniform {m:?}");
    }
    let cells = |ms: &[e3d::Metrics]| ms.iter().map(|m| m.distinct_effects).sum::<usize>();
    assert!(
        cells(&e3d) >= cells(&uniform) + 10,
        "E3D reached {} cells in 2 sessions, the uniform sampler {}",
        cells(&e3d),
        cells(&uniform)
    );
}

#[test]
fn sessions_are_the_same_whatever_the_threads() {
    let scene = continuous();
    let space = scene.value_space().unwrap();
    let configs: Vec<SessionConfig> = (0..3)
        .map(|seed| SessionConfig {
            trials: 40,
            seed: 10 + seed,
            use_reward: false,
        })
        .collect();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let exec = Executor::for_values(&scene, &work(&configs)).unwrap();
            let learner =
                || GaussianE3d::new(&space, 225, &Params::TASK1, &Target::Uniform).unwrap();
            crate::common::value_sessions(
                &exec,
                &configs,
                configs.iter().map(|_| learner()).collect(),
            )
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    // and each is the session run alone
    let mut w = scene.as_continuous().unwrap().world(1);
    let mut l = GaussianE3d::new(&space, 225, &Params::TASK1, &Target::Uniform).unwrap();
    assert_eq!(
        run_value_session(&mut w, &mut l, &configs[1]).unwrap(),
        one[1]
    );
    // every value inside its range
    for r in &one {
        for t in 0..r.trials() {
            assert!(space.check(r.values_of(t)).is_ok());
        }
    }
}

#[test]
fn a_rare_effect_pulls_the_means_towards_its_draw_and_a_common_one_pushes_away() {
    let space = ValueSpace::new(vec![(-1.0, 1.0); 3]).unwrap();
    let mut rng = SessionRng::seed_from_u64(4);
    let o = |effect| Outcome {
        effect,
        reward: 0.0,
        point: [0.0, 0.0],
    };
    // a first trial sets the baseline; then effect 1 again and again
    // becomes common (p(1) > p* = 1/4): its draws lose
    let mut l = GaussianE3d::new(&space, 4, &Params::TASK1, &Target::Uniform).unwrap();
    let mut v = Vec::new();
    for _ in 0..200 {
        l.propose(&mut rng, &mut v);
        l.learn(&v, &o(1));
    }
    assert!(l.baseline() < 0.0, "{}", l.baseline());
    // an effect never seen has p(e) near 0 < p*: a large positive drive,
    // and the means move towards the values that reached it
    let before: Vec<f64> = (0..3).map(|s| l.slot_gaussian(s).0).collect();
    let draw = [0.9, -0.9, 0.5];
    l.learn(&draw, &o(3));
    for s in 0..3 {
        let after = l.slot_gaussian(s).0;
        assert!(
            (draw[s] - after).abs() < (draw[s] - before[s]).abs(),
            "slot {s}: {} -> {after}, towards {}",
            before[s],
            draw[s]
        );
    }
    // the uniform sampler learns nothing and covers each range
    let mut u = UniformValues::new(&space);
    let mut lo = [1.0f64; 3];
    let mut hi = [-1.0f64; 3];
    for _ in 0..2000 {
        u.propose(&mut rng, &mut v);
        for s in 0..3 {
            lo[s] = lo[s].min(v[s]);
            hi[s] = hi[s].max(v[s]);
        }
    }
    assert!(lo.iter().all(|&x| x < -0.99) && hi.iter().all(|&x| x > 0.99));
}

#[test]
fn the_cli_runs_execs_and_refuses_continuous_scenes() {
    // scene exec accepts numbers, and prints arm7's outcome for +-+0000
    let out = e3d(&[
        "scene",
        "exec",
        "arm7_continuous",
        "1.8, -1.2, 0.75, 0, 0, 0, 0",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let arm = e3d(&["scene", "exec", "arm7", "+-+0000"]);
    let text = String::from_utf8(out.stdout).unwrap();
    let arm = String::from_utf8(arm.stdout).unwrap();
    let row = text.lines().nth(1).unwrap();
    assert_eq!(text.lines().next(), Some("values,effect,reward,x,y"));
    assert!(row.starts_with("\"1.8,-1.2,0.75,0,0,0,0\","), "{row}");
    // the same effect, reward and point as the command of symbols
    let tail = |l: &str| l.rsplitn(5, ',').take(4).collect::<Vec<_>>().join(",");
    assert_eq!(tail(row), tail(arm.lines().nth(1).unwrap()));

    let bad = e3d(&["scene", "exec", "arm7_continuous", "1,2,3"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("has 3 values, expected 7"));

    // e3d run: the files, the same bytes on 1 and 2 threads
    let dir = temp_path("continuous");
    let _ = std::fs::remove_dir_all(&dir);
    let run = |threads: &str, sub: &str| {
        let d = dir.join(sub);
        let out = e3d_command()
            .env("RAYON_NUM_THREADS", threads)
            .args([
                "run",
                "arm7_continuous",
                "--trials",
                "30",
                "--sessions",
                "3",
                "--out",
            ])
            .arg(&d)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        (
            std::fs::read_to_string(d.join("trials.csv")).unwrap(),
            std::fs::read_to_string(d.join("summary.json")).unwrap(),
            String::from_utf8(out.stdout).unwrap(),
        )
    };
    let (csv, json, stdout) = run("1", "one");
    assert_eq!((csv.clone(), json.clone()), {
        let (c, j, _) = run("2", "two");
        (c, j)
    });
    assert_eq!(csv.lines().count(), 1 + 3 * 30);
    assert_eq!(
        csv.lines().next(),
        Some("session,trial,values,effect,reward,x,y")
    );
    assert!(
        stdout.contains("learner e3d (continuous) | 30 trials x 3 sessions"),
        "{stdout}"
    );
    let summary: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(summary["execution"], "live");
    assert_eq!(summary["sessions"].as_array().unwrap().len(), 3);
    assert_eq!(
        summary["sessions"][0]["final_policy"]
            .as_array()
            .unwrap()
            .len(),
        7
    );
    // e3d report reads the quoted values: heat maps, and per slot the
    // spread of its values
    let out = e3d(&["report", dir.join("one").to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let page = std::fs::read_to_string(dir.join("one/report.html")).unwrap();
    assert!(page.contains("<p>90 trials</p>"), "90 trials in 3 sessions");
    for s in 0..7 {
        assert!(page.contains(&format!("slot {s}: sd of the values and mean |value|")));
    }
    assert!(page.contains("early: trials 1..9"));
    let _ = std::fs::remove_dir_all(&dir);

    // scene check lists the ranges and samples the reach uniformly
    let out = e3d(&["scene", "check", "arm7_continuous", "--samples", "60"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("  0: a value in [-1.8, 1.8] (j1): Torque { joint: \"j1\" }"),
        "{text}"
    );
    assert!(
        text.contains("distinct commands: infinitely many"),
        "{text}"
    );
    assert!(
        text.contains("reach (estimate): 60 random commands of infinitely many, drawn uniformly in their ranges"),
        "{text}"
    );
    // render and animate one command of values
    let svg = temp_path("continuous").with_extension("svg");
    for animate in [false, true] {
        let mut args = vec![
            "scene",
            "render",
            "arm7_continuous",
            "--command",
            "1.8,-1.2,0,0,0,0,0",
            "--out",
        ];
        args.push(svg.to_str().unwrap());
        if animate {
            args.push("--animate");
        }
        let out = e3d(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let page = std::fs::read_to_string(&svg).unwrap();
        assert!(page.contains("1.8,-1.2,0,0,0,0,0"), "the command is shown");
        assert_eq!(page.contains("<animate"), animate);
    }
    let _ = std::fs::remove_file(&svg);

    // what cannot apply says so, naming the scene
    for (args, says) in [
        (
            &[
                "run",
                "arm7_continuous",
                "--learner",
                "egreedy",
                "--trials",
                "3",
            ][..],
            "learner `egreedy` takes symbols; continuous commands take one of: e3d, uniform",
        ),
        (
            &["scene", "table", "arm7_continuous"][..],
            "for `e3d scene table` (an outcome table), but this scene's slots take values",
        ),
        (
            &["run", "arm7_continuous", "--table-cache", "/tmp"][..],
            "--table-cache: scene `arm7_continuous` takes continuous commands",
        ),
    ] {
        let out = e3d(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

/// The trials of a record as CSV bytes, without a session column.
fn csv_of(rec: &e3d::session::ValueSessionRecord, space: &ValueSpace) -> Vec<u8> {
    let mut out = Vec::new();
    rec.write_trials_csv(space, None, false, &mut out).unwrap();
    out
}

#[test]
fn sessions_of_exact_copies_step_together_and_give_the_bytes_of_each_alone() {
    let scene = Scene::parse(PUCK_HEADINGS, "puck_headings.ron").unwrap();
    let space = scene.value_space().unwrap();
    // sessions of unequal lengths: the shorter ones stop proposing first
    let configs: Vec<SessionConfig> = [60, 45, 60, 1, 30]
        .iter()
        .enumerate()
        .map(|(i, &trials)| SessionConfig {
            trials,
            seed: 20 + i as u64,
            use_reward: false,
        })
        .collect();
    let learner = || GaussianE3d::new(&space, 18, &Params::TASK1, &Target::Uniform).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let (groups, copies, together) = pool.install(|| {
        let exec = Executor::for_values(&scene, &work(&configs)).unwrap();
        let recs = crate::common::value_sessions(
            &exec,
            &configs,
            configs.iter().map(|_| learner()).collect(),
        );
        (exec.session_groups(configs.len()), exec.plan().copies, recs)
    });
    // one thread: the five sessions are one group, on a world of 5 copies
    assert_eq!(groups, vec![0..5]);
    assert_eq!(copies, 5, "copies per world");
    for (cfg, rec) in configs.iter().zip(&together) {
        let mut world = scene.as_continuous().unwrap().world(1);
        let alone = run_value_session(&mut world, &mut learner(), cfg).unwrap();
        assert_eq!(rec.trials(), cfg.trials);
        assert_eq!(
            csv_of(rec, &space),
            csv_of(&alone, &space),
            "seed {}",
            cfg.seed
        );
        assert_eq!(rec.final_policy, alone.final_policy);
    }
    // the puck goes somewhere: not every trial in the start cell
    let cells: std::collections::BTreeSet<usize> =
        together.iter().flat_map(|r| r.effects.clone()).collect();
    assert!(cells.len() >= 4, "cells reached: {cells:?}");

    // arm7_continuous's copies are not exact: one session per world
    let arm = continuous();
    let exec = Executor::for_values(&arm, &work(&configs)).unwrap();
    assert_eq!(exec.plan().copies, 1);
    assert_eq!(exec.session_groups(5).len(), 5);
}

#[test]
fn run_sessions_of_a_continuous_scene_in_lockstep_write_the_bytes_of_runs_alone() {
    let dir = temp_path("continuous_lockstep");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("puck_headings.ron");
    std::fs::write(&file, PUCK_HEADINGS).unwrap();
    let run = |extra: &[&str], sub: &str| {
        let d = dir.join(sub);
        let out = e3d_command()
            .env("RAYON_NUM_THREADS", "1")
            .arg("run")
            .arg(&file)
            .args(["--trials", "40"])
            .args(extra)
            .arg("--out")
            .arg(&d)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let csv = std::fs::read_to_string(d.join("trials.csv")).unwrap();
        (csv, String::from_utf8(out.stderr).unwrap())
    };
    let (together, said) = run(&["--sessions", "4", "--seed", "7"], "together");
    assert!(
        said.contains("in lockstep up to 4 sessions per world"),
        "{said}"
    );
    for i in 0..4 {
        let seed = (7 + i).to_string();
        let (alone, _) = run(&["--seed", &seed], &format!("alone{i}"));
        // the rows of session i, without their session column
        let rows: Vec<&str> = together
            .lines()
            .skip(1)
            .filter_map(|l| l.strip_prefix(&format!("{i},")))
            .collect();
        let want: Vec<&str> = alone.lines().skip(1).collect();
        assert_eq!(rows.len(), 40);
        assert_eq!(rows, want, "session {i}");
    }
}
