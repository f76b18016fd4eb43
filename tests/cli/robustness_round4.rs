//! Bad input and faults, round 4 (issue 30): a sweep's journal streamed,
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
