//! Bad input and faults, round 4 of issue 48: names, counts a file
//! declares, per-context work, FIFOs, thread caps and messages that name
//! what the user wrote. Each test fails on the code before its fix.

use crate::common::{e3d, e3d_command, grid_with_contexts, ok, temp_dir};
use std::path::Path;
use std::process::Output;
use std::time::{Duration, Instant};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The exit code, which must be `code`, and standard error.
fn refused(o: Output, code: i32) -> String {
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(code), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    e
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// `e3d ARGS`, killed after `secs` seconds (then the test fails: it
/// blocked).
fn e3d_within_secs(secs: u64, args: &[&str]) -> Output {
    let mut child = e3d_command()
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("e3d {args:?} still ran after {secs} s: it blocked");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

#[cfg(unix)]
fn mkfifo(p: &Path) {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(p.as_os_str().as_bytes()).unwrap();
    // SAFETY: a valid C string
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
}

// ---- names ------------------------------------------------------------------

/// A start context's name passes the one name check: a `,` (which went raw
/// into trials.csv, so that `e3d report` refused e3d's own folder), a line
/// feed, ESC and a right-to-left override are refused with the file, the
/// place and the code point.
#[test]
fn context_names_pass_the_name_check() {
    let d = temp_dir("faults-context-names");
    for (bad, code) in [
        ("a,b", "U+002C"),
        ("a\nb", "U+000A"),
        ("a\u{1b}[31m", "U+001B"),
        ("a\u{7}", "U+0007"),
        ("evil\u{202e}txt", "U+202E"),
    ] {
        let scene = grid_with_contexts(&format!(
            r#"(name: "{bad}", cell: (0, 0)), (name: "b", cell: (2, 5))"#
        ));
        let f = write(&d, "names.ron", &scene);
        let e = refused(e3d(&["scene", "check", &f]), 2);
        assert!(e.contains(&format!("{f}:")), "{e}");
        assert!(e.contains("name") && e.contains(code), "{bad}: {e}");
        assert!(
            !e.contains('\u{1b}') && !e.contains('\u{7}') && !e.contains('\u{202e}'),
            "{e}"
        );
    }
}

/// A scene name with a right-to-left override is refused, and the code
/// point is shown, never the character (it was printed raw).
#[test]
fn a_bidi_override_in_a_scene_name_is_refused() {
    let d = temp_dir("faults-bidi-name");
    let text = std::fs::read_to_string("scenes/two_rooms.ron")
        .unwrap()
        .replace("name: \"two_rooms\"", "name: \"two\u{202e}rooms\"");
    let f = write(&d, "bidi.ron", &text);
    let e = refused(e3d(&["scene", "check", &f]), 2);
    assert!(e.contains("U+202E") && e.contains("field `name`"), "{e}");
    assert!(!e.contains('\u{202e}'), "printed raw: {e}");
}

// ---- counts a file declares --------------------------------------------------

/// 3000 contexts (a 90 KB scene whose tables took 1.5 GB) and 10^5
/// contexts are refused at load by the documented bound, naming
/// the file and the bound.
#[test]
fn too_many_contexts_are_refused_by_the_bound() {
    let d = temp_dir("faults-many-contexts");
    for n in [3000, 100_000] {
        let list: Vec<String> = (0..n)
            .map(|k| format!(r#"(name: "c{k}", cell: ({}, {}))"#, k % 3, k % 6))
            .collect();
        let f = write(&d, "many.ron", &grid_with_contexts(&list.join(", ")));
        let e = refused(e3d(&["scene", "table", &f]), 2);
        assert!(e.contains(&format!("{f}:")), "{e}");
        assert!(
            e.contains("at most 1024 start contexts") && e.contains(&n.to_string()),
            "{e}"
        );
    }
}

/// The tables of every context together are bounded as one table is
/// (2^22 outcomes): 1000 contexts of a 4^7-command scene are refused
/// before any work, naming the product.
#[test]
fn context_tables_are_bounded_in_all() {
    let d = temp_dir("faults-context-tables");
    let list: Vec<String> = (0..1000)
        .map(|k| format!(r#"(name: "c{k}", cell: ({}, {}))"#, k % 3, k % 6))
        .collect();
    let f = write(&d, "many.ron", &grid_with_contexts(&list.join(", ")));
    let e = refused(e3d(&["scene", "table", &f]), 2);
    assert!(e.contains("1000 contexts x 16384 commands"), "{e}");
    assert!(e.contains("at most 4194304"), "{e}");
}

/// A trials.csv of 1100 distinct start contexts (3000 made `report` grow
/// past 3 GB) is refused naming the file, the line and the bound.
#[test]
fn report_bounds_the_start_contexts_of_trials_csv() {
    let d = temp_dir("faults-report-starts");
    let mut csv = String::from("session,episode,command,context,start,symbols,effect,reward\n");
    for k in 0..1100 {
        csv.push_str(&format!("0,{},1,0,s{k},EE,1,0\n", k + 1));
    }
    std::fs::write(d.join("trials.csv"), csv).unwrap();
    let e = refused(e3d(&["report", d.to_str().unwrap()]), 2);
    assert!(e.contains("trials.csv:1026:"), "{e}");
    assert!(e.contains("at most 1024 distinct start contexts"), "{e}");
}

/// A summary.csv of 30,000 columns (it took more than 30 s) is refused
/// with the bound; a column named twice (silently ignored) is refused
/// with its place; a negative session count (drawn) too; a BOM is
/// ignored, and every message names summary.csv.
#[test]
fn report_checks_the_columns_of_summary_csv() {
    let head = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,sessions";
    let row = "two_rooms,e3d,false,0.3,1,0.03,0.01,,3";
    let d = temp_dir("faults-summary-columns");
    let dir = d.to_str().unwrap();
    let wide: Vec<String> = (0..30_000).map(|k| format!("m{k}_mean")).collect();
    std::fs::write(
        d.join("summary.csv"),
        format!("{head},{}\n{row}{}\n", wide.join(","), ",1".repeat(30_000)),
    )
    .unwrap();
    let e = refused(e3d(&["report", dir]), 2);
    assert!(e.contains("summary.csv:1:1: at most 1024 columns"), "{e}");

    std::fs::write(
        d.join("summary.csv"),
        format!("{head},h_mean,h_mean\n{row},0.5,0.6\n"),
    )
    .unwrap();
    let e = refused(e3d(&["report", dir]), 2);
    assert!(
        e.contains("summary.csv:1:") && e.contains("`h_mean` appears twice"),
        "{e}"
    );

    std::fs::write(
        d.join("summary.csv"),
        format!("{head},h_mean\ntwo_rooms,e3d,false,0.3,1,0.03,0.01,,-3,0.5\n"),
    )
    .unwrap();
    let e = refused(e3d(&["report", dir]), 2);
    assert!(
        e.contains("summary.csv:2:")
            && e.contains("column `sessions`: expected a whole number >= 0"),
        "{e}"
    );

    std::fs::write(
        d.join("summary.csv"),
        format!("\u{feff}{head},h_mean\n{row},0.5\n"),
    )
    .unwrap();
    ok(e3d(&["report", dir]));
    std::fs::write(d.join("summary.csv"), "\u{feff}nothing,here\n").unwrap();
    let e = refused(e3d(&["report", dir]), 2);
    assert!(e.contains("summary.csv:1:1: not a sweep summary"), "{e}");
}

// ---- contexts at load ---------------------------------------------------------

/// 1000 physics contexts load in well under a second each way (checks at
/// load were quadratic: 20k contexts took over 30 s).
#[test]
fn physics_contexts_load_in_linear_time() {
    let d = temp_dir("faults-physics-contexts");
    let text = std::fs::read_to_string("scenes/puck_contexts.ron").unwrap();
    let list: Vec<String> = (0..1000)
        .map(|k| {
            format!(
                r#"(name: "c{k}", bodies: [(body: "puck", position: ({}, {}))])"#,
                0.5 + (k % 5) as f64 * 0.5,
                0.5 + (k % 4) as f64 * 0.5
            )
        })
        .collect();
    let old = r#"contexts: [
            (name: "room_a", bodies: [(body: "puck", position: (0.5, 2.5))]),
            (name: "room_b", bodies: [(body: "puck", position: (5.5, 0.5))]),
        ],"#;
    assert!(text.contains(old));
    let f = write(
        &d,
        "many.ron",
        &text.replace(old, &format!("contexts: [{}],", list.join(", "))),
    );
    ok(e3d(&["scene", "check", &f]));
}

/// A context that puts the puck outside the room is warned about as the
/// scene's own start is.
#[test]
fn a_context_outside_the_room_is_warned_about() {
    let d = temp_dir("faults-context-outside");
    let text = std::fs::read_to_string("scenes/puck_contexts.ron")
        .unwrap()
        .replace(
            r#"(name: "room_b", bodies: [(body: "puck", position: (5.5, 0.5))])"#,
            r#"(name: "room_b", bodies: [(body: "puck", position: (9.5, 0.5))])"#,
        );
    let f = write(&d, "outside.ron", &text);
    let o = ok(e3d(&["scene", "check", &f]));
    let e = stderr(&o);
    assert!(
        e.contains("context `room_b`") && e.contains("outside the effect grid"),
        "{e}"
    );
    assert!(!e.contains("context `room_a`"), "{e}");
}

/// A `Continuous` scene with start contexts is refused at load (`run`
/// used only the scene's start, `sweep` failed every session and exited 0).
#[test]
fn a_continuous_scene_with_contexts_is_refused() {
    let d = temp_dir("faults-continuous-contexts");
    let text = crate::common::PUCK_HEADINGS.replace(
        "        schedule:",
        r#"        contexts: [
            (name: "a", bodies: [(body: "puck", position: (0.5, 2.5))]),
            (name: "b", bodies: [(body: "puck", position: (5.5, 0.5))]),
        ],
        schedule:"#,
    );
    let f = write(&d, "cont.ron", &text);
    for args in [
        vec!["scene", "check", f.as_str()],
        vec!["run", f.as_str(), "--trials", "5"],
    ] {
        let e = refused(e3d(&args), 2);
        assert!(
            e.contains(&format!("{f}:")) && e.contains("field `contexts`"),
            "{e}"
        );
        assert!(
            e.contains("Continuous") && e.contains("2 context(s)"),
            "{e}"
        );
    }
}

// ---- feature ranges -----------------------------------------------------------

/// Every binned range whose width overflows or whose bins cannot be told
/// apart is refused with its place.
#[test]
fn binned_ranges_with_degenerate_bins_are_refused() {
    let d = temp_dir("faults-bins");
    let text = std::fs::read_to_string("scenes/cart_pole.ron").unwrap();
    for (range, says) in [
        ("(-1.7e308, 1.7e308)", "overflows to infinity"),
        ("(0, 5e-324)", "too narrow"),
        ("(1e15, 1.0000000000001e15)", "too narrow"),
    ] {
        let bad = text.replace(
            r#"Joint(joint: "rail", bins: 7, range: (-1.4, 1.4))"#,
            &format!(r#"Joint(joint: "rail", bins: 3, range: {range})"#),
        );
        assert_ne!(bad, text);
        let f = write(&d, "bins.ron", &bad);
        let e = refused(e3d(&["scene", "check", &f]), 2);
        assert!(
            e.contains(&format!("{f}:")) && e.contains("field `range`") && e.contains(says),
            "{range}: {e}"
        );
    }
}

// ---- FIFOs ----------------------------------------------------------------------

/// `scene table --cache` whose table file is a FIFO (it blocked for ever)
/// is refused by name, at once; the same for a context table.
#[cfg(unix)]
#[test]
fn a_fifo_table_file_is_refused_by_name() {
    let d = temp_dir("faults-fifo-table");
    for scene in ["two_rooms", "scenes/two_rooms_contexts.ron"] {
        let cache = d.join(scene.replace('/', "_"));
        let c = cache.to_str().unwrap();
        ok(e3d(&["scene", "table", scene, "--cache", c]));
        let files: Vec<_> = std::fs::read_dir(&cache)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "e3dtable"))
            .collect();
        assert!(!files.is_empty());
        std::fs::remove_file(&files[0]).unwrap();
        mkfifo(&files[0]);
        let e = refused(
            e3d_within_secs(60, &["scene", "table", scene, "--cache", c]),
            3,
        );
        assert!(
            e.contains(&files[0].display().to_string()) && e.contains("not a regular file"),
            "{e}"
        );
    }
}

/// `run --table-cache` with a FIFO where the table goes ends (the table
/// is computed and not kept), instead of blocking on the FIFO.
#[cfg(unix)]
#[test]
fn run_with_a_fifo_table_file_does_not_block() {
    let d = temp_dir("faults-fifo-run");
    let cache = d.join("cache");
    let c = cache.to_str().unwrap();
    ok(e3d(&["scene", "table", "two_rooms", "--cache", c]));
    let file = std::fs::read_dir(&cache)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "e3dtable"))
        .unwrap();
    std::fs::remove_file(&file).unwrap();
    mkfifo(&file);
    let out = d.join("out");
    let o = e3d_within_secs(
        120,
        &[
            "run",
            "two_rooms",
            "--trials",
            "2000",
            "--table-cache",
            c,
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // the plan says the table is not kept, and no more that it will be
    let said = stderr(&o);
    if said.contains("could not be kept") {
        assert!(!said.contains("will be kept"), "{said}");
    }
}

/// `scene exec --table-cache` on a scene with start contexts is refused
/// (the option was ignored without a word).
#[test]
fn exec_table_cache_on_a_context_scene_is_refused() {
    let d = temp_dir("faults-exec-contexts");
    let e = refused(
        e3d(&[
            "scene",
            "exec",
            "--table-cache",
            d.to_str().unwrap(),
            "scenes/two_rooms_contexts.ron",
            "EEEEEEE",
        ]),
        2,
    );
    assert!(
        e.contains("--table-cache") && e.contains("2 start contexts"),
        "{e}"
    );
}

// ---- the lock of a sweep folder --------------------------------------------------

/// A `.lock` that is a symbolic link is named as such (the message was
/// "Too many levels of symbolic links").
#[cfg(unix)]
#[test]
fn a_lock_that_is_a_symlink_is_named() {
    let d = temp_dir("faults-lock-link");
    let f = d.join("s.ron");
    std::fs::write(
        &f,
        r#"Sweep(scenes: ["two_rooms"], learners: [uniform], use_reward: [true],
        sessions: 1, trials: 20, seed: 1, metrics: [normalized_entropy])"#,
    )
    .unwrap();
    let out = d.join("out");
    std::fs::create_dir(&out).unwrap();
    std::os::unix::fs::symlink(d.join("elsewhere"), out.join(".lock")).unwrap();
    let e = refused(
        e3d(&[
            "sweep",
            f.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--resume",
        ]),
        3,
    );
    assert!(e.contains(".lock") && e.contains("a symbolic link"), "{e}");
    assert!(!e.contains("Too many levels"), "{e}");
    assert!(!d.join("elsewhere").exists());
}

// ---- closed-loop and compare --------------------------------------------------------

/// `closed-loop --threads 4096` is capped as `sweep` and `compare` are.
#[test]
fn closed_loop_threads_are_capped() {
    let o = ok(e3d(&[
        "closed-loop",
        "--threads",
        "4096",
        "--episodes",
        "2",
        "--seeds",
        "1",
    ]));
    let e = stderr(&o);
    assert!(e.contains("warning: --threads 4096: capped at"), "{e}");
}

/// closed-loop's refusals name its flags and the scene: `--commands 13`
/// (was: field `slots`: at most 64 slots, found 65), a grid with
/// contexts (was: the learner keeps 1 contexts), `--gamma 1e300` (was 301
/// digits).
#[test]
fn closed_loop_names_its_flags() {
    let e = refused(
        e3d(&[
            "closed-loop",
            "--commands",
            "13",
            "--episodes",
            "2",
            "--seeds",
            "1",
        ]),
        2,
    );
    assert!(
        e.contains("--commands = 13") && e.contains("at most 12"),
        "{e}"
    );
    assert!(!e.contains("field `slots`"), "{e}");

    let e = refused(
        e3d(&[
            "closed-loop",
            "scenes/two_rooms_contexts.ron",
            "--episodes",
            "2",
            "--seeds",
            "1",
        ]),
        2,
    );
    assert!(
        e.contains("2 start contexts") && e.contains("without `contexts`"),
        "{e}"
    );

    let e = refused(
        e3d(&["closed-loop", "--gamma", "1e300", "--episodes", "2"]),
        2,
    );
    assert!(
        e.contains("--gamma = 1e300: expected a number in [0, 1]"),
        "{e}"
    );
    assert!(e.len() < 200, "{e}");
}

/// `compare --scenes two_rooms,two_rooms` names `--scenes`, never a
/// `<SweepSpec>`, and makes no folder.
#[test]
fn compare_names_its_scenes_flag() {
    let d = temp_dir("faults-compare");
    let out = d.join("out");
    let e = refused(
        e3d(&[
            "compare",
            "--scenes",
            "two_rooms,two_rooms",
            "--out",
            out.to_str().unwrap(),
        ]),
        2,
    );
    assert!(
        e.contains("--scenes two_rooms,two_rooms: `two_rooms` is listed twice"),
        "{e}"
    );
    assert!(!e.contains("SweepSpec"), "{e}");
    assert!(!out.exists());
}

/// A 50-context run on a 128 x 128 grid: the per-context maps share the
/// budget of cells drawn one by one (the page was 300 MB); it stays small.
#[test]
fn report_per_context_maps_share_the_cell_budget() {
    let d = temp_dir("faults-report-maps");
    let mut csv = String::from("session,episode,command,context,start,symbols,effect,reward\n");
    for k in 0..1000 {
        // effect 16383 once: a plain 128 x 128 grid (no summary.json)
        let effect = if k == 0 { 16383 } else { (k * 37) % 16384 };
        csv.push_str(&format!(
            "0,{},1,{},s{},EE,{effect},0\n",
            k + 1,
            k % 50,
            k % 50
        ));
    }
    std::fs::write(d.join("trials.csv"), csv).unwrap();
    let page = d.join("page.html");
    ok(e3d(&[
        "report",
        d.to_str().unwrap(),
        "--out",
        page.to_str().unwrap(),
    ]));
    let bytes = std::fs::metadata(&page).unwrap().len();
    assert!(bytes < 20 << 20, "{bytes} bytes");
    let text = std::fs::read_to_string(&page).unwrap();
    assert!(text.contains("s49, early") && text.contains("Per start context"));
}

/// A trials.csv whose header names a column twice is refused with its
/// place (the second was silently ignored).
#[test]
fn report_refuses_a_duplicated_trials_column() {
    let d = temp_dir("faults-report-dup");
    std::fs::write(
        d.join("trials.csv"),
        "trial,command,effect,reward,effect\n1,EE,3,0,4\n",
    )
    .unwrap();
    let e = refused(e3d(&["report", d.to_str().unwrap()]), 2);
    assert!(
        e.contains("trials.csv:1:") && e.contains("`effect` appears twice"),
        "{e}"
    );
}
