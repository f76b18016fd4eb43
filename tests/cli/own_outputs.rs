//! e3d's own outputs under bad input and faults: the readers of its own
//! outputs, a report that knows its scene, memory bounds, e3d's own
//! folders (non-regular files, temporary files), terminals and formats,
//! caches to trust. Each test fails on the code before these fixes.

use e3d::csv::parse_trials;
use e3d::csv::Summary;
use e3d::{OutcomeTable, Scene};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn e3d() -> Command {
    Command::new(env!("CARGO_BIN_EXE_e3d"))
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("e3d-round3-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(args: &[&str]) -> Output {
    e3d().args(args).stdin(Stdio::null()).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[cfg(unix)]
fn mkfifo(p: &Path) {
    let c = std::ffi::CString::new(p.to_str().unwrap()).unwrap();
    // SAFETY: a valid C string
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
}

/// Feeds `bytes` into the FIFO `p` from a thread (blocked until a reader
/// opens it: if e3d never does, the thread waits until the test ends).
/// Code that opened the FIFO would read those bytes and not block.
#[cfg(unix)]
fn feed(p: &Path, bytes: &'static [u8]) {
    let p = p.to_path_buf();
    std::thread::spawn(move || {
        if let Ok(mut f) = std::fs::OpenOptions::new().write(true).open(&p) {
            let _ = std::io::Write::write_all(&mut f, bytes);
        }
    });
}

// ---- 1. readers of e3d's own outputs ----------------------------------

#[test]
fn trials_csv_values_are_bounded_and_finite_with_their_place() {
    let e = parse_trials("trial,command,effect,reward\n1,NE,4000000000,0\n")
        .unwrap_err()
        .0;
    assert_eq!(
        e,
        "trials.csv:2:6: column `effect`: expected a whole number below 1048576, found `4000000000`"
    );
    let e = parse_trials("trial,command,effect,reward\n1,NE,3,inf\n")
        .unwrap_err()
        .0;
    assert_eq!(
        e,
        "trials.csv:2:8: column `reward`: expected a finite number, found `inf`"
    );
    let e = parse_trials("trial,values,effect,reward\n1,\"0.5,NaN\",3,0\n")
        .unwrap_err()
        .0;
    assert!(e.starts_with("trials.csv:2:3: column `values`"), "{e}");
    // a 100,000-character command: refused, and the echo cut
    let long = "N".repeat(100_000);
    let e = parse_trials(&format!("trial,command,effect,reward\n1,{long},3,0\n"))
        .unwrap_err()
        .0;
    assert!(
        e.starts_with("trials.csv:2:3: column `command`: expected at most 64 symbols"),
        "{e}"
    );
    assert!(e.len() < 400, "{}", e.len());
}

#[test]
fn report_refuses_a_huge_effect_instead_of_allocating_it() {
    let d = tmp("huge-effect");
    std::fs::write(
        d.join("trials.csv"),
        "trial,command,effect,reward\n1,NE,4000000000,0\n",
    )
    .unwrap();
    let o = run(&["report", d.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("trials.csv:2:6: column `effect`"),
        "{}",
        stderr(&o)
    );
}

const SUMMARY_HEAD: &str = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,sessions,h_mean,h_sd,h_ci_low,h_ci_high\n";

#[test]
fn summary_csv_refuses_non_finite_numbers_with_their_place() {
    let csv = format!(
        "{SUMMARY_HEAD}g,e3d,false,0.3,1,0.03,0.01,,3,0.9,0.01,0.88,0.92\ng,e3d,false,0.3,inf,0.03,0.01,,3,0.8,0.01,0.78,0.82\n"
    );
    let e = Summary::parse(&csv).unwrap_err().0;
    assert_eq!(
        e,
        "summary.csv:3:17: column `beta`: expected a finite number, found `inf`"
    );
    let csv = format!("{SUMMARY_HEAD}g,e3d,false,0.3,1,0.03,0.01,,3,NaN,0.01,0.88,0.92\n");
    assert!(Summary::parse(&csv)
        .unwrap_err()
        .0
        .contains("column `h_mean`"));
}

#[test]
fn plot_refuses_an_infinite_beta() {
    let d = tmp("plot-inf");
    std::fs::write(
        d.join("summary.csv"),
        format!(
            "{SUMMARY_HEAD}g,e3d,false,0.3,1,0.03,0.01,,3,0.9,0.01,0.88,0.92\ng,e3d,false,0.3,inf,0.03,0.01,,3,0.8,0.01,0.78,0.82\n"
        ),
    )
    .unwrap();
    let out = d.join("p.svg");
    let o = run(&[
        "plot",
        d.to_str().unwrap(),
        "--x",
        "beta",
        "--metric",
        "h",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("summary.csv:3:17"), "{}", stderr(&o));
    assert!(!out.exists());
}

#[test]
fn a_reward_that_would_make_a_metric_infinite_is_refused_at_load() {
    let text = Scene::builtin("two_rooms")
        .unwrap()
        .spec()
        .to_ron()
        .replace("value: 1.0", "value: 1e308");
    assert!(text.contains("1e308"));
    let e = Scene::parse(&text, "big.ron").unwrap_err().to_string();
    assert!(
        e.contains("field `value`") && e.contains("at most 1e12"),
        "{e}"
    );
}

/// A two-session sweep into `dir`; returns the sweep file.
fn small_sweep(dir: &Path) -> PathBuf {
    let f = dir.join("s.ron");
    std::fs::write(
        &f,
        r#"Sweep(scenes: ["two_rooms"], learners: [uniform], use_reward: [true],
        sessions: 2, trials: 50, seed: 1, metrics: [normalized_entropy, cumulative_reward(50)])"#,
    )
    .unwrap();
    f
}

#[test]
fn resume_refuses_a_resealed_journal_line_holding_inf() {
    let d = tmp("journal-inf");
    let f = small_sweep(&d);
    let out = d.join("out");
    let o = run(&["sweep", f.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = out.join("journal.txt");
    let text = std::fs::read_to_string(&j).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    // the last data line: its entropy replaced by inf, and resealed
    let last = lines.pop().unwrap();
    let (_, payload) = last.split_once(' ').unwrap();
    let mut fields: Vec<&str> = payload.split(',').collect();
    let n = fields.len();
    fields[n - 3] = "inf";
    let payload = fields.join(",");
    lines.push(format!(
        "{:016x} {payload}",
        e3d::sweep::fnv1a64(payload.as_bytes())
    ));
    std::fs::write(&j, lines.join("\n") + "\n").unwrap();
    std::fs::remove_file(out.join("summary.csv")).unwrap();
    std::fs::remove_file(out.join("results.csv")).unwrap();
    let o = run(&[
        "sweep",
        f.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resume",
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("journal.txt:5:")
            && e.contains("column `normalized_entropy`")
            && e.contains("`inf`"),
        "{e}"
    );
    assert!(!out.join("summary.csv").exists());
}

// ---- 2. a report knows its scene ----------------------------------------

#[test]
fn report_draws_on_the_recorded_grid_not_a_builtin_of_the_same_name() {
    let d = tmp("report-grid");
    // a user's scene named like the built-in one, on a 10 x 10 grid
    let text = Scene::builtin("two_rooms")
        .unwrap()
        .spec()
        .to_ron()
        .replace("rows: 3", "rows: 10")
        .replace("cols: 6", "cols: 10")
        .replace("walls: [((0, 2), (0, 3)), ((2, 2), (2, 3))]", "walls: []");
    let scene = d.join("two_rooms.ron");
    std::fs::write(&scene, &text).unwrap();
    let out = d.join("run");
    let o = run(&[
        "run",
        scene.to_str().unwrap(),
        "--trials",
        "300",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(json.contains("\"scene_record\""), "{json}");
    assert!(json.contains(&format!(
        "\"path\": \"{}\"",
        std::fs::canonicalize(&scene).unwrap().display()
    )));
    let o = run(&["report", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    // two heat maps of 10 x 10 cells, not 3 x 6 (no elite map: every
    // command is 7 moves, the same effort)
    assert_eq!(page.matches("<rect class=\"cell\"").count(), 200);
    assert!(page.contains("(row 9, col 9)"));
}

#[test]
fn report_without_a_scene_record_says_so() {
    let d = tmp("report-no-record");
    std::fs::write(
        d.join("trials.csv"),
        "trial,command,effect,reward\n1,NE,3,0\n2,NE,5,1\n",
    )
    .unwrap();
    std::fs::write(d.join("summary.json"), "{\"scene\": \"two_rooms\"}\n").unwrap();
    let o = run(&["report", d.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("records no scene grid"),
        "{}",
        stderr(&o)
    );
    let page = std::fs::read_to_string(d.join("report.html")).unwrap();
    assert!(page.contains("not on the scene&#39;s grid"), "{page}");
    // not the built-in's 3 x 6 grid: 6 effects on a 2 x 3 grid, two maps
    // (no scene, no elite map)
    assert_eq!(page.matches("<rect class=\"cell\"").count(), 12);
}

// ---- 3. memory bounded by design ----------------------------------------

#[test]
fn a_stdin_line_without_end_is_cut_at_the_cap() {
    let mut child = e3d()
        .args(["scene", "exec", "two_rooms", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    // 4 MB without a line feed; e3d stops reading past 64 KiB
    let writer = std::thread::spawn(move || {
        let chunk = vec![b'N'; 1 << 16];
        for _ in 0..64 {
            if std::io::Write::write_all(&mut stdin, &chunk).is_err() {
                break;
            }
        }
    });
    let o = child.wait_with_output().unwrap();
    writer.join().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("stdin line 1: a line of more than 65536 bytes"),
        "{e}"
    );
    assert!(e.len() < 400, "{}", e.len());
}

#[test]
fn did_you_mean_skips_huge_names() {
    let a = "x".repeat(5000);
    let b = format!("{a}y");
    assert_eq!(e3d::scene::did_you_mean(&b, &[&a]), "");
    assert_eq!(
        e3d::scene::did_you_mean("colz", &["cols", "rows"]),
        " (did you mean `cols`?)"
    );
}

#[test]
fn threads_are_capped_with_a_warning() {
    let (n, w) = e3d::sweep::cap_threads(4096);
    assert_eq!(n, e3d::sweep::max_threads());
    assert!(w.unwrap().contains("--threads 4096: capped at"));
    assert_eq!(e3d::sweep::cap_threads(1), (1, None));
    let d = tmp("threads");
    let f = small_sweep(&d);
    let o = run(&[
        "sweep",
        f.to_str().unwrap(),
        "--out",
        d.join("out").to_str().unwrap(),
        "--threads",
        "4096",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: --threads 4096: capped at"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn motions_stream_frame_by_frame_as_a_whole_motion_holds_them() {
    let scene = Scene::builtin("arm7").unwrap();
    let c = scene.command_space().parse("+0-0+0-").unwrap();
    let whole = scene.physics_world().unwrap().motion(&c).unwrap();
    let mut seen = Vec::new();
    let m = scene
        .physics_world()
        .unwrap()
        .motion_each(&c, &mut |k, f| seen.push((k, f)))
        .unwrap();
    assert!(m.frames.is_empty());
    assert_eq!(m.outcome, whole.outcome);
    assert_eq!(seen.len(), whole.frames.len());
    for (k, (i, f)) in seen.into_iter().enumerate() {
        assert_eq!(i, k);
        assert_eq!(f, whole.frames[k]);
    }
}

// ---- 4. e3d's own folders ------------------------------------------------

#[cfg(unix)]
#[test]
fn a_fifo_where_e3d_reads_its_own_files_is_refused() {
    let d = tmp("fifo");
    let scene = Scene::builtin("two_rooms").unwrap();
    // a table cache file
    let p = OutcomeTable::cache_path(&scene, &d);
    mkfifo(&p);
    feed(&p, b"E3DTAB02 junk");
    let e = OutcomeTable::read_file(&p, &scene).unwrap_err().to_string();
    assert!(e.contains("not a regular file"), "{e}");
    // summary.csv given to plot
    let s = d.join("plot");
    std::fs::create_dir_all(&s).unwrap();
    mkfifo(&s.join("summary.csv"));
    feed(&s.join("summary.csv"), b"scene,learner\n");
    let o = run(&[
        "plot",
        s.to_str().unwrap(),
        "--x",
        "beta",
        "--metric",
        "h",
        "--out",
        d.join("p.svg").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    // a sweep's sweep.ron and journal.txt on --resume
    let f = small_sweep(&d);
    let out = d.join("out");
    assert!(
        run(&["sweep", f.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .status
            .success()
    );
    for name in ["journal.txt", "sweep.ron"] {
        let backup = std::fs::read(out.join(name)).unwrap();
        std::fs::remove_file(out.join(name)).unwrap();
        mkfifo(&out.join(name));
        feed(&out.join(name), b"# e3d sweep journal v1\n");
        let o = run(&[
            "sweep",
            f.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--resume",
        ]);
        assert_eq!(o.status.code(), Some(3), "{name}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("not a regular file"),
            "{name}: {}",
            stderr(&o)
        );
        std::fs::remove_file(out.join(name)).unwrap();
        std::fs::write(out.join(name), backup).unwrap();
    }
}

#[cfg(unix)]
#[test]
fn a_link_to_dev_zero_is_refused_as_a_table_cache() {
    let d = tmp("zero");
    let scene = Scene::builtin("two_rooms").unwrap();
    let p = OutcomeTable::cache_path(&scene, &d);
    std::os::unix::fs::symlink("/dev/null", &p).unwrap();
    let e = OutcomeTable::read_file(&p, &scene).unwrap_err().to_string();
    assert!(e.contains("not a regular file"), "{e}");
}

/// The PID of a process that has ended.
fn dead_pid() -> u32 {
    let mut c = Command::new("true").spawn().unwrap();
    let pid = c.id();
    c.wait().unwrap();
    pid
}

#[test]
fn the_next_run_removes_temporary_files_left_by_a_dead_one() {
    let d = tmp("stale");
    let pid = dead_pid();
    let stale = [
        d.join(format!(".trials.csv.tmp-{pid}-0-1f")),
        d.join(format!(".summary.json.tmp-{pid}-3-2a")),
    ];
    for s in &stale {
        std::fs::write(s, "half").unwrap();
    }
    // one of a process that runs (this test) is kept
    let alive = d.join(format!(".trials.csv.tmp-{}-0-1", std::process::id()));
    std::fs::write(&alive, "mine").unwrap();
    let o = run(&[
        "run",
        "two_rooms",
        "--trials",
        "50",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for s in &stale {
        assert!(!s.exists(), "{}", s.display());
    }
    assert!(alive.exists());
}

#[cfg(unix)]
#[test]
fn sigterm_and_ctrl_c_during_run_out_leave_no_temporary_file() {
    for sig in [libc::SIGTERM, libc::SIGINT] {
        let d = tmp(&format!("signal{sig}"));
        let mut command = e3d();
        command
            .args(["run", "two_rooms", "--trials", "100000000", "--out"])
            .arg(&d)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        // a test run in the background of a shell inherits SIGINT ignored
        // (and e3d keeps an ignored signal ignored, as nohup wants): give
        // the child the default actions whatever started the tests
        use std::os::unix::process::CommandExt;
        // SAFETY: signal(2) is async-signal-safe, called between fork and exec
        unsafe {
            command.pre_exec(|| {
                libc::signal(libc::SIGINT, libc::SIG_DFL);
                libc::signal(libc::SIGTERM, libc::SIG_DFL);
                Ok(())
            });
        }
        let child = command.spawn().unwrap();
        let temporary = |d: &Path| {
            std::fs::read_dir(d)
                .unwrap()
                .flatten()
                .any(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        };
        while !temporary(&d) {
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        // SAFETY: signals our own child
        unsafe {
            libc::kill(child.id() as libc::pid_t, sig);
        }
        let out = child.wait_with_output().unwrap();
        use std::os::unix::process::ExitStatusExt;
        assert_eq!(
            out.status.signal(),
            Some(sig),
            "{:?}: {}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        let left: Vec<String> = std::fs::read_dir(&d)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert!(left.is_empty(), "{left:?}");
    }
}

// ---- 5. terminals and formats --------------------------------------------

#[test]
fn control_characters_in_a_command_are_escaped_on_stderr() {
    let o = run(&["scene", "exec", "two_rooms", "NE\x1b[31m\x07"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!o.stderr.contains(&0x1b) && !o.stderr.contains(&0x07));
    assert!(stderr(&o).contains("NE\\x1b[31m\\x07"), "{}", stderr(&o));
}

#[test]
fn names_with_control_characters_and_the_symbol_quote_are_refused() {
    let base = Scene::builtin("two_rooms").unwrap().spec().to_ron();
    let e = Scene::parse(
        &base.replace("name: \"two_rooms\"", "name: \"a\\u{1b}b\""),
        "x.ron",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("field `name`") && e.contains("U+001B"), "{e}");
    let e = Scene::parse(&base.replace("symbol: 'N'", "symbol: '\"'"), "x.ron")
        .unwrap_err()
        .to_string();
    assert!(e.contains("field `symbol`") && e.contains("U+0022"), "{e}");
    let arm = Scene::builtin("arm7").unwrap().spec().to_ron();
    let e = Scene::parse(&arm.replace("\"link7\"", "\"link\\u{7}7\""), "x.ron")
        .unwrap_err()
        .to_string();
    assert!(e.contains("U+0007"), "{e}");
}

#[test]
fn svg_of_a_scene_with_an_esc_in_its_name_is_well_formed() {
    // a control character in a scene's name is refused at load (the
    // name is printed and written into CSV files); XML's own characters
    // are escaped in the picture
    let mut spec = Scene::builtin("two_rooms").unwrap().into_spec();
    spec.name = "a\x1b<b>".into();
    let e = spec.clone().validate().unwrap_err().to_string();
    assert!(e.contains("U+001B"), "{e}");
    spec.name = "a<b>&'".into();
    let scene = spec.validate().unwrap();
    let svg = e3d::report::scene_svg::scene_svg(&scene, None);
    assert!(svg.contains("a&lt;b&gt;&amp;&#39;"), "{svg}");
    let mut csv = String::from(SUMMARY_HEAD);
    csv.push_str("g\x1b,e3d,false,0.3,1,0.03,0.01,,3,0.9,0.01,0.88,0.92\ng\x1b,e3d,false,0.3,10,0.03,0.01,,3,0.8,0.01,0.78,0.82\n");
    let spec = e3d::report::sweep_plot::PlotSpec {
        x: "beta".into(),
        y: None,
        metric: "h".into(),
        filters: vec![("scene".into(), "g\x1b".into())],
    };
    let svg = e3d::report::sweep_plot::plot(&Summary::parse(&csv).unwrap(), &spec).unwrap();
    assert!(!svg.contains('\x1b'));
}

#[test]
fn errors_echo_a_bounded_length() {
    let name = "q".repeat(100_000);
    let o = run(&["run", &name, "--trials", "10"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(o.stderr.len() < 10_000, "{}", o.stderr.len());
}

// ---- 6. caches to trust -----------------------------------------------

#[test]
fn the_table_key_holds_the_physics_fingerprint() {
    let fp = e3d::sweep::PHYSICS_FINGERPRINT;
    assert_eq!(fp.len(), 8);
    assert!(fp.chars().all(|c| c.is_ascii_hexdigit()));
    assert_eq!(
        e3d::sweep::VERSION,
        format!("{}+physics.{fp}", env!("CARGO_PKG_VERSION"))
    );
    let scene = Scene::builtin("two_rooms").unwrap();
    let canonical = ron::to_string(&scene).unwrap();
    let version_only =
        e3d::sweep::fnv1a64(format!("e3d {} {canonical}", env!("CARGO_PKG_VERSION")).as_bytes());
    assert_ne!(OutcomeTable::key(&scene), version_only);
}

#[test]
fn a_resealed_table_with_nan_rewards_is_refused() {
    let d = tmp("reseal");
    let scene = Scene::builtin("two_rooms").unwrap();
    let table = OutcomeTable::build_scene(&scene).unwrap();
    let mut b = table.to_bytes(OutcomeTable::key(&scene));
    // the reward of the first record (after the 32-byte header and its
    // effect), then the checksum recomputed
    b[36..44].copy_from_slice(&f64::NAN.to_le_bytes());
    let body = b.len() - 8;
    let sum = e3d::sweep::fnv1a64(&b[..body]);
    b[body..].copy_from_slice(&sum.to_le_bytes());
    let p = d.join("t.e3dtable");
    std::fs::write(&p, &b).unwrap();
    let e = OutcomeTable::read_file(&p, &scene).unwrap_err().to_string();
    assert!(e.contains("a reward that is not the scene's"), "{e}");
}

#[test]
fn memos_saved_at_once_into_one_file_lose_no_entry() {
    let d = tmp("memo-race");
    let scene = Scene::builtin("two_rooms").unwrap();
    let table = OutcomeTable::build_scene(&scene).unwrap();
    let space = scene.command_space();
    let p = d.join("m.e3dtable");
    let writers = 8u64;
    let rounds = 12u64;
    std::thread::scope(|s| {
        for w in 0..writers {
            let (scene, table, space, p) = (&scene, &table, &space, &p);
            s.spawn(move || {
                for r in 0..rounds {
                    let memo =
                        e3d::world::OutcomeMemo::new(space, scene.num_effects(), 1 << 20).unwrap();
                    let i = w * rounds + r;
                    memo.insert(i, *table.get(i));
                    memo.save(p, scene).unwrap();
                }
            });
        }
    });
    match OutcomeTable::read_file(&p, &scene).unwrap() {
        e3d::world::CachedOutcomes::Partial(e) => {
            assert_eq!(e.len() as u64, writers * rounds);
        }
        e3d::world::CachedOutcomes::Full(_) => panic!("not a whole table"),
    }
}
