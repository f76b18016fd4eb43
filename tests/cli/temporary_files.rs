//! `run --out` leaves no temporary file however e3d ends: on any signal
//! that ends a process and can be caught (a closed terminal, a closed
//! pipe, `kill -USR1`, ...), and when standard output fails.

use crate::common::{e3d_command, temp_dir};
use std::path::Path;
use std::process::{Child, Stdio};

/// The names in `dir`.
fn names(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect()
}

/// Waits until `dir` holds a temporary file (the streamed trials).
fn wait_for_temporary(dir: &Path, child: &mut Child) {
    while !names(dir).iter().any(|n| n.contains(".tmp-")) {
        assert!(child.try_wait().unwrap().is_none(), "e3d ended early");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// `run --out DIR` of `trials` trials, its output going to `stdout`.
fn run_out(dir: &Path, trials: &str, stdout: Stdio) -> Child {
    e3d_command()
        .args(["run", "two_rooms", "--trials", trials, "--out"])
        .arg(dir)
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

#[cfg(unix)]
#[test]
fn hangup_and_other_ending_signals_leave_no_temporary_file() {
    use std::os::unix::process::ExitStatusExt;
    for sig in [libc::SIGHUP, libc::SIGUSR1, libc::SIGUSR2, libc::SIGALRM] {
        let dir = temp_dir(&format!("temporary-files-signal{sig}"));
        let mut child = run_out(&dir, "100000000", Stdio::null());
        wait_for_temporary(&dir, &mut child);
        // SAFETY: signals our own child
        unsafe {
            libc::kill(child.id() as libc::pid_t, sig);
        }
        let status = child.wait().unwrap();
        assert_eq!(status.signal(), Some(sig), "signal {sig}");
        assert!(names(&dir).is_empty(), "signal {sig}: {:?}", names(&dir));
    }
}

#[cfg(unix)]
#[test]
fn a_closed_pipe_leaves_no_temporary_file() {
    use std::os::unix::process::ExitStatusExt;
    let dir = temp_dir("temporary-files-pipe");
    let mut child = run_out(&dir, "1000000", Stdio::piped());
    // the reader goes (`e3d run ... | head -0`): the first write of the
    // results, with the trials streamed, ends e3d
    drop(child.stdout.take());
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(libc::SIGPIPE));
    assert!(names(&dir).is_empty(), "{:?}", names(&dir));
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_standard_output_leaves_no_temporary_file() {
    let dir = temp_dir("temporary-files-full");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let mut child = run_out(&dir, "1000000", Stdio::from(full));
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(3));
    assert!(names(&dir).is_empty(), "{:?}", names(&dir));
}
