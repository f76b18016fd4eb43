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
        r#"child: "lower""#,
        "child",
        "two different bodies, but it joins `lower` to itself",
    );
}

#[test]
fn a_mass_that_is_not_positive() {
    check(
        "mass: 0.2, position: (0.75",
        "mass: -0.2, position: (0.75",
        "mass: -0.2",
        "mass",
        "body `lower`: a mass > 0 in kg, found -0.2",
    );
}

#[test]
fn a_size_that_is_not_positive() {
    check(
        "shape: Cuboid(width: 4.0,",
        "shape: Cuboid(width: 0.0,",
        "shape: Cuboid(width: 0.0",
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
        "torque: inf",
        "torque",
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
        r#"action: Torque(joint: "hip""#,
        "action",
        "symbol '+': a known joint, but there is no joint `hip`; joints: shoulder, elbow",
    );
}

#[test]
fn a_target_on_a_joint_without_motor() {
    check(
        r#"Target(joint: "elbow""#,
        r#"Target(joint: "shoulder""#,
        r#"action: Target(joint: "shoulder""#,
        "action",
        "a Target on a joint with a `motor: (stiffness: ..., damping: ...)`, but joint `shoulder` has none",
    );
}

#[test]
fn a_move_in_a_physics_world() {
    check(
        "(symbol: '0', action: Idle)",
        "(symbol: '0', action: Move(drow: 0, dcol: 1))",
        "action: Move",
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
    assert!(e.starts_with("g.ron:6:23: "), "{e}");
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
        "child_anchor: (-0.25, 0.0), motor",
        "child_anchor",
        "joint `elbow`: anchors that meet at the start pose",
    );
}

#[test]
fn a_body_with_two_parents() {
    check(
        r#"child: "upper", child_anchor: (-0.25, 0.0)"#,
        r#"child: "lower", child_anchor: (-0.75, 0.0)"#,
        "child: \"lower\",\n",
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
        r#"child: "wall""#,
        "child",
        "a dynamic child body, but `wall` is Fixed",
    );
}

#[test]
fn mass_and_density_together() {
    check(
        "mass: 0.2, position: (0.75",
        "mass: 0.2, density: 3.0, position: (0.75",
        "mass: 0.2, density",
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
        "position: (0.0, -1.0)",
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

/// A scene that writes every number field of a physics scene (BASE leaves
/// many at their defaults).
const FULL: &str = r#"Scene(
    name: "full",
    world: Physics(
        gravity: (0.5, -9.81), dt: 0.05, max_speed: 50.0,
        bodies: [
            (name: "wall", kind: Fixed, shape: Cuboid(width: 4.0, height: 0.1), density: 2.0, position: (0.1, -1.0), angle: 0.1),
            (name: "upper", shape: Capsule(a: (-0.2, 0.0), b: (0.2, 0.0), radius: 0.05), mass: 0.2, position: (0.25, 0.0),
             friction: 0.3, restitution: 0.4),
            (name: "puck", shape: Ball(radius: 0.1), mass: 1.0, position: (3.0, 3.0),
             linear_damping: 0.1, angular_damping: 0.2),
            (name: "lower", shape: Ball(radius: 0.1), density: 3.0, position: (0.75, 0.0)),
            (name: "rail", kind: Fixed, shape: Segment(a: (-1.0, 0.5), b: (1.0, 0.5))),
            (name: "fence", kind: Fixed, shape: Polyline(points: [(-1.0, 0.9), (0.0, 0.8), (1.0, 0.9)])),
        ],
        joints: [
            (name: "shoulder", parent: "ground", child: "upper", parent_anchor: (0.0, 0.0), child_anchor: (-0.25, 0.0),
             limits: (-1.5, 1.5), damping: 0.01),
            (name: "elbow", parent: "upper", child: "lower",
             parent_anchor: (0.25, 0.0), child_anchor: (-0.25, 0.0), motor: (stiffness: 5.0, damping: 0.5)),
        ],
        schedule: Simultaneous(push: 0.25, settle: 0.5),
        effect: (body: "lower", point: (0.05, 0.02),
                 grid: (rows: 4, cols: 4, min: (-1.5, -1.5), max: (1.5, 1.5))),
    ),
    command: Slots([
        (alphabet: [(symbol: '-', action: Torque(joint: "shoulder", torque: -1.0)),
                    (symbol: 'i', action: Impulse(body: "puck", impulse: (0.1, 0.2))),
                    (symbol: 'f', action: Force(body: "upper", force: (0.3, -0.4)))]),
        (alphabet: [(symbol: '0', action: Idle),
                    (symbol: 't', action: Target(joint: "elbow", angle: 0.5))]),
    ]),
    reward: (cells: [(0, 0)], value: 2.0),
)"#;

/// The byte ranges of the numbers written in `text` (outside strings and
/// symbols).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = (b[i].is_ascii_digit()
            || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit)))
            && i > 0
            && !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'\'' || b[i - 1] == b'_');
        if starts {
            let mut j = i + 1;
            while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.' || b[j] == b'e') {
                j += 1;
            }
            out.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

