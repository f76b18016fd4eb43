//! `e3d scene exec`: batched and parallel, yet the same rows as executing
//! one command at a time; streaming (a row comes back before stdin ends);
//! look-ups in a cached outcome table. And the progress of `scene table`
//! stays on stderr.

use crate::common::{e3d_command, temp_path};
use e3d::{OutcomeTable, Scene, World};
use std::io::{BufRead, BufReader, Write};
use std::process::Stdio;
use std::sync::mpsc;
use std::time::Duration;

/// `count` commands of `scene` spread over its space (with repeats when
/// the space is smaller), as text.
fn commands(scene: &Scene, count: u64) -> Vec<String> {
    let space = scene.command_space();
    let n = space.num_commands().unwrap();
    (0..count)
        .map(|k| space.format(&space.command_at(k * 7919 % n)))
        .collect()
}

/// The CSV that `e3d scene exec` must print for `texts`: each command
/// executed alone by the library's world.
fn expected_csv(scene: &Scene, texts: &[String]) -> Vec<String> {
    let mut world = scene.build();
    let space = world.command_space().clone();
    let mut lines = vec!["command,effect,reward,x,y".to_string()];
    for t in texts {
        let c = space.parse(t).unwrap();
        let o = world.execute(&c).unwrap();
        lines.push(format!(
            "{},{},{},{},{}",
            space.format(&c),
            o.effect,
            o.reward,
            o.point[0],
            o.point[1]
        ));
    }
    lines
}

/// Runs `e3d scene exec ARGS -` with `input` on stdin (written from
/// another thread, so that a large output cannot block it).
fn exec_stdin(args: &[&str], input: String) -> std::process::Output {
    let mut child = e3d_command()
        .args(["scene", "exec"])
        .args(args)
        .arg("-")
        // two threads: 2 x 2 x 32 = 128 commands at most per chunk, so
        // that 200 commands take more than one
        .env("RAYON_NUM_THREADS", "2")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    out
}

/// On puck_rooms (32 copies per Rapier world) and arm7 (one copy, a
/// symmetry), the rows of 200 commands (and 60), in chunks on two threads,
/// equal line for line those of single `execute` calls.
#[test]
fn exec_rows_equal_single_executes_line_for_line() {
    for (name, count) in [("puck_rooms", 200), ("arm7", 60)] {
        let scene = Scene::builtin(name).unwrap();
        let mut texts = commands(&scene, count);
        // a repeat and a blank line change nothing
        texts.push(texts[3].clone());
        let input = texts.join("\n") + "\n\n";
        let out = exec_stdin(&[name], input);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        // nothing on stderr but the cost line, which a loaded machine's
        // slower calibration may bring out: no warning, no error
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.lines()
                .all(|l| l.contains(" commands so far") && l.contains("by the cost model")),
            "{err}"
        );
        let got = String::from_utf8(out.stdout).unwrap();
        let got: Vec<&str> = got.lines().collect();
        let want = expected_csv(&scene, &texts);
        assert_eq!(got.len(), want.len(), "{name}");
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g, w, "{name}, line {}", k + 1);
        }
    }
}

/// A command on stdin comes back as a row while stdin is still open (a
/// hang fails after a timeout rather than blocking the tests).
#[test]
fn exec_answers_each_line_before_stdin_ends() {
    for (name, command) in [("two_rooms", "EEEEEEE"), ("puck_rooms", "SEEEEES")] {
        let mut child = e3d_command()
            .args(["scene", "exec", name, "-"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let stdout = child.stdout.take().unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                if tx.send(line.unwrap()).is_err() {
                    return;
                }
            }
        });
        let mut stdin = child.stdin.take().unwrap();
        let mut next_line = |what: &str| match rx.recv_timeout(Duration::from_secs(60)) {
            Ok(line) => line,
            Err(_) => {
                let _ = child.kill();
                panic!("{name}: no {what} within 60 s while stdin is open");
            }
        };
        for round in 0..2 {
            writeln!(stdin, "{command}").unwrap();
            stdin.flush().unwrap();
            if round == 0 {
                assert_eq!(next_line("header"), "command,effect,reward,x,y");
            }
            let row = next_line("row");
            assert!(row.starts_with(&format!("{command},")), "{name}: {row}");
        }
        drop(stdin);
        assert!(child.wait().unwrap().success(), "{name}");
    }
}

