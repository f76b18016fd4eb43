//! `e3d scene exec` under a scene's `noise`: `--repeat` and its shares,
//! the same bytes whatever the threads, and the refusals of tables.

use crate::common::{e3d, e3d_command, ok, temp_path};
use e3d::Scene;

const NOISY: &str = "tests/scenes/puck_noisy.ron";

/// `count` commands of puck_rooms spread over its space.
fn commands(count: u64) -> Vec<String> {
    let space = Scene::builtin("puck_rooms").unwrap().command_space();
    (0..count)
        .map(|k| space.format(&space.command_at(k * 7919 % 16384)))
        .collect()
}

/// `e3d scene exec SCENE ARGS COMMANDS` on `threads` threads: its stdout.
fn exec(scene: &str, args: &[&str], cmds: &[String], threads: usize) -> String {
    let out = e3d_command()
        .env("RAYON_NUM_THREADS", threads.to_string())
        .args(["scene", "exec", scene])
        .args(args)
        .args(cmds)
        .output()
        .unwrap();
    String::from_utf8(ok(out).stdout).unwrap()
}

/// The rows of a `--repeat` output: (command, effect, share, runs).
fn shares(text: &str) -> Vec<(String, usize, f64, u32)> {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("command,effect,share,runs"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[0].to_string(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
            )
        })
        .collect()
}

#[test]
fn repeat_on_a_noise_free_scene_keeps_every_effect() {
    let cmds = commands(12);
    let rows = shares(&exec("puck_rooms", &["--repeat", "5"], &cmds, 2));
    let plain = exec("puck_rooms", &[], &cmds, 2);
    assert_eq!(rows.len(), cmds.len());
    for (row, line) in rows.iter().zip(plain.lines().skip(1)) {
        assert_eq!((row.2, row.3), (1.0, 5), "{row:?}");
        let effect: usize = line.split(',').nth(1).unwrap().parse().unwrap();
        assert_eq!(row.1, effect, "{row:?}");
    }
}

#[test]
fn repeat_on_a_noisy_scene_is_seeded_and_thread_free() {
    let cmds = commands(40);
    let args = ["--repeat", "12", "--seed", "3"];
    let one = exec(NOISY, &args, &cmds, 1);
    assert_eq!(exec(NOISY, &args, &cmds, 2), one);
    let rows = shares(&one);
    assert_eq!(rows.len(), 40);
    assert!(rows.iter().all(|r| r.3 == 12 && r.2 > 0.0 && r.2 <= 1.0));
    assert!(
        rows.iter().any(|r| r.2 < 1.0),
        "no command changed effect:\n{one}"
    );
    // another seed, other draws
    let other = exec(NOISY, &["--repeat", "12", "--seed", "4"], &cmds, 2);
    assert_ne!(other, one);
    // one run per command: the same bytes on 1 and 2 threads, and each
    // row the first run of --repeat (keyed by the seed, run 0, index)
    let single = exec(NOISY, &["--seed", "3"], &cmds, 1);
    assert_eq!(exec(NOISY, &["--seed", "3"], &cmds, 2), single);
    let trace = temp_path("noise-trace").with_extension("csv");
    let traced = exec(
        NOISY,
        &["--seed", "3", "--trace", trace.to_str().unwrap()],
        &cmds[..3],
        1,
    );
    let _ = std::fs::remove_file(&trace);
    let head: Vec<&str> = single.lines().take(4).collect();
    assert_eq!(traced.lines().collect::<Vec<_>>(), head);
    assert_ne!(single, exec("puck_rooms", &[], &cmds, 1));
}