#[test]
fn every_number_field_refuses_what_f32_cannot_hold() {
    Scene::parse(FULL, "full.ron").expect("the full scene is valid");
    let spots = numbers(FULL);
    assert!(spots.len() >= 60, "only {} numbers", spots.len());
    let line_re = |e: &str| {
        let rest = e.strip_prefix("full.ron:")?;
        let mut it = rest.splitn(3, ':');
        let l: usize = it.next()?.parse().ok()?;
        let c: usize = it.next()?.parse().ok()?;
        Some((l, c))
    };
    let mut refused = 0;
    for &(a, z) in &spots {
        let written = &FULL[a..z];
        // the reward's value is not simulated: NaN and inf are refused,
        // huge values are fine (f64)
        let in_reward = FULL[..a].contains("reward: (");
        for bad in ["NaN", "inf", "-inf", "1e39", "-1e39", "1e-40", "-1e-40"] {
            if in_reward && !matches!(bad, "NaN" | "inf" | "-inf") {
                continue;
            }
            let text = format!("{}{bad}{}", &FULL[..a], &FULL[z..]);
            let e = match Scene::parse(&text, "full.ron") {
                Ok(_) => panic!("`{written}` at byte {a} replaced by {bad} is accepted"),
                Err(e) => e.to_string(),
            };
            assert!(
                line_re(&e).is_some() && e.contains("field `"),
                "`{written}` -> {bad}: `{e}` lacks its place or field"
            );
            refused += 1;
        }
    }
    assert_eq!(refused, 492);
}

#[test]
fn overflowing_numbers_are_refused_with_the_value_and_the_limit() {
    // a torque Rapier's motor constraint panicked on (exit 101)
    check(
        "torque: 1.0",
        "torque: 1e37",
        "torque: 1e37",
        "torque",
        "symbol '+': a torque that adds at most 1e6 rad/s to a body in one step, but 1e37 N·m adds",
    );
    // a joint damping that is infinite in f32
    check(
        r#"child_anchor: (-0.25, 0.0)),"#,
        r#"child_anchor: (-0.25, 0.0), damping: 1e39),"#,
        "damping: 1e39",
        "damping",
        "joint `shoulder`: a damping in [0, 1e9] N·m·s/rad, 0 or at least 1.2e-38 in magnitude (f32), found 1e39",
    );
    // a mass that is 0 in f32, one that is infinite
    for m in ["1e-46", "4e38"] {
        check(
            "mass: 0.2, position: (0.75",
            &format!("mass: {m}, position: (0.75"),
            &format!("mass: {m}"),
            "mass",
            &format!("body `lower`: a mass in [1e-6, 1e9] kg, found {m}"),
        );
    }
    // a density whose mass is out of range
    check(
        "mass: 0.2, position: (0.75",
        "density: 1e-5, position: (0.75",
        "density: 1e-5",
        "density",
        "body `lower`: a mass (density x area) in [1e-6, 1e9] kg, found 2.5e-7",
    );
    // Rapier's own 400 m/s cap must not be reached before the check
    check(
        "schedule:",
        "max_speed: 400.0, schedule:",
        "max_speed:",
        "max_speed",
        "a speed in [1.2e-38, 399] m/s (Rapier caps speeds at 400 m/s, silently), found 400",
    );
    check(
        "schedule:",
        "gravity: (1e20, 0.0), schedule:",
        "gravity:",
        "gravity",
        "components |value| <= 1e6 m/s², 0 or at least 1.2e-38 in magnitude (f32), found 1e20",
    );
}

