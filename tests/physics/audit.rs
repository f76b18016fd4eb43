//! The audit of docs/physics.md: every body field and every action on
//! every kind of body (a free body, the root of a chain hung on `ground`,
//! a link of it, the root of a free-floating chain, a link of it, a fixed
//! body) either acts as documented or is refused at load with the field's
//! line:column and what to write instead. Nothing is a silent no-op.

use e3d::Scene;

/// The kinds of body, and the body of that kind in [`world`].
const KINDS: [(&str, &str); 6] = [
    ("free body", "puck"),
    ("root of a chain on ground", "g1"),
    ("link of a chain on ground", "g2"),
    ("root of a free-floating chain", "f1"),
    ("link of a free-floating chain", "f2"),
    ("fixed body", "wall"),
];

/// A world holding one body of each kind, `field` added to body `target`
/// (on a line of its own), the command's one symbol doing `action`.
fn world(target: &str, field: &str, action: &str) -> String {
    let body = |name: &str, rest: &str| {
        let extra = if name == target {
            format!(",\n             {field}")
        } else {
            String::new()
        };
        format!("            (name: \"{name}\", {rest}{extra}),\n")
    };
    let mut bodies = String::new();
    bodies += &body(
        "puck",
        "shape: Ball(radius: 0.1), mass: 1.0, position: (0.0, 2.0)",
    );
    bodies += &body(
        "g1",
        "shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (0.2, 0.0)",
    );
    bodies += &body(
        "g2",
        "shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (0.6, 0.0)",
    );
    bodies += &body(
        "f1",
        "shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (0.2, -2.0)",
    );
    bodies += &body(
        "f2",
        "shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (0.6, -2.0)",
    );
    bodies += &body(
        "wall",
        "kind: Fixed, shape: Cuboid(width: 0.1, height: 1.0), position: (3.0, 0.0)",
    );
    format!(
        r#"Scene(
    name: "audit",
    world: Physics(
        bodies: [
{bodies}        ],
        joints: [
            (name: "jg1", parent: "ground", child: "g1", child_anchor: (-0.2, 0.0)),
            (name: "jg2", parent: "g1", child: "g2", parent_anchor: (0.2, 0.0), child_anchor: (-0.2, 0.0)),
            (name: "jf2", parent: "f1", child: "f2", parent_anchor: (0.2, 0.0), child_anchor: (-0.2, 0.0)),
        ],
        schedule: Simultaneous(push: 0.5, settle: 0.5),
        effect: (body: "puck", grid: (rows: 2, cols: 2, min: (-4.0, -4.0), max: (4.0, 4.0))),
    ),
    command: Slots([(alphabet: [(symbol: 'a', action: {action}), (symbol: '0', action: Idle)])]),
)"#
    )
}

/// The line (1-based) on which `needle` starts in `text`.
fn line_of(text: &str, needle: &str) -> usize {
    let at = text.find(needle).unwrap_or_else(|| panic!("no {needle}"));
    text[..at].matches('\n').count() + 1
}

/// The terminal state of every body after `a` and after `0` (Idle).
fn states(text: &str) -> (Vec<[f64; 6]>, Vec<[f64; 6]>) {
    let s = Scene::parse(text, "audit.ron").unwrap_or_else(|e| panic!("{e}"));
    let mut w = s.physics_world().unwrap();
    let run = |w: &mut e3d::world::PhysicsWorld, c: &str| {
        let m = w.motion(&s.command_space().parse(c).unwrap()).unwrap();
        let f = m.frames.last().unwrap();
        f.poses
            .iter()
            .zip(&f.velocities)
            .map(|(p, v)| [p.position[0], p.position[1], p.angle, v[0], v[1], v[2]])
            .collect::<Vec<_>>()
    };
    (run(&mut w, "a"), run(&mut w, "0"))
}

fn index(body: &str) -> usize {
    ["puck", "g1", "g2", "f1", "f2", "wall"]
        .iter()
        .position(|b| *b == body)
        .unwrap()
}

/// Loads `field` on every kind of body: where refused, the error names
/// the file, the field's line and column and what to write instead.
fn refused_or_loaded(field: &str, name: &str) -> Vec<(&'static str, Result<Scene, String>)> {
    KINDS
        .iter()
        .map(|(kind, body)| {
            let text = world(body, field, "Idle");
            let r = Scene::parse(&text, "audit.ron").map_err(|e| {
                let msg = e.to_string();
                let line = line_of(&text, field.split(':').next().unwrap());
                assert!(
                    msg.starts_with(&format!("audit.ron:{line}:")),
                    "{name} on {kind}: `{msg}` is not placed at line {line}"
                );
                assert!(msg.contains(name), "{msg}");
                msg
            });
            (*kind, r)
        })
        .collect()
}

