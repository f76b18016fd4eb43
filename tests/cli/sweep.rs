//! `e3d sweep` and `e3d merge`: byte-identical results with any number of
//! threads, after a kill and a resume, and from shards.

use crate::common::{e3d, e3d_command, ok, temp_dir};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A small sweep on two_rooms: 2 x 3 e3d cells, 2 egreedy cells, 1 uniform,
/// with and without reward.
fn small_sweep(dir: &Path, sessions: usize, trials: usize) -> PathBuf {
    let text = format!(
        r#"// a small test sweep
Sweep(
    scenes: ["two_rooms"],
    learners: [e3d, egreedy, uniform],
    use_reward: [false, true],
    params: (
        beta: [1, 100],
        eta: (scale: Log, from: 0.003, to: 0.03, steps: 3),
        epsilon: [0.05, 0.2],
    ),
    sessions: {sessions},
    trials: {trials},
    seed: 7,
    metrics: [normalized_entropy, kl_to_target, distinct_effects, cumulative_reward({trials}), first_reward_trial],
)
"#
    );
    let p = dir.join("small.ron");
    std::fs::write(&p, text).unwrap();
    p
}

pub(crate) const FINAL_FILES: [&str; 4] =
    ["results.csv", "summary.csv", "sweep.ron", "version.txt"];

pub(crate) fn assert_same_files(a: &Path, b: &Path, files: &[&str]) {
    for f in files {
        let x = std::fs::read(a.join(f)).unwrap_or_else(|e| panic!("{}: {e}", a.join(f).display()));
        let y = std::fs::read(b.join(f)).unwrap_or_else(|e| panic!("{}: {e}", b.join(f).display()));
        assert!(
            x == y,
            "{f} differs between {} and {}",
            a.display(),
            b.display()
        );
    }
}

fn journal_rows(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("journal.txt"))
        .map(|t| t.lines().filter(|l| !l.starts_with('#')).count())
        .unwrap_or(0)
}

#[test]
fn one_thread_and_two_threads_give_the_same_bytes() {
    let d = temp_dir("sweep-threads");
    let file = small_sweep(&d, 3, 400);
    let f = file.to_str().unwrap();
    let (a, b) = (d.join("a"), d.join("b"));
    ok(e3d(&[
        "sweep",
        f,
        "--out",
        a.to_str().unwrap(),
        "--threads",
        "1",
    ]));
    ok(e3d(&[
        "sweep",
        f,
        "--out",
        b.to_str().unwrap(),
        "--threads",
        "2",
    ]));
    assert_same_files(&a, &b, &FINAL_FILES);

    // 1 scene x (e3d 2 beta x 3 eta + egreedy 2 epsilon + uniform 1) x 2 rewards
    let results = std::fs::read_to_string(a.join("results.csv")).unwrap();
    let lines: Vec<&str> = results.lines().collect();
    assert_eq!(lines.len(), 1 + 18 * 3);
    assert_eq!(
        lines[0],
        "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,session,seed,\
         normalized_entropy,kl_to_target,distinct_effects,cumulative_reward_at_400,first_reward_trial,failure"
    );
    // canonical order: e3d first, no reward, beta 1, eta 0.003, sessions 0..3
    assert!(lines[1].starts_with("two_rooms,e3d,false,0.3,1,0.03,0.003,,0,"));
    assert!(lines[3].starts_with("two_rooms,e3d,false,0.3,1,0.03,0.003,,2,"));
    assert!(lines[4].starts_with("two_rooms,e3d,false,0.3,1,0.03,0.00948683298051,,0,"));
    // unused parameters are empty; uniform uses none
    assert!(lines[1 + 6 * 3].starts_with("two_rooms,e3d,true,"));
    assert!(lines[1 + 12 * 3].starts_with("two_rooms,egreedy,false,0.3,,,,0.05,0,"));
    assert!(lines[1 + 16 * 3].starts_with("two_rooms,uniform,false,,,,,,0,"));
    // without reward, the cumulative reward is 0 and there is no first
    // reward; the session did not fail
    assert!(lines[1].ends_with(",0,,"));
    // the seed column is the documented function of the identity
    let seed: u64 = lines[1].split(',').nth(9).unwrap().parse().unwrap();
    assert_eq!(
        seed,
        e3d::sweep::session_seed(
            7,
            "scene=two_rooms;learner=e3d;use_reward=false;alpha=0.3;beta=1;lambda=0.03;eta=0.003;epsilon=-;session=0"
        )
    );
    let summary = std::fs::read_to_string(a.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 1 + 18);
    assert!(summary
        .lines()
        .nth(1)
        .unwrap()
        .starts_with("two_rooms,e3d,false,0.3,1,0.03,0.003,,3,0,"));
}

#[test]
fn the_library_gives_the_rows_the_command_line_writes() {
    let d = temp_dir("sweep-library");
    let file = small_sweep(&d, 2, 300);
    let out = d.join("out");
    ok(e3d(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "2",
    ]));
    let sweep = e3d::Sweep::load(&file).unwrap();
    let results = sweep.run(2).unwrap();
    let mut csv = sweep.results_header() + "\n";
    for r in &results {
        csv += &(sweep.result_row(r) + "\n");
    }
    assert_eq!(
        csv,
        std::fs::read_to_string(out.join("results.csv")).unwrap()
    );
}

