//! Loading a sweep file never panics: mutated shipped and test sweep
//! files, RON-like text and arbitrary bytes give either a checked sweep or
//! an error that names the file.
//!
//! A short run is part of the test suite (256 cases per property). A long
//! run: `PROPTEST_CASES=100000 cargo test --release --test library fuzz_sweeps::`
//! (see docs/robustness.md for the figures).

use e3d::sweep::Sweep;
use proptest::prelude::*;
use std::path::Path;

/// The sweep files of the repository, with the folder their scene paths
/// are relative to.
fn sweeps() -> Vec<(String, String)> {
    let mut v = Vec::new();
    for dir in ["scenes/sweeps", "tests/bad_inputs/sweeps"] {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|e| e == "ron") {
                v.push((dir.to_string(), std::fs::read_to_string(&p).unwrap()));
            }
        }
    }
    v.sort();
    v
}

/// Tokens that hit the corners of the sweep parser and its checks.
const TOKENS: &[&str] = &[
    "(",
    ")",
    "[",
    "]",
    ",",
    ":",
    "\"",
    "-",
    "0",
    "1",
    "-1",
    "1e308",
    "-1e308",
    "NaN",
    "inf",
    "1e-320",
    "18446744073709551615",
    "18446744073709551616",
    "1000000000",
    "99999",
    "scale: Log",
    "scale: Linear",
    "from: 0",
    "to: 0",
    "steps: 0",
    "steps: 100000",
    "e3d",
    "uniform",
    "egreedy",
    "true",
    "false",
    "alpha",
    "beta",
    "lambda",
    "eta",
    "epsilon",
    "sessions",
    "trials",
    "seed",
    "metrics",
    "cumulative_reward(0)",
    "cumulative_reward(",
    "normalized_entropy",
    "\"two_rooms\"",
    "\"arm7\"",
    "\"/dev/zero\"",
    "\"..\"",
    "\"\"",
    "Some(",
    "None",
    "//",
    "/*",
    "\n",
    "\r",
    "\u{feff}",
    "é",
    "\u{0}",
];

fn check(text: &str, base: &str) {
    match Sweep::parse(text, "fuzz.ron", Some(Path::new(base))) {
        Ok(sweep) => {
            // a sweep that loads is within its bounds
            let n = sweep.num_sessions();
            assert!((1..=e3d::sweep::MAX_SESSIONS).contains(&n), "{n} sessions");
            assert!((1..=e3d::sweep::MAX_TRIALS).contains(&sweep.spec.trials));
            assert!(!sweep.metric_columns().is_empty());
        }
        Err(e) => {
            let m = e.to_string();
            // the sweep file, or a scene file it names
            assert!(
                m.starts_with("fuzz.ron") || m.starts_with('/') || m.starts_with(base),
                "{m}"
            );
        }
    }
}

#[derive(Debug, Clone)]
enum Edit {
    Delete(usize, usize),
    Insert(usize, usize),
    Replace(usize, usize, usize),
    Duplicate(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), 1usize..12).prop_map(|(a, n)| Edit::Delete(a, n)),
        (any::<usize>(), any::<usize>()).prop_map(|(a, t)| Edit::Insert(a, t)),
        (any::<usize>(), 1usize..6, any::<usize>()).prop_map(|(a, n, t)| Edit::Replace(a, n, t)),
        (any::<usize>(), 1usize..40).prop_map(|(a, n)| Edit::Duplicate(a, n)),
    ]
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for e in edits {
        let len = chars.len().max(1);
        let token = |t: usize| TOKENS[t % TOKENS.len()].chars().collect::<Vec<char>>();
        match *e {
            Edit::Delete(a, n) => {
                let a = a % len;
                let b = (a + n).min(chars.len());
                if a < b {
                    chars.drain(a..b);
                }
            }
            Edit::Insert(a, t) => {
                let a = a % (chars.len() + 1);
                chars.splice(a..a, token(t));
            }
            Edit::Replace(a, n, t) => {
                let a = a % len;
                let b = (a + n).min(chars.len());
                if a <= b {
                    chars.splice(a..b, token(t));
                }
            }
            Edit::Duplicate(a, n) => {
                let a = a % len;
                let b = (a + n).min(chars.len());
                let piece: Vec<char> = chars[a.min(b)..b].to_vec();
                chars.splice(b..b, piece);
            }
        }
    }
    chars.into_iter().collect()
}

proptest! {
    #[test]
    fn mutated_sweep_files_load_or_fail_cleanly(which in any::<usize>(), edits in prop::collection::vec(edit(), 1..6)) {
        let files = sweeps();
        let (base, text) = &files[which % files.len()];
        check(&apply(text, &edits), base);
    }

    #[test]
    fn arbitrary_ron_like_sweeps_load_or_fail_cleanly(text in r#"Sweep\(scenes: \["two_rooms"\], ([a-z_]{1,10}: ?[A-Za-z0-9_(),:\[\]" .-]{0,30}, ?){0,6}\)"#) {
        check(&text, ".");
    }

    #[test]
    fn arbitrary_bytes_fail_cleanly(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        check(&String::from_utf8_lossy(&bytes), ".");
    }
}

#[test]
fn the_shipped_sweeps_load() {
    for (base, text) in sweeps() {
        if base == "scenes/sweeps" {
            check(&text, &base);
            Sweep::parse(&text, "shipped.ron", Some(Path::new(&base))).unwrap();
        }
    }
}