#[test]
fn a_noisy_scene_refuses_table_caches_naming_its_noise() {
    let dir = temp_path("noise-cache");
    let dir = dir.to_str().unwrap();
    let cmd = commands(1);
    for args in [
        vec!["scene", "exec", NOISY, "--table-cache", dir, &cmd[0]],
        vec!["scene", "table", NOISY],
        vec!["run", NOISY, "--trials", "10", "--outcomes", "table"],
        vec!["run", NOISY, "--trials", "10", "--table-cache", dir],
    ] {
        let out = e3d(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(
            err.contains("scene `puck_noisy` has a `noise` section"),
            "{args:?}: {err}"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// A sweep over the noisy scene: the same bytes on 1 and 2 threads, and
/// from two shards merged.
#[test]
fn a_noisy_sweep_gives_the_same_bytes_on_threads_and_shards() {
    use crate::sweep::{assert_same_files, FINAL_FILES};
    let d = crate::common::temp_dir("noise-sweep");
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(NOISY);
    let text = format!(
        r#"Sweep(
    scenes: ["{}"],
    learners: [e3d, uniform],
    params: (beta: [1, 100]),
    sessions: 3,
    trials: 60,
    seed: 11,
    metrics: [normalized_entropy, distinct_effects],
)
"#,
        scene.display()
    );
    let file = d.join("noisy.ron");
    std::fs::write(&file, text).unwrap();
    let f = file.to_str().unwrap();
    let run = |name: &str, extra: &[&str]| {
        let out = d.join(name);
        let mut args = vec!["sweep", f];
        args.extend_from_slice(extra);
        args.extend(["--out", out.to_str().unwrap()]);
        ok(e3d(&args));
        out
    };
    let one = run("one", &["--threads", "1"]);
    let two = run("two", &["--threads", "2"]);
    assert_same_files(&one, &two, &FINAL_FILES);
    let s1 = run("s1", &["--threads", "1", "--shard", "1/2"]);
    let s2 = run("s2", &["--threads", "2", "--shard", "2/2"]);
    let merged = d.join("merged");
    ok(e3d(&[
        "merge",
        s2.to_str().unwrap(),
        s1.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]));
    assert_same_files(&one, &merged, &FINAL_FILES);
}

/// `e3d run NOISY ARGS --out DIR` on `threads` threads: its stdout and its
/// summary.json.
fn run_noisy(
    scene: &str,
    args: &[&str],
    threads: usize,
    dir: &std::path::Path,
) -> (String, String) {
    let out = e3d_command()
        .args(["run", scene, "--trials", "40", "--seed", "5", "--threads"])
        .arg(threads.to_string())
        .args(args)
        .arg("--out")
        .arg(dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8(ok(out).stdout).unwrap();
    (
        stdout,
        std::fs::read_to_string(dir.join("summary.json")).unwrap(),
    )
}

/// [`run_noisy`] on 1 and on 2 threads (in `dir`'s `one` and `two`):
/// asserts that the printed lines (all but the folder written) and the
/// sessions of summary.json are the same, and returns the printed text
/// and those sessions.
fn run_noisy_on_1_and_2_threads(
    scene: &str,
    args: &[&str],
    dir: &std::path::Path,
) -> (String, serde_json::Value) {
    let (out1, sum1) = run_noisy(scene, args, 1, &dir.join("one"));
    let (out2, sum2) = run_noisy(scene, args, 2, &dir.join("two"));
    let kept = |out: &str| -> Vec<String> {
        let lines = out.lines().filter(|l| !l.starts_with("wrote "));
        lines.map(str::to_string).collect()
    };
    assert_eq!(kept(&out1), kept(&out2));
    let sessions =
        |sum: &str| serde_json::from_str::<serde_json::Value>(sum).unwrap()["sessions"].clone();
    assert_eq!(sessions(&sum1), sessions(&sum2));
    (out1, sessions(&sum1))
}

#[test]
fn run_reports_the_reproducibility_on_a_noisy_scene_the_same_on_1_and_2_threads() {
    let d = crate::common::temp_dir("noise-run-repro");
    let args = ["--sessions", "2", "--repeat", "4"];
    let (out1, sessions) = run_noisy_on_1_and_2_threads(NOISY, &args, &d);
    let lines: Vec<&str> = out1
        .lines()
        .filter(|l| l.contains("reproducibility"))
        .collect();
    assert_eq!(lines.len(), 2, "{out1}");
    assert!(lines[0].starts_with("seed 5: reproducibility 0."), "{out1}");
    assert!(
        lines[0].contains("of 64 commands drawn from the final policy"),
        "{out1}"
    );
    assert!(lines[0].contains("90% of 4 noisy runs"), "{out1}");
    for s in sessions.as_array().unwrap() {
        let r = &s["reproducibility"];
        assert_eq!(
            (r["commands"].as_u64(), r["runs"].as_u64()),
            (Some(64), Some(4))
        );
        let share = r["share"].as_f64().unwrap();
        assert!(share > 0.0 && share <= 1.0, "{share}");
        // the share of 64 commands
        assert_eq!((share * 64.0).round() / 64.0, share);
    }
    // --repeat 0 and a noise-free scene: no line, no field
    for (scene, args) in [
        (NOISY, ["--repeat", "0"]),
        ("puck_rooms", ["--repeat", "4"]),
    ] {
        let (out, sum) = run_noisy(scene, &args, 2, &d.join(format!("none-{}", args[1])));
        assert!(!out.contains("reproducibility"), "{out}");
        assert!(!sum.contains("reproducibility"), "{sum}");
    }
}

#[test]
fn scene_exec_repeat_gives_the_library_reevaluation() {
    use e3d::session::reevaluate;
    let scene = Scene::load(NOISY).unwrap();
    let cmds = commands(5);
    let rows = shares(&exec(NOISY, &["--repeat", "7", "--seed", "3"], &cmds, 2));
    let space = scene.command_space();
    let parsed: Vec<e3d::Command> = cmds.iter().map(|c| space.parse(c).unwrap()).collect();
    let lib = reevaluate(&mut *scene.build(), &parsed, 7, 3).unwrap();
    for (row, r) in rows.iter().zip(&lib) {
        assert_eq!(
            (row.1, row.2, row.3),
            (r.effect, (r.share() * 1e4).round() / 1e4, 7)
        );
    }
    assert_eq!(rows.len(), 5);
}

#[test]
fn a_sweep_reports_the_reproducibility_the_same_on_1_and_2_threads() {
    let d = crate::common::temp_dir("noise-sweep-repro");
    let text = |scene: &std::path::Path| {
        format!(
            "Sweep(scenes: [{:?}], learners: [uniform], sessions: 2, trials: 10, seed: 4, metrics: [distinct_effects, reproducibility])",
            scene.display()
        )
    };
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut values = Vec::new();
    for (name, scene) in [
        ("noisy", root.join(NOISY)),
        ("plain", root.join("scenes/puck_rooms.ron")),
    ] {
        let file = d.join(format!("{name}.ron"));
        std::fs::write(&file, text(&scene)).unwrap();
        let mut outs = Vec::new();
        for threads in ["1", "2"] {
            let out = d.join(format!("{name}-{threads}"));
            let f = file.to_str().unwrap();
            ok(e3d(&[
                "sweep",
                f,
                "--threads",
                threads,
                "--out",
                out.to_str().unwrap(),
            ]));
            outs.push(std::fs::read_to_string(out.join("results.csv")).unwrap());
        }
        assert_eq!(outs[0], outs[1]);
        let mut lines = outs[0].lines();
        assert!(lines
            .next()
            .unwrap()
            .ends_with(",distinct_effects,reproducibility,failure"));
        let col = |l: &str| -> f64 { l.split(',').rev().nth(1).unwrap().parse().unwrap() };
        values.push(lines.map(col).collect::<Vec<f64>>());
    }
    // a noise-free scene: every command keeps its effect
    assert_eq!(values[1], [1.0, 1.0]);
    assert!(values[0].iter().all(|&v| v > 0.0 && v < 1.0), "{values:?}");
}

#[test]
fn scene_check_lists_the_noise_section() {
    let out = ok(e3d(&["scene", "check", NOISY, "--samples", "0"]));
    let text = String::from_utf8(out.stdout).unwrap();
    let at = text
        .find("noise (drawn anew at every execution")
        .expect(&text);
    let lines: Vec<&str> = text[at..].lines().skip(1).take(2).collect();
    assert_eq!(
        lines,
        [
            "  actions: each slot's action times 1 + N(0, 0.05) cut at 3 sd",
            "  start of body `puck`: x and y (m) + N(0, 0.02) cut at 3 sd",
        ]
    );
    // a noise-free scene lists none
    let plain =
        String::from_utf8(ok(e3d(&["scene", "check", "puck_rooms", "--samples", "0"])).stdout)
            .unwrap();
    assert!(!plain.contains("noise"), "{plain}");
}

/// `path`'s scene with `noise` as its noise section, written into `dir`.
fn with_noise(path: &str, noise: &str, dir: &std::path::Path) -> String {
    let text = std::fs::read_to_string(path).unwrap().replace(
        "effect: (body: \"puck\"",
        &format!("noise: {noise},\n        effect: (body: \"puck\""),
    );
    let name = std::path::Path::new(path).file_name().unwrap();
    let out = dir.join(name);
    std::fs::write(&out, text).unwrap();
    out.to_str().unwrap().to_string()
}

#[test]
fn repeat_on_a_noisy_continuous_scene_is_seeded_and_thread_free() {
    let d = crate::common::temp_dir("noise-values");
    let noise =
        r#"(actions: Gaussian(sd: 0.15), starts: [(body: "puck", position: Gaussian(sd: 0.1))])"#;
    let scene = with_noise("tests/scenes/puck_headings.ron", noise, &d);
    let values: Vec<String> = (0..12)
        .map(|k| {
            let a = -3.0 + 0.5 * k as f64;
            format!("{a}, {}, 0.5", -a / 2.0)
        })
        .collect();
    let args = ["--repeat", "10", "--seed", "2"];
    let one = exec(&scene, &args, &values, 1);
    assert_eq!(exec(&scene, &args, &values, 2), one);
    let mut lines = one.lines();
    assert_eq!(lines.next(), Some("values,effect,share,runs"));
    let shares: Vec<f64> = lines
        .map(|l| l.rsplit(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(shares.len(), 12);
    assert!(shares.iter().all(|&s| s > 0.0 && s <= 1.0), "{one}");
    assert!(shares.iter().any(|&s| s < 1.0), "{one}");
    assert_ne!(
        exec(&scene, &["--repeat", "10", "--seed", "3"], &values, 1),
        one
    );
    // one run per command: keyed by the seed and the index, the first run
    // of --repeat, whatever the threads
    let single = exec(&scene, &["--seed", "2"], &values, 1);
    assert_eq!(exec(&scene, &["--seed", "2"], &values, 2), single);
    assert_ne!(exec(&scene, &["--seed", "3"], &values, 1), single);
    // a noise-free scene: share 1
    let plain = exec("tests/scenes/puck_headings.ron", &args, &values, 2);
    assert!(
        plain.lines().skip(1).all(|l| l.ends_with(",1.0000,10")),
        "{plain}"
    );
}

#[test]
fn run_on_a_noisy_continuous_scene_reports_the_reproducibility() {
    let d = crate::common::temp_dir("noise-run-values");
    let noise = r#"(actions: Gaussian(sd: 0.15))"#;
    let scene = with_noise("tests/scenes/puck_headings.ron", noise, &d);
    let args = ["--sessions", "2", "--repeat", "4"];
    let (out1, sessions) = run_noisy_on_1_and_2_threads(&scene, &args, &d);
    let lines: Vec<&str> = (out1.lines())
        .filter(|l| l.contains("reproducibility"))
        .collect();
    assert_eq!(lines.len(), 2, "{out1}");
    assert!(lines[1].starts_with("seed 6: reproducibility "), "{out1}");
    for s in sessions.as_array().unwrap() {
        let share = s["reproducibility"]["share"].as_f64().unwrap();
        assert!(share > 0.0 && share <= 1.0, "{share}");
        assert_eq!((share * 64.0).round() / 64.0, share);
    }
}

#[test]
fn episodes_run_under_noise_the_same_on_1_and_2_threads() {
    let d = crate::common::temp_dir("noise-episodes");
    let noise = r#"(actions: Gaussian(sd: 0.1), starts: [(body: "puck", position: Gaussian(sd: 0.05))], body_numbers: [(body: "puck", per: Session, linear_damping: Uniform(half_width: 0.3))])"#;
    let scene = with_noise("scenes/puck_contexts.ron", noise, &d);
    let args = ["--sessions", "2", "--repeat", "3", "--commands", "2"];
    let (out1, sum1) = run_noisy(&scene, &args, 1, &d.join("one"));
    let (out2, sum2) = run_noisy(&scene, &args, 2, &d.join("two"));
    let kept = |out: &str| -> Vec<String> {
        let lines = out.lines().filter(|l| !l.starts_with("wrote "));
        lines.map(str::to_string).collect()
    };
    assert_eq!(kept(&out1), kept(&out2));
    assert_eq!(sum1, sum2);
    let trials = |dir: &std::path::Path| std::fs::read(dir.join("trials.csv")).unwrap();
    assert_eq!(trials(&d.join("one")), trials(&d.join("two")));
    let lines: Vec<&str> = (out1.lines())
        .filter(|l| l.contains("reproducibility"))
        .collect();
    assert_eq!(lines.len(), 2, "{out1}");
    assert!(
        lines[0].contains("of 64 episodes drawn from the final policy"),
        "{out1}"
    );
    // the noise-free scene's episodes differ
    let (plain, _) = run_noisy("scenes/puck_contexts.ron", &args, 2, &d.join("plain"));
    assert_ne!(kept(&plain), kept(&out1));
    assert!(!plain.contains("reproducibility"), "{plain}");
    // a table cache is refused, naming the noise
    let out = e3d_command()
        .args(["run", &scene, "--trials", "10", "--table-cache"])
        .arg(d.join("tables"))
        .output()
        .unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(!out.status.success());
    assert!(err.contains("has a `noise` section"), "{err}");
}
