//! Scene mistakes in physics scenes: each is refused with the file, the
//! line and column, the field and what was expected.

use e3d::Scene;

/// A small valid physics scene; tests replace one piece of it.
const BASE: &str = r#"Scene(
    name: "base",
    world: Physics(
        bodies: [
            (name: "wall", kind: Fixed, shape: Cuboid(width: 4.0, height: 0.1), position: (0.0, -1.0)),
            (name: "upper", shape: Cuboid(width: 0.5, height: 0.05), mass: 0.2, position: (0.25, 0.0)),
            (name: "lower", shape: Cuboid(width: 0.5, height: 0.05), mass: 0.2, position: (0.75, 0.0)),
        ],
        joints: [
            (name: "shoulder", parent: "ground", child: "upper", child_anchor: (-0.25, 0.0)),
            (name: "elbow", parent: "upper", child: "lower",
             parent_anchor: (0.25, 0.0), child_anchor: (-0.25, 0.0), motor: (stiffness: 5.0)),
        ],
        schedule: Simultaneous(push: 0.25, settle: 0.5),
        effect: (body: "lower", point: (0.25, 0.0),
                 grid: (rows: 4, cols: 4, min: (-1.0, -1.0), max: (1.0, 1.0))),
    ),
    command: Slots([
        (alphabet: [(symbol: '-', action: Torque(joint: "shoulder", torque: -1.0)),
                    (symbol: '+', action: Torque(joint: "shoulder", torque: 1.0))]),
        (alphabet: [(symbol: '0', action: Idle),
                    (symbol: 't', action: Target(joint: "elbow", angle: 0.5))]),
    ]),
)"#;

/// Parses BASE with `from` replaced by `to` (which must occur once) and
/// returns the error's text.
fn error(from: &str, to: &str) -> String {
    assert_eq!(BASE.matches(from).count(), 1, "`{from}` must occur once");
    let text = BASE.replacen(from, to, 1);
    match Scene::parse(&text, "s.ron") {
        Ok(_) => panic!("accepted: {to}"),
        Err(e) => e.to_string(),
    }
}

/// The 1-based line and column of the first occurrence of `needle` in the
/// edited text.
fn pos(from: &str, to: &str, needle: &str) -> String {
    let text = BASE.replacen(from, to, 1);
    let at = text.find(needle).expect("needle");
    let line = text[..at].matches('\n').count() + 1;
    let col = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
    format!("s.ron:{line}:{col}: ")
}

fn check(from: &str, to: &str, needle: &str, field: &str, expect: &str) {
    let e = error(from, to);
    let p = pos(from, to, needle);
    assert!(e.starts_with(&p), "`{e}` should start with `{p}`");
    assert!(
        e.contains(&format!("field `{field}`")),
        "`{e}` should name field `{field}`"
    );
    assert!(e.contains(expect), "`{e}` should say `{expect}`");
}

#[test]
fn the_base_scene_is_valid() {
    let s = Scene::parse(BASE, "s.ron").unwrap();
    assert_eq!(s.num_effects(), 16);
    let mut w = s.build();
    let c = w.command_space().parse("+t").unwrap();
    assert!(w.execute(&c).is_ok());
}

#[test]
fn an_unknown_body_in_a_joint() {
    check(
        r#"child: "lower""#,
        r#"child: "lowr""#,
        r#""lowr""#,
        "child",
        "a known body, but there is no body `lowr` (did you mean `lower`?)",
    );
}

