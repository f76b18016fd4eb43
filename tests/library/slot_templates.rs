//! Slot templates (`Template`: one alphabet, slot k acting on
//! `cycle[k mod m]`) and the declared slot count (`slots: N`).

use e3d::scene::{Action, CommandSpec, Scene, SceneErrorKind};
use e3d::World;

const TEMPLATE: &str = r#"Scene(
    name: "tmpl",
    slots: 5,
    world: Physics(
        chains: [(links: 2, length: 0.3, width: 0.05, mass: 0.1)],
        schedule: Sequential(phase: 0.25, settle: 0.5),
        effect: (body: "link2", point: (0.15, 0.0),
                 grid: (rows: 4, cols: 4, min: (-0.6, -0.6), max: (0.6, 0.6))),
    ),
    command: Template(
        slots: 5,
        alphabet: [
            (symbol: '-', action: Torque(joint: "*", torque: -0.05)),
            (symbol: '0', action: Idle),
            (symbol: '+', action: Torque(joint: "*", torque: 0.05)),
        ],
        cycle: ["j1", "j2"],
    ),
)"#;

/// The same scene with its five slots written one by one.
fn written_out() -> String {
    let slot = |j: &str| {
        format!(
            r#"(name: "{j}", alphabet: [
            (symbol: '-', action: Torque(joint: "{j}", torque: -0.05)),
            (symbol: '0', action: Idle),
            (symbol: '+', action: Torque(joint: "{j}", torque: 0.05)),
        ])"#
        )
    };
    let slots: Vec<String> = ["j1", "j2", "j1", "j2", "j1"]
        .iter()
        .map(|j| slot(j))
        .collect();
    let start = TEMPLATE.find("    command: Template(").unwrap();
    format!(
        "{}    command: Slots([\n{}\n    ]),\n)",
        &TEMPLATE[..start],
        slots.join(",\n")
    )
}

#[test]
fn a_template_loads_as_the_slots_it_stands_for() {
    let t = Scene::parse(TEMPLATE, "tmpl.ron").unwrap();
    let w = Scene::parse(&written_out(), "written.ron").unwrap();
    assert_eq!(t, w);
    assert_eq!(t.spec().to_ron(), w.spec().to_ron());
    let CommandSpec::Slots(slots) = &t.spec().command else {
        panic!("a loaded template is Slots")
    };
    let names: Vec<&str> = slots.iter().map(|s| s.name.as_deref().unwrap()).collect();
    assert_eq!(names, ["j1", "j2", "j1", "j2", "j1"]);
    assert_eq!(
        slots[3].alphabet[2].action,
        Action::Torque {
            joint: "j2".into(),
            torque: 0.05
        }
    );
    assert_eq!(t.command_space().num_commands(), Some(243));
    // and it executes the same bits
    let (mut a, mut b) = (t.build(), w.build());
    for text in ["+-0+-", "--+++", "00000", "+0-0+"] {
        let c = t.command_space().parse(text).unwrap();
        assert_eq!(a.execute(&c).unwrap(), b.execute(&c).unwrap(), "{text}");
    }
    // `to_ron` reads back equal (the expanded form, with its declared count)
    assert_eq!(Scene::parse(&t.spec().to_ron(), "back.ron").unwrap(), t);
    assert!(t.spec().to_ron().contains("    slots: 5,\n"));
}

#[test]
fn a_template_built_in_code_is_validated_and_built() {
    let loaded = Scene::parse(TEMPLATE, "tmpl.ron").unwrap();
    let mut s = loaded.to_spec();
    s.command = CommandSpec::Template {
        slots: 5,
        alphabet: vec![
            e3d::scene::SymbolSpec {
                symbol: '-',
                action: Action::Torque {
                    joint: "*".into(),
                    torque: -0.05,
                },
            },
            e3d::scene::SymbolSpec {
                symbol: '0',
                action: Action::Idle,
            },
            e3d::scene::SymbolSpec {
                symbol: '+',
                action: Action::Torque {
                    joint: "*".into(),
                    torque: 0.05,
                },
            },
        ],
        cycle: vec!["j1".into(), "j2".into()],
    };
    assert!(s.validate().is_ok());
    let c = loaded.command_space().parse("+-0+-").unwrap();
    assert_eq!(
        s.validate().unwrap().build().execute(&c).unwrap(),
        loaded.build().execute(&c).unwrap()
    );
    s.expand().unwrap();
    assert_eq!(s, *loaded.spec());
    // a cycle naming a joint that does not exist
    if let CommandSpec::Slots(slots) = &mut s.command {
        slots[1].alphabet[0].action = Action::Torque {
            joint: "j9".into(),
            torque: 1.0,
        };
    }
    assert!(s.validate().is_err());
}

