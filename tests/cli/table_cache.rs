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
    let summary = |dir: &str| -> (serde_json::Value, serde_json::Value) {
        let text = std::fs::read_to_string(root.join(dir).join("summary.json")).unwrap();
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let execution = v.as_object_mut().unwrap().remove("execution").unwrap();
        (v, execution)
    };
    let (plain, how) = summary("plain");
    assert_eq!(how["strategy"], "table");
    assert_eq!(how["on_disk"]["state"], "nocache");
    for (out, state) in [("cached-1", "missing"), ("cached-2", "full")] {
        assert_eq!(
            std::fs::read(root.join("plain").join("trials.csv")).unwrap(),
            std::fs::read(root.join(out).join("trials.csv")).unwrap(),
            "{out}/trials.csv"
        );
        // every field but how the outcomes were obtained
        let (cached, how) = summary(out);
        assert_eq!(plain, cached, "{out}/summary.json");
        assert_eq!(how["on_disk"]["state"], state, "{out}");
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