#[test]
fn a_duplicate_body_name() {
    let e = error(r#"(name: "lower","#, r#"(name: "upper","#);
    // the second `"upper"` (line 7, where "lower" was) is the duplicate
    assert!(e.starts_with("s.ron:7:20: "), "{e}");
    assert!(
        e.contains("field `name`") && e.contains("distinct body names, but `upper` is used twice"),
        "{e}"
    );
}

#[test]
fn a_joint_from_a_body_to_itself() {
    check(
        r#"(name: "elbow", parent: "upper", child: "lower""#,
        r#"(name: "elbow", parent: "lower", child: "lower""#,
        r#""elbow""#,
        "child",
        "two different bodies, but it joins `lower` to itself",
    );
}

#[test]
fn a_mass_that_is_not_positive() {
    check(
        "mass: 0.2, position: (0.75",
        "mass: -0.2, position: (0.75",
        r#""lower""#,
        "mass",
        "body `lower`: a mass > 0 in kg, found -0.2",
    );
}

#[test]
fn a_size_that_is_not_positive() {
    check(
        "shape: Cuboid(width: 4.0,",
        "shape: Cuboid(width: 0.0,",
        r#""wall""#,
        "shape",
        "body `wall`: a width and height > 0, found 0 x 0.1",
    );
}

#[test]
fn a_number_that_is_not_finite() {
    check(
        "push: 0.25",
        "push: NaN",
        "push:",
        "push",
        "a duration >= 0 in seconds, found NaN",
    );
    check(
        "torque: 1.0",
        "torque: inf",
        "'+'",
        "action",
        "symbol '+': a finite torque in N·m, found inf",
    );
}

#[test]
fn a_tracked_point_on_a_missing_body() {
    check(
        r#"effect: (body: "lower""#,
        r#"effect: (body: "hand""#,
        r#""hand""#,
        "body",
        "the effect's tracked point: a known body, but there is no body `hand`",
    );
}

#[test]
fn an_unknown_joint_in_an_action() {
    check(
        r#"Torque(joint: "shoulder", torque: 1.0)"#,
        r#"Torque(joint: "hip", torque: 1.0)"#,
        "'+'",
        "action",
        "symbol '+': a known joint, but there is no joint `hip`; joints: shoulder, elbow",
    );
}

#[test]
fn a_target_on_a_joint_without_motor() {
    check(
        r#"Target(joint: "elbow""#,
        r#"Target(joint: "shoulder""#,
        "'t'",
        "action",
        "a Target on a joint with a `motor: (stiffness: ..., damping: ...)`, but joint `shoulder` has none",
    );
}

#[test]
fn a_move_in_a_physics_world() {
    check(
        "(symbol: '0', action: Idle)",
        "(symbol: '0', action: Move(drow: 0, dcol: 1))",
        "'0'",
        "action",
        "Move is for Grid worlds",
    );
}

#[test]
fn an_actuator_symbol_in_a_grid_world() {
    let text = r#"Scene(
    name: "g",
    world: Grid(rows: 2, cols: 2, start: (0, 0)),
    command: Repeat(slots: 2, alphabet: [
        (symbol: 'E', action: Move(drow: 0, dcol: 1)),
        (symbol: 'T', action: Torque(joint: "j1", torque: 1.0)),
    ]),
)"#;
    let e = Scene::parse(text, "g.ron").unwrap_err().to_string();
    assert!(e.starts_with("g.ron:6:18: "), "{e}");
    assert!(
        e.contains("field `action`")
            && e.contains("symbol 'T': a Grid world takes Move or Idle actions only"),
        "{e}"
    );
}

#[test]
fn anchors_that_do_not_meet() {
    check(
        "parent_anchor: (0.25, 0.0), child_anchor",
        "parent_anchor: (0.2, 0.0), child_anchor",
        r#""elbow""#,
        "child_anchor",
        "joint `elbow`: anchors that meet at the start pose",
    );
}

#[test]
fn a_body_with_two_parents() {
    check(
        r#"child: "upper", child_anchor: (-0.25, 0.0)"#,
        r#"child: "lower", child_anchor: (-0.75, 0.0)"#,
        r#""elbow""#,
        "child",
        "a body that is the child of one joint only (joints form trees), but `lower` is already the child of `shoulder`",
    );
}

#[test]
fn a_duration_that_is_not_a_whole_number_of_steps() {
    check(
        "settle: 0.5",
        "settle: 0.51",
        "settle:",
        "settle",
        "a whole number of time steps",
    );
}

