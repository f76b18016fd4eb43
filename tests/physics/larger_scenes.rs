//! The two larger canonical scenes: puck_rooms14 (puck_rooms with 14 slots)
//! and arm7x5 (arm7 with five torques per joint). Their sizes, that they are
//! their parents but for the command, arm7x5's mirror symmetry, and the
//! effects of a few commands (measured with `e3d scene exec`, pinned here).

use e3d::scene::{Action, CommandSpec, Symmetry, WorldSpec};
use e3d::{OutcomeTable, Scene, World};

fn scene(name: &str) -> Scene {
    let s = Scene::builtin(name).unwrap_or_else(|| panic!("{name} is a built-in scene"));
    // the built-in text is the shipped file
    assert_eq!(s, Scene::load(format!("scenes/{name}.ron")).unwrap());
    s
}

/// Executes `commands` and checks each one's effect and terminal point
/// (`(command, effect, x, y)`, measured with `e3d scene exec`). The points
/// are checked to 1e-4 m, the effects exactly.
fn check_outcomes(scene: &Scene, expected: &[(&str, usize, f64, f64)]) {
    let mut w = scene.build();
    let space = w.command_space().clone();
    let cols = scene.effect_grid().cols;
    let rewarded = scene.reward_table();
    for &(text, effect, x, y) in expected {
        let o = w.execute(&space.parse(text).unwrap()).unwrap();
        assert_eq!(
            o.effect,
            effect,
            "{} {text}: cell ({}, {}), expected ({}, {})",
            scene.spec().name,
            o.effect / cols,
            o.effect % cols,
            effect / cols,
            effect % cols
        );
        assert!(
            (o.point[0] - x).abs() < 1e-4 && (o.point[1] - y).abs() < 1e-4,
            "{} {text}: {:?}, expected ({x}, {y})",
            scene.spec().name,
            o.point
        );
        assert_eq!(o.reward, rewarded[effect]);
    }
}

#[test]
fn both_load_with_their_sizes() {
    let p = scene("puck_rooms14");
    assert_eq!(p.command_space().num_slots(), 14);
    assert_eq!(p.command_space().num_commands(), Some(268_435_456)); // 4^14
    assert_eq!(p.spec().steps_per_command(), Some(960)); // 14 x 60 + 120
    assert_eq!(p.num_effects(), 18);
    assert_eq!(p.spec().reward.cells, [(2, 5)]);

    let a = scene("arm7x5");
    assert_eq!(a.command_space().num_slots(), 7);
    assert_eq!(a.command_space().num_commands(), Some(78_125)); // 5^7
    assert_eq!(a.spec().steps_per_command(), Some(120)); // 15 + 105
    assert_eq!(a.num_effects(), 225);
    // the rule's cell, from `e3d scene reward-cell scenes/arm7x5.ron`
    // (all 78125 commands; a few minutes, so not rerun here)
    assert_eq!(a.spec().reward.cells, [(5, 5)]);
    assert_eq!(a.reward_table().iter().filter(|&&r| r > 0.0).count(), 1);
}

#[test]
fn puck_rooms14_is_puck_rooms_with_14_slots() {
    let big = scene("puck_rooms14");
    let small = scene("puck_rooms");
    assert_eq!(big.spec().world, small.spec().world);
    assert_eq!(big.spec().reward, small.spec().reward);
    match (&big.spec().command, &small.spec().command) {
        (
            CommandSpec::Repeat {
                slots: 14,
                alphabet: a,
            },
            CommandSpec::Repeat {
                slots: 7,
                alphabet: b,
            },
        ) => assert_eq!(a, b),
        other => panic!("{other:?}"),
    }
    // too many commands for an outcome table: sessions execute every trial
    let w = big.build();
    assert!(!OutcomeTable::worthwhile(&big, w.as_ref(), u64::MAX));
}

#[test]
fn arm7x5_is_arm7_with_half_torques_added() {
    let big = scene("arm7x5");
    let small = scene("arm7");
    assert_eq!(big.spec().world, small.spec().world);
    for (k, (a, b)) in big.spec().slots().zip(small.spec().slots()).enumerate() {
        let symbols: String = a.iter().map(|s| s.symbol).collect();
        assert_eq!(symbols, "-m0p+", "slot {k}");
        // '-', '0', '+' are arm7's symbols, with arm7's actions
        assert_eq!([&a[0], &a[2], &a[4]], [&b[0], &b[1], &b[2]], "slot {k}");
        let torque = |action: &Action| match action {
            Action::Torque { joint, torque } => {
                assert_eq!(joint, &format!("j{}", k + 1));
                *torque
            }
            other => panic!("slot {k}: {other:?}"),
        };
        let t = torque(&a[4].action);
        assert_eq!(torque(&a[0].action), -t);
        assert_eq!(torque(&a[1].action), -t / 2.0, "slot {k}: 'm' is -t/2");
        assert_eq!(torque(&a[3].action), t / 2.0, "slot {k}: 'p' is +t/2");
        assert_eq!(a[2].action, Action::Idle);
    }
}

