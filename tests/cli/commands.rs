//! The command line: outputs, refusals and exit codes.

use crate::common::{e3d, e3d_command, fresh_path, temp_path};
use std::path::Path;
use std::process::{Command, Output};

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap()
}

#[test]
fn run_writes_trials_and_summary_and_the_same_seed_gives_the_same_bytes() {
    let (a, b) = (fresh_path("cli-run-a"), fresh_path("cli-run-b"));
    for d in [&a, &b] {
        let o = e3d(&[
            "run",
            "scenes/two_rooms.ron",
            "--beta",
            "100",
            "--seed",
            "4",
            "--trials",
            "2000",
            "--out",
            d.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert_eq!(read(&a.join("trials.csv")), read(&b.join("trials.csv")));
    assert_eq!(read(&a.join("summary.json")), read(&b.join("summary.json")));
    let csv = String::from_utf8(read(&a.join("trials.csv"))).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("trial,command,effect,reward"));
    assert_eq!(csv.lines().count(), 2001);
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(row[0], "1");
    assert_eq!(row[1].len(), 7);
    assert!(row[1].chars().all(|c| "ESWN".contains(c)));
    let json: serde_json::Value = serde_json::from_slice(&read(&a.join("summary.json"))).unwrap();
    for key in [
        "normalized_entropy",
        "kl_to_target",
        "distinct_effects",
        "cumulative_reward",
        "first_reward_trial",
        "alpha",
        "beta",
        "lambda",
        "eta",
        "epsilon",
        "seed",
        "trials",
        "learner",
        "scene",
    ] {
        assert!(json.get(key).is_some(), "summary.json lacks {key}");
    }
    assert_eq!(json["beta"], 100.0);
    assert_eq!(json["seed"], 4);
    // the summary agrees with the trials
    let total: f64 = csv
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse::<f64>().unwrap())
        .sum();
    assert_eq!(json["cumulative_reward"].as_f64().unwrap(), total);
}

#[test]
fn run_refuses_to_overwrite_without_force() {
    let d = fresh_path("cli-overwrite");
    let out = d.to_str().unwrap();
    assert!(e3d(&["run", "--trials", "10", "--out", out])
        .status
        .success());
    let before = read(&d.join("trials.csv"));
    let o = e3d(&["run", "--trials", "20", "--out", out]);
    assert_eq!(o.status.code(), Some(3));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("trials.csv exists; pass --force"), "{err}");
    assert_eq!(read(&d.join("trials.csv")), before, "nothing was touched");
    assert!(e3d(&["run", "--trials", "20", "--out", out, "--force"])
        .status
        .success());
    assert_eq!(
        String::from_utf8(read(&d.join("trials.csv")))
            .unwrap()
            .lines()
            .count(),
        21
    );
}

