//! Scenes in code: `to_ron` reads back equal; an edited spec is refused by
//! `validate` with the loader's own message, never a panic, and a spec
//! that validates builds a world that executes; every scene error has a
//! kind a program can match.

use crate::common::temp_path;
use e3d::scene::{
    ron_options, Action, CommandSpec, Scene, SceneError, SceneErrorKind, SceneSpec, Symmetry,
    WorldSpec, BUILTIN,
};
use e3d::sweep::SweepError;
use e3d::World;
use proptest::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Every shipped scene (built in, and the files of `scenes/` and
/// `tests/scenes/`), with where it came from.
fn every_scene() -> Vec<(String, Scene)> {
    let mut out: Vec<(String, Scene)> = BUILTIN
        .iter()
        .map(|(n, _)| (format!("builtin {n}"), Scene::builtin(n).unwrap()))
        .collect();
    for dir in ["scenes", "tests/scenes"] {
        let mut files: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "ron"))
            .collect();
        files.sort();
        for f in files {
            out.push((f.display().to_string(), Scene::load(&f).unwrap()));
        }
    }
    out
}

fn physics(s: &mut SceneSpec) -> &mut e3d::scene::PhysicsSpec {
    match &mut s.world {
        WorldSpec::Physics(p) => p,
        WorldSpec::Grid(_) => panic!("{} is a grid scene", s.name),
    }
}

fn alphabet(s: &mut SceneSpec, slot: usize) -> &mut Vec<e3d::scene::SymbolSpec> {
    match &mut s.command {
        CommandSpec::Repeat { alphabet, .. } | CommandSpec::Template { alphabet, .. } => alphabet,
        CommandSpec::Slots(slots) => &mut slots[slot].alphabet,
        CommandSpec::Continuous(_) => panic!("{} has continuous slots", s.name),
    }
}

#[test]
fn every_shipped_scene_reads_back_equal_from_to_ron() {
    let scenes = every_scene();
    assert!(scenes.len() >= 2 * BUILTIN.len(), "{}", scenes.len());
    for (from, scene) in scenes {
        let text = scene.spec().to_ron();
        let back = Scene::parse(&text, "to_ron.ron").unwrap_or_else(|e| panic!("{from}: {e}"));
        assert_eq!(back, scene, "{from}");
        // the text is a fixed point
        assert_eq!(back.spec().to_ron(), text, "{from}");
        // and a file like the others
        assert!(text.starts_with("Scene(\n"), "{from}");
    }
}

/// Why `to_ron` exists: plain `ron::to_string` writes what the scene
/// dialect (`ron_options`) does not read.
#[test]
fn plain_ron_is_not_the_scene_dialect() {
    let grid = Scene::builtin("two_rooms").unwrap();
    let plain = ron::to_string(&grid).unwrap();
    // the newtype variant keeps its inner parentheses...
    assert!(plain.contains("world:Grid((rows:3"), "{plain}");
    // ...which the dialect, that unwraps them, reads as a field name
    let e = Scene::parse(&plain, "plain.ron").unwrap_err();
    assert!(matches!(e.kind(), SceneErrorKind::Syntax { .. }), "{e}");
    assert!(e.to_string().contains("expected identifier"), "{e}");
    // plain RON reads it back, but that is not what a scene file is
    assert_eq!(ron::from_str::<SceneSpec>(&plain).unwrap(), *grid.spec());

    // with the newtype unwrapped by hand, `Some((..))` of a tuple is
    // refused too: the dialect reads options without `Some`
    let arm = Scene::builtin("arm7").unwrap();
    let plain = ron::to_string(&arm)
        .unwrap()
        .replace("world:Physics((", "world:Physics(")
        .replace(")),command:", "),command:");
    assert!(plain.contains("limits:Some((-2.5,2.5))"));
    let e = Scene::parse(&plain, "plain.ron").unwrap_err();
    assert!(
        e.to_string().contains("field `limits`: expected float"),
        "{e}"
    );
    // floats are not the trouble: Rust writes the shortest text that
    // reads back the same bits
    for v in [0.1, 1.0 / 60.0, 1e-320, 1.7976931348623157e308, -0.0] {
        let back: f64 = ron::from_str(&ron::to_string(&v).unwrap()).unwrap();
        assert_eq!(back.to_bits(), f64::to_bits(v));
    }
}

type Edit = fn(&mut SceneSpec);

