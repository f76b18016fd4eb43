//! `e3d sweep` with scene axes (`axes: {"path": values}`): the axis is a
//! column named by its path, its value is in every session's identity,
//! and the bytes are the same whatever the threads, shards and resumes.

use super::sweep::{assert_same_files, FINAL_FILES};
use crate::common::{e3d, ok, temp_dir};
use std::path::{Path, PathBuf};

/// puck_rooms with its action noise (a `noise` section the scene does
/// not have, created by the path) x the puck's mass: 4 derived scenes,
/// e3d and uniform, 3 sessions of 40 trials.
fn axes_sweep(dir: &Path) -> PathBuf {
    let text = r#"// scene axes
Sweep(
    scenes: ["puck_rooms"],
    learners: [e3d, uniform],
    use_reward: [false],
    axes: {
        "noise.actions.Gaussian.sd": [0.0, 0.1],
        "bodies.puck.mass": [1, 2.5],
    },
    sessions: 3,
    trials: 40,
    seed: 5,
    metrics: [normalized_entropy, distinct_effects],
)
"#;
    let p = dir.join("axes.ron");
    std::fs::write(&p, text).unwrap();
    p
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn scene_axes_are_columns_named_by_their_paths_and_threads_change_no_byte() {
    let d = temp_dir("sweep-axes-threads");
    let file = axes_sweep(&d);
    let f = file.to_str().unwrap();
    let (one, two) = (d.join("one"), d.join("two"));
    ok(e3d(&[
        "sweep",
        f,
        "--out",
        one.to_str().unwrap(),
        "--threads",
        "1",
    ]));
    ok(e3d(&[
        "sweep",
        f,
        "--out",
        two.to_str().unwrap(),
        "--threads",
        "2",
    ]));
    assert_same_files(&one, &two, &FINAL_FILES);

    let results = read(&one.join("results.csv"));
    let mut lines = results.lines();
    assert_eq!(
        lines.next().unwrap(),
        "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,noise.actions.Gaussian.sd,bodies.puck.mass,session,seed,normalized_entropy,distinct_effects,failure"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // 4 derived scenes x 2 learners x 3 sessions, the last axis fastest
    assert_eq!(rows.len(), 24);
    let axes: Vec<(&str, &str, &str)> =
        rows.iter().step_by(3).map(|r| (r[1], r[8], r[9])).collect();
    assert_eq!(
        axes,
        [
            ("e3d", "0", "1"),
            ("uniform", "0", "1"),
            ("e3d", "0", "2.5"),
            ("uniform", "0", "2.5"),
            ("e3d", "0.1", "1"),
            ("uniform", "0.1", "1"),
            ("e3d", "0.1", "2.5"),
            ("uniform", "0.1", "2.5"),
        ]
    );
    // the axes' values are in the identities: every seed differs
    let mut seeds: Vec<&str> = rows.iter().map(|r| r[11]).collect();
    seeds.sort();
    seeds.dedup();
    assert_eq!(seeds.len(), 24);
    // a heavier puck, a noisier push: other effects (the sessions ran
    // on the derived scenes)
    let effects = |noise: &str, mass: &str| -> Vec<&str> {
        (rows
            .iter()
            .filter(|r| r[1] == "uniform" && r[8] == noise && r[9] == mass))
        .map(|r| r[12])
        .collect()
    };
    assert_ne!(effects("0", "1"), effects("0", "2.5"));
    assert_ne!(effects("0", "1"), effects("0.1", "1"));

    let summary = read(&one.join("summary.csv"));
    let head = summary.lines().next().unwrap();
    assert!(
        head.starts_with("scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,noise.actions.Gaussian.sd,bodies.puck.mass,sessions,"),
        "{head}"
    );
    assert_eq!(summary.lines().count(), 1 + 8);
    // the journal names each derived scene's content
    let journal = read(&one.join("journal.txt"));
    assert_eq!(
        journal
            .lines()
            .nth(1)
            .unwrap()
            .matches("@puck_rooms")
            .count(),
        4
    );

    // figures over an axis, by its path
    let svg = d.join("mass.svg");
    ok(e3d(&[
        "plot",
        one.to_str().unwrap(),
        "--x",
        "bodies.puck.mass",
        "--metric",
        "normalized_entropy",
        "--where",
        "noise.actions.Gaussian.sd=0.1",
        "--out",
        svg.to_str().unwrap(),
    ]));
    let svg = read(&svg);
    assert!(
        svg.contains("bodies.puck.mass") && svg.contains("uniform"),
        "{svg}"
    );
    // the report plots every metric against each axis
    ok(e3d(&["report", one.to_str().unwrap()]));
    let page = read(&one.join("report.html"));
    assert!(page.contains("<h2>Against noise.actions.Gaussian.sd</h2>"));
    assert!(page.contains("<h2>Against bodies.puck.mass</h2>"));
    let bad = e3d(&[
        "plot",
        one.to_str().unwrap(),
        "--x",
        "bodies.puck.mas",
        "--metric",
        "normalized_entropy",
        "--out",
        d.join("x.svg").to_str().unwrap(),
    ]);
    let msg = String::from_utf8_lossy(&bad.stderr);
    assert!(msg.contains("expected one of: alpha, beta, lambda, eta, epsilon, noise.actions.Gaussian.sd, bodies.puck.mass"), "{msg}");
}

#[test]
fn a_sweep_with_axes_in_shards_or_resumed_gives_the_one_process_bytes() {
    let d = temp_dir("sweep-axes-shards");
    let file = axes_sweep(&d);
    let f = file.to_str().unwrap();
    let whole = d.join("whole");
    ok(e3d(&[
        "sweep",
        f,
        "--out",
        whole.to_str().unwrap(),
        "--threads",
        "2",
    ]));
    let shards: Vec<String> = (1..=2)
        .map(|k| {
            let out = d.join(format!("shard{k}"));
            let shard = format!("{k}/2");
            ok(e3d(&[
                "sweep",
                f,
                "--shard",
                &shard,
                "--out",
                out.to_str().unwrap(),
            ]));
            out.display().to_string()
        })
        .collect();
    let merged = d.join("merged");
    ok(e3d(&[
        "merge",
        &shards[1],
        &shards[0],
        "--out",
        merged.to_str().unwrap(),
    ]));
    assert_same_files(&whole, &merged, &FINAL_FILES);

    // an interrupted sweep: the journal of the first 10 sessions, no results
    let cut = d.join("cut");
    std::fs::create_dir(&cut).unwrap();
    for f in ["sweep.ron", "version.txt"] {
        std::fs::copy(whole.join(f), cut.join(f)).unwrap();
    }
    let journal = read(&whole.join("journal.txt"));
    let kept: Vec<&str> = journal.lines().take(3 + 10).collect();
    assert!(kept[..3].iter().all(|l| l.starts_with('#')));
    std::fs::write(cut.join("journal.txt"), kept.join("\n") + "\n").unwrap();
    let out = ok(e3d(&[
        "sweep",
        f,
        "--out",
        cut.to_str().unwrap(),
        "--resume",
        "--threads",
        "1",
    ]));
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(msg.contains("(10 from an earlier run, 14 now)"), "{msg}");
    assert_same_files(&whole, &cut, &FINAL_FILES);
}

#[test]
fn a_bad_axis_is_refused_at_its_line_and_column_with_the_fields_there() {
    let d = temp_dir("sweep-axes-bad");
    let file = axes_sweep(&d);
    let text = read(&file);
    let cases = [
        (
            "\"bodies.puck.mass\"",
            "\"bodies.puck.mas\"",
            "bad.ron:8:9: field `axes`: expected a path to a field of scene `puck_rooms` and values it takes, found `bodies.puck.mas` = 1: unknown field `mas`, expected one of `name`, `kind`, `shape`",
        ),
        (
            "\"bodies.puck.mass\"",
            "\"bodies.pluck.mass\"",
            "bad.ron:8:9: field `axes`: expected a path to a field of scene `puck_rooms` and values it takes, found `bodies.pluck.mass` = 1: no item named `pluck`; the names: wall_south,",
        ),
        (
            "[1, 2.5]",
            "[1, -2.5]",
            "bad.ron:8:9: field `axes`: expected a path to a field of scene `puck_rooms` and values it takes, found `bodies.puck.mass` = -2.5: body `puck`: a mass > 0 in kg, found -2.5",
        ),
        (
            "[1, 2.5]",
            "[1, 1.0]",
            "bad.ron:8:9: field `axes`: expected distinct values, but 1 appears twice",
        ),
        (
            "\"bodies.puck.mass\"",
            "\"seed\"",
            "bad.ron:8:9: field `axes`: expected a scene field's path",
        ),
    ];
    for (from, to, expected) in cases {
        let bad = d.join("bad.ron");
        std::fs::write(&bad, text.replacen(from, to, 1)).unwrap();
        let out = e3d(&[
            "sweep",
            bad.to_str().unwrap(),
            "--out",
            d.join("o").to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(2), "{to}");
        let msg = String::from_utf8_lossy(&out.stderr);
        let msg = msg
            .replace(&*d.display().to_string(), "")
            .replace("error: /", "");
        assert!(msg.starts_with(expected), "{to}: {msg}");
        assert!(!d.join("o").exists());
    }
}