#[test]
fn a_killed_sweep_resumes_to_the_same_bytes() {
    let d = temp_dir("sweep-kill");
    let file = small_sweep(&d, 25, 2000);
    let f = file.to_str().unwrap();
    let whole = d.join("whole");
    ok(e3d(&[
        "sweep",
        f,
        "--out",
        whole.to_str().unwrap(),
        "--threads",
        "2",
    ]));
    let total = 18 * 25;

    let killed = d.join("killed");
    let k = killed.to_str().unwrap();
    // kill twice with SIGKILL, at two points of the run
    for (round, at_least) in [(0, 20), (1, 60)] {
        let mut args = vec!["sweep", f, "--out", k, "--threads", "2"];
        if round > 0 {
            args.push("--resume");
        }
        let mut child = e3d_command()
            .args(&args)
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let start = Instant::now();
        while journal_rows(&killed) < at_least && start.elapsed() < Duration::from_secs(120) {
            std::thread::sleep(Duration::from_millis(5));
        }
        child.kill().unwrap(); // SIGKILL on Unix
        child.wait().unwrap();
        let rows = journal_rows(&killed);
        assert!(
            rows >= at_least,
            "the sweep was too slow to reach {at_least} sessions"
        );
        assert!(
            rows < total,
            "the sweep finished before it was killed; make it larger"
        );
        assert!(!killed.join("results.csv").exists());
    }
    // a torn last line, as a write cut short would leave
    use std::io::Write;
    let mut j = std::fs::OpenOptions::new()
        .append(true)
        .open(killed.join("journal.txt"))
        .unwrap();
    j.write_all(b"00000000deadbeef 3,two_rooms,e3d,fal")
        .unwrap();
    drop(j);

    // without --resume, the folder is refused and left alone
    let refused = e3d(&["sweep", f, "--out", k]);
    assert_eq!(refused.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--resume"));

    let out = ok(e3d(&["sweep", f, "--out", k, "--resume", "--threads", "1"]));
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(msg.contains("from an earlier run"), "{msg}");
    assert_same_files(&whole, &killed, &FINAL_FILES);
    // resuming a complete sweep runs nothing and changes nothing
    let again = ok(e3d(&["sweep", f, "--out", k, "--resume"]));
    assert!(String::from_utf8_lossy(&again.stderr)
        .contains(&format!("({total} from an earlier run, 0 now)")));
    assert_same_files(&whole, &killed, &FINAL_FILES);
}

/// A folder that is not empty is refused before the sweep prints its
/// plan: the error alone, no "N cells x M sessions" line that looks like
/// a start.
#[test]
fn a_refused_folder_prints_no_plan() {
    let d = temp_dir("sweep-refuse-first");
    let a = small_sweep(&d, 1, 50);
    let out = d.join("out");
    let o = out.to_str().unwrap();
    let first = ok(e3d(&["sweep", a.to_str().unwrap(), "--out", o]));
    assert!(String::from_utf8_lossy(&first.stderr).contains("cells x 1 sessions"));
    let r = e3d(&["sweep", a.to_str().unwrap(), "--out", o]);
    assert_eq!(r.status.code(), Some(3));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains("exists and is not empty; pass --resume to complete the sweep it holds"),
        "{err}"
    );
    assert!(
        !err.contains("cells x"),
        "the plan came before the refusal: {err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    // a resume of a complete sweep says what an earlier run did
    let r = ok(e3d(&["sweep", a.to_str().unwrap(), "--out", o, "--resume"]));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains("; 18 of the 18 done by an earlier run"),
        "{err}"
    );
}

#[test]
fn resume_refuses_a_folder_of_another_sweep() {
    let d = temp_dir("sweep-other");
    let a = small_sweep(&d, 1, 100);
    let out = d.join("out");
    ok(e3d(&[
        "sweep",
        a.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]));
    let b = d.join("b.ron");
    std::fs::write(
        &b,
        std::fs::read_to_string(&a)
            .unwrap()
            .replace("seed: 7", "seed: 8"),
    )
    .unwrap();
    let r = e3d(&[
        "sweep",
        b.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resume",
    ]);
    assert_eq!(r.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&r.stderr).contains("sweep.ron: differs"));
}

