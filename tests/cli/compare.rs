//! `e3d compare`: every drive on chosen scenes, a table, a figure and the
//! sessions' rows, the same whatever the threads.

use std::process::Command;

fn compare(out: &std::path::Path, threads: &str) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_e3d"))
        .args([
            "compare",
            "--scenes",
            "two_rooms",
            "--sessions",
            "4",
            "--trials",
            "2000",
        ])
        .args(["--threads", threads, "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn compare_writes_the_table_the_figure_and_the_rows() {
    let dir = std::env::temp_dir().join(format!("e3d-compare-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let stdout = compare(&dir.join("a"), "1");
    let md = std::fs::read_to_string(dir.join("a/drives.md")).unwrap();
    assert!(stdout.contains(&md));
    // one row per learner, in the sweep's order
    let rows: Vec<&str> = md
        .lines()
        .filter(|l| l.starts_with("| two_rooms |"))
        .collect();
    let learners: Vec<&str> = rows
        .iter()
        .map(|l| l.split(" | ").nth(1).unwrap())
        .collect();
    assert_eq!(
        learners,
        ["e3d", "e3d_relax", "count", "smm", "uniform", "egreedy"]
    );
    let csv = std::fs::read_to_string(dir.join("a/drives.csv")).unwrap();
    let value = |learner: &str, col: usize| -> f64 {
        let line = csv
            .lines()
            .find(|l| l.starts_with(&format!("two_rooms,{learner},")))
            .unwrap();
        line.split(',').nth(col).unwrap().parse().unwrap()
    };
    // task 1: E3D spreads the cells more than the uniform policy
    assert!(value("e3d", 2) > value("uniform", 2) + 0.1);
    // task 2: E3D gathers more reward than the uniform policy
    assert!(value("e3d", 4) > 100.0 * value("uniform", 4).max(1.0));
    // 4 task-2 sessions each
    assert_eq!(value("e3d", 8), 4.0);
    let svg = std::fs::read_to_string(dir.join("a/drives.svg")).unwrap();
    assert!(svg.contains("task 1: normalised entropy") && svg.contains(">smm</text>"));
    // results.csv: a header and 20 cells (4 learners x 2 betas x 2 tasks, and 2 x 2 tasks) x 4 sessions
    let results = std::fs::read_to_string(dir.join("a/results.csv")).unwrap();
    assert_eq!(results.lines().count(), 1 + 20 * 4);
    // the same bytes on two threads
    compare(&dir.join("b"), "2");
    for f in ["drives.md", "drives.csv", "drives.svg", "results.csv"] {
        assert_eq!(
            std::fs::read(dir.join("a").join(f)).unwrap(),
            std::fs::read(dir.join("b").join(f)).unwrap(),
            "{f}"
        );
    }
    // an earlier comparison is not overwritten without --force
    let o = Command::new(env!("CARGO_BIN_EXE_e3d"))
        .args([
            "compare",
            "--scenes",
            "two_rooms",
            "--sessions",
            "1",
            "--trials",
            "10",
            "--out",
        ])
        .arg(dir.join("a"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("pass --force"));
    let _ = std::fs::remove_dir_all(&dir);
}