fn refused(text: &str) -> String {
    match Scene::parse(text, "t.ron") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => {
            assert!(matches!(e.kind(), SceneErrorKind::Invalid { .. }), "{e}");
            e.to_string()
        }
    }
}

#[test]
fn a_declared_count_that_the_command_does_not_have_is_refused_with_its_place() {
    let six_two = r#"Scene(
    name: "six_two",
    slots: 6,
    world: Grid(rows: 3, cols: 6, start: (0, 0)),
    command: Slots([
        (alphabet: [(symbol: 'E', action: Move(drow: 0, dcol: 1))]),
        (alphabet: [(symbol: 'S', action: Move(drow: 1, dcol: 0))]),
    ]),
)"#;
    assert_eq!(
        refused(six_two),
        "t.ron:5:14: field `Slots`: expected 6 slot(s), as the scene's `slots: 6` declares, found 2: `Slots` lists 2"
    );
    // the same count is accepted
    assert!(Scene::parse(&six_two.replace("slots: 6", "slots: 2"), "t.ron").is_ok());
    // a Repeat, a Template
    let rep = r#"Scene(name: "r", slots: 6, world: Grid(rows: 1, cols: 2, start: (0, 0)),
    command: Repeat(slots: 7, alphabet: [(symbol: 'E', action: Move(drow: 0, dcol: 1))]))"#;
    assert_eq!(
        refused(rep),
        "t.ron:2:14: field `Repeat`: expected 6 slot(s), as the scene's `slots: 6` declares, found 7: `Repeat` has `slots: 7`"
    );
    assert!(refused(&TEMPLATE.replacen("slots: 5", "slots: 6", 1))
        .starts_with("t.ron:10:14: field `Template`: expected 6 slot(s)"));
}

#[test]
fn template_mistakes_are_refused_with_their_place() {
    // `*` without a cycle
    let no_cycle = TEMPLATE.replace("        cycle: [\"j1\", \"j2\"],\n", "");
    assert_eq!(
        refused(&no_cycle),
        "t.ron:13:50: field `cycle`: expected a `cycle: [\"name\", ...]` of the joints or bodies that `*` stands for (slot k takes cycle[k mod m]), found none"
    );
    // a cycle that nothing uses
    let unused = TEMPLATE.replace("joint: \"*\"", "joint: \"j1\"");
    let e = refused(&unused);
    assert!(
        e.starts_with("t.ron:17:9: field `cycle`: expected an action naming `*`"),
        "{e}"
    );
    // a cycle naming a joint that does not exist: placed at the name
    let unknown = TEMPLATE.replace("[\"j1\", \"j2\"]", "[\"j1\", \"j7\"]");
    let e = refused(&unknown);
    assert_eq!(
        e,
        "t.ron:17:23: field `cycle`: expected cycle[1]: a joint (the alphabet's `*` names a joint), but there is no joint `j7` (did you mean `j1`?); joints: j1, j2"
    );
    // no slots, too many
    let zero = TEMPLATE.replace("slots: 5", "slots: 0");
    assert!(
        refused(&zero).contains("at least one slot"),
        "{}",
        refused(&zero)
    );
    let many = TEMPLATE
        .replacen("    slots: 5,\n", "", 1)
        .replace("slots: 5", "slots: 65");
    assert!(refused(&many).contains("between 1 and 64 slots, found 65"));
}