#[test]
fn arm7x5s_mirror_image_of_every_symbol_is_in_its_slot() {
    let s = scene("arm7x5");
    let WorldSpec::Physics(spec) = &s.spec().world else {
        panic!("a physics scene")
    };
    assert_eq!(spec.symmetry, Some(Symmetry::FlipY));
    for (k, alphabet) in s.spec().slots().enumerate() {
        for sym in alphabet {
            let m = Symmetry::FlipY.mirror_action(&sym.action);
            let image: Vec<char> = alphabet
                .iter()
                .filter(|t| t.action == m)
                .map(|t| t.symbol)
                .collect();
            let expected = match sym.symbol {
                '-' => '+',
                'm' => 'p',
                '0' => '0',
                'p' => 'm',
                '+' => '-',
                c => panic!("slot {k}: unexpected symbol {c}"),
            };
            assert_eq!(image, [expected], "slot {k}, '{}'", sym.symbol);
        }
    }
    // 78125 = 1 command that is its own mirror image (0000000) + 2 x 39062:
    // one of each pair is simulated (what `e3d scene check` prints)
    assert_eq!(OutcomeTable::simulated_commands(&s), Some(39_063));
    let w = s.physics_world().unwrap();
    let space = s.command_space();
    let twin = w.twin(&space.parse("+---m+-").unwrap()).unwrap();
    assert_eq!(space.format(&twin), "-+++p-+");
}

#[test]
fn arm7x5_commands_give_the_recorded_effects() {
    // `e3d scene exec arm7x5 -- 0000000 -+++p-+ ...`
    check_outcomes(
        &scene("arm7x5"),
        &[
            // nothing moves: the rest cell (7, 14)
            ("0000000", 7 * 15 + 14, 1.75, 0.0),
            // the two commands reaching the reward cell (5, 5) ...
            ("-+++p-+", 5 * 15 + 5, -0.39598697, 0.42305136),
            ("-++++m0", 5 * 15 + 5, -0.42300087, 0.38508838),
            // ... and the mirror image of the first, in (9, 5)
            ("+---m+-", 9 * 15 + 5, -0.39598697, -0.42305136),
            ("ppppppp", 73, 1.58275211, 0.71538824),
            ("mmmmmmm", 163, 1.58275211, -0.71538824),
            ("pm0pm0p", 118, 1.61136746, 0.03482144),
            ("p+0-m0p", 112, -0.00632066, -0.04804029),
            // arm7's rewarded command: its arm7 cell (6, 5), no longer rewarded
            ("-++++--", 6 * 15 + 5, -0.38234302, 0.27598378),
        ],
    );
    // a command of arm7 (symbols -, 0, +) does the same in both scenes,
    // bit for bit
    let text = "-++++--";
    let run = |name: &str| {
        let mut w = scene(name).build();
        let c = w.command_space().parse(text).unwrap();
        w.execute(&c).unwrap().point.map(f64::to_bits)
    };
    assert_eq!(run("arm7x5"), run("arm7"));
}

#[test]
fn puck_rooms14_commands_give_the_recorded_effects() {
    // `e3d scene exec puck_rooms14 EEEEEEEEEEEEEE ...`
    check_outcomes(
        &scene("puck_rooms14"),
        &[
            // the inner wall stops the puck in room A, on row 0
            ("EEEEEEEEEEEEEE", 2, 2.38163853, 2.5),
            ("SSSSSSSSSSSSSS", 12, 0.5, 0.56835932),
            // puck_rooms's way to the reward, SEEEEES, then 7 more south:
            // still the rewarded corner
            ("SEEEEESSSSSSSS", 17, 5.71751118, 0.53631234),
            ("SEEEEESSEEEEES", 17, 5.45722055, 0.48669910),
            ("SEEEEESNSNSNSN", 11, 5.71751118, 1.39620674),
            ("NNNWWWWNNNWWWW", 0, 0.52976137, 2.46024704),
            ("ESESESEESESESE", 14, 2.39728355, 0.54026199),
            // the first of the 20,000 random commands of docs/scenes.md
            ("NSNNSNWNNESSEN", 8, 2.78028512, 1.34741211),
        ],
    );
}

#[test]
fn puck_rooms14_with_a_repeated_pattern_in_its_last_slots_stays_in_the_rooms() {
    // a puck_rooms command, then 7 slots repeating a short pattern (back
    // and forth, a loop, always the same way): the puck ends at a finite
    // point inside the floor, at least its radius (0.2 m) from the outer
    // walls, in a cell of the grid
    let s = scene("puck_rooms14");
    let mut w = s.build();
    let space = w.command_space().clone();
    let mut cells = Vec::new();
    for head in ["SEEEEES", "EEEEEEE", "NNNWWWW"] {
        for tail in ["EWEWEWE", "NSNSNSN", "ESWNESW", "SSSSSSS"] {
            let text = format!("{head}{tail}");
            let o = w.execute(&space.parse(&text).unwrap()).unwrap();
            let [x, y] = o.point;
            assert!(x.is_finite() && y.is_finite(), "{text}: {:?}", o.point);
            let eps = 1e-3;
            assert!(
                (0.2 - eps..=5.8 + eps).contains(&x) && (0.2 - eps..=2.8 + eps).contains(&y),
                "{text}: {:?}",
                o.point
            );
            assert!(o.effect < 18, "{text}: {}", o.effect);
            assert_eq!(o.effect, s.effect_grid().effect_of(o.point), "{text}");
            cells.push(o.effect);
        }
    }
    // the back-and-forth tail after SEEEEES leaves the puck in room B's
    // lower-right corner (17: rewarded), as the pinned SEEEEESEWEWEWE shows
    assert_eq!(cells[0], 17);
}
