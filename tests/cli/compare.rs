//! `e3d compare`: every drive on chosen scenes, a table, a figure and the
//! sessions' rows, the same whatever the threads.

use crate::common::{e3d_command, temp_path};

fn compare(out: &std::path::Path, threads: &str) -> String {
    let o = e3d_command()
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
    let dir = temp_path("compare");
    let _ = std::fs::remove_dir_all(&dir);
    let stdout = compare(&dir.join("a"), "1");
    let md = std::fs::read_to_string(dir.join("a/drives.md")).unwrap();
    assert!(stdout.contains(&md));
    // one row per learner, in the sweep's order
    let rows: Vec<&str> = md
        .split("\nBest per scene")
        .next()
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("| two_rooms |"))
        .collect();
    let learners: Vec<&str> = rows
        .iter()
        .map(|l| l.split(" | ").nth(1).unwrap())
        .collect();
    assert_eq!(
        learners,
        [
            "e3d",
            "e3d_relax",
            "count",
            "smm",
            "uniform",
            "egreedy",
            "goal_babbling",
            "archive"
        ]
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
    // the 95% intervals: mean ± t(3) sd / sqrt 4, t(3) = 3.182446
    let t3 = e3d::report::t_quantile_975(3);
    assert!((t3 - 3.182446).abs() < 1e-6);
    assert!(csv.lines().next().unwrap().ends_with(
        ",task1_entropy_ci95_lo,task1_entropy_ci95_hi,task1_coverage_ci95_lo,task1_coverage_ci95_hi,task2_reward_ci95_lo,task2_reward_ci95_hi,task2_first_reward_q1,task2_first_reward_q3,task1_trials_to_50_ci95_lo,task1_trials_to_50_ci95_hi,task1_trials_to_90_ci95_lo,task1_trials_to_90_ci95_hi,task1_qd_score_mean,task1_qd_score_sd,task1_qd_score_ci95_lo,task1_qd_score_ci95_hi,task1_qd_scored"
    ));
    // two_rooms' commands all have the same effort: no QD-score
    assert_eq!(value("e3d", 36), 0.0);
    for learner in ["e3d", "uniform", "archive"] {
        for (mean, sd, lo, hi) in [(2, 3, 20, 21), (9, 10, 22, 23), (4, 5, 24, 25)] {
            let half = t3 * value(learner, sd) / 2.0;
            assert!((value(learner, lo) - (value(learner, mean) - half)).abs() < 1e-9);
            assert!((value(learner, hi) - (value(learner, mean) + half)).abs() < 1e-9);
        }
    }
    // the median first reward lies within its quartiles
    let (q1, q3) = (value("e3d", 26), value("e3d", 27));
    assert!(q1 <= value("e3d", 6) && value("e3d", 6) <= q3, "{q1} {q3}");
    // trials to 50%: over the sessions that got there (column 13)
    let n50 = value("e3d", 13);
    let t = e3d::report::t_quantile_975(n50 as usize - 1);
    let half = t * value("e3d", 12) / n50.sqrt();
    assert!((value("e3d", 28) - (value("e3d", 11) - half)).abs() < 1e-9);
    assert!((value("e3d", 29) - (value("e3d", 11) + half)).abs() < 1e-9);
    assert!(md.contains("| entropy: 95% (t) | coverage: 95% (t) | QD-score: 95% (t) | to 50%: 95% (t) | to 90%: 95% (t) | reward: 95% (t) | first reward: Q1..Q3 |"));
    let svg = std::fs::read_to_string(dir.join("a/drives.svg")).unwrap();
    assert!(svg.contains("task 1: normalised entropy") && svg.contains(">smm</text>"));
    // results.csv: a header and 24 cells (4 learners x 2 betas x 2 tasks, and 4 x 2 tasks) x 4 sessions
    let results = std::fs::read_to_string(dir.join("a/results.csv")).unwrap();
    assert_eq!(results.lines().count(), 1 + 24 * 4);
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
    let o = e3d_command()
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