#[test]
fn scene_check_refuses_a_declared_count_with_its_place() {
    let dir = std::env::temp_dir().join(format!("e3d-slot-templates-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("six_two.ron");
    std::fs::write(
        &f,
        "Scene(\n    name: \"six_two\",\n    slots: 6,\n    world: Grid(rows: 3, cols: 6, start: (0, 0)),\n    command: Slots([\n        (alphabet: [(symbol: 'E', action: Move(drow: 0, dcol: 1))]),\n        (alphabet: [(symbol: 'S', action: Move(drow: 1, dcol: 0))]),\n    ]),\n)\n",
    )
    .unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_e3d"))
        .args(["scene", "check"])
        .arg(&f)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("six_two.ron:5:14: field `Slots`: expected 6 slot(s), as the scene's `slots: 6` declares, found 2"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A template whose cycle mixes a body and a joint: slot 0 pushes the
/// free puck with a `Force`, slot 1 turns the rod's hinge with a
/// `Torque`, each symbol written once per kind.
const MIXED: &str = include_str!("../scenes/mixed_template.ron");

#[test]
fn a_template_mixing_a_bodys_force_and_a_joints_torque_does_both() {
    let s = Scene::parse(MIXED, "mixed.ron").unwrap_or_else(|e| panic!("{e}"));
    let CommandSpec::Slots(slots) = &s.spec().command else {
        panic!("a loaded template is Slots")
    };
    assert_eq!(slots[0].name.as_deref(), Some("puck"));
    assert_eq!(
        slots[0].alphabet[2].action,
        Action::Force {
            body: "puck".into(),
            force: (1.0, 0.0)
        }
    );
    assert_eq!(
        slots[1].alphabet[0].action,
        Action::Torque {
            joint: "pin".into(),
            torque: -0.01
        }
    );
    assert_eq!(s.command_space().num_commands(), Some(9));
    // the puck's x and the hinge's angle at the end of a command
    let end = |c: &str| {
        let mut w = s.physics_world().unwrap();
        let m = w.motion(&s.command_space().parse(c).unwrap()).unwrap();
        let f = m.frames.last().unwrap();
        (f.poses[0].position[0], f.joint_angles[0])
    };
    let (both, push, turn) = (end("++"), end("+0"), end("0+"));
    // the two parts do not touch: the command's end is the sum of theirs
    assert_eq!(both, (push.0, turn.1));
    assert_eq!((turn.0, push.1), (0.0, 0.0));
    assert_eq!(end("--"), (-both.0, -both.1));
    // 1 N on 2 kg for 0.5 s, then 1 s at the speed reached: 0.3125 m;
    // 0.01 N·m on the rod (I = 0.5 (0.4² + 0.04²) / 12 kg·m²) in the
    // second phase, then 0.5 s at the spin reached: 0.557 rad
    let i = 0.5 * (0.4f64.powi(2) + 0.04f64.powi(2)) / 12.0;
    let (a, alpha) = (1.0 / 2.0, 0.01 / i);
    let x = a * 0.25 / 2.0 + a * 0.5 * 1.0;
    let angle = alpha * 0.25 / 2.0 + alpha * 0.5 * 0.5;
    println!(
        "mixed template: x {} for {x}, angle {} for {angle}",
        both.0, both.1
    );
    assert!((both.0 / x - 1.0).abs() < 0.02, "x {} for {x}", both.0);
    assert!(
        (both.1 / angle - 1.0).abs() < 0.02,
        "angle {} for {angle}",
        both.1
    );
}

#[test]
fn a_mixed_template_refuses_a_symbol_without_an_action_of_the_entrys_kind() {
    let one_sided = MIXED.replace(
        "            (symbol: '+', action: Force(body: \"*\", force: (1.0, 0.0))),\n",
        "",
    );
    assert_eq!(
        refused(&one_sided),
        "t.ron:27:9: field `cycle`: expected cycle[0]: `puck` is a body, so every symbol naming `*` needs an action on a body (Force or Impulse on \"*\"), but symbol '+' has none: in a cycle of joints and bodies, write each such symbol twice, once for each"
    );
    let e = refused(&MIXED.replace("[\"puck\", \"pin\"]", "[\"puck\", \"pim\"]"));
    assert!(
        e.starts_with("t.ron:28:9: field `cycle`: expected cycle[1]: a joint or a body (the alphabet's `*` names joints in some actions, bodies in others), but there is neither `pim` (did you mean `pin`?)"),
        "{e}"
    );
}