/// With `--table-cache`, the commands are looked up in the scene's table
/// file, whole or partial; the new ones are simulated and added to the
/// file, which grows into a whole table; a file that cannot be used is
/// said in one line and replaced. The rows are the same every time.
#[test]
fn exec_with_a_table_cache_gives_the_same_rows() {
    use e3d::world::CachedOutcomes;
    let dir = temp_path("exec-cache");
    let _ = std::fs::remove_dir_all(&dir);
    let scene = Scene::builtin("pendulum3").unwrap();
    let texts = commands(&scene, 125);
    let want = expected_csv(&scene, &texts).join("\n") + "\n";
    let run = |texts: &[String]| {
        let out = exec_stdin(
            &["pendulum3", "--table-cache", dir.to_str().unwrap()],
            texts.join("\n"),
        );
        assert!(out.status.success(), "{out:?}");
        (
            String::from_utf8(out.stdout).unwrap(),
            String::from_utf8(out.stderr).unwrap(),
        )
    };
    let path = OutcomeTable::cache_path(&scene, &dir);
    let entries = || match OutcomeTable::read_file(&path, &scene).unwrap() {
        CachedOutcomes::Full(t) => t.len(),
        CachedOutcomes::Partial(e) => e.len(),
    };
    // nothing there yet: said, simulated, kept (10 of 125 commands)
    let (rows, err) = run(&texts[..10]);
    assert_eq!(rows.lines().count(), 11);
    assert!(want.starts_with(&rows));
    // the note first and alone of its kind (progress and cost lines, which
    // depend on the machine's speed, may follow on a loaded machine)
    let first = err.lines().next().unwrap_or_default();
    assert!(
        first.starts_with("note: no outcome table ")
            && first.ends_with("; simulating the commands, keeping their outcomes there"),
        "{err}"
    );
    assert!(
        err.lines()
            .skip(1)
            .all(|l| !l.contains("note:") && !l.contains("error")),
        "{err}"
    );
    assert_eq!(entries(), 10);
    // the partial file is used, the others added: now a whole table
    let (rows, err) = run(&texts);
    assert_eq!(rows, want);
    // nothing said of the cache (progress and cost lines, which depend on
    // the machine's speed, may be there on a loaded machine)
    assert!(!err.contains("note:") && !err.contains("error"), "{err}");
    assert!(matches!(
        OutcomeTable::read_file(&path, &scene),
        Ok(CachedOutcomes::Full(_))
    ));
    // the whole table, as `scene table --cache` also reads it
    let out = e3d_command()
        .args(["scene", "table", "pendulum3", "--cache"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("read from"));
    let (rows, err) = run(&texts);
    assert_eq!(rows, want);
    // nothing said of the cache (progress and cost lines, which depend on
    // the machine's speed, may be there on a loaded machine)
    assert!(!err.contains("note:") && !err.contains("error"), "{err}");
    // a broken file: said, simulated, replaced
    std::fs::write(&path, b"not a table").unwrap();
    let (rows, err) = run(&texts);
    assert_eq!(rows, want);
    assert!(
        err.starts_with("note: cannot use the outcome table "),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(entries(), 125);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A command that does not parse ends the output with an error naming its
/// line and what was expected (exit code 2); the rows before it stay.
#[test]
fn a_bad_line_is_an_error_after_the_rows_before_it() {
    let out = exec_stdin(&["two_rooms"], "EEEEEEE\n\nSSSSSSS\nEEX\nNNNNNNN\n".into());
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("stdin line 4: command `EEX` has 3 symbols, expected 7 (one per slot)"),
        "{err}"
    );
    let rows = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<&str> = rows.lines().collect();
    assert_eq!(rows.len(), 3, "{rows:?}");
    assert!(rows[1].starts_with("EEEEEEE,") && rows[2].starts_with("SSSSSSS,"));
}

/// The progress and cost of `scene table` go to stderr; its stdout is its
/// two lines of result.
#[test]
fn scene_table_says_its_cost_on_stderr_only() {
    let out = e3d_command()
        .args(["scene", "table", "pendulum3"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let stdout = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert!(
        lines[0].starts_with("scene pendulum3: 125 commands in "),
        "{stdout}"
    );
    assert_eq!(lines[1], "not written (give --cache DIR to keep it)");
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.starts_with("scene pendulum3: simulating 125 commands on "),
        "{stderr}"
    );
}
