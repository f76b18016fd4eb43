//! Table, memo or live: the same results, bit for bit, whatever the cost
//! rule chooses, the threads, the lockstep groups and the table folder.

use crate::common::{e3d, fresh_path, ok};
use e3d::sweep::{SessionResult, Sweep};
use e3d::world::{
    CachedOutcomes, ExecOptions, ExecutionPlan, Executor, OnDisk, Strategy, Workload,
    DEFAULT_MEMO_CAP,
};
use e3d::{OutcomeTable, Scene, World};
use std::path::PathBuf;

fn sweep(scene: &str, sessions: usize, trials: usize) -> Sweep {
    let text = format!(
        r#"Sweep(scenes: ["{scene}"], learners: [e3d, uniform, egreedy], use_reward: [false, true],
           params: (beta: [1, 100]), sessions: {sessions}, trials: {trials}, seed: 11)"#
    );
    Sweep::parse(&text, "test.ron", None).unwrap()
}

fn run(s: Sweep, strategy: Option<Strategy>, threads: usize) -> Vec<SessionResult> {
    s.with_strategy(strategy).unwrap().run(threads).unwrap()
}

fn builtin_text(name: &str) -> String {
    let (_, text) = e3d::scene::BUILTIN
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap();
    text.to_string()
}

#[test]
fn table_memo_and_live_give_the_same_sweep_on_any_threads() {
    // puck_rooms: exact copies, so lockstep groups step many commands per
    // world; 8 cells x 4 = 32 sessions
    let base = run(sweep("puck_rooms", 4, 30), Some(Strategy::Live), 1);
    assert_eq!(base.len(), 32);
    assert!(base.iter().all(|r| r.failure.is_none()));
    for (strategy, threads) in [
        (Some(Strategy::Live), 2),
        (Some(Strategy::Memo), 1),
        (Some(Strategy::Memo), 2),
        (None, 2),
    ] {
        assert_eq!(
            run(sweep("puck_rooms", 4, 30), strategy, threads),
            base,
            "{strategy:?} on {threads} threads"
        );
    }
    // with the memo off, the memo strategy cannot be used: live, same bytes
    let off = sweep("puck_rooms", 4, 30).with_memo_cap(0);
    assert_eq!(run(off, Some(Strategy::Memo), 2), base);
    // a memo of 5 entries: full at once, the rest simulated every time
    let tiny = sweep("puck_rooms", 4, 30).with_memo_cap(5);
    assert_eq!(run(tiny, Some(Strategy::Memo), 2), base);
}

#[test]
fn a_table_gives_the_same_sweep_as_the_memo_on_a_grid_and_a_puck() {
    for scene in ["two_rooms", "puck_rooms"] {
        let table = run(sweep(scene, 2, 25), Some(Strategy::Table), 2);
        let memo = run(sweep(scene, 2, 25), Some(Strategy::Memo), 2);
        assert_eq!(table, memo, "{scene}");
        // the values are real numbers, not all empty
        assert!(table[0].values.iter().any(|v| v.is_some_and(|x| x > 0.0)));
    }
}