#[test]
fn three_shards_merge_to_the_one_process_bytes() {
    let d = temp_dir("sweep-shards");
    let file = small_sweep(&d, 4, 300);
    let f = file.to_str().unwrap();
    let whole = d.join("whole");
    ok(e3d(&["sweep", f, "--out", whole.to_str().unwrap()]));
    // three separate processes at once
    let children: Vec<_> = (1..=3)
        .map(|k| {
            e3d_command()
                .args([
                    "sweep",
                    f,
                    "--threads",
                    "1",
                    "--shard",
                    &format!("{k}/3"),
                    "--out",
                ])
                .arg(d.join(format!("shard{k}")))
                .output()
        })
        .collect();
    for c in children {
        ok(c.unwrap());
    }
    let rows: Vec<usize> = (1..=3)
        .map(|k| {
            std::fs::read_to_string(d.join(format!("shard{k}/results.csv")))
                .unwrap()
                .lines()
                .count()
                - 1
        })
        .collect();
    assert_eq!(rows, vec![24, 24, 24]); // 72 sessions, round robin
    assert!(!d.join("shard1/summary.csv").exists());

    let s: Vec<String> = (1..=3)
        .map(|k| d.join(format!("shard{k}")).display().to_string())
        .collect();
    // a missing shard, a shard twice
    let r = e3d(&[
        "merge",
        &s[0],
        &s[1],
        "--out",
        d.join("bad").to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&r.stderr).contains("missing shard(s) 3/3"));
    let r = e3d(&[
        "merge",
        &s[0],
        &s[0],
        &s[1],
        &s[2],
        "--out",
        d.join("bad").to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("shard 1/3 given twice"));

    let merged = d.join("merged");
    ok(e3d(&[
        "merge",
        &s[2],
        &s[0],
        &s[1],
        "--out",
        merged.to_str().unwrap(),
    ]));
    assert_same_files(&whole, &merged, &FINAL_FILES);
}

#[test]
fn bad_sweep_files_are_refused_with_their_place() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs/sweeps");
    let cases: &[(&str, &str)] = &[
        ("unknown_param.ron", "unknown_param.ron:6:9: unknown field `alpah` in `params` (did you mean `alpha`?)"),
        ("empty_range.ron", "empty_range.ron:6:9: field `beta`: expected a range of at least 1 step, found steps: 0"),
        ("empty_list.ron", "empty_list.ron:5:25: field `eta`: expected at least one value, found an empty list"),
        ("log_through_zero.ron", "log_through_zero.ron:6:9: field `eta`: expected a log range between two numbers > 0, found from: 0, to: 0.1"),
        ("eta_out_of_range.ron", "eta_out_of_range.ron:5:25: field `eta`: expected a number in (0, 1], found 1.5"),
        ("no_such_scene.ron", "no_such_scene.ron:2:14: field `scenes`: expected a scene file (relative to the sweep file) or a built-in scene (two_rooms, puck_rooms, arm7, pendulum3, maze3, puck_rooms14, arm7x5, three_rooms, arm4_gravity, arm7_continuous, arm_push, swimmer, cart_pole, four_rooms, reacher, swimmer_drag), found `two_room`"),
        ("zero_sessions.ron", "zero_sessions.ron:5:5: field `sessions`: expected at least 1 session per cell, found 0"),
        ("zero_trials.ron", "zero_trials.ron:6:5: field `trials`: expected at least 1 trial per session, found 0"),
        ("negative_sessions.ron", "negative_sessions.ron:5:16: field `sessions`: integer is out of bounds: expected a whole number >= 0, found -4"),
        ("too_many_trials.ron", "too_many_trials.ron:6:5: field `trials`: expected at most 100000000 trials per session (as `e3d run --trials`), found 1000000000"),
        ("unknown_learner.ron", "unknown_learner.ron:3:25: unknown variant `e3b` for `LearnerKind` (did you mean `e3d`?); expected one of: e3d, uniform, egreedy, e3d_relax, count, smm, goal_babbling, archive, archive_reached, map_elites, qlearning_moves"),
        ("range_without_scale.ron", "range_without_scale.ron:6:46: missing field `scale` in a range; expected `scale: Linear` or `scale: Log`"),
        ("bad_metric.ron", "bad_metric.ron:7:29: field `metrics`: expected cumulative_reward(T) with T in 1..=100 (the trials), found 500"),
        ("zero_commands.ron", "zero_commands.ron:6:5: field `commands`: expected 1 to 64 commands per episode, found 0"),
        ("too_many_episode_commands.ron", "too_many_episode_commands.ron:6:5: field `commands`: expected at most 100000000 commands in all per session (episodes x commands), found 100000000 episodes of 64 commands"),
        ("gamma_without_closed_loop.ron", "gamma_without_closed_loop.ron:7:5: field `gamma`: expected closed_loop: true with a gamma (the discount of Q_ref and of Q-learning)"),
        ("context_metric_out_of_range.ron", "context_metric_out_of_range.ron:8:35: field `metrics`: expected normalized_entropy_context(I) with I below 1 (the most start contexts of the sweep's scenes), found 1"),
    ];
    let out = temp_dir("sweep-bad");
    for (file, expected) in cases {
        let path = dir.join(file);
        let r = e3d(&[
            "sweep",
            path.to_str().unwrap(),
            "--out",
            out.join(file).to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{file}: {err}");
        assert!(
            err.contains(expected),
            "{file}:\n  got      {err}\n  expected {expected}"
        );
        // refused before any work: no output folder
        assert!(
            !out.join(file).exists(),
            "{file}: an output folder was made"
        );
    }
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    files.sort();
    assert_eq!(
        files.len(),
        cases.len(),
        "every file in {} has a case",
        dir.display()
    );
    // did you mean, for a scene name
    let r = e3d(&[
        "sweep",
        dir.join("no_such_scene.ron").to_str().unwrap(),
        "--out",
        out.join("x").to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("(did you mean `two_rooms`?)"));
}

#[test]
fn shipped_sweeps_parse() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let paper = e3d::Sweep::load(root.join("scenes/sweeps/paper.ron")).unwrap();
    // e3d: 2 rewards x 7 beta x 4 eta; uniform and egreedy: 2 rewards each
    assert_eq!(paper.cells().len(), 56 + 2 + 2);
    assert_eq!(paper.num_sessions(), 1200);
    // closed_loop.ron: 2 scenes x (e3d at 2 beta, egreedy, uniform), episodes
    let cl = e3d::Sweep::load(root.join("scenes/sweeps/closed_loop.ron")).unwrap();
    assert_eq!((cl.cells().len(), cl.num_sessions()), (8, 160));
    assert!(cl.runs_episodes(0) && cl.runs_episodes(1));
    assert_eq!((cl.start_contexts(0), cl.start_contexts(1)), (1, 2));
    assert_eq!(cl.observe(), e3d::episode::Observe::State);
    let columns: Vec<String> = cl.metrics().iter().map(|m| m.column()).collect();
    let tail: Vec<String> = [
        "normalized_entropy_context_",
        "cumulative_reward_context_",
        "first_reward_trial_context_",
    ]
    .iter()
    .flat_map(|m| [format!("{m}0"), format!("{m}1")])
    .collect();
    assert!(columns.ends_with(&tail), "{columns:?}");
    // arm7.ron names scenes/arm7.ron, which the physics scenes bring
    if root.join("scenes/arm7.ron").exists() {
        let arm = e3d::Sweep::load(root.join("scenes/sweeps/arm7.ron")).unwrap();
        assert!(arm.num_sessions() > 0);
    } else {
        let err = e3d::Sweep::load(root.join("scenes/sweeps/arm7.ron"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("arm7.ron"), "{err}");
    }
}

#[test]
fn plots_are_drawn_from_the_summary() {
    let d = temp_dir("sweep-plot");
    let file = small_sweep(&d, 2, 200);
    let out = d.join("out");
    let o = out.to_str().unwrap();
    ok(e3d(&["sweep", file.to_str().unwrap(), "--out", o]));
    let svg = d.join("beta.svg");
    ok(e3d(&[
        "plot",
        o,
        "--x",
        "beta",
        "--metric",
        "normalized_entropy",
        "--where",
        "use_reward=false",
        "--out",
        svg.to_str().unwrap(),
    ]));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg"));
    // one line per eta, the baselines as dashed lines, labelled in words
    for label in [
        "e3d, eta 0.003",
        "e3d, eta 0.009487",
        "e3d, eta 0.03",
        "uniform",
        "egreedy, epsilon 0.05",
        "Normalised entropy against beta (without reward)",
        "beta (inverse temperature), log scale",
        "normalised entropy: mean, 95% CI of the mean",
    ] {
        assert!(text.contains(label), "no `{label}` in the plot");
    }
    // the swept betas are 1 and 100: the log axis ticks at the decades 1,
    // 10, 100, not at the swept values alone
    let texts: Vec<&str> = text
        .split("</text>")
        .filter_map(|t| t.rsplit('>').next())
        .map(str::trim)
        .collect();
    for tick in ["1", "10", "100"] {
        assert!(texts.contains(&tick), "no tick {tick}: {texts:?}");
    }
    // no snake_case title, no legend titled "legend"
    assert!(
        !texts.iter().any(|t| t.contains("normalized_entropy")),
        "{texts:?}"
    );
    assert!(!texts.contains(&"legend"), "{texts:?}");
    // 12 series (e3d: 2 reward settings x 3 eta; egreedy: 2 x 2 epsilon;
    // uniform: 2): all in the legend, under the plot
    let all = d.join("all.svg");
    ok(e3d(&[
        "plot",
        o,
        "--x",
        "beta",
        "--metric",
        "normalized_entropy",
        "--out",
        all.to_str().unwrap(),
    ]));
    let all = std::fs::read_to_string(&all).unwrap();
    for label in [
        "e3d, without reward, eta 0.003",
        "e3d, with reward, eta 0.03",
        "egreedy, with reward, epsilon 0.2",
        "uniform, with reward",
    ] {
        assert!(
            all.contains(&format!("\n{label}\n")),
            "no `{label}` in the legend"
        );
    }
    // an existing figure is not overwritten without --force
    let again = e3d(&[
        "plot",
        o,
        "--x",
        "beta",
        "--metric",
        "normalized_entropy",
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(again.status.code(), Some(3));
    // a heat map, with one value of beta only (a single column)
    let heat = d.join("heat.svg");
    ok(e3d(&[
        "plot",
        o,
        "--x",
        "beta",
        "--y",
        "eta",
        "--metric",
        "kl_to_target",
        "--where",
        "use_reward=true",
        "--where",
        "beta=100",
        "--out",
        heat.to_str().unwrap(),
    ]));
    assert!(std::fs::read_to_string(&heat).unwrap().contains("<rect"));
    // mistakes are explained
    let r = e3d(&[
        "plot",
        o,
        "--x",
        "beta",
        "--metric",
        "normalised_entropy",
        "--out",
        d.join("x.svg").to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains(
        "no metric `normalised_entropy` in the summary (did you mean `normalized_entropy`?)"
    ));
    let r = e3d(&[
        "plot",
        o,
        "--x",
        "beta",
        "--y",
        "eta",
        "--metric",
        "kl_to_target",
        "--out",
        d.join("y.svg").to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&r.stderr)
        .contains("these columns vary: use_reward (false, true); choose with --where"));
    let r = e3d(&[
        "plot",
        o,
        "--x",
        "bta",
        "--metric",
        "kl_to_target",
        "--out",
        d.join("z.svg").to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&r.stderr)
        .contains("`bta` is not a parameter (did you mean `beta`?)"));
}

/// The known behaviour of the paper's task 2 on two_rooms (docs/canonical-scenes.md):
/// E3D keeps the reward only when beta * lambda > log(18), that is beta >
/// 96 with lambda = 0.03; the uniform policy finds it 9 times in 16384.
#[test]
fn the_sweep_shows_the_beta_threshold_of_task_2() {
    let text = r#"Sweep(
        scenes: ["two_rooms"], learners: [e3d, uniform], use_reward: [true],
        params: (beta: [10, 300]), sessions: 4, trials: 3000, seed: 5,
        metrics: [cumulative_reward(3000), first_reward_trial],
    )"#;
    let sweep = e3d::Sweep::parse(text, "threshold.ron", None).unwrap();
    let results = sweep.run(2).unwrap();
    let mean = |cell: usize| {
        let v: Vec<f64> = results
            .iter()
            .filter(|r| r.session.cell == cell)
            .map(|r| r.values[0].unwrap())
            .collect();
        assert_eq!(v.len(), 4);
        v.iter().sum::<f64>() / 4.0
    };
    let (below, above, uniform) = (mean(0), mean(1), mean(2));
    assert!(below < 400.0, "beta 10: {below}");
    assert!(above > 1500.0, "beta 300: {above}");
    // 3000 x 9 / 16384 = 1.6 expected
    assert!(uniform < 8.0, "uniform: {uniform}");
}

#[test]
fn resume_refuses_a_folder_that_holds_no_sweep() {
    let d = temp_dir("sweep-foreign");
    let file = small_sweep(&d, 1, 100);
    let out = d.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let r = e3d(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resume",
    ]);
    assert_eq!(r.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&r.stderr).contains("holds no sweep.ron"));
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 1);
}

/// `journal.txt` replaced by a symbolic link (to another file) is refused
/// on `--resume`: the file it points to is neither truncated nor appended
/// to.
#[cfg(unix)]
#[test]
fn a_journal_that_is_a_symbolic_link_is_refused() {
    let dir = temp_dir("sweep-symlink");
    let file = small_sweep(&dir, 1, 20);
    let out = dir.join("out");
    let f = file.to_str().unwrap();
    let o = out.to_str().unwrap();
    ok(e3d(&["sweep", f, "--out", o, "--threads", "1"]));
    let journal = out.join("journal.txt");
    let victim = dir.join("victim.txt");
    std::fs::copy(&journal, &victim).unwrap();
    let before = std::fs::read(&victim).unwrap();
    std::fs::remove_file(&journal).unwrap();
    std::os::unix::fs::symlink(&victim, &journal).unwrap();
    let r = e3d(&["sweep", f, "--out", o, "--resume"]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(3), "{err}");
    assert!(
        err.contains("journal.txt: is a symbolic link; refused"),
        "{err}"
    );
    assert_eq!(std::fs::read(&victim).unwrap(), before);
}

/// `--shard 1/18446744073709551615`: the first shard holds session 0 (its
/// count overflowed into 0 sessions, and the sweep never completed).
#[test]
fn a_shard_of_the_largest_n_holds_its_sessions() {
    let dir = temp_dir("sweep-hugeshard");
    let file = small_sweep(&dir, 1, 5);
    let out = dir.join("out");
    let o = ok(e3d(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--shard",
        "1/18446744073709551615",
    ]));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("shard 1/18446744073709551615 (1 sessions)"),
        "{err}"
    );
    let results = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(results.lines().count(), 2, "{results}");
}

