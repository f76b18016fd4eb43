//! Every file in tests/bad_inputs/*.ron holds one mistake; its first line
//! says `// expect: TEXT`, a text the error must contain. The error must
//! also start with the file's path.

use e3d::Scene;
use std::path::Path;

/// Files that cannot carry their expectation in a comment.
const SPECIAL: &[(&str, &str)] = &[
    (
        "empty.ron",
        "the file is empty; expected `Scene(name: ..., world: ..., command: ...)`",
    ),
    ("not_utf8.ron", "1:14: the file is not valid UTF-8 text"),
    (
        "cr_only.ron",
        "the file's lines end with CR only (old Mac line endings), which are not supported; expected a RON scene with LF or CRLF line endings",
    ),
];

#[test]
fn every_bad_scene_is_refused_with_its_place_and_what_was_expected() {
    let mut checked = 0;
    let mut entries: Vec<_> = std::fs::read_dir("tests/bad_inputs")
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().unwrap().to_str().unwrap();
        let expect = match SPECIAL.iter().find(|(n, _)| *n == name) {
            Some((_, e)) => e.to_string(),
            None => {
                let text = std::fs::read_to_string(&path).unwrap();
                // a byte order mark is no part of the expectation
                text.trim_start_matches('\u{feff}')
                    .lines()
                    .next()
                    .and_then(|l| l.strip_prefix("// expect: "))
                    .unwrap_or_else(|| panic!("{name}: first line must be `// expect: ...`"))
                    .to_string()
            }
        };
        let err = Scene::load(&path).expect_err(name).to_string();
        let prefix = format!("{}:", path.display());
        assert!(
            err.starts_with(&prefix),
            "{name}: `{err}` does not start with the file"
        );
        assert!(err.contains(&expect), "{name}: `{err}` lacks `{expect}`");
        checked += 1;
    }
    assert!(checked >= 17, "only {checked} bad scenes");
}

#[test]
fn a_directory_or_a_missing_file_is_a_clear_error() {
    let e = Scene::load("tests").unwrap_err().to_string();
    assert_eq!(
        e,
        "tests: this is a directory; expected a scene file (.ron)"
    );
    let e = Scene::load("tests/no_such.ron").unwrap_err().to_string();
    assert!(
        e.starts_with("tests/no_such.ron: cannot read the file:"),
        "{e}"
    );
    assert!(Path::new("scenes/two_rooms.ron").exists());
}

#[test]
fn the_cli_exits_with_code_2_and_prints_the_place() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_e3d"))
        .args(["run", "tests/bad_inputs/unknown_field.ron"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("tests/bad_inputs/unknown_field.ron:4:26: unknown field `colz`"),
        "{err}"
    );
}

#[cfg(unix)]
#[test]
fn a_device_a_fifo_or_a_huge_file_is_refused_not_read() {
    // /dev/zero never ends: it was read until the process was killed
    let e = Scene::load("/dev/zero").unwrap_err().to_string();
    assert_eq!(
        e,
        "/dev/zero: this is not a regular file (a pipe, a device or a socket); expected a scene file (.ron)"
    );
    let dir = std::env::temp_dir().join(format!("e3d-bad-files-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // a FIFO without writer would block for ever
    let fifo = dir.join("fifo.ron");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid C string path
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let e = e3d::sweep::Sweep::load(&fifo).unwrap_err().to_string();
    assert!(
        e.ends_with("fifo.ron: this is not a regular file (a pipe, a device or a socket); expected a sweep file (.ron)"),
        "{e}"
    );
    // a file one byte over 16 MiB (sparse: nothing is written)
    let big = dir.join("big.ron");
    let f = std::fs::File::create(&big).unwrap();
    f.set_len(16 * 1024 * 1024 + 1).unwrap();
    let e = Scene::load(&big).unwrap_err().to_string();
    assert!(
        e.ends_with("big.ron: the file holds 16777217 bytes; a scene file may hold at most 16777216 bytes (16 MiB)"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn too_many_commands_are_counted_exactly() {
    // 4^64 commands printed as 18446744073709551615 (u64::MAX)
    let dir = std::env::temp_dir().join(format!("e3d-big-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("big.ron");
    std::fs::write(
        &p,
        r#"Scene(name: "big", world: Grid(rows: 2, cols: 2, start: (0, 0)),
    command: Repeat(slots: 64, alphabet: [(symbol: 'E', action: Move(drow: 0, dcol: 1)),
        (symbol: 'W', action: Idle), (symbol: 'S', action: Idle), (symbol: 'N', action: Idle)]))"#,
    )
    .unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_e3d"))
        .args(["scene", "table", p.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("error: 340282366920938463463374607431768211456 commands: too many for an outcome table (at most 4194304)"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