/// `linear_damping` and `angular_damping`: act on free bodies and on
/// free-floating chains (the body slows down as docs/scenes.md says);
/// refused on links of chains hung on ground (damp the joint instead)
/// and on fixed bodies.
#[test]
fn damping_acts_or_is_refused_on_every_kind_of_body() {
    for (field, name) in [
        ("linear_damping: 2.0", "linear_damping"),
        ("angular_damping: 2.0", "angular_damping"),
    ] {
        for (kind, r) in refused_or_loaded(field, name) {
            let body = KINDS.iter().find(|k| k.0 == kind).unwrap().1;
            let acts = matches!(body, "puck" | "f1" | "f2");
            match r {
                Ok(_) => {
                    assert!(acts, "{name} on {kind} loads but cannot act");
                    // a push, damped and undamped
                    let push = if name == "linear_damping" {
                        format!("Impulse(body: \"{body}\", impulse: (0.5, 0.2))")
                    } else {
                        "Torque(joint: \"jf2\", torque: 0.3)".to_string()
                    };
                    let push = if body == "puck" && name == "angular_damping" {
                        "Force(body: \"puck\", force: (0.0, 0.0))".to_string()
                    } else {
                        push
                    };
                    let (damped, _) = states(&world(body, field, &push));
                    let (plain, _) = states(&world(body, "friction: 0.5", &push));
                    let i = index(body);
                    if body == "puck" && name == "angular_damping" {
                        // a ball without spin: nothing to damp; the law
                        // test checks the decay of a spinning body
                        continue;
                    }
                    let speed = |s: &[[f64; 6]]| s[i][3].hypot(s[i][4]) + s[i][5].abs();
                    println!(
                        "audit {name} on {kind}: speed {:.4} damped, {:.4} undamped",
                        speed(&damped),
                        speed(&plain)
                    );
                    assert!(
                        speed(&damped) < 0.9 * speed(&plain),
                        "{name} on {kind} does not slow it down"
                    );
                }
                Err(msg) => {
                    assert!(!acts, "{name} on {kind} refused: {msg}");
                    println!("audit {name} on {kind}: refused: {msg}");
                }
            }
        }
    }
}

/// `lock_rotation`: keeps a free body and a free-floating chain's root
/// from turning; refused on links of chains hung on ground and on fixed
/// bodies.
#[test]
fn lock_rotation_acts_or_is_refused_on_every_kind_of_body() {
    for (kind, r) in refused_or_loaded("lock_rotation: true", "lock_rotation") {
        let body = KINDS.iter().find(|k| k.0 == kind).unwrap().1;
        match r {
            Ok(_) => {
                // an off-centre push: a torque on the joint turns a chain,
                // a force with a torque... a free body is pushed by the
                // wall-less impulse (no spin); turn the chains by their joint
                let push = match body {
                    "puck" => "Impulse(body: \"puck\", impulse: (0.5, 0.2))",
                    _ => "Torque(joint: \"jf2\", torque: 0.5)",
                };
                let (locked, _) = states(&world(body, "lock_rotation: true", push));
                let (free, _) = states(&world(body, "friction: 0.5", push));
                let i = index(body);
                println!(
                    "audit lock_rotation on {kind}: angle {:.2e} locked, {:.4} free",
                    locked[i][2], free[i][2]
                );
                assert!(
                    locked[i][2].abs() < 1e-6,
                    "{kind} turned by {}",
                    locked[i][2]
                );
                if body != "puck" {
                    assert!(
                        free[i][2].abs() > 1e-3,
                        "{kind}: the push turns it when free"
                    );
                }
                assert!(matches!(body, "puck" | "f1" | "f2"), "{kind} loads");
            }
            Err(msg) => {
                assert!(
                    matches!(body, "g1" | "g2" | "wall"),
                    "{kind} refused: {msg}"
                );
                println!("audit lock_rotation on {kind}: refused: {msg}");
            }
        }
    }
}

