//! Output paths and streams under bad input and faults: a sweep's journal streamed,
//! every `scene` subcommand on continuous scenes, control characters in
//! names that become files or text, and a new hostile round. Each test
//! fails on the code before its fix.

use crate::common::{e3d, e3d_command, ok, temp_dir};
use std::path::{Path, PathBuf};
use std::process::Output;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `e3d ARGS` with its address space limited to `bytes` (`ulimit -v`).
#[cfg(unix)]
fn e3d_within(bytes: u64, args: &[&str]) -> Output {
    use std::os::unix::process::CommandExt;
    let mut c = e3d_command();
    c.args(args);
    // SAFETY: setrlimit is async-signal-safe; nothing else runs in the child
    unsafe {
        c.pre_exec(move || {
            let lim = libc::rlimit {
                rlim_cur: bytes as libc::rlim_t,
                rlim_max: bytes as libc::rlim_t,
            };
            if libc::setrlimit(libc::RLIMIT_AS, &lim) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    c.output().unwrap()
}

/// A two-session sweep into `dir`; returns the sweep file.
fn small_sweep(dir: &Path, name: &str) -> PathBuf {
    let f = dir.join(name);
    std::fs::write(
        &f,
        r#"Sweep(scenes: ["two_rooms"], learners: [uniform], use_reward: [true],
        sessions: 2, trials: 50, seed: 1, metrics: [normalized_entropy])"#,
    )
    .unwrap();
    f
}

// ---- a sweep's journal is streamed ------------------------------------------

/// A journal whose tail is 3.9 GiB of zeros (a sparse file: what a crash
/// can leave, or a hostile edit) is read a line at a time: `--resume`
/// within 1.5 GiB of address space drops the tail and completes the sweep
/// to the same bytes. It was read whole (an allocation of 3.9 GiB, an
/// abort).
#[cfg(unix)]
#[test]
fn a_journal_is_streamed_in_bounded_memory() {
    let d = temp_dir("round4-journal-stream");
    let f = small_sweep(&d, "s.ron");
    let out = d.join("out");
    let (f, o) = (f.to_str().unwrap(), out.to_str().unwrap());
    ok(e3d(&["sweep", f, "--out", o, "--threads", "1"]));
    let results = std::fs::read(out.join("results.csv")).unwrap();
    let j = out.join("journal.txt");
    let whole = std::fs::read(&j).unwrap();
    std::fs::remove_file(out.join("results.csv")).unwrap();
    std::fs::remove_file(out.join("summary.csv")).unwrap();
    let file = std::fs::OpenOptions::new().write(true).open(&j).unwrap();
    file.set_len(3_900_000_000).unwrap();
    drop(file);
    let r = e3d_within(
        3 << 29,
        &["sweep", f, "--out", o, "--resume", "--threads", "1"],
    );
    assert!(r.status.success(), "{}: {}", r.status, stderr(&r));
    assert_eq!(std::fs::read(out.join("results.csv")).unwrap(), results);
    // the zeros were cut off: the journal is what the first run wrote
    assert_eq!(std::fs::read(&j).unwrap(), whole);
}

// ---- every `scene` subcommand on continuous scenes --------------------------

/// The invocations of each `scene` subcommand tried on a continuous scene
/// (`OUT` is replaced by a file in a fresh folder; a command of 7 values
/// fits arm7_continuous, other scenes refuse it with a message).
const SCENE_INVOCATIONS: &[(&str, &[&str])] = &[
    ("check", &[]),
    ("check", &["--samples", "0"]),
    (
        "check",
        &["--samples", "3", "--seed", "18446744073709551615"],
    ),
    ("check", &["--expanded"]),
    ("render", &["--out", "OUT.svg"]),
    (
        "render",
        &["--out", "OUT.svg", "--command", "0,0,0,0,0,0,0"],
    ),
    ("render", &["--out", "OUT.svg", "--command", "+-0+-0+"]),
    (
        "render",
        &[
            "--out",
            "OUT.html",
            "--animate",
            "--command",
            "-1.8,1.2,0,0,0,0,0.06",
        ],
    ),
    (
        "render",
        &[
            "--out",
            "OUT.svg",
            "--animate",
            "--command",
            "1e-320,0,0,0,0,0,-0",
        ],
    ),
    (
        "exec",
        &["0,0,0,0,0,0,0", "1.8,-1.2,0.75,0.45,0.24,0.12,-0.06"],
    ),
    ("exec", &["--trace", "OUT.csv", "0.5,0,0,0,0,0,0"]),
    ("exec", &["--table-cache", "OUT", "0,0,0,0,0,0,0"]),
    ("exec", &["nan,0,0,0,0,0,0"]),
    ("exec", &["inf,0,0,0,0,0,0"]),
    ("exec", &["9,0,0,0,0,0,0"]),
    ("exec", &["0,0,0"]),
    ("exec", &["1.8,,0,0,0,0,0"]),
    ("exec", &["+-0+-0+"]),
    ("exec", &["-"]),
    ("reward-cell", &[]),
    ("reward-cell", &["--from", "0,0"]),
    ("table", &[]),
    ("table", &["--cache", "OUT"]),
    ("stats", &[]),
    ("export", &["--mjcf"]),
    ("export", &["--mjcf", "--out", "OUT.xml"]),
    ("import", &[]),
];

/// The subcommands `e3d scene --help` lists (but `help`).
fn scene_subcommands() -> Vec<String> {
    let help = String::from_utf8(ok(e3d(&["scene", "--help"])).stdout).unwrap();
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(String::from)
        .collect()
}

/// Runs every invocation of [`SCENE_INVOCATIONS`] on `scene`, standard
/// input holding two good commands and a bad one; returns, for each, the
/// exit code and standard error. Fails on a panic or a signal.
fn run_every_scene_subcommand(scene: &Path, dir: &Path) -> Vec<(String, Option<i32>, String)> {
    let mut seen = Vec::new();
    for (k, (sub, args)) in SCENE_INVOCATIONS.iter().enumerate() {
        let out = dir.join(format!("out{k}"));
        let args: Vec<String> = args
            .iter()
            .map(|a| a.replace("OUT", out.to_str().unwrap()))
            .collect();
        let mut c = e3d_command();
        c.arg("scene").arg(sub).arg(scene).args(&args);
        c.stdin(std::process::Stdio::piped());
        c.stdout(std::process::Stdio::piped());
        c.stderr(std::process::Stdio::piped());
        let mut child = c.spawn().unwrap();
        {
            use std::io::Write;
            let mut stdin = child.stdin.take().unwrap();
            let _ = stdin.write_all(b"0,0,0,0,0,0,0\n\n-1.8,0,0,0,0,0,0\n1,2\n");
        }
        let o = child.wait_with_output().unwrap();
        let what = format!("e3d scene {sub} {} {}", scene.display(), args.join(" "));
        let err = stderr(&o);
        assert!(
            o.status.code().is_some() && o.status.code() != Some(101) && !err.contains("panicked"),
            "{what}: {}\n{err}",
            o.status
        );
        if !o.status.success() {
            assert_eq!(o.status.code(), Some(2), "{what}:\n{err}");
            let last = err.lines().last().unwrap_or("");
            assert!(
                last.starts_with("error: ") && last.len() > 40,
                "{what}: not a clear error:\n{err}"
            );
        }
        seen.push((what, o.status.code(), err));
    }
    seen
}

/// Every `scene` subcommand on every continuous scene of `scenes/`, and on
/// every bad continuous scene of `tests/bad_inputs/continuous`: no panic
/// (exit code 101, "panicked"), no signal, and where refused, exit code 2
/// with an `error:` line. The bad scenes are refused with their file,
/// line and column; the valid scene's refusals say why (`Continuous`).
#[test]
fn every_scene_subcommand_on_continuous_scenes_ends_cleanly() {
    let listed = scene_subcommands();
    for sub in &listed {
        assert!(
            SCENE_INVOCATIONS.iter().any(|(s, _)| s == sub),
            "`e3d scene {sub}` is not tried on continuous scenes: add it to SCENE_INVOCATIONS"
        );
    }
    assert!(listed.len() >= 6, "{listed:?}");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let d = temp_dir("round4-continuous-subcommands");
    let mut good = Vec::new();
    for e in std::fs::read_dir(root.join("scenes")).unwrap() {
        let p = e.unwrap().path();
        let is_continuous = p.extension().is_some_and(|x| x == "ron")
            && std::fs::read_to_string(&p).unwrap().contains("Continuous(");
        if is_continuous {
            good.push(p);
        }
    }
    good.sort();
    assert!(!good.is_empty());
    for scene in &good {
        let seen = run_every_scene_subcommand(scene, &d);
        let ran = seen.iter().filter(|s| s.1 == Some(0)).count();
        assert!(
            ran >= 8,
            "{}: only {ran} invocations succeeded",
            scene.display()
        );
        for (what, code, err) in &seen {
            let enumerates = ["reward-cell", "table", "stats", "--table-cache"]
                .iter()
                .any(|w| what.contains(w));
            if enumerates {
                assert_eq!(*code, Some(2), "{what}");
                assert!(err.contains("`Continuous`"), "{what}: {err}");
            }
        }
    }
    let mut bad: Vec<PathBuf> = std::fs::read_dir(root.join("tests/bad_inputs/continuous"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    bad.sort();
    assert!(bad.len() >= 6);
    for scene in &bad {
        let name = scene.file_name().unwrap().to_str().unwrap().to_string();
        for (what, code, err) in run_every_scene_subcommand(scene, &d) {
            assert_eq!(code, Some(2), "{what}");
            assert!(err.contains(&format!("{name}:")), "{what}: {err}");
        }
    }
}

// ---- a new hostile round ----------------------------------------------------

/// A valid scene with a 1024 x 1024 effect grid (2^20 cells, the most a
/// scene may have): a 100-trial run's report draws its reached cells over
/// one background, not a rectangle per cell: the page holds little more
/// than the summary.json it shows (9.5 MB; it held 396 MB, and took 21 s
/// and 820 MB of memory).
#[test]
fn a_report_on_a_million_cell_grid_draws_only_the_reached_cells() {
    let d = temp_dir("round4-million-cells");
    let text =
        String::from_utf8(ok(e3d(&["scene", "check", "puck_rooms", "--expanded"])).stdout).unwrap();
    let at = text.find("grid: (").unwrap();
    let end = at + text[at..].find("min:").unwrap();
    let grid = text[at..end]
        .lines()
        .map(|l| {
            if l.trim_start().starts_with("rows:") {
                "rows: 1024,"
            } else if l.trim_start().starts_with("cols:") {
                "cols: 1024,"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let scene = d.join("big_grid.ron");
    std::fs::write(&scene, format!("{}{grid}{}", &text[..at], &text[end..])).unwrap();
    let out = d.join("run");
    let (s, o) = (scene.to_str().unwrap(), out.to_str().unwrap());
    ok(e3d(&[
        "run", s, "--trials", "100", "--seed", "3", "--out", o,
    ]));
    ok(e3d(&["report", o]));
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    // the page holds summary.json (5 bytes an effect count) and little else
    let summary = std::fs::metadata(out.join("summary.json")).unwrap().len() as usize;
    assert!(
        page.len() < summary + 1_000_000,
        "{} bytes, summary.json {summary}",
        page.len()
    );
    assert!(page.contains("1048576 cells; those never reached are not drawn one by one"));
    // each heat map draws the cells reached, at most one per trial
    let cells = page.matches(r#"<rect class="cell""#).count();
    let maps = page.matches("1048576 cells;").count();
    assert!(
        maps >= 1 && cells >= maps && cells <= 100 * maps,
        "{cells} cells, {maps} maps"
    );
}

/// A command refused after it prepared its `--out` folder leaves no
/// empty folder behind (`compare` with an unknown scene, `run` with a
/// learner that does not fit the scene left one); a folder that existed
/// before is kept.
#[test]
fn a_refused_command_leaves_no_out_folder_it_created() {
    let d = temp_dir("round4-out-folders");
    let fresh = d.join("a/b/c");
    let f = fresh.to_str().unwrap();
    for args in [
        vec!["compare", "--scenes", "nope", "--out", f],
        vec![
            "run",
            "arm7_continuous",
            "--learner",
            "count",
            "--trials",
            "5",
            "--out",
            f,
        ],
    ] {
        let o = e3d(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            !d.join("a").exists(),
            "{args:?} left {}",
            d.join("a").display()
        );
    }
    let kept = d.join("kept");
    std::fs::create_dir(&kept).unwrap();
    let o = e3d(&[
        "compare",
        "--scenes",
        "nope",
        "--out",
        kept.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(kept.is_dir());
}

#[test]
fn an_output_named_for_a_format_not_written_is_refused_before_any_work() {
    let dir = temp_dir("output_formats");
    let at = |f: &str| dir.join(f).to_string_lossy().into_owned();
    let sweep_out = dir.join("no-such-run");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "scene".into(),
                "render".into(),
                "two_rooms".into(),
                "--out".into(),
                at("s.png"),
            ],
            "--out ",
        ),
        (
            vec![
                "scene".into(),
                "render".into(),
                "two_rooms".into(),
                "--command".into(),
                "EEEEEEE".into(),
                "--animate".into(),
                "--out".into(),
                at("a.gif"),
            ],
            "expected a file ending in .svg or .html or .htm",
        ),
        (
            vec![
                "scene".into(),
                "render".into(),
                "arm7_continuous".into(),
                "--out".into(),
                at("c"),
            ],
            "found no extension",
        ),
        (
            vec![
                "scene".into(),
                "exec".into(),
                "puck_rooms".into(),
                "--trace".into(),
                at("t.txt"),
                "EEEEEEE".into(),
            ],
            "--trace ",
        ),
        (
            vec![
                "report".into(),
                sweep_out.to_string_lossy().into_owned(),
                "--out".into(),
                at("r.svg"),
            ],
            "expected a file ending in .html or .htm",
        ),
        (
            vec![
                "plot".into(),
                sweep_out.to_string_lossy().into_owned(),
                "--x".into(),
                "beta".into(),
                "--metric".into(),
                "normalized_entropy".into(),
                "--out".into(),
                at("p.png"),
            ],
            "expected a file ending in .svg",
        ),
    ];
    for (args, says) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = e3d(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(says) && err.contains("(the format written)"),
            "{args:?}: {err}"
        );
    }
    // nothing was written, and the formats written are accepted in any case
    assert_eq!(std::fs::read_dir(&*dir).unwrap().count(), 0);
    let svg = at("S.SVG");
    ok(e3d(&["scene", "render", "two_rooms", "--out", &svg]));
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
}

#[test]
fn a_stream_output_is_written_through_whatever_its_name() {
    // `--out /dev/stdout`: the picture on standard output, no format refused
    let o = ok(e3d(&[
        "scene",
        "render",
        "two_rooms",
        "--out",
        "/dev/stdout",
    ]));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.starts_with("<svg") && out.contains("</svg>"), "{out}");
    let o = ok(e3d(&[
        "scene",
        "exec",
        "puck_rooms",
        "--trace",
        "/dev/stdout",
        "EEEEEEE",
    ]));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.starts_with("command,step,time,"),
        "{}",
        &out[..80.min(out.len())]
    );
    assert!(
        out.contains("EEEEEEE,2,0,"),
        "the outcome line follows the trace"
    );
}

#[test]
fn a_cache_folder_that_is_a_file_is_refused_before_any_work() {
    let dir = temp_dir("cache_is_a_file");
    let f = dir.join("afile");
    std::fs::write(&f, "x").unwrap();
    let f = f.to_string_lossy().into_owned();
    let sweep = small_sweep(&dir, "s.ron");
    let sweep = sweep.to_string_lossy().into_owned();
    let out = dir.join("out").to_string_lossy().into_owned();
    for args in [
        vec!["scene", "table", "puck_rooms", "--cache", &f],
        vec![
            "scene",
            "exec",
            "puck_rooms",
            "--table-cache",
            &f,
            "EEEEEEE",
        ],
        vec!["run", "puck_rooms", "--trials", "20", "--table-cache", &f],
        vec!["sweep", &sweep, "--out", &out, "--table-cache", &f],
    ] {
        let o = e3d(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(3), "{args:?}: {err}");
        assert!(
            err.contains("exists and is not a folder"),
            "{args:?}: {err}"
        );
    }
    assert_eq!(std::fs::read_to_string(&f).unwrap(), "x");
    assert!(!dir.join("out").exists(), "the sweep made no folder");
}

/// Every command that writes into a folder claims it, as a sweep does:
/// while another process holds the folder's lock, `run`, `reproduce`,
/// `compare`, `closed-loop`, `plot`, `merge` and `report` are refused
/// before any work,
/// naming the folder and the process that holds it, and write nothing;
/// once it is released, each runs and leaves no lock file behind.
#[cfg(unix)]
#[test]
fn every_command_refuses_a_folder_another_process_writes_into() {
    let d = temp_dir("locked-out");
    let sweep = d.join("s.ron");
    std::fs::write(
        &sweep,
        r#"Sweep(scenes: ["two_rooms"], learners: [e3d], params: (beta: [1, 10]),
        sessions: 1, trials: 20, metrics: [normalized_entropy])"#,
    )
    .unwrap();
    let results = d.join("sweep");
    ok(e3d(&[
        "sweep",
        sweep.to_str().unwrap(),
        "--out",
        results.to_str().unwrap(),
    ]));
    let out = d.join("out");
    let o = out.to_str().unwrap();
    let plot = out.join("p.svg");
    let r = results.to_str().unwrap();
    let page = out.join("r.html");
    let commands: [Vec<&str>; 7] = [
        vec!["run", "two_rooms", "--trials", "20", "--out", o],
        vec!["reproduce", "--sessions", "1", "--trials", "20", "--out", o],
        vec!["compare", "--sessions", "1", "--trials", "20", "--out", o],
        vec![
            "closed-loop",
            "--episodes",
            "20",
            "--seeds",
            "1",
            "--out",
            o,
        ],
        vec![
            "plot",
            r,
            "--x",
            "beta",
            "--metric",
            "normalized_entropy",
            "--out",
            plot.to_str().unwrap(),
        ],
        vec!["merge", r, "--out", o],
        vec!["report", r, "--out", page.to_str().unwrap()],
    ];
    for args in &commands {
        std::fs::create_dir_all(&out).unwrap();
        {
            let _held = e3d::io::DirLock::acquire(&out).unwrap();
            let refused = e3d(args);
            let err = stderr(&refused);
            assert_eq!(refused.status.code(), Some(3), "{args:?}: {err}");
            let me = format!(
                "{}: in use by e3d pid={} host=",
                out.display(),
                std::process::id()
            );
            assert!(err.contains(&me), "{args:?}: {err}");
            let names: Vec<_> = std::fs::read_dir(&out)
                .unwrap()
                .map(|e| e.unwrap().file_name())
                .collect();
            assert_eq!(names, [".lock"], "{args:?} wrote into a locked folder");
        }
        ok(e3d(args));
        assert!(!out.join(".lock").exists(), "{args:?} left its lock");
        std::fs::remove_dir_all(&out).unwrap();
    }
}

/// Episodes are streamed: a run of ten million episodes with start
/// contexts keeps its figures, not its episodes, and finishes within
/// 256 MiB of address space (it held every episode: an abort), and its
/// trials.csv is written as the episodes run, the same bytes as before.
#[cfg(unix)]
#[test]
fn episodes_run_in_bounded_memory() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/two_rooms_contexts.ron");
    let big = e3d_within(256 << 20, &["run", scene, "--trials", "10000000"]);
    assert_eq!(big.status.code(), Some(0), "{}", stderr(&big));
    let out = String::from_utf8_lossy(&big.stdout);
    assert!(
        out.contains("seed 0: first reward at episode never, cumulative reward 0, normalised entropy of the terminal cells per start context: room_a 0.99"),
        "{out}"
    );
    // the streamed file: a header, then a row per command
    let d = temp_dir("episodes-streamed");
    let o = d.join("out");
    ok(e3d(&[
        "run",
        scene,
        "--trials",
        "500",
        "--sessions",
        "2",
        "--commands",
        "2",
        "--out",
        o.to_str().unwrap(),
    ]));
    let csv = std::fs::read_to_string(o.join("trials.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "session,episode,command,context,start,symbols,effect,reward"
    );
    assert_eq!(lines.len(), 1 + 2 * 500 * 2);
    assert!(lines[1].starts_with("0,1,1,"), "{}", lines[1]);
    assert!(lines[2].starts_with("0,1,2,"), "{}", lines[2]);
    assert!(lines[2000].starts_with("1,500,2,"), "{}", lines[2000]);
}