/// Edits of shipped scenes that loading would refuse: `(scene, what, edit,
/// field at fault, a part of the message)`.
fn bad_edits() -> Vec<(&'static str, &'static str, Edit, &'static str, &'static str)> {
    vec![
        (
            "puck_rooms",
            "a NaN mass",
            |s| physics(s).bodies.last_mut().unwrap().mass = Some(f64::NAN),
            "mass",
            "body `puck`: a mass > 0 in kg, found NaN",
        ),
        (
            "arm7",
            "a torque changed under symmetry FlipY",
            |s| {
                alphabet(s, 0)[2].action = Action::Torque {
                    joint: "j1".into(),
                    torque: 2.0,
                }
            },
            "action",
            "symmetry FlipY: the mirror image of every symbol's action in the same slot, but slot 0 has none for '-'",
        ),
        (
            "arm7",
            "a NaN torque",
            |s| {
                alphabet(s, 3)[0].action = Action::Torque {
                    joint: "j4".into(),
                    torque: f64::NAN,
                }
            },
            "torque",
            "a finite torque in N·m, found NaN",
        ),
        (
            "arm7",
            "a torque on no joint",
            |s| {
                alphabet(s, 1)[0].action = Action::Torque {
                    joint: "j9".into(),
                    torque: -1.2,
                }
            },
            "action",
            "a known joint, but there is no joint `j9`",
        ),
        (
            "two_rooms",
            "zero slots",
            |s| {
                if let CommandSpec::Repeat { slots, .. } = &mut s.command {
                    *slots = 0;
                }
            },
            "command",
            "at least one slot",
        ),
        (
            "arm7",
            "no slots at all",
            |s| s.command = CommandSpec::Slots(Vec::new()),
            "command",
            "at least one slot",
        ),
        (
            "two_rooms",
            "65 slots",
            |s| {
                if let CommandSpec::Repeat { slots, .. } = &mut s.command {
                    *slots = 65;
                }
            },
            "slots",
            "at most 64 slots, found 65",
        ),
        (
            "two_rooms",
            "an empty alphabet",
            |s| alphabet(s, 0).clear(),
            "alphabet",
            "slot 0: at least one symbol in the alphabet, found none",
        ),
        (
            "two_rooms",
            "a symbol twice",
            |s| {
                let first = alphabet(s, 0)[0].clone();
                alphabet(s, 0).push(first)
            },
            "symbol",
            "distinct symbols, but 'E' appears twice",
        ),
        (
            "two_rooms",
            "a grid of no rows",
            |s| {
                if let WorldSpec::Grid(g) = &mut s.world {
                    g.rows = 0;
                }
            },
            "rows",
            "at least one cell, found 0 rows x 6 columns",
        ),
        (
            "two_rooms",
            "a reward cell outside the grid",
            |s| s.reward.cells.push((3, 0)),
            "cells",
            "reward cells inside the 3 x 6 effect grid, found (3, 0)",
        ),
        (
            "maze3",
            "a NaN reward",
            |s| s.reward.value = f64::NAN,
            "value",
            "a finite reward value",
        ),
        ("two_rooms", "no name", |s| s.name.clear(), "name", "a non-empty name"),
        (
            "puck_rooms",
            "a zero time step",
            |s| physics(s).dt = 0.0,
            "dt",
            "a time step in (0, 1] seconds, found 0",
        ),
        (
            "arm7",
            "a NaN gravity",
            |s| physics(s).gravity = (0.0, f64::NAN),
            "gravity",
            "finite numbers",
        ),
        (
            "puck_rooms",
            "a symmetry the scene does not have",
            |s| physics(s).symmetry = Some(Symmetry::FlipX),
            "position",
            "symmetry FlipX: every body its own mirror image, on the mirror line (x = 0)",
        ),
        (
            "puck_rooms",
            "an untracked effect body",
            |s| physics(s).effect.body = "ghost".into(),
            "body",
            "there is no body `ghost`",
        ),
        (
            "arm7",
            "a body the child of two joints",
            |s| physics(s).joints[2].child = "link1".into(),
            "child",
            "joint `j3`: a body that is the child of one joint only (joints form trees), but `link1` is already the child of `j1`",
        ),
        (
            "arm7",
            "an effect grid of no rows",
            |s| physics(s).effect.grid.as_mut().unwrap().rows = 0,
            "grid",
            "a valid grid: at least one cell",
        ),
    ]
}