/// A run killed while copying `sweep.ron` into a new folder leaves only a
/// temporary file there: a fresh run and `--resume` both accept the folder
/// (they refused it: not empty, and no sweep.ron to resume).
#[test]
fn a_folder_left_by_a_kill_during_the_first_copy_is_accepted() {
    let dir = temp_dir("sweep-killcopy");
    let file = small_sweep(&dir, 1, 5);
    let f = file.to_str().unwrap();
    for resume in [false, true] {
        let out = dir.join(format!("out-{resume}"));
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(out.join(".sweep.ron.tmp-4242-0-1f"), "Sweep(sce").unwrap();
        let mut args = vec!["sweep", f, "--out", out.to_str().unwrap()];
        if resume {
            args.push("--resume");
        }
        ok(e3d(&args));
        assert!(out.join("results.csv").exists());
        assert!(!out.join(".sweep.ron.tmp-4242-0-1f").exists());
    }
}

/// Two sweeps into one folder: the second is refused with who holds the
/// lock (both did all the work); a lock file left by a killed run is
/// taken over with a warning; the lock file goes when the run ends.
#[cfg(unix)]
#[test]
fn a_second_sweep_into_a_locked_folder_is_refused() {
    let dir = temp_dir("sweep-lock");
    let file = small_sweep(&dir, 1, 5);
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let args = [
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    {
        let _held = e3d::io::DirLock::acquire(&out).unwrap();
        let r = e3d(&args);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(3), "{err}");
        let me = format!("in use by e3d pid={} host=", std::process::id());
        assert!(err.contains(&me), "{err}");
        assert!(!out.join("journal.txt").exists());
    }
    // released: a lock file without a live holder is taken over
    std::fs::write(out.join(".lock"), "pid=4194999 host=gone\n").unwrap();
    let r = ok(e3d(&args));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains("warning: ") && err.contains("took over the lock of a run that ended without releasing it (pid=4194999 host=gone)"),
        "{err}"
    );
    assert!(out.join("results.csv").exists());
    assert!(!out.join(".lock").exists());
}