#[test]
fn bad_parameters_and_scenes_exit_with_code_2_and_say_why() {
    let o = e3d(&["run", "--eta", "1.5"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--eta = 1.5: expected a number in (0, 1]"));
    let o = e3d(&["run", "no/such/scene.ron"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no such file"));
    let o = e3d(&["run", "--learner", "greedy"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_hyper_parameter_the_learner_does_not_read_gets_a_note() {
    let err = |args: &[&str]| {
        let o = e3d(args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let base = ["run", "two_rooms", "--trials", "20"];
    fn with<'a>(base: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        [base, extra].concat()
    }
    let e = err(&with(&base, &["--learner", "uniform", "--alpha", "0.5"]));
    assert!(
        e.contains("note: --alpha does nothing for learner uniform (it reads no hyper-parameter)"),
        "{e}"
    );
    let e = err(&with(
        &base,
        &["--epsilon", "0.5", "--goal-progress", "0.2", "--beta", "3"],
    ));
    assert!(
        e.contains(
            "note: --epsilon does nothing for learner e3d (it reads alpha, beta, lambda, eta)"
        ),
        "{e}"
    );
    assert!(
        e.contains("note: --goal-progress does nothing for learner e3d"),
        "{e}"
    );
    assert!(!e.contains("--beta does nothing"), "{e}");
    // defaults and the parameters a learner reads: no note
    assert!(!err(&base).contains("note:"));
    assert!(!err(&with(&base, &["--learner", "egreedy", "--epsilon", "0.2"])).contains("note:"));
}

#[test]
fn reproduce_writes_the_same_bytes_whatever_the_number_of_threads() {
    let outs: Vec<_> = ["1", "2"]
        .iter()
        .map(|threads| {
            let d = fresh_path(&format!("cli-repro-{threads}"));
            let o = e3d_command()
                .args([
                    "reproduce",
                    "--sessions",
                    "4",
                    "--trials",
                    "1500",
                    "--out",
                    d.to_str().unwrap(),
                ])
                .env("RAYON_NUM_THREADS", threads)
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            assert!(String::from_utf8_lossy(&o.stdout).contains("| 2 | E3D (beta 100) |"));
            d
        })
        .collect();
    for f in ["fig2.svg", "fig2.csv", "fig3.svg", "fig3.csv", "summary.md"] {
        let a = read(&outs[0].join(f));
        assert!(a.len() > 200, "{f} is nearly empty");
        assert_eq!(a, read(&outs[1].join(f)), "{f} differs");
    }
    let svg = String::from_utf8(read(&outs[0].join("fig2.svg"))).unwrap();
    assert!(svg.contains("uniform policy") && svg.contains("E3D"));
}

#[test]
fn an_unwritable_output_folder_is_a_clear_error() {
    let d = fresh_path("cli-unwritable");
    std::fs::create_dir_all(&d).unwrap();
    let file = d.join("a-file");
    std::fs::write(&file, b"x").unwrap();
    let out = file.join("sub");
    let o = e3d(&["run", "--trials", "10", "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("a-file/sub: cannot create the folder"),
        "{err}"
    );
    let o = e3d(&[
        "reproduce",
        "--sessions",
        "1",
        "--trials",
        "10",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&o.stderr).contains("exists and is not a directory"));
}

/// A reader that closes the pipe early (`| head`) ends e3d quietly: no
/// panic, no backtrace.
#[cfg(unix)]
#[test]
fn a_closed_stdout_ends_quietly() {
    let dir = temp_path("pipe");
    std::fs::create_dir_all(&dir).unwrap();
    let commands = dir.join("commands.txt");
    std::fs::write(&commands, "SEEEEES\n".repeat(200_000)).unwrap();
    let err = dir.join("stderr.txt");
    let script = format!(
        "'{}' scene exec two_rooms - < '{}' 2> '{}' | head -n 2",
        env!("CARGO_BIN_EXE_e3d"),
        commands.display(),
        err.display()
    );
    let out = Command::new("sh").arg("-c").arg(&script).output().unwrap();
    let head = String::from_utf8(out.stdout).unwrap();
    assert_eq!(head.lines().count(), 2, "{head}");
    let stderr = std::fs::read_to_string(&err).unwrap();
    assert!(stderr.is_empty(), "e3d wrote to stderr: {stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Output that cannot be written is exit code 3 with a message, never a
/// panic (101) nor a silent success: a full device on stdout or stderr,
/// and a closed stdout (`>&-`, whose output Rust would discard).
#[cfg(unix)]
#[test]
fn unwritable_or_closed_output_is_exit_code_3() {
    let bin = env!("CARGO_BIN_EXE_e3d");
    let sh = |script: String| {
        let o = Command::new("sh").arg("-c").arg(&script).output().unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let (code, err) = sh(format!("'{bin}' scene check two_rooms > /dev/full"));
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("error: cannot write to stdout: No space left on device"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    let (code, err) = sh(format!("'{bin}' scene check two_rooms >&-"));
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("error: standard output is closed"), "{err}");
    // /dev/null is a fine place for results
    let (code, err) = sh(format!("'{bin}' scene check two_rooms > /dev/null"));
    assert_eq!(code, Some(0), "{err}");
    // stderr full: the progress line of a sweep cannot be written
    let dir = temp_path("full");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("s.ron"),
        "Sweep(scenes: [\"two_rooms\"], learners: [uniform], sessions: 1, trials: 5)",
    )
    .unwrap();
    let o = Command::new(bin)
        .args(["sweep", dir.join("s.ron").to_str().unwrap(), "--out"])
        .arg(dir.join("out"))
        .stderr(std::fs::File::create("/dev/full").unwrap())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(3));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `e3d bench`: a CSV line per measure, each a median no faster than the
/// best of its slices, and the measures of both kinds of scene.
#[test]
fn bench_prints_every_measure_with_its_median_and_best() {
    let o = e3d(&["bench", "two_rooms", "pendulum3", "--seconds", "0.05"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8(o.stdout).unwrap();
    let mut lines = out.lines();
    assert_eq!(lines.next(), Some("scene,measure,rate,best,unit"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let measures: Vec<String> = rows.iter().map(|r| format!("{},{}", r[0], r[1])).collect();
    for want in [
        "two_rooms,rollouts",
        "two_rooms,outcome table build (16384 commands; 16384 simulated;",
        "two_rooms,e3d trials (outcome table)",
        "two_rooms,e3d trial (outcome table)",
        "pendulum3,rollouts",
        "pendulum3,steps",
        "pendulum3,rollouts (32 copies per world; not bit-identical: tables use one copy)",
        "pendulum3,outcome table build (125 commands; 125 simulated;",
        "pendulum3,e3d trials (outcome table)",
    ] {
        assert!(
            measures.iter().any(|m| m.starts_with(want)),
            "no `{want}` in\n{out}"
        );
    }
    for r in &rows {
        assert_eq!(r.len(), 5, "{r:?}");
        let (rate, best): (f64, f64) = (r[2].parse().unwrap(), r[3].parse().unwrap());
        assert!(rate > 0.0 && rate.is_finite(), "{r:?}");
        // a rate's best is at least its median; a time's at most
        if r[4] == "1/s" {
            assert!(best >= rate, "{r:?}");
        } else {
            assert!(best <= rate, "{r:?}");
        }
    }
    // pendulum3 runs 120 steps a command: steps are 120 rollouts
    let get = |m: &str| {
        rows.iter()
            .find(|r| r[0] == "pendulum3" && r[1] == m)
            .unwrap()[2]
    };
    let (rollouts, steps): (f64, f64) = (
        get("rollouts").parse().unwrap(),
        get("steps").parse().unwrap(),
    );
    assert!(
        (steps / rollouts - 120.0).abs() < 0.1,
        "{steps} / {rollouts}"
    );
    // a time that is not a number of seconds is refused
    let o = e3d(&["bench", "two_rooms", "--seconds", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("--seconds 0: expected a number in (0, 3600]")
    );
}

/// `reproduce --seed`: session i uses SEED + i, which must not wrap past
/// 2^64 - 1 (it did, silently).
#[test]
fn a_reproduce_seed_that_would_wrap_is_refused() {
    let o = e3d(&[
        "reproduce",
        "--seed",
        "18446744073709551615",
        "--sessions",
        "2",
        "--out",
        "/nonexistent/x",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--seed 18446744073709551615 with --sessions 2: session i uses seed SEED + i, which would pass 2^64 - 1; expected a seed of at most 18446744073709551614"),
        "{err}"
    );
}

/// A one-slot command `-` cannot be an argument of `scene exec` (`-`
/// means standard input); on standard input it is a command like any other.
#[test]
fn a_command_written_minus_is_given_on_stdin() {
    use std::io::Write;
    let dir = temp_path("minus");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("minus.ron");
    std::fs::write(
        &scene,
        r#"Scene(name: "minus", world: Grid(rows: 1, cols: 2, start: (0, 0)),
    command: Repeat(slots: 1, alphabet: [(symbol: '-', action: Move(drow: 0, dcol: 1)), (symbol: '0', action: Idle)]))"#,
    )
    .unwrap();
    let mut child = e3d_command()
        .args(["scene", "exec", scene.to_str().unwrap(), "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(b"-\n0\n").unwrap();
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success());
    let out = String::from_utf8(o.stdout).unwrap();
    let rows: Vec<String> = out
        .lines()
        .map(|l| l.split(',').take(2).collect::<Vec<_>>().join(","))
        .collect();
    assert_eq!(rows, ["command,effect", "-,1", "0,0"], "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `reproduce` follows the rule of `run` and `plot`: its default folder
/// `out` is created on a fresh clone (the README's first command), but an
/// earlier reproduction's files are replaced only with `--force`, and a
/// refusal names `--force` and touches nothing.
#[test]
fn reproduce_refuses_to_replace_an_earlier_reproduction_without_force() {
    let d = fresh_path("cli-repro-force");
    std::fs::create_dir_all(&d).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["reproduce", "--sessions", "1", "--trials", "50"];
        args.extend_from_slice(extra);
        e3d_command().args(&args).current_dir(&d).output().unwrap()
    };
    // no out/ yet: the README's `cargo run --release -- reproduce`
    let o = run(&[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let fig2 = d.join("out").join("fig2.svg");
    let before = read(&fig2);
    let o = run(&["--seed", "5"]);
    assert_eq!(o.status.code(), Some(3));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("out/fig2.svg exists; pass --force to overwrite it, or choose another --out"),
        "{err}"
    );
    assert!(o.stdout.is_empty(), "refused before any work");
    assert_eq!(read(&fig2), before, "nothing was touched");
    let o = run(&["--seed", "5", "--force"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_ne!(read(&fig2), before, "--force replaced it");
    // any one of its five files is enough to refuse
    std::fs::remove_dir_all(d.join("out")).unwrap();
    std::fs::create_dir_all(d.join("out")).unwrap();
    std::fs::write(d.join("out").join("summary.md"), "mine").unwrap();
    let o = run(&[]);
    assert_eq!(o.status.code(), Some(3));
    assert_eq!(
        std::fs::read_to_string(d.join("out").join("summary.md")).unwrap(),
        "mine"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// `run` prints the parameters its learner uses, none for the uniform
/// policy, and spells "normalised" as the docs do.
#[test]
fn run_prints_only_the_parameters_its_learner_uses() {
    let first_line = |learner: &str| {
        let o = e3d(&["run", "--learner", learner, "--trials", "20"]);
        assert!(o.status.success());
        let out = String::from_utf8(o.stdout).unwrap();
        assert!(
            out.contains("normalised entropy") && !out.contains("normalized"),
            "{out}"
        );
        out.lines().next().unwrap().to_string()
    };
    assert_eq!(
        first_line("uniform"),
        "scene two_rooms | learner uniform | 20 trials | seed 0"
    );
    assert_eq!(
        first_line("egreedy"),
        "scene two_rooms | learner egreedy | 20 trials | seed 0 | alpha 0.3 epsilon 0.1"
    );
    assert_eq!(
        first_line("e3d"),
        "scene two_rooms | learner e3d | 20 trials | seed 0 | alpha 0.3 beta 1 lambda 0.03 eta 0.01"
    );
}

/// `scene check` gives one answer about the reward: the cells of a region
/// are the scene's reward cells (maze3), and a scene without reward says so.
#[test]
fn scene_check_lists_the_cells_of_reward_regions_as_reward_cells() {
    let out = |scene: &str| {
        let o = e3d(&["scene", "check", scene]);
        assert!(o.status.success());
        String::from_utf8(o.stdout).unwrap()
    };
    let maze = out("maze3");
    assert!(
        maze.contains("reward region `corner C`: [5.5, 6] x [0, 0.5], cells [(3, 11)]")
            && maze.contains("reward cells: [(3, 11)] (from the region above), value 1"),
        "{maze}"
    );
    assert!(!maze.contains("reward cells: none"), "{maze}");
    assert!(out("two_rooms").contains("reward cells: [(2, 5)], value 1\n"));
    assert!(out("pendulum3")
        .contains("reward cells: none (the scene declares no reward cell or region)"));
}

/// `plot --metric` reads summary.csv, and its help says so.
#[test]
fn plot_help_names_the_file_it_reads() {
    let o = e3d(&["plot", "--help"]);
    let help = String::from_utf8(o.stdout).unwrap();
    assert!(help.contains("summary.csv names it"), "{help}");
    assert!(!help.contains("results.csv"), "{help}");
}

/// `scene check --expanded` prints the scene with its shorthands expanded:
/// RON that loads back as the same scene (and as the file it replaced).
#[test]
fn scene_check_expanded_prints_a_scene_that_loads_back_equal() {
    for name in ["arm7", "puck_rooms"] {
        let path = format!("scenes/{name}.ron");
        let o = e3d(&["scene", "check", "--expanded", &path]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = String::from_utf8(o.stdout).unwrap();
        assert!(text.starts_with("Scene(\n"), "{text}");
        assert!(
            !text.contains("chains:") && !text.contains("walls:"),
            "{text}"
        );
        let file = fresh_path(&format!("cli-expanded_{name}.ron"));
        std::fs::write(&file, &text).unwrap();
        let back = e3d::Scene::load(&file).unwrap();
        assert_eq!(back, e3d::Scene::load(&path).unwrap(), "{name}");
        let before = e3d::Scene::load(format!("tests/scenes/{name}_expanded.ron")).unwrap();
        assert_eq!(back, before, "{name}");
        // the built-in scene of that name too
        let o = e3d(&["scene", "check", "--expanded", name]);
        assert_eq!(String::from_utf8(o.stdout).unwrap(), text);
    }
}

fn ok(o: &Output) -> (String, String) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn report_writes_a_run_folders_page_and_says_where() {
    let d = fresh_path("cli-report-run");
    let ds = d.to_str().unwrap();
    ok(&e3d(&["run", "two_rooms", "--trials", "500", "--out", ds]));
    let (out, _) = ok(&e3d(&["report", ds]));
    let page_path = d.join("report.html");
    assert_eq!(out, format!("wrote {} (run report)\n", page_path.display()));
    let page = String::from_utf8(read(&page_path)).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>"));
    assert!(page.contains("<title>e3d run: two_rooms</title>"));
    assert!(page.contains("<p>500 trials</p>"));
    // two heat maps of the 3 x 6 cells of two_rooms (no elite map: every
    // command is 7 moves, the same effort), a chart per slot
    assert_eq!(page.matches(r#"class="cell""#).count(), 36);
    assert!(page.contains("slot 6:") && !page.contains("slot 7:"));
    assert!(!page.contains("<script"));
    // --out elsewhere
    let other = d.join("elsewhere.html");
    let (out, _) = ok(&e3d(&["report", ds, "--out", other.to_str().unwrap()]));
    assert!(out.contains(&other.display().to_string()));
    assert_eq!(read(&other), read(&page_path));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn report_writes_a_sweep_folders_page_with_its_summary() {
    let d = fresh_path("cli-report-sweep");
    std::fs::create_dir_all(&d).unwrap();
    let file = d.join("s.ron");
    std::fs::write(
        &file,
        r#"Sweep(
    name: "tiny",
    scenes: ["two_rooms"],
    learners: [e3d, uniform],
    params: (beta: [1, 100], eta: [0.003, 0.03]),
    sessions: 2,
    trials: 200,
    seed: 1,
    metrics: [normalized_entropy, distinct_effects],
)
"#,
    )
    .unwrap();
    let out = d.join("out");
    let os = out.to_str().unwrap();
    ok(&e3d(&["sweep", file.to_str().unwrap(), "--out", os]));
    let (stdout, _) = ok(&e3d(&["report", os]));
    assert!(stdout.contains("(sweep report)"), "{stdout}");
    let page = String::from_utf8(read(&out.join("report.html"))).unwrap();
    assert!(page.contains("<title>e3d sweep: tiny</title>"));
    let summary = String::from_utf8(read(&out.join("summary.csv"))).unwrap();
    let header: Vec<&str> = summary.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // every cell's exact mean and sd are on the page
    for line in summary.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        for m in ["normalized_entropy", "distinct_effects"] {
            let (mean, sd) = (f[col(&format!("{m}_mean"))], f[col(&format!("{m}_sd"))]);
            assert!(
                page.contains(&format!("mean {mean}, sd {sd},")),
                "{m} {mean}"
            );
        }
    }
    assert_eq!(page.matches("<tr>").count(), summary.lines().count());
    for p in ["beta", "eta", "learner"] {
        assert!(page.contains(&format!("<th>{p}</th>")), "{p}");
    }
    assert!(page.contains("<h2>Against beta</h2>") && page.contains("<h2>Against eta</h2>"));
    assert!(page.contains("normalized_entropy against beta"));
    assert!(page.contains("name: &quot;tiny&quot;") || page.contains("name: \"tiny\""));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn report_refuses_a_missing_folder_and_one_without_results_naming_it() {
    let d = fresh_path("cli-report-bad");
    let missing = d.join("nothing-here");
    let o = e3d(&["report", missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&format!("{}: no such folder", missing.display())),
        "{err}"
    );
    std::fs::create_dir_all(&d).unwrap();
    let o = e3d(&["report", d.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&format!("{}: no results to report", d.display())),
        "{err}"
    );
    // a shard: results.csv without summary.csv
    std::fs::write(d.join("results.csv"), "scene\n").unwrap();
    let o = e3d(&["report", d.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("e3d merge"), "{err}");
    assert!(!d.join("report.html").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn scene_render_animate_writes_smil_for_physics_and_grids() {
    let d = fresh_path("cli-animate");
    std::fs::create_dir_all(&d).unwrap();
    // physics: an SVG and a page
    let svg = d.join("arm7.svg");
    let (out, _) = ok(&e3d(&[
        "scene",
        "render",
        "arm7",
        "--command=+0-+0-+",
        "--animate",
        "--out",
        svg.to_str().unwrap(),
    ]));
    assert!(
        out.starts_with(&format!("wrote {} (", svg.display())),
        "{out}"
    );
    assert!(out.contains("frames"), "{out}");
    let text = String::from_utf8(read(&svg)).unwrap();
    assert!(text.starts_with("<svg") && text.contains("<animateTransform"));
    assert!(text.contains(r#"repeatCount="indefinite""#) && text.contains("t = "));
    let html = d.join("arm7.html");
    ok(&e3d(&[
        "scene",
        "render",
        "arm7",
        "--command=+0-+0-+",
        "--animate",
        "--out",
        html.to_str().unwrap(),
    ]));
    let page = String::from_utf8(read(&html)).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>") && page.contains("<animateTransform"));
    // a grid: the cell path, a keyframe per slot and the start
    let grid = d.join("two_rooms.svg");
    let (out, _) = ok(&e3d(&[
        "scene",
        "render",
        "two_rooms",
        "--command",
        "EEESSEE",
        "--animate",
        "--out",
        grid.to_str().unwrap(),
    ]));
    assert!(out.contains("8 keyframes"), "{out}");
    let text = String::from_utf8(read(&grid)).unwrap();
    assert!(text.contains(r#"<circle class="agent""#));
    assert!(text.contains(r#"<animate attributeName="cx" calcMode="discrete""#));
    assert_eq!(text.matches(r#"class="keyframe""#).count(), 8);
    assert!(text.contains("slot 7/7: E → cell (2, 2)"));
    // a bad command: exit 2, naming the slot, no file
    for (scene, cmd, want) in [
        ("two_rooms", "EEESXEE", "symbol 'X' at slot 4"),
        ("arm7", "+0-+0-x", "at slot 6"),
    ] {
        let bad = d.join(format!("bad-{scene}.svg"));
        let o = e3d(&[
            "scene",
            "render",
            scene,
            &format!("--command={cmd}"),
            "--animate",
            "--out",
            bad.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{scene}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(want), "{scene}: {err}");
        assert!(!bad.exists());
    }
    // --animate without --command is refused by the parser
    let o = e3d(&["scene", "render", "arm7", "--animate", "--out", "x.svg"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--command"));
    let _ = std::fs::remove_dir_all(&d);
}

/// `e3d` with the global rayon pool of `threads` threads and `stdin`.
fn e3d_threads(args: &[&str], threads: usize, stdin: Option<&str>) -> Output {
    use std::io::Write;
    let mut child = e3d_command()
        .args(args)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut input = child.stdin.take().unwrap();
    if let Some(text) = stdin {
        input.write_all(text.as_bytes()).unwrap();
    }
    drop(input);
    child.wait_with_output().unwrap()
}

/// Episode runs (`run --commands K`, `--closed-loop`, start contexts)
/// say what they will cost, as every `run` does: a line after the
/// description with the commands (sessions x episodes x commands per
/// episode), the steps and the threads; then progress (its timing is not
/// checked: the lines come by the clock). 1500 commands of arm7: about
/// 2 s by the model on an idle machine, above the 1 s from which a
/// cost is said.
#[test]
fn episode_runs_print_their_estimated_cost_and_progress() {
    let runs: [(&[&str], &str, &str); 3] = [
        (
            &["run", "arm7", "--commands", "2", "--trials", "750"],
            "episodes: 1 sessions of 750 episodes of 2 commands, learner e3d,",
            "run arm7: 1500 command(s) (120 steps each) on 1 thread(s): about ",
        ),
        (
            &["run", "arm7", "--commands", "2", "--closed-loop", "--trials", "750"],
            "episodes: 1 sessions of 750 episodes of 2 commands, learner e3d_closed_loop,",
            "run arm7: 1500 command(s) (120 steps each) on 1 thread(s): about ",
        ),
        (
            &["run", "scenes/arm7_poses.ron", "--trials", "1500"],
            "episodes: 1 sessions of 1500 episodes of 1 command, learner e3d, 3 contexts observed as the start context",
            "run arm7_poses: 1500 command(s) (120 steps each) on 1 thread(s): about ",
        ),
    ];
    for (args, describe, cost) in runs {
        let (_, err) = ok(&e3d_threads(args, 1, None));
        let lines: Vec<&str> = err.lines().collect();
        assert!(lines[0].starts_with(describe), "{err}");
        assert!(
            lines[1].starts_with(cost)
                && lines[1]
                    .ends_with(" s (the cost model, calibrated on at least 3 timed rollouts here)"),
            "{err}"
        );
        let label = cost.split(':').next().unwrap();
        // the progress lines that came: the run's label and its episodes
        for l in &lines[2..] {
            assert!(
                l.starts_with(&format!("{label}: ")) && l.contains(" episodes"),
                "{l}\n{err}"
            );
        }
    }
}

/// The long scene tools say what they will cost before they start (the
/// progress lines that follow come every 5 s off a terminal: not checked);
/// the short ones stay quiet.
#[test]
fn long_scene_tools_print_their_estimated_cost_first() {
    // every command: always said, with the steps and the threads
    let (_, err) = ok(&e3d_threads(&["scene", "table", "pendulum3"], 2, None));
    let first = err.lines().next().unwrap();
    assert!(
        first.starts_with("scene pendulum3: simulating 125 commands on 2 thread(s) (")
            && first.contains(" steps each): about ")
            && first.ends_with(" by the cost model (calibrated on timed rollouts here)"),
        "{err}"
    );
    // a large sample: 2000 arm7 rollouts of 120 steps on one thread (about
    // 3 s by the model: 600, about 1 s, sat on the threshold and went
    // unsaid when the calibration's few rollouts ran fast)
    let (_, err) = ok(&e3d_threads(
        &["scene", "check", "arm7", "--samples", "2000"],
        2,
        None,
    ));
    let line = err
        .lines()
        .find(|l| l.starts_with("scene check arm7: "))
        .unwrap_or_else(|| panic!("no cost line: {err}"));
    assert!(
        line.starts_with(
            "scene check arm7: 2000 command(s) (120 steps each) on 1 thread(s): about "
        ) && line.ends_with(" s (the cost model, calibrated on at least 3 timed rollouts here)"),
        "{line}"
    );
    // scene exec of 1200 commands on one thread (the model says about
    // 3 s, three times the threshold, so a loaded machine's calibration
    // keeps it above): said before
    let many: Vec<&str> = std::iter::repeat_n("+0-+0-+", 1200).collect();
    let mut args = vec!["scene", "exec", "arm7"];
    args.extend(&many);
    let (out, err) = ok(&e3d_threads(&args, 1, None));
    assert_eq!(out.lines().count(), 1201);
    assert!(
        err.lines().next().unwrap_or_default().starts_with(
            "scene exec arm7: 1200 command(s) (120 steps each) on 1 thread(s): about "
        ),
        "{err}"
    );
    // the same on stdin: said once those read so far reach it
    let (out, err) = ok(&e3d_threads(
        &["scene", "exec", "arm7", "-"],
        1,
        Some(&(many.join("\n") + "\n")),
    ));
    assert_eq!(out.lines().count(), 1201);
    let said: Vec<&str> = err.lines().filter(|l| l.contains("so far")).collect();
    assert_eq!(said.len(), 1, "{err}");
    assert!(
        said[0].starts_with("scene exec arm7: ")
            && said[0].contains(" commands so far (120 steps each), about ")
            && said[0].ends_with(
                " each on 1 thread(s) by the cost model, calibrated here; more as stdin gives them"
            ),
        "{err}"
    );
    // short ones: nothing on stderr
    let (_, err) = ok(&e3d_threads(
        &["scene", "exec", "arm7", "+0-+0-+", "0000000"],
        1,
        None,
    ));
    assert_eq!(err, "");
    let d = fresh_path("cli-quiet-animate");
    std::fs::create_dir_all(&d).unwrap();
    let f = d.join("a.svg");
    let (_, err) = ok(&e3d_threads(
        &[
            "scene",
            "render",
            "arm7",
            "--command=+0-+0-+",
            "--animate",
            "--out",
            f.to_str().unwrap(),
        ],
        1,
        None,
    ));
    assert_eq!(err, "");
    let _ = std::fs::remove_dir_all(&d);
}

/// Every file e3d writes in its own folders is created through `e3d::io`
/// (exclusive temporary files, renamed into place): a `File::create` or
/// `fs::write` elsewhere is how a planted symbolic link got written
/// through (the streamed `trials.csv` of `run --out`).
#[test]
fn output_files_are_created_only_through_e3d_io() {
    fn visit(dir: &Path, found: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                visit(&p, found);
            } else if p.extension().is_some_and(|e| e == "rs") && !p.ends_with("src/io.rs") {
                let text = std::fs::read_to_string(&p).unwrap();
                // a file's own unit tests may write what they like
                let code = text.split("#[cfg(test)]").next().unwrap_or("");
                for (i, line) in code.lines().enumerate() {
                    let l = line.trim_start();
                    if l.starts_with("//") {
                        continue;
                    }
                    if ["File::create", "fs::write(", "OpenOptions::new()"]
                        .iter()
                        .any(|w| l.contains(w))
                    {
                        found.push(format!("{}:{}: {l}", p.display(), i + 1));
                    }
                }
            }
        }
    }
    let mut found = Vec::new();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    visit(&root.join("src"), &mut found);
    visit(&root.join("python/src"), &mut found);
    assert!(
        found.is_empty(),
        "files created outside e3d::io:\n{}",
        found.join("\n")
    );
}

/// `run --out` leaves its folder with exactly its two files: the streamed
/// trials go to an exclusive temporary file that is renamed into place.
#[test]
fn run_out_leaves_only_its_files_and_writes_through_no_planted_link() {
    let dir = fresh_path("cli-run-planted-link");
    std::fs::create_dir_all(&dir).unwrap();
    let victim = dir.with_extension("victim");
    std::fs::write(&victim, "keep me").unwrap();
    // the former fixed temporary names, for the next few process ids
    #[cfg(unix)]
    for pid in 0..4u32 {
        let me = std::process::id() + pid;
        let _ = std::os::unix::fs::symlink(&victim, dir.join(format!(".trials.csv.session0-{me}")));
    }
    let out = e3d(&[
        "run",
        "two_rooms",
        "--trials",
        "200",
        "--out",
        dir.to_str().unwrap(),
        "--force",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
    let trials = std::fs::read_to_string(dir.join("trials.csv")).unwrap();
    assert_eq!(trials.lines().count(), 201, "a header and 200 trials");
    assert!(!std::fs::symlink_metadata(dir.join("trials.csv"))
        .unwrap()
        .file_type()
        .is_symlink());
    // nothing left behind but the two files and the planted links
    let mut left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with(".trials.csv.session0-"))
        .collect();
    left.sort();
    assert_eq!(left, ["summary.json", "trials.csv"]);
    std::fs::remove_dir_all(&dir).unwrap();
    let _ = std::fs::remove_file(&victim);
}

/// `--target`: the default (`all`) is the run of before, byte for byte
/// (its stdout and trials as printed by e3d before the flag existed);
/// `reachable` spreads p* over the 13 cells four_rooms' commands reach,
/// and says so; runs of episodes refuse it.
#[test]
fn run_target_all_is_the_default_and_reachable_shifts_the_target() {
    let dir = crate::common::temp_dir("run-target");
    let run = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "run",
            "four_rooms",
            "--trials",
            "2000",
            "--seed",
            "3",
            "--beta",
            "100",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", out.to_str().unwrap()]);
        let o = crate::common::ok(crate::common::e3d(&args));
        let stdout = String::from_utf8(o.stdout).unwrap();
        let trials = std::fs::read_to_string(out.join("trials.csv")).unwrap();
        let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
        (
            stdout.replace(out.to_str().unwrap(), "OUT"),
            trials,
            summary,
        )
    };
    let plain = run("plain", &[]);
    assert_eq!(
        plain.0,
        "scene four_rooms | learner e3d | 2000 trials | seed 3 | alpha 0.3 beta 100 lambda 0.03 eta 0.01\n\
         normalised entropy 0.6775 (last 1000: 0.6912) | KL to target 1.1556 nats | 13 of 36 effects reached\n\
         over the 13 reachable cells: normalised entropy 0.9466\n\
         coverage 1.0000 of the 13 reachable cells | 50% by trial 11 | 90% by trial 243\n\
         cumulative reward 0 | first reward at trial -\n\
         exact effect distribution of the final policy: normalised entropy 0.4948\n\
         wrote OUT/trials.csv and OUT/summary.json\n"
    );
    // the trials of before: their first and last rows, count and a checksum of the effects
    let rows: Vec<&str> = plain.1.lines().collect();
    assert_eq!(rows.len(), 2001);
    assert_eq!(
        rows[..4],
        [
            "trial,command,effect,reward",
            "1,EWWSS,24,0",
            "2,EWNNS,12,0",
            "3,SENEN,2,0"
        ]
    );
    assert_eq!(rows[2000], "2000,EESEW,14,0");
    let (mut sum, mut h) = (0u64, 0u64);
    for r in &rows[1..] {
        let e: u64 = r.split(',').nth(2).unwrap().parse().unwrap();
        sum += e;
        h = (h * 31 + e) % 1_000_000_007;
    }
    assert_eq!((sum, h), (25305, 935175152));
    assert!(!plain.2.contains("target_reachable_cells"));
    // --target all: the same bytes
    let all = run("all", &["--target", "all"]);
    assert_eq!(all, plain);
    // --target reachable: p* on the 13 reachable cells, another session
    let reach = run("reach", &["--target", "reachable"]);
    assert!(
        reach
            .0
            .contains("target: uniform over the 13 reachable cells (of 36)\n"),
        "{}",
        reach.0
    );
    assert!(reach.0.contains("KL to target 0.0738 nats"), "{}", reach.0);
    assert_ne!(reach.1, plain.1);
    assert!(reach.2.contains("\"target_reachable_cells\": 13"));
    let bad = crate::common::e3d(&[
        "run",
        "four_rooms",
        "--commands",
        "2",
        "--target",
        "reachable",
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr)
        .contains("--target reachable: this run is of episodes"));
}