#[test]
fn the_cost_rule_takes_the_cheaper_way() {
    let work = |trials, sessions| Workload {
        trials,
        sessions,
        threads: 2,
    };
    let choose = |scene: &Scene, trials, sessions| {
        ExecutionPlan::choose(scene, &work(trials, sessions), None, DEFAULT_MEMO_CAP)
    };
    let puck = Scene::builtin("puck_rooms").unwrap();
    assert_eq!(choose(&puck, 5000, 1).strategy, Strategy::Table);
    assert_eq!(choose(&puck, 300, 1).strategy, Strategy::Memo);
    let grid = Scene::builtin("two_rooms").unwrap();
    assert_eq!(choose(&grid, 5000, 1).strategy, Strategy::Table);
    // a grid of 11 slots (4^11 commands) for 10 trials: moves, no table
    let text = builtin_text("two_rooms").replace("slots: 7", "slots: 11");
    let big_grid = Scene::parse(&text, "grid11.ron").unwrap();
    let plan = choose(&big_grid, 10, 1);
    assert_eq!(plan.strategy, Strategy::Live, "{plan}");
    // the puck with 14 slots: no table fits; 100 sessions in 4 groups of 25
    let text = builtin_text("puck_rooms").replace("slots: 7", "slots: 14");
    let puck14 = Scene::parse(&text, "puck14.ron").unwrap();
    let plan = choose(&puck14, 500_000, 100);
    assert_eq!(plan.strategy, Strategy::Memo);
    assert_eq!((plan.groups, plan.copies), (4, 25), "{plan}");
    assert!(plan.to_string().contains("too many for a table"), "{plan}");
    // arm7: copies are not exact, so one command per world
    let arm = Scene::builtin("arm7").unwrap();
    let plan = choose(&arm, 5000, 10);
    assert_eq!(plan.copies, 1);
    assert_eq!(plan.simulated, Some(1094));
    // a whole table on disk is always taken
    let on_disk = OnDisk::Full {
        path: PathBuf::from("t"),
    };
    let plan = ExecutionPlan::choose(&puck, &work(10, 1), Some(&on_disk), DEFAULT_MEMO_CAP);
    assert_eq!(plan.strategy, Strategy::Table);
}