#[test]
fn a_child_that_is_fixed() {
    check(
        r#"child: "upper""#,
        r#"child: "wall""#,
        r#""shoulder""#,
        "child",
        "a dynamic child body, but `wall` is Fixed",
    );
}

#[test]
fn mass_and_density_together() {
    check(
        "mass: 0.2, position: (0.75",
        "mass: 0.2, density: 3.0, position: (0.75",
        r#""lower""#,
        "mass",
        "`mass` or `density`, not both",
    );
}

#[test]
fn a_body_named_ground() {
    check(
        r#"(name: "wall""#,
        r#"(name: "ground""#,
        r#""ground""#,
        "name",
        "a body name other than `ground`",
    );
}

#[test]
fn an_unknown_field_is_named_with_a_suggestion() {
    let e = error("mass: 0.2, position: (0.75", "mas: 0.2, position: (0.75");
    assert!(e.starts_with("s.ron:7:"), "{e}");
    assert!(
        e.contains("unknown field `mas`") && e.contains("did you mean `mass`?"),
        "{e}"
    );
}

#[test]
fn a_reward_region_outside_every_cell() {
    let text = BASE.replacen(
        "    command: Slots([",
        "    reward: (regions: [(name: \"far\", min: (5.0, 5.0), max: (6.0, 6.0))]),\n    command: Slots([",
        1,
    );
    let e = Scene::parse(&text, "s.ron").unwrap_err().to_string();
    assert!(e.starts_with("s.ron:18:31: "), "{e}");
    assert!(
        e.contains("field `regions`: expected region `far`: a rectangle holding the centre of at least one effect cell"),
        "{e}"
    );
    // a region over cells gives their reward
    let ok = BASE.replacen(
        "    command: Slots([",
        "    reward: (regions: [(name: \"right\", min: (0.0, -1.0), max: (1.0, 1.0))]),\n    command: Slots([",
        1,
    );
    let s = Scene::parse(&ok, "s.ron").unwrap();
    let r = s.reward_table();
    assert_eq!(r.iter().filter(|&&v| v == 1.0).count(), 8);
    assert_eq!((r[2], r[3], r[0]), (1.0, 1.0, 0.0));
}

#[test]
fn a_symmetry_the_scene_does_not_have() {
    let sched = "schedule: Simultaneous(push: 0.25, settle: 0.5),";
    // the wall lies off the mirror line
    check(
        sched,
        &format!("{sched} symmetry: FlipY,"),
        r#""wall""#,
        "position",
        "symmetry FlipY: every body its own mirror image, on the mirror line (y = 0), but `wall` is at (0.0, -1.0)",
    );
    // about the y axis, the bodies do not point along the line
    check(
        sched,
        &format!("{sched} symmetry: FlipX,"),
        r#""wall""#,
        "angle",
        "symmetry FlipX: every body along the mirror line (angle pi/2 or -pi/2), but `wall` has angle 0",
    );
}

#[test]
fn a_symmetry_without_the_mirror_image_of_a_symbol() {
    // arm7 declares FlipY; a torque without its opposite breaks it, and the
    // error points at that slot's symbol, not at the first '+'
    let text = std::fs::read_to_string("scenes/arm7.ron").unwrap();
    let from = r#"(symbol: '+', action: Torque(joint: "j7", torque: 0.06))"#;
    assert_eq!(text.matches(from).count(), 1);
    let bad = text.replacen(
        from,
        r#"(symbol: '+', action: Torque(joint: "j7", torque: 0.07))"#,
        1,
    );
    let e = Scene::parse(&bad, "arm7.ron").unwrap_err().to_string();
    let at = bad.find(r#"'-', action: Torque(joint: "j7""#).unwrap();
    let line = bad[..at].matches('\n').count() + 1;
    assert!(e.starts_with(&format!("arm7.ron:{line}:")), "{e}");
    assert!(
        e.contains("field `action`")
            && e.contains("symmetry FlipY: the mirror image of every symbol's action in the same slot, but slot 6 has none for '-'"),
        "{e}"
    );
}