#[test]
fn an_edited_scene_is_refused_by_validate_not_a_panic() {
    for (name, what, edit, field, part) in bad_edits() {
        let mut scene = Scene::builtin(name).unwrap().to_spec();
        assert!(scene.validate().is_ok());
        edit(&mut scene);
        let e = scene.validate().expect_err(what);
        let msg = e.to_string();
        match e.kind() {
            SceneErrorKind::Invalid {
                field: f,
                expected,
                position,
            } => {
                assert_eq!(f, field, "{what}: {msg}");
                assert!(expected.contains(part), "{what}: {msg}");
                assert_eq!(*position, None, "{what}");
            }
            k => panic!("{what}: {k:?}"),
        }
        assert_eq!(e.file(), format!("<scene {}>", scene.name), "{what}");
        assert_eq!(
            msg,
            format!("<scene {}>: field `{field}`: expected {}", scene.name, {
                let SceneErrorKind::Invalid { expected, .. } = e.kind() else {
                    unreachable!()
                };
                expected
            })
        );
        // the loader runs the same checks: the scene written out and read
        // back is refused for the same reason, now placed in the text
        let loaded = Scene::parse(&scene.to_ron(), "edited.ron").expect_err(what);
        match (loaded.kind(), e.kind()) {
            (
                SceneErrorKind::Invalid {
                    field: f1,
                    expected: e1,
                    position,
                },
                SceneErrorKind::Invalid {
                    field: f2,
                    expected: e2,
                    ..
                },
            ) => {
                assert_eq!((f1, e1), (f2, e2), "{what}");
                assert!(position.is_some(), "{what}: {loaded}");
            }
            k => panic!("{what}: {k:?}"),
        }
    }
}

/// The byte ranges of the numbers of a RON text, outside strings and
/// character literals.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            q @ (b'"' | b'\'') => {
                i += 1;
                while i < b.len() && b[i] != q {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
            }
            c if c.is_ascii_digit() || c == b'-' => {
                let start = i;
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b".-+".contains(&b[i])) {
                    i += 1;
                }
                out.push((start, i));
            }
            c if c.is_ascii_alphabetic() || c == b'_' => {
                // an identifier (link1): its digits are no number
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                    i += 1;
                }
            }
            _ => i += 1,
        }
    }
    out
}

const VALUES: &[&str] = &[
    "NaN", "inf", "-inf", "-1.0", "0.0", "-0.0", "1e300", "1e-320", "1e9", "0.5", "0", "1", "70",
    "3",
];