/// A scene edited between shards, or before `--resume`, would mix two
/// versions of it in one results file: both are refused, naming the scene.
#[test]
fn a_scene_edited_between_shards_or_before_resume_is_refused() {
    let dir = temp_dir("sweep-edited");
    let scene = dir.join("rooms.ron");
    let original = std::fs::read_to_string("scenes/two_rooms.ron").unwrap();
    std::fs::write(&scene, &original).unwrap();
    let file = dir.join("s.ron");
    std::fs::write(
        &file,
        "Sweep(scenes: [\"rooms.ron\"], learners: [uniform], sessions: 4, trials: 5)",
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let (a, b) = (dir.join("a"), dir.join("b"));
    ok(e3d(&[
        "sweep",
        f,
        "--out",
        a.to_str().unwrap(),
        "--shard",
        "1/2",
    ]));
    // the reward moves: another scene under the same name
    let edited = original.replacen("value: 1.0", "value: 2.0", 1);
    assert_ne!(edited, original);
    std::fs::write(&scene, &edited).unwrap();
    let r = e3d(&[
        "sweep",
        f,
        "--out",
        a.to_str().unwrap(),
        "--shard",
        "1/2",
        "--resume",
    ]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(3), "{err}");
    assert!(
        err.contains("journal.txt: scene `two_rooms` changed since this folder's sessions ran"),
        "{err}"
    );
    ok(e3d(&[
        "sweep",
        f,
        "--out",
        b.to_str().unwrap(),
        "--shard",
        "2/2",
    ]));
    let m = dir.join("merged");
    let r = e3d(&[
        "merge",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--out",
        m.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(3), "{err}");
    assert!(
        err.contains("ran scene `two_rooms` with other content"),
        "{err}"
    );
    // comments and layout are not content
    std::fs::write(&scene, format!("// a comment\n{original}")).unwrap();
    ok(e3d(&[
        "sweep",
        f,
        "--out",
        a.to_str().unwrap(),
        "--shard",
        "1/2",
        "--resume",
    ]));
}

/// A table built for a sweep is told as it goes (every simulated command,
/// then the end), and the results are the same as without it; a table
/// read whole is not told.
#[test]
fn table_progress_tells_every_simulated_command_and_changes_nothing() {
    use std::sync::{Arc, Mutex};
    let d = temp_dir("sweep-table-progress");
    let file = d.join("p.ron");
    std::fs::write(
        &file,
        r#"Sweep(
    scenes: ["pendulum3", "two_rooms"],
    learners: [e3d],
    params: (beta: [1, 100]),
    sessions: 2,
    trials: 200,
    seed: 5,
    metrics: [normalized_entropy, distinct_effects],
)
"#,
    )
    .unwrap();
    let table = Some(e3d::world::Strategy::Table);
    let calls: Arc<Mutex<Vec<(String, u64, u64)>>> = Arc::default();
    let seen = calls.clone();
    let cache = d.join("tables");
    let told = e3d::Sweep::load(&file)
        .unwrap()
        .with_strategy(table)
        .unwrap()
        .with_table_cache(&cache)
        .with_table_progress(move |scene, k, total| {
            seen.lock().unwrap().push((scene.to_string(), k, total))
        });
    let with = told.run(2).unwrap();
    let calls = calls.lock().unwrap().clone();
    for scene in ["pendulum3", "two_rooms"] {
        let mine: Vec<&(String, u64, u64)> = calls.iter().filter(|c| c.0 == scene).collect();
        assert!(mine.len() >= 2, "{scene}: {calls:?}");
        // the end, once, last
        assert_eq!(mine.last().map(|c| (c.1, c.2)), Some((0, 0)), "{scene}");
        assert_eq!(mine.iter().filter(|c| c.2 == 0).count(), 1, "{scene}");
        let total = mine[0].2;
        assert!(mine[..mine.len() - 1].iter().all(|c| c.2 == total));
        let simulated: u64 = mine.iter().map(|c| c.1).sum();
        assert_eq!(simulated, total, "{scene}");
    }
    let pendulum_total = calls.iter().find(|c| c.0 == "pendulum3").unwrap().2;
    assert_eq!(pendulum_total, 125);
    // without progress, and with the tables read whole from the cache
    // (nothing to tell): the same results
    let again: Arc<Mutex<u64>> = Arc::default();
    let count = again.clone();
    let without = e3d::Sweep::load(&file)
        .unwrap()
        .with_strategy(table)
        .unwrap()
        .with_table_cache(&cache)
        .with_table_progress(move |_, _, _| *count.lock().unwrap() += 1)
        .run(2)
        .unwrap();
    assert_eq!(*again.lock().unwrap(), 0);
    let plain = e3d::Sweep::load(&file).unwrap().run(1).unwrap();
    let rows = |rs: &[e3d::sweep::SessionResult]| {
        let s = e3d::Sweep::load(&file).unwrap();
        rs.iter().map(|r| s.result_row(r)).collect::<Vec<_>>()
    };
    assert_eq!(rows(&with), rows(&without));
    assert_eq!(rows(&with), rows(&plain));
}

/// A closed-loop sweep on a scene with start contexts and one without:
/// 2 scenes x (e3d at 2 beta, egreedy, uniform) x 4 sessions of 300
/// episodes of 3 commands.
fn closed_loop_sweep(dir: &Path) -> PathBuf {
    let scene = dir.join("contexts.ron");
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/two_rooms_contexts.ron"),
        &scene,
    )
    .unwrap();
    let p = dir.join("closed.ron");
    std::fs::write(
        &p,
        r#"Sweep(
    scenes: ["four_rooms", "contexts.ron"],
    learners: [e3d, egreedy, uniform],
    params: (beta: [1, 100]),
    sessions: 4,
    trials: 300,
    seed: 11,
    commands: 3,
    closed_loop: true,
    gamma: 0.8,
)
"#,
    )
    .unwrap();
    p
}