#[test]
fn the_memo_grows_its_file_and_a_damaged_file_is_replaced() {
    let dir = fresh_path("outcomes-memo");
    let puck = Scene::builtin("puck_rooms").unwrap();
    let base = run(sweep("puck_rooms", 2, 20), Some(Strategy::Live), 2);
    let cached = |strategy| {
        sweep("puck_rooms", 2, 20)
            .with_table_cache(&dir)
            .with_strategy(strategy)
            .unwrap()
            .run(2)
            .unwrap()
    };
    assert_eq!(cached(Some(Strategy::Memo)), base);
    let path = OutcomeTable::cache_path(&puck, &dir);
    let Ok(CachedOutcomes::Partial(first)) = OutcomeTable::read_file(&path, &puck) else {
        panic!("a partial table file")
    };
    assert!(
        first.len() > 100 && first.len() <= 8 * 2 * 20,
        "{}",
        first.len()
    );
    // every kept outcome is the world's own
    let mut world = puck.build();
    let space = puck.command_space();
    for (i, o) in first.iter().step_by(37) {
        assert_eq!(world.execute(&space.command_at(*i)).unwrap(), *o);
    }
    // a second run reads it, simulates only new commands, and adds them
    let options = ExecOptions {
        cache: Some(dir.clone()),
        force: Some(Strategy::Memo),
        ..ExecOptions::default()
    };
    let work = Workload {
        trials: 100,
        sessions: 1,
        threads: 1,
    };
    let exec = Executor::new(&puck, &work, &options).unwrap();
    assert_eq!(
        exec.plan().on_disk,
        OnDisk::Partial {
            path: path.clone(),
            entries: first.len() as u64
        }
    );
    assert_eq!(exec.memo().unwrap().len(), first.len());
    // a damaged body: said, not used, and replaced by this run's file
    let mut bytes = std::fs::read(&path).unwrap();
    let k = bytes.len() / 2;
    bytes[k] ^= 0x40;
    std::fs::write(&path, &bytes).unwrap();
    let exec = Executor::new(&puck, &work, &options).unwrap();
    let OnDisk::Unusable { reason, .. } = &exec.plan().on_disk else {
        panic!("{:?}", exec.plan().on_disk)
    };
    assert!(reason.contains("checksum"), "{reason}");
    assert!(exec.plan().to_string().contains("not used: damaged"));
    assert_eq!(cached(Some(Strategy::Memo)), base);
    assert!(matches!(
        OutcomeTable::read_file(&path, &puck),
        Ok(CachedOutcomes::Partial(_))
    ));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs the binary, which must succeed; its stdout and stderr.
fn e3d_outputs(args: &[&str]) -> (String, String) {
    let o = ok(e3d(args));
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    (String::from_utf8_lossy(&o.stdout).to_string(), err)
}

#[test]
fn e3d_run_says_how_and_gives_the_same_trials_every_way() {
    let root = fresh_path("outcomes-run");
    let out = |s: &str| root.join(s).to_str().unwrap().to_string();
    let mut csv = Vec::new();
    for how in ["live", "memo", "table", "auto"] {
        let (_, err) = e3d_outputs(&[
            "run",
            "puck_rooms",
            "--trials",
            "150",
            "--outcomes",
            how,
            "--out",
            &out(how),
        ]);
        let said = match how {
            "table" => "outcomes: puck_rooms: outcome table of 16384 commands",
            "live" => "outcomes: puck_rooms: live: every proposal executed",
            _ => "outcomes: puck_rooms: outcome memo",
        };
        assert!(err.contains(said), "{how}: {err}");
        csv.push(std::fs::read_to_string(root.join(how).join("trials.csv")).unwrap());
    }
    assert_eq!(csv[0].lines().count(), 151);
    assert!(csv.iter().all(|c| *c == csv[0]));
    // three sessions in lockstep: session 0 is the single run of seed 0,
    // session 2 that of seed 2
    let (stdout, _) = e3d_outputs(&[
        "run",
        "puck_rooms",
        "--trials",
        "150",
        "--sessions",
        "3",
        "--out",
        &out("three"),
    ]);
    assert!(
        stdout.contains("150 trials x 3 sessions | seed 0..=2"),
        "{stdout}"
    );
    let three = std::fs::read_to_string(root.join("three").join("trials.csv")).unwrap();
    assert_eq!(
        three.lines().next(),
        Some("session,trial,command,effect,reward")
    );
    assert_eq!(three.lines().count(), 451);
    let session = |k: &str| -> Vec<String> {
        three
            .lines()
            .skip(1)
            .filter_map(|l| l.strip_prefix(k).map(str::to_string))
            .collect()
    };
    let single: Vec<String> = csv[0].lines().skip(1).map(str::to_string).collect();
    assert_eq!(session("0,"), single);
    e3d_outputs(&[
        "run",
        "puck_rooms",
        "--trials",
        "150",
        "--seed",
        "2",
        "--out",
        &out("seed2"),
    ]);
    let seed2 = std::fs::read_to_string(root.join("seed2").join("trials.csv")).unwrap();
    let seed2: Vec<String> = seed2.lines().skip(1).map(str::to_string).collect();
    assert_eq!(session("2,"), seed2);
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_command_and_its_mirror_image_share_one_memo_entry() {
    let arm = Scene::builtin("arm7").unwrap();
    let space = arm.command_space();
    let memo = e3d::world::OutcomeMemo::new(&space, arm.num_effects(), 100).unwrap();
    let mut world = e3d::world::Memoized::new(arm.build(), &memo);
    let mut plain = arm.build();
    let c = space.parse("+-0+0-+").unwrap();
    let image = space.parse("-+0-0+-").unwrap();
    assert!(plain.mirror_of(&c).is_some() != plain.mirror_of(&image).is_some());
    assert_eq!(world.execute(&c).unwrap(), plain.execute(&c).unwrap());
    assert_eq!(
        world.execute(&image).unwrap(),
        plain.execute(&image).unwrap()
    );
    assert_eq!((memo.len(), memo.misses(), memo.hits()), (1, 1, 1));
    // in one batch: the pair and a repeat, one simulation
    let d = space.parse("0+++---").unwrap();
    let d_image = space.parse("0---+++").unwrap();
    let mut out = Vec::new();
    world.execute_batch(
        &[d.clone(), d_image.clone(), c.clone(), d.clone()],
        &mut out,
    );
    let expected: Vec<_> = [&d, &d_image, &c, &d]
        .iter()
        .map(|x| plain.execute(x))
        .collect();
    assert_eq!(out, expected);
    assert_eq!(memo.len(), 2);
    // a sweep on arm7 through the memo: the same results as live
    let text = r#"Sweep(scenes: ["arm7"], learners: [e3d, uniform], use_reward: [false],
        params: (), sessions: 2, trials: 40, seed: 5)"#;
    let s = || Sweep::parse(text, "arm.ron", None).unwrap();
    assert_eq!(
        run(s(), Some(Strategy::Memo), 2),
        run(s(), Some(Strategy::Live), 2)
    );
}

#[test]
fn a_sweep_too_large_to_plan_is_refused_at_once_with_its_size() {
    // 100000 x 1000 values: 1e8 cells, refused before any cell is made
    let text = r#"Sweep(scenes: ["two_rooms"], learners: [e3d], use_reward: [false],
        params: (beta: (scale: Log, from: 1, to: 1000, steps: 100000),
                 eta: (scale: Linear, from: 0.001, to: 0.1, steps: 1000)),
        sessions: 1, trials: 10, seed: 1)"#;
    let e = Sweep::parse(text, "huge.ron", None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("at most 10000000 sessions in all") && e.contains("100000000 cells x 1"),
        "{e}"
    );
}