/// The edited spec, checked every way: `validate` and the loader (of
/// `to_ron`'s text) agree, none panics, and a valid scene's world
/// executes without a panic.
fn agree(scene: &SceneSpec) -> Result<(), TestCaseError> {
    let verdict = catch_unwind(AssertUnwindSafe(|| scene.validate()));
    let Ok(verdict) = verdict else {
        return Err(TestCaseError::fail("validate panicked"));
    };
    // a world of symbols, or for a continuous scene its physics world: a
    // closure that executes one command
    type Run<'a> = Box<dyn FnMut() -> Result<(), e3d::WorldError> + 'a>;
    let built = catch_unwind(AssertUnwindSafe(|| -> Result<Run<'_>, String> {
        let scene = verdict.as_ref().map_err(|e| e.to_string())?;
        match (scene.value_space(), scene.physics_world()) {
            (Some(space), Some(mut world)) => {
                let lows: Vec<f64> = space.ranges().iter().map(|r| r.0).collect();
                Ok(Box::new(move || world.execute_values(&lows).map(drop)))
            }
            _ => {
                let mut world = scene.build();
                let c = world.command_space().first();
                Ok(Box::new(move || world.execute(&c).map(drop)))
            }
        }
    }));
    let Ok(built) = built else {
        return Err(TestCaseError::fail("build panicked"));
    };
    let loaded = Scene::parse(&scene.to_ron(), "edited.ron");
    match (&verdict, built, loaded) {
        (Ok(valid), Ok(mut run), Ok(back)) => {
            prop_assert_eq!(&back, valid);
            // a valid scene executes (or reports a blow-up) without a panic
            let ran = catch_unwind(AssertUnwindSafe(&mut run));
            prop_assert!(ran.is_ok(), "execute panicked");
        }
        (Err(v), Err(_), Err(l)) => match (v.kind(), l.kind()) {
            (
                SceneErrorKind::Invalid {
                    field: f1,
                    expected: e1,
                    ..
                },
                SceneErrorKind::Invalid {
                    field: f2,
                    expected: e2,
                    ..
                },
            ) => prop_assert_eq!((f1, e1), (f2, e2)),
            (a, b) => return Err(TestCaseError::fail(format!("{a:?} / {b:?}"))),
        },
        (v, b, l) => {
            return Err(TestCaseError::fail(format!(
                "validate {:?}, build {:?}, load {:?}",
                v.as_ref().map(drop),
                b.map(drop),
                l.map(drop)
            )))
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Any number of a shipped scene replaced by an awkward value (NaN,
    /// infinities, 0, huge, subnormal, ...).
    #[test]
    fn an_edited_number_is_refused_or_builds(which in any::<usize>(), at in any::<usize>(), value in 0..VALUES.len()) {
        let scenes = every_scene();
        let (_, scene) = &scenes[which % scenes.len()];
        let text = scene.spec().to_ron();
        let spots = numbers(&text);
        let (a, b) = spots[at % spots.len()];
        let edited_text = format!("{}{}{}", &text[..a], VALUES[value], &text[b..]);
        // the value as a program would set it: the RON read without checks
        let Ok(edited) = ron_options().from_str::<SceneSpec>(&edited_text) else {
            // not of the field's type (NaN for a count)
            return Ok(());
        };
        agree(&edited)?;
    }

    /// Symbols removed, copied or changed, slots added or dropped.
    #[test]
    fn an_edited_command_is_refused_or_builds(which in any::<usize>(), edits in prop::collection::vec((0..5u8, any::<usize>(), any::<usize>(), -3.0..3.0f64), 1..4)) {
        let scenes = every_scene();
        let (_, scene) = &scenes[which % scenes.len()];
        let mut scene = scene.to_spec();
        for (kind, i, j, x) in edits {
            let n = scene.slots().count();
            if (n == 0 || scene.is_continuous()) && kind < 3 {
                continue;
            }
            match kind {
                0 => {
                    let a = alphabet(&mut scene, i % n);
                    if !a.is_empty() {
                        a.remove(j % a.len());
                    }
                }
                1 => {
                    let a = alphabet(&mut scene, i % n);
                    if !a.is_empty() {
                        let s = a[j % a.len()].clone();
                        a.push(s);
                    }
                }
                2 => {
                    let a = alphabet(&mut scene, i % n);
                    if !a.is_empty() {
                        let k = j % a.len();
                        a[k].action = match &a[k].action {
                            Action::Torque { joint, .. } => Action::Torque { joint: joint.clone(), torque: x },
                            Action::Impulse { body, .. } => Action::Impulse { body: body.clone(), impulse: (x, 0.0) },
                            Action::Target { joint, .. } => Action::Target { joint: joint.clone(), angle: x },
                            Action::Move { .. } => Action::Move { drow: x as i32, dcol: 0 },
                            other => other.clone(),
                        };
                    }
                }
                3 => match &mut scene.command {
                    CommandSpec::Repeat { slots, .. } | CommandSpec::Template { slots, .. } => {
                        *slots = j % 70
                    }
                    CommandSpec::Slots(s) => s.truncate(j % (s.len() + 1)),
                    CommandSpec::Continuous(s) => s.truncate(j % (s.len() + 1)),
                },
                _ => {
                    if let CommandSpec::Slots(s) = &mut scene.command {
                        if !s.is_empty() {
                            let k = s[i % s.len()].clone();
                            s.push(k);
                        }
                    }
                }
            }
        }
        agree(&scene)?;
    }
}

#[test]
fn every_mistake_has_a_kind() {
    // a file that is not there: the I/O error, as the source
    let e = Scene::load("tests/no_such.ron").unwrap_err();
    assert!(
        matches!(e.kind(), SceneErrorKind::Io(io) if io.kind() == std::io::ErrorKind::NotFound),
        "{e:?}"
    );
    let source = std::error::Error::source(&e).expect("the I/O error");
    assert!(source.downcast_ref::<std::io::Error>().is_some());
    assert_eq!(e.file(), "tests/no_such.ron");
    assert_eq!(e.position(), None);
    let SceneErrorKind::Io(io) = e.into_kind() else {
        unreachable!()
    };
    assert_eq!(io.kind(), std::io::ErrorKind::NotFound);

    assert!(matches!(
        Scene::load("tests").unwrap_err().kind(),
        SceneErrorKind::Directory
    ));
    assert!(matches!(
        Scene::load("/dev/zero").unwrap_err().kind(),
        SceneErrorKind::NotRegularFile
    ));
    let e = Scene::resolve("no_such_scene").unwrap_err();
    assert!(matches!(e.kind(), SceneErrorKind::NoSuchScene), "{e:?}");
    assert_eq!(e.file(), "no_such_scene");
    assert!(!e.to_string().contains("did you mean"), "{e}");
    // a near miss of a built-in name is suggested, from a path too
    for typo in ["puck_room", "scenes/puck_room.ron", "Puck_Rooms"] {
        let e = Scene::resolve(typo).unwrap_err();
        assert!(
            e.to_string().starts_with(&format!(
                "{typo}: no such file, and no built-in scene of that name (did you mean `puck_rooms`?); expected"
            )),
            "{e}"
        );
    }

    let dir = temp_path("scene-api");
    std::fs::create_dir_all(&dir).unwrap();
    let big = dir.join("big.ron");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(e3d::scene::MAX_FILE_BYTES + 1)
        .unwrap();
    let e = Scene::load(&big).unwrap_err();
    assert!(
        matches!(e.kind(), SceneErrorKind::TooLarge { bytes: Some(n) } if *n == e3d::scene::MAX_FILE_BYTES + 1),
        "{e:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();

    // the shipped bad inputs: each its kind, and a position exactly when
    // the message has one
    let syntax = [
        "syntax_error.ron",
        "unknown_field.ron",
        "bom_unknown_field.ron",
        "wrong_type.ron",
        "missing_field.ron",
        "unknown_variant.ron",
        "negative_rows.ron",
    ];
    let mut seen = 0;
    for entry in std::fs::read_dir("tests/bad_inputs").unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|x| x != "ron") {
            continue;
        }
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        let e: SceneError = Scene::load(&path).unwrap_err();
        let k = e.kind();
        match name.as_str() {
            "empty.ron" => assert!(matches!(k, SceneErrorKind::Empty), "{name}"),
            "cr_only.ron" => assert!(matches!(k, SceneErrorKind::CrLineEndings), "{name}"),
            "not_utf8.ron" => {
                assert!(
                    matches!(
                        k,
                        SceneErrorKind::NotUtf8 {
                            line: 1,
                            col: 14,
                            ..
                        }
                    ),
                    "{name}"
                );
                assert!(std::error::Error::source(&e).is_some());
            }
            n if syntax.contains(&n) => {
                assert!(matches!(k, SceneErrorKind::Syntax { .. }), "{name}: {k:?}");
                assert!(std::error::Error::source(&e).is_none());
            }
            _ => assert!(
                matches!(
                    k,
                    SceneErrorKind::Invalid {
                        position: Some(_),
                        ..
                    }
                ),
                "{name}: {k:?}"
            ),
        }
        let prefix = match e.position() {
            Some((l, c)) => format!("{}:{l}:{c}: ", path.display()),
            None => format!("{}: ", path.display()),
        };
        assert!(e.to_string().starts_with(&prefix), "{name}: {e}");
        seen += 1;
    }
    assert!(seen >= 30, "{seen}");

    // a sweep file's mistakes are scene errors too
    let SweepError::Input(e) = e3d::Sweep::parse("  \n", "s.ron", None).unwrap_err() else {
        panic!()
    };
    assert!(matches!(e.kind(), SceneErrorKind::Empty));
    assert_eq!(
        e.to_string(),
        "s.ron: the file is empty; expected `Sweep(scenes: [...], learners: [...], sessions: N, trials: T)`"
    );
}

#[test]
fn a_ron_mistake_about_a_field_names_it() {
    let cases = [
        ("Scene(name: 3)", Some("name")),
        ("Scene(name: \"x\", wrold: Grid(rows: 1))", Some("wrold")),
        ("Scene(name: \"x\", name: \"y\")", Some("name")),
        ("Scene(name: \"x\", world: Grdi(rows: 1))", Some("world")),
        (
            "Scene(name: \"x\", world: Grid(rows: 1, cols: 2, start: (0, 0)))",
            Some("command"),
        ),
        ("Scene(", None),
        ("[1, 2]", None),
    ];
    for (text, field) in cases {
        let e = Scene::parse(text, "x.ron").unwrap_err();
        assert!(
            matches!(e.kind(), SceneErrorKind::Syntax { .. }),
            "{text}: {e}"
        );
        assert_eq!(e.field(), field, "{text}: {e}");
    }
    // a value the scene cannot hold names its field too
    let e = Scene::parse(
        "Scene(name: \"x\", world: Grid(rows: 0, cols: 2, start: (0, 0)), command: Repeat(slots: 1, alphabet: [(symbol: 'a', action: Idle)]))",
        "x.ron",
    )
    .unwrap_err();
    assert!(e.field().is_some(), "{e}");
}
