//! Every message e3d prints, on standard output as on standard error,
//! shows control characters escaped: a path, a name or a command echoed
//! in a message cannot drive the terminal (ESC, BEL, carriage return).

use crate::common::{e3d, ok, temp_dir};

/// A folder name with an OSC title sequence, a colour, a bell and a
/// carriage return in it: legal on Unix, and echoed by `run --out`.
const HOSTILE: &str = "out\u{1b}]0;owned\u{7}\u{1b}[31mred\rback";

#[test]
fn paths_in_progress_and_result_lines_are_escaped() {
    let dir = temp_dir("console-escapes");
    let out_dir = dir.join(HOSTILE);
    let o = ok(e3d(&[
        "run",
        "--trials",
        "20",
        "--out",
        out_dir.to_str().unwrap(),
    ]));
    // the files are where asked
    assert!(out_dir.join("trials.csv").is_file());
    assert!(out_dir.join("summary.json").is_file());
    for (what, bytes) in [("stdout", &o.stdout), ("stderr", &o.stderr)] {
        let text = String::from_utf8_lossy(bytes);
        let raw: Vec<char> = text
            .chars()
            .filter(|&c| c.is_control() && c != '\n' && c != '\t')
            .collect();
        assert!(raw.is_empty(), "{what} holds raw controls {raw:?}: {text}");
    }
    let stdout = String::from_utf8(o.stdout).unwrap();
    let wrote = stdout.lines().find(|l| l.starts_with("wrote ")).unwrap();
    assert!(
        wrote.contains("out\\x1b]0;owned\\x07\\x1b[31mred\\x0dback/trials.csv"),
        "{wrote}"
    );
}

#[test]
fn errors_on_stderr_are_escaped() {
    let dir = temp_dir("console-escapes-warn");
    // a --table-cache that is a file, not a folder: the error names it
    let cache = dir.join("cache\u{1b}[2J\u{7}");
    std::fs::write(&cache, b"not a folder").unwrap();
    let o = e3d(&[
        "run",
        "--trials",
        "20",
        "--table-cache",
        cache.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3));
    let stderr = String::from_utf8(o.stderr).unwrap();
    assert!(stderr.contains("cache\\x1b[2J\\x07"), "{stderr}");
    assert!(
        !stderr.contains('\u{1b}') && !stderr.contains('\u{7}'),
        "{stderr}"
    );
}