#[test]
fn a_closed_loop_sweep_on_start_contexts_is_the_same_bytes_whatever_the_threads_shards_and_resumes()
{
    let d = temp_dir("sweep-closed-loop");
    let file = closed_loop_sweep(&d);
    let f = file.to_str().unwrap();
    let out = |name: &str| d.join(name).to_str().unwrap().to_string();
    let (one, two) = (out("one"), out("two"));
    let plan = ok(e3d(&["sweep", f, "--out", &one, "--threads", "1"]));
    let told = String::from_utf8_lossy(&plan.stderr);
    assert!(
        told.contains("contexts: episodes of 3 commands from 2 start contexts"),
        "{told}"
    );
    ok(e3d(&["sweep", f, "--out", &two, "--threads", "2"]));
    assert_same_files(Path::new(&one), Path::new(&two), &FINAL_FILES);
    // two shards, merged
    for k in 1..=2 {
        let shard = out(&format!("shard{k}"));
        ok(e3d(&[
            "sweep",
            f,
            "--shard",
            &format!("{k}/2"),
            "--out",
            &shard,
        ]));
    }
    let merged = out("merged");
    ok(e3d(&[
        "merge",
        &out("shard2"),
        &out("shard1"),
        "--out",
        &merged,
    ]));
    assert_same_files(Path::new(&one), Path::new(&merged), &FINAL_FILES);
    // a run cut short (the last 10 sessions missing from its journal)
    // resumes to the same bytes
    let journal = d.join("two/journal.txt");
    let text = std::fs::read_to_string(&journal).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let kept = lines[..lines.len() - 10].join("\n") + "\n";
    std::fs::write(&journal, kept).unwrap();
    for f in ["results.csv", "summary.csv"] {
        std::fs::remove_file(d.join("two").join(f)).unwrap();
    }
    let resumed = ok(e3d(&[
        "sweep",
        f,
        "--out",
        &two,
        "--resume",
        "--threads",
        "2",
    ]));
    assert!(String::from_utf8_lossy(&resumed.stderr).contains("(22 from an earlier run, 10 now)"));
    assert_same_files(Path::new(&one), Path::new(&two), &FINAL_FILES);

    // the per-context columns, and the numbers of run_episodes
    let results = std::fs::read_to_string(d.join("one/results.csv")).unwrap();
    let rows: Vec<Vec<&str>> = results.lines().map(|l| l.split(',').collect()).collect();
    let header = &rows[0];
    assert_eq!(rows.len(), 1 + 2 * 4 * 4);
    let col = |name: &str| header.iter().position(|c| *c == name).unwrap();
    let (c0, c1) = (
        col("normalized_entropy_context_0"),
        col("normalized_entropy_context_1"),
    );
    let (reward, first) = (col("cumulative_reward_at_300"), col("first_reward_trial"));
    let (r0, f0) = (
        col("cumulative_reward_context_0"),
        col("first_reward_trial_context_0"),
    );
    for row in &rows[1..] {
        assert_eq!(row[c1].is_empty(), row[0] == "four_rooms", "{row:?}");
        if row[0] == "four_rooms" {
            // one start context: its reward is the session's
            assert_eq!((row[r0], row[f0]), (row[reward], row[first]), "{row:?}");
        }
        assert!(row.last().unwrap().is_empty(), "a failed session: {row:?}");
    }
    use e3d::episode::{run_episodes, EpisodeConfig, Observe};
    use e3d::learner::ContextualLearner;
    let scene = e3d::Scene::load(d.join("contexts.ron")).unwrap();
    let mut checked = 0;
    for row in rows[1..].iter().filter(|r| r[0] == "two_rooms_contexts") {
        let kind: e3d::LearnerKind = row[1].parse().unwrap();
        let seed: u64 = row[9].parse().unwrap();
        let mut world = scene.build();
        let cfg = EpisodeConfig {
            episodes: 300,
            commands: 3,
            seed,
            use_reward: true,
            observe: Observe::State,
        };
        let closed = matches!(kind, e3d::LearnerKind::E3d | e3d::LearnerKind::Egreedy);
        let mut learner = e3d::learner::LearnerSetup::new(kind)
            .params(e3d::Params {
                beta: row[4].parse().unwrap_or(1.0),
                ..e3d::Params::TASK1
            })
            .closed_loop(closed)
            .gamma(0.8)
            .contexts(
                &scene.command_space(),
                scene.num_effects(),
                cfg.num_contexts(&*world),
            )
            .unwrap();
        assert_eq!(learner.num_contexts(), 18);
        let rec = run_episodes(
            &mut *world,
            &mut *learner,
            &cfg,
            &e3d::session::Control::default(),
        )
        .unwrap();
        let per_start = rec.entropy_per_start(2);
        assert_eq!(row[c0], e3d::sweep::format_number(per_start[0]), "{row:?}");
        assert_eq!(row[c1], e3d::sweep::format_number(per_start[1]), "{row:?}");
        assert_eq!(
            row[reward],
            e3d::sweep::format_number(rec.cumulative_reward())
        );
        let first_episode = rec
            .first_reward_episode()
            .map_or(String::new(), |e| e.to_string());
        assert_eq!(row[first], first_episode);
        // the reward per start context: the sums add up to the session's,
        // the first rewarded episode is the earliest of the contexts'
        let (rewards, firsts) = (rec.reward_per_start(2), rec.first_reward_per_start(2));
        for i in 0..2 {
            assert_eq!(
                row[col(&format!("cumulative_reward_context_{i}"))],
                e3d::sweep::format_number(rewards[i])
            );
            assert_eq!(
                row[col(&format!("first_reward_trial_context_{i}"))],
                firsts[i].map_or(String::new(), |e| e.to_string())
            );
        }
        assert_eq!(rewards[0] + rewards[1], rec.cumulative_reward());
        assert_eq!(
            firsts.iter().flatten().min(),
            rec.first_reward_episode().as_ref()
        );
        assert!(
            per_start.iter().all(|h| *h > 0.5 && *h <= 1.0),
            "{per_start:?}"
        );
        checked += 1;
    }
    assert_eq!(checked, 16);
    // (no session reaches a reward in 300 episodes here: the per-context
    // sums are checked on rewards in tests/library/contexts.rs)
    // the summary: per cell, the per-context means and their counts
    let summary = std::fs::read_to_string(d.join("one/summary.csv")).unwrap();
    let srows: Vec<Vec<&str>> = summary.lines().map(|l| l.split(',').collect()).collect();
    let scol = |name: &str| srows[0].iter().position(|c| *c == name).unwrap();
    let (n1, m1) = (
        scol("normalized_entropy_context_1_n"),
        scol("normalized_entropy_context_1_mean"),
    );
    assert_eq!(srows.len(), 1 + 8);
    let (rn1, rm1) = (
        scol("cumulative_reward_context_1_n"),
        scol("cumulative_reward_context_1_mean"),
    );
    for r in &srows[1..] {
        if r[0] == "four_rooms" {
            assert_eq!((r[n1], r[m1]), ("0", ""));
            assert_eq!((r[rn1], r[rm1]), ("0", ""));
        } else {
            assert_eq!((r[n1], r[rn1]), ("4", "4"));
            assert!(r[rm1].parse::<f64>().unwrap() >= 0.0);
            let m: f64 = r[m1].parse().unwrap();
            assert!(m > 0.5 && m <= 1.0, "{r:?}");
        }
    }
    // the page and a plot of a per-context column
    ok(e3d(&["report", &one]));
    let page = std::fs::read_to_string(d.join("one/report.html")).unwrap();
    assert!(page.contains("<th>normalized_entropy_context_1<br>mean ± sd</th>"));
    let svg = d.join("h1.svg");
    ok(e3d(&[
        "plot",
        &one,
        "--x",
        "beta",
        "--metric",
        "normalized_entropy_context_1",
        "--where",
        "scene=two_rooms_contexts",
        "--out",
        svg.to_str().unwrap(),
    ]));
    let svg = std::fs::read_to_string(svg).unwrap();
    assert!(
        svg.contains("Normalized entropy context 1 against beta (two_rooms_contexts)"),
        "{svg}"
    );
}