#[test]
fn a_table_completed_from_a_partial_file_equals_the_built_one() {
    for name in ["pendulum3", "arm7"] {
        let scene = Scene::builtin(name).unwrap();
        let built = OutcomeTable::build_scene(&scene).unwrap();
        // every third command known (arm7: simulated and mirrored ones)
        let known: Vec<_> = built
            .outcomes()
            .enumerate()
            .filter(|(i, _)| i % 3 == 0)
            .map(|(i, o)| (i as u64, *o))
            .collect();
        let completed =
            OutcomeTable::complete_with(&scene, &known, &e3d::Control::default()).unwrap();
        let a: Vec<_> = built.outcomes().collect();
        let b: Vec<_> = completed.outcomes().collect();
        assert_eq!(a, b, "{name}");
    }
    // a run asked for a table over a partial file completes and keeps it
    let dir = fresh_path("outcomes-complete");
    let scene = Scene::builtin("pendulum3").unwrap();
    let built = OutcomeTable::build_scene(&scene).unwrap();
    let part: Vec<_> = (0..40u64).map(|i| (i, *built.get(i))).collect();
    let path = OutcomeTable::cache_path(&scene, &dir);
    OutcomeTable::write_partial(&path, &scene, &part).unwrap();
    let work = Workload {
        trials: 1000,
        sessions: 1,
        threads: 2,
    };
    let options = ExecOptions {
        cache: Some(dir.clone()),
        ..ExecOptions::default()
    };
    let exec = Executor::new(&scene, &work, &options).unwrap();
    assert_eq!(exec.plan().strategy, Strategy::Table, "{}", exec.plan());
    assert!(matches!(
        OutcomeTable::read_file(&path, &scene),
        Ok(CachedOutcomes::Full(_))
    ));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn e3d_run_gives_the_entropy_over_the_reachable_cells_when_a_table_knows_them() {
    // the README's "0.93 over its 68 reachable cells" next to 0.7250 over 225
    let (stdout, err) = e3d_outputs(&["run", "arm7", "--no-reward"]);
    assert!(
        err.contains("outcomes: arm7: outcome table of 2187 commands"),
        "{err}"
    );
    assert!(
        stdout.contains("normalised entropy 0.7250 (last 1000: 0.7328)")
            && stdout.contains("68 of 225 effects reached")
            && stdout.contains("over the 68 reachable cells: normalised entropy 0.9306"),
        "{stdout}"
    );
    // two_rooms reaches every cell: no second figure
    let (stdout, _) = e3d_outputs(&["run", "two_rooms", "--no-reward", "--trials", "500"]);
    assert!(!stdout.contains("reachable cells"), "{stdout}");
}

#[test]
fn an_executor_building_a_table_reports_every_simulated_command() {
    use std::sync::atomic::{AtomicU64, Ordering};
    for name in ["two_rooms", "pendulum3"] {
        let scene = Scene::builtin(name).unwrap();
        let (done, total) = (AtomicU64::new(0), AtomicU64::new(0));
        let add = |k| {
            done.fetch_add(k, Ordering::Relaxed);
        };
        let size = |t| total.store(t, Ordering::Relaxed);
        let exec = Executor::with_control(
            &scene,
            &Workload {
                trials: 1000,
                sessions: 1,
                threads: 2,
            },
            &ExecOptions {
                force: Some(Strategy::Table),
                ..ExecOptions::default()
            },
            &e3d::Control {
                progress: &add,
                total: &size,
                ..e3d::Control::default()
            },
        )
        .unwrap();
        let n = scene.command_space().num_commands().unwrap();
        let simulated = exec.plan().simulated.unwrap_or(n);
        assert!(exec.table().is_some());
        assert_eq!(done.load(Ordering::Relaxed), simulated, "{name}");
        assert_eq!(total.load(Ordering::Relaxed), simulated, "{name}");
    }
}

/// A table build that its caller stops (a Ctrl-C in Python) ends within a
/// chunk of commands with `stopped`, without falling back to a memo and
/// without writing a table file; it ran to the end of the table before.
#[test]
fn a_stopped_table_build_ends_early_and_keeps_nothing() {
    use std::sync::atomic::{AtomicU64, Ordering};
    for name in ["puck_rooms", "arm7", "two_rooms"] {
        let scene = Scene::builtin(name).unwrap();
        let total = OutcomeTable::simulated_commands(&scene).unwrap();
        let done = AtomicU64::new(0);
        let progress = |k: u64| {
            done.fetch_add(k, Ordering::Relaxed);
        };
        // stop once some commands are simulated
        let stop = || done.load(Ordering::Relaxed) > 0;
        let control = e3d::Control {
            progress: &progress,
            stop: &stop,
            ..e3d::Control::default()
        };
        let e = OutcomeTable::build_scene_with(&scene, &control).unwrap_err();
        assert_eq!(e, e3d::WorldError::Stopped);
        assert_eq!(e.to_string(), "stopped");
        let simulated = done.load(Ordering::Relaxed);
        // at most a chunk of commands per worker after the first
        let threads = rayon::current_num_threads() as u64;
        assert!(
            simulated < total && simulated <= 2 * 64 * (threads + 1),
            "{name}: {simulated} of {total}"
        );
        // an executor asked for a table: stopped, no memo, no file
        let dir = fresh_path(&format!("stopped-table-{name}"));
        let options = ExecOptions {
            cache: Some(dir.clone()),
            force: Some(Strategy::Table),
            ..ExecOptions::default()
        };
        let work = Workload {
            trials: 10,
            sessions: 1,
            threads: 1,
        };
        let always = || true;
        let control = e3d::Control {
            stop: &always,
            ..e3d::Control::default()
        };
        let r = Executor::with_control(&scene, &work, &options, &control);
        assert!(matches!(r, Err(e3d::WorldError::Stopped)), "{name}");
        let left: Vec<_> = std::fs::read_dir(&dir)
            .map(|d| d.map(|e| e.unwrap().file_name()).collect())
            .unwrap_or_default();
        assert!(
            !left
                .iter()
                .any(|n| n.to_string_lossy().ends_with(".e3dtable")),
            "{left:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
    // never stopped: the same table as before
    for name in ["two_rooms", "pendulum3"] {
        let scene = Scene::builtin(name).unwrap();
        assert_eq!(
            OutcomeTable::build_scene_with(&scene, &e3d::Control::default())
                .unwrap()
                .to_bytes(0),
            OutcomeTable::build_scene(&scene).unwrap().to_bytes(0)
        );
    }
}