/// Actions on every kind of body: `Impulse` changes the momentum by J on a
/// free body and on free-floating chains, and is refused on links of a
/// chain hung on ground (use `Force`) and on a fixed body; `Force` acts on
/// every dynamic body and is refused on a fixed one.
#[test]
fn impulses_and_forces_act_or_are_refused_on_every_kind_of_body() {
    for (what, action) in [
        ("Impulse", "Impulse(body: \"B\", impulse: (0.5, 0.2))"),
        ("Force", "Force(body: \"B\", force: (2.0, 0.5))"),
    ] {
        for (kind, body) in KINDS {
            let text = world(body, "friction: 0.5", &action.replace('B', body));
            match Scene::parse(&text, "audit.ron") {
                Ok(_) => {
                    let (a, idle) = states(&text);
                    let i = index(body);
                    let moved = (a[i][0] - idle[i][0]).hypot(a[i][1] - idle[i][1]);
                    println!("audit {what} on {kind}: moves it {moved:.4} m");
                    assert!(moved > 1e-3, "{what} on {kind} is a no-op");
                    assert!(
                        what == "Force" && body != "wall" || matches!(body, "puck" | "f1" | "f2"),
                        "{what} on {kind} loads"
                    );
                }
                Err(e) => {
                    let msg = e.to_string();
                    let line = line_of(&text, "(symbol: 'a'");
                    assert!(msg.starts_with(&format!("audit.ron:{line}:")), "{msg}");
                    println!("audit {what} on {kind}: refused: {msg}");
                    let expected_refusal =
                        body == "wall" || (what == "Impulse" && matches!(body, "g1" | "g2"));
                    assert!(expected_refusal, "{what} on {kind} refused: {msg}");
                    if body != "wall" {
                        assert!(msg.contains("Force(body:"), "says what to write: {msg}");
                    }
                }
            }
        }
    }
}

/// `Torque` acts on hinges whatever their trees; a `Torque` on a slider is
/// refused (push its child with `Force`).
#[test]
fn torques_act_on_hinges_and_are_refused_on_sliders() {
    for joint in ["jg1", "jg2", "jf2"] {
        let text = world(
            "puck",
            "friction: 0.5",
            &format!("Torque(joint: \"{joint}\", torque: 0.5)"),
        );
        let (a, idle) = states(&text);
        let turned: f64 = a.iter().zip(&idle).map(|(x, y)| (x[2] - y[2]).abs()).sum();
        assert!(turned > 1e-3, "Torque on {joint} is a no-op");
    }
    let text = world("puck", "friction: 0.5", "Idle").replace(
        "(name: \"jf2\", parent: \"f1\", child: \"f2\",",
        "(name: \"jf2\", parent: \"f1\", child: \"f2\", kind: Prismatic(axis: (1.0, 0.0)),",
    );
    let text = text.replace(
        "action: Idle), (symbol: '0'",
        "action: Torque(joint: \"jf2\", torque: 0.5)), (symbol: '0'",
    );
    let msg = Scene::parse(&text, "audit.ron").unwrap_err().to_string();
    assert!(
        msg.contains("is a slider") && msg.contains("Force(body: \"f2\""),
        "{msg}"
    );
}

/// `e3d scene check --samples N` on every shipped scene, for several N
/// (continuous scenes included): no panic, exit code 0.
#[test]
fn scene_check_samples_never_panics() {
    for &(scene, _) in e3d::scene::BUILTIN {
        for n in ["0", "1", "2", "7"] {
            let out = std::process::Command::new(env!("CARGO_BIN_EXE_e3d"))
                .args(["scene", "check", "--samples", n, scene])
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(out.status.success(), "{scene} --samples {n}: {err}");
            assert!(!err.contains("panicked"), "{scene} --samples {n}: {err}");
        }
    }
}

/// The slider example of docs/scenes.md loads and its cart slides.
#[test]
fn the_slider_example_of_the_docs_loads() {
    let doc = include_str!("../../docs/scenes.md");
    let start = doc.find("<!-- example: slider -->").expect("the example");
    let text = &doc[start..];
    let text = &text[text.find("```ron").unwrap() + 6..];
    let text = &text[..text.find("```").unwrap()];
    let s = Scene::parse(text, "docs/scenes.md").unwrap_or_else(|e| panic!("{e}"));
    let mut w = s.physics_world().unwrap();
    let m = w.motion(&s.command_space().parse("+").unwrap()).unwrap();
    let q = m.frames.last().unwrap().joint_angles[0];
    assert!(q > 0.1, "the cart moved {q} m");
}