#[test]
fn numbers_at_the_limits_simulate_without_panic() {
    // the largest torque the limit lets through, on the lightest links, with
    // the stiffest motor: reported as a blow-up (or not), never a panic
    let text = BASE
        .replace("mass: 0.2", "mass: 0.000001")
        .replace(
            "motor: (stiffness: 5.0)",
            "motor: (stiffness: 1e9, damping: 1e9), damping: 1e9",
        )
        .replace("torque: -1.0", "torque: -1.2")
        .replace("torque: 1.0", "torque: 1.2");
    let s = Scene::parse(&text, "s.ron").unwrap();
    let mut w = s.build();
    for c in ["+t", "-t", "+0", "-0"] {
        let c = w.command_space().parse(c).unwrap();
        let _ = w.execute(&c);
    }
    // one step further is refused
    let over = text.replace("torque: 1.2", "torque: 1.3");
    let e = Scene::parse(&over, "s.ron").unwrap_err().to_string();
    assert!(e.contains("adds 1.0297e6 rad/s to `upper`"), "{e}");
}

/// A scene of `n` balls (fixed, so that nothing is simulated).
fn many_bodies(n: usize) -> String {
    let bodies: String = (0..n)
        .map(|i| {
            format!(
                "(name: \"b{i}\", kind: Fixed, shape: Ball(radius: 0.1), position: ({}.0, 5.0)),\n",
                i % 1000
            )
        })
        .collect();
    BASE.replacen(
        "        bodies: [\n",
        &format!("        bodies: [\n{bodies}"),
        1,
    )
}

#[test]
fn body_names_are_checked_in_linear_time_and_bodies_are_capped() {
    // 40,000 bodies took 21.6 s to validate (every name against every
    // earlier one); the time of 10,000 is a benchmark (benches/physics.rs,
    // `scene_parse/10000_bodies`), not a test: CI machines are loaded
    let text = many_bodies(10_000 - 3);
    Scene::parse(&text, "s.ron").unwrap();
    let e = Scene::parse(&many_bodies(10_000 - 2), "s.ron")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("s.ron:4:9: field `bodies`: expected at most 10000 bodies, found 10001"),
        "{e}"
    );
    // a duplicate among many is still found, and pointed at
    let dup = text.replacen("(name: \"b9000\",", "(name: \"b17\",", 1);
    let e = Scene::parse(&dup, "s.ron").unwrap_err().to_string();
    assert!(
        e.contains("distinct body names, but `b17` is used twice"),
        "{e}"
    );
    assert!(e.starts_with("s.ron:9005:"), "{e}");
}

/// Drag and inertia: numbers checked at load, on dynamic bodies only,
/// and a drag weak enough for one explicit step.
#[test]
fn a_drag_or_an_inertia_that_cannot_be() {
    let lower = "mass: 0.2, position: (0.75, 0.0)),";
    check(
        lower,
        "mass: 0.2, position: (0.75, 0.0), drag: (along: 0.1, across: 20.0)),",
        "across: 20.0",
        "across",
        "body `lower`: a drag of at most mass / dt = 12.0000 (one step of 0.016666666666666666 s would reverse the motion), found 20",
    );
    check(
        lower,
        "mass: 0.2, position: (0.75, 0.0), drag: (along: -0.1, across: 1.0)),",
        "along: -0.1",
        "along",
        "a finite drag >= 0, found -0.1",
    );
    check(
        lower,
        "mass: 0.2, position: (0.75, 0.0), inertia: 0.0),",
        "inertia: 0.0",
        "inertia",
        "body `lower`: an inertia > 0 in kg·m², found 0",
    );
    check(
        "position: (0.0, -1.0)),",
        "position: (0.0, -1.0), drag: (along: 0.1, across: 1.0)),",
        "drag:",
        "drag",
        "body `wall`: no `drag` here, because `wall` is Fixed: it never moves",
    );
}

/// A centre-of-mass feature names known, dynamic bodies, each once.
#[test]
fn a_centre_of_mass_of_bodies_that_cannot_be() {
    let from = r#"effect: (body: "lower", point: (0.25, 0.0),
                 grid: (rows: 4, cols: 4, min: (-1.0, -1.0), max: (1.0, 1.0))),"#;
    let centre = |bodies: &str| {
        format!("effect: (features: [Centre(bodies: [{bodies}], grid: (rows: 4, cols: 4, min: (-1.0, -1.0), max: (1.0, 1.0)))]),")
    };
    let ok = BASE.replacen(from, &centre(r#""upper", "lower""#), 1);
    let s = Scene::parse(&ok, "s.ron").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.num_effects(), 16);
    let e = error(from, &centre(r#""upper", "wall""#));
    assert!(
        e.contains("field `bodies`") && e.contains("`wall` never moves"),
        "{e}"
    );
    let e = error(from, &centre(r#""upper", "upper""#));
    assert!(e.contains("`upper` is twice"), "{e}");
    let e = error(from, &centre(r#""uper""#));
    assert!(e.contains("no body `uper`"), "{e}");
}
