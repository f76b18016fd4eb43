//! Outcome tables kept on disk change no result.

use std::process::Command;

fn e3d(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_e3d"))
        .args(args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn runs_and_sweeps_give_the_same_bytes_with_and_without_a_table_cache() {
    let root = std::env::temp_dir().join(format!("e3d-cache-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let cache = root.join("cache");
    let p = |s: &str| root.join(s).to_str().unwrap().to_string();
    e3d(&["run", "--trials", "800", "--out", &p("plain")]);
    // twice with the cache: the first run writes the table, the second reads it
    for out in ["cached-1", "cached-2"] {
        e3d(&[
            "run",
            "--trials",
            "800",
            "--out",
            &p(out),
            "--table-cache",
            cache.to_str().unwrap(),
        ]);
    }
    let tables: Vec<_> = std::fs::read_dir(&cache).unwrap().collect();
    assert_eq!(tables.len(), 1, "one table for two_rooms");
    for out in ["cached-1", "cached-2"] {
        for f in ["trials.csv", "summary.json"] {
            assert_eq!(
                std::fs::read(root.join("plain").join(f)).unwrap(),
                std::fs::read(root.join(out).join(f)).unwrap(),
                "{out}/{f}"
            );
        }
    }
    let sweep = "scripts/slurm/test-sweep.ron";
    e3d(&["sweep", sweep, "--out", &p("sweep-plain"), "--threads", "2"]);
    e3d(&[
        "sweep",
        sweep,
        "--out",
        &p("sweep-cached"),
        "--threads",
        "2",
        "--table-cache",
        cache.to_str().unwrap(),
    ]);
    for f in ["results.csv", "summary.csv"] {
        assert_eq!(
            std::fs::read(root.join("sweep-plain").join(f)).unwrap(),
            std::fs::read(root.join("sweep-cached").join(f)).unwrap(),
            "{f}"
        );
    }
    let _ = std::fs::remove_dir_all(&root);
}
