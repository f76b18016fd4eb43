//! Loading never panics: mutated shipped scenes and arbitrary RON-like text
//! give either a scene or an error that names the file.
//!
//! A short run is part of the test suite (256 cases per property). A long
//! run: `PROPTEST_CASES=200000 cargo test --release --test library fuzz_scenes::`
//! (see docs/robustness.md for the figures).

use e3d::Scene;
use proptest::prelude::*;

fn shipped() -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = std::fs::read_dir("scenes")
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .map(|p| {
            (
                p.display().to_string(),
                std::fs::read_to_string(&p).unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

/// Tokens that make mutations hit the parser's and the validator's corners.
const TOKENS: &[&str] = &[
    "(",
    ")",
    "[",
    "]",
    ",",
    ":",
    "\"",
    "'",
    "-",
    "0",
    "1",
    "-1",
    "1e308",
    "-1e308",
    "NaN",
    "inf",
    "1e-320",
    "18446744073709551616",
    "99999999999",
    "Some(",
    "None",
    "Grid",
    "Idle",
    "Move",
    "name",
    "rows",
    "cols",
    "slots",
    "alphabet",
    "cells",
    "walls",
    "start",
    // the shorthands
    "chains",
    "links",
    "doors",
    "room",
    "closed",
    "Outside",
    "//",
    "/*",
    "\n",
    "é",
    "\u{0}",
];

fn check(text: &str) {
    match Scene::parse(text, "fuzz.ron") {
        Ok(scene) => {
            // a scene that loads is written back as text that loads equal
            match Scene::parse(&scene.spec().to_ron(), "fuzz.ron") {
                Ok(back) => assert_eq!(back, scene),
                Err(e) => panic!("to_ron does not load back: {e}"),
            }
            // its warnings (the closed-room check among them) never panic
            if let e3d::scene::WorldSpec::Physics(p) = &scene.spec().world {
                let _ = p.warnings();
            }
            // and can be built and executed
            if let Some(space) = scene.value_space() {
                let mut w = scene
                    .physics_world()
                    .expect("continuous scenes are physics");
                let lows: Vec<f64> = space.ranges().iter().map(|r| r.0).collect();
                let _ = w.execute_values(&lows);
                let c = scene.command_space().first();
                assert!(
                    scene.build().execute(&c).is_err(),
                    "a continuous scene's world refuses commands of symbols"
                );
                return;
            }
            let mut w = scene.build();
            let c = w.command_space().first();
            let _ = w.execute(&c);
        }
        Err(e) => {
            let m = e.to_string();
            assert!(m.starts_with("fuzz.ron"), "{m}");
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
                let tok: Vec<char> = TOKENS[t % TOKENS.len()].chars().collect();
                chars.splice(a..a, tok);
            }
            Edit::Replace(a, n, t) => {
                let a = a % len;
                let b = (a + n).min(chars.len());
                let tok: Vec<char> = TOKENS[t % TOKENS.len()].chars().collect();
                if a <= b {
                    chars.splice(a..b, tok);
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
    fn mutated_shipped_scenes_load_or_fail_cleanly(which in any::<usize>(), edits in prop::collection::vec(edit(), 1..6)) {
        let scenes = shipped();
        let (_, text) = &scenes[which % scenes.len()];
        check(&apply(text, &edits));
    }

    #[test]
    fn arbitrary_ron_like_text_loads_or_fails_cleanly(text in r#"Scene\(([a-z_]{1,8}: ?[A-Za-z0-9_(),:\[\]"' .-]{0,30}, ?){0,6}\)"#) {
        check(&text);
    }

    #[test]
    fn arbitrary_bytes_fail_cleanly(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        check(&String::from_utf8_lossy(&bytes));
    }
}

#[test]
fn every_shipped_scene_loads() {
    for (path, _) in shipped() {
        Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    }
}
