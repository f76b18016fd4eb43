//! The `chains` and `walls` shorthands: the shipped scenes written with them
//! expand to exactly the scenes they replaced (kept in `tests/scenes/*_expanded.ron`),
//! and mistakes in them are refused with the shorthand's place in the file.

use e3d::scene::{Scene, WorldSpec};

/// `scenes/NAME.ron` (with shorthands) and `tests/scenes/NAME_expanded.ron`
/// (the scene as it was written before, body by body): equal once loaded.
fn same_as_before(name: &str) {
    let new = Scene::load(format!("scenes/{name}.ron")).unwrap();
    let old = Scene::load(format!("tests/scenes/{name}_expanded.ron")).unwrap();
    let text = std::fs::read_to_string(format!("scenes/{name}.ron")).unwrap();
    assert!(
        text.contains("chains:") || text.contains("walls:"),
        "{name} uses no shorthand"
    );
    let (WorldSpec::Physics(n), WorldSpec::Physics(o)) = (&new.spec().world, &old.spec().world)
    else {
        panic!("{name}: not physics")
    };
    assert_eq!(n.bodies.len(), o.bodies.len(), "{name}");
    for (a, b) in n.bodies.iter().zip(&o.bodies) {
        assert_eq!(a, b, "{name}: body {}", b.name);
        // bit for bit, not just ==
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "{name}");
    }
    assert_eq!(n.joints, o.joints, "{name}");
    assert!(n.chains.is_empty() && n.walls.is_empty());
    assert_eq!(new, old, "{name}");
    assert_eq!(new.spec().to_ron(), old.spec().to_ron(), "{name}");
}

#[test]
fn arm7_expands_to_the_scene_it_replaced() {
    same_as_before("arm7");
}

#[test]
fn puck_rooms_expands_to_the_scene_it_replaced() {
    same_as_before("puck_rooms");
}

#[test]
fn arm4_gravity_expands_to_the_scene_it_replaced() {
    same_as_before("arm4_gravity");
}

#[test]
fn pendulum3_expands_to_the_scene_it_replaced() {
    same_as_before("pendulum3");
}

/// A scene with a free puck inside the closed wall `wall`.
fn puck_in(wall: &str) -> String {
    format!(
        r#"Scene(
    name: "closed",
    world: Physics(
        walls: [{wall}],
        bodies: [(name: "puck", shape: Ball(radius: 0.2), mass: 1.0, position: (1.0, 1.0), lock_rotation: true)],
        schedule: Sequential(phase: 1.0, settle: 1.0),
        effect: (body: "puck", grid: (rows: 3, cols: 3, min: (-1.0, -1.0), max: (3.0, 3.0))),
    ),
    command: Repeat(slots: 1, alphabet: [(symbol: 'E', action: Impulse(body: "puck", impulse: (1.0, 0.0)))]),
)"#
    )
}

fn leaks(text: &str) -> Option<(f64, f64)> {
    let s = Scene::parse(text, "closed.ron").unwrap_or_else(|e| panic!("{e}"));
    let WorldSpec::Physics(p) = &s.spec().world else {
        panic!()
    };
    e3d::scene::enclosure::leak(p).map(|l| l.point)
}

/// A closed wall is closed at every corner, whatever its placement and its
/// corners' angles (a triangle, a pentagon, either way round, a room); a
/// door wider than the puck opens it, and the way out is named near the door.
#[test]
fn closed_walls_enclose_their_inside_except_at_doors() {
    let shapes = [
        "points: [(-0.5, -0.5), (2.8, 0.2), (0.6, 2.9)]",
        "points: [(0.6, 2.9), (2.8, 0.2), (-0.5, -0.5)]",
        "points: [(1.0, -0.6), (2.6, 0.5), (2.0, 2.4), (0.0, 2.4), (-0.6, 0.5)]",
        "room: ((-0.5, -0.5), (2.5, 2.5))",
    ];
    for shape in shapes {
        for placement in ["Centred", "Outside", "Inside"] {
            let closed = if shape.starts_with("room") {
                ""
            } else {
                "closed: true, "
            };
            let wall =
                format!("(name: \"w\", {shape}, {closed}thickness: 0.05, placement: {placement})");
            assert_eq!(leaks(&puck_in(&wall)), None, "{wall}");
            // an open polyline is open between its ends
            if !shape.starts_with("room") {
                let open = wall.replace("closed: true, ", "");
                assert!(leaks(&puck_in(&open)).is_some(), "{open}");
            }
        }
    }
    // a door of 0.8 m in the room's east side, x = 2.5, y in [0.6, 1.4]
    let wall = "(name: \"w\", room: ((-0.5, -0.5), (2.5, 2.5)), thickness: 0.05, doors: [((2.5, 0.6), (2.5, 1.4))])";
    let (x, y) = leaks(&puck_in(wall)).expect("a door wider than the puck");
    assert!(
        (2.4..2.6).contains(&x) && (0.6..1.4).contains(&y),
        "({x}, {y})"
    );
    // its generated boxes: the east side in two, named in order
    let s = Scene::parse(&puck_in(wall), "door.ron").unwrap();
    let WorldSpec::Physics(p) = &s.spec().world else {
        panic!()
    };
    let names: Vec<&str> = p.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(
        names,
        ["w_south", "w_north", "w_west", "w_east1", "w_east2", "puck"]
    );
}

/// The example of docs/scenes.md ("Walls (shorthand)") loads, and generates
/// what the page says.
#[test]
fn the_docs_example_generates_what_the_docs_say() {
    let doc = std::fs::read_to_string("docs/scenes.md").unwrap();
    let block = doc
        .split("<!-- example: shorthands -->\n```ron\n")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("the example in docs/scenes.md");
    let s = Scene::parse(block, "docs/scenes.md").unwrap_or_else(|e| panic!("{e}"));
    let WorldSpec::Physics(p) = &s.spec().world else {
        panic!()
    };
    let names: Vec<&str> = p.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "room_south",
            "room_north",
            "room_west",
            "room_east",
            "split1",
            "split2",
            "arm1",
            "arm2"
        ]
    );
    let joints: Vec<(&str, &str, &str)> = p
        .joints
        .iter()
        .map(|j| (j.name.as_str(), j.parent.as_str(), j.child.as_str()))
        .collect();
    assert_eq!(
        joints,
        [("hinge1", "ground", "arm1"), ("hinge2", "arm1", "arm2")]
    );
    assert_eq!(p.joints[0].parent_anchor, (0.5, 1.0));
    assert_eq!(p.joints[1].damping, 0.1);
    assert_eq!(p.bodies[6].position, (0.65, 1.0));
    assert_eq!(p.bodies[7].position, (0.95, 1.0));
    assert_eq!(p.bodies[4].position, (2.0, 0.25));
    assert_eq!(p.bodies[5].position, (2.0, 1.75));
    // and it runs
    let mut w = s.build();
    let c = s.command_space().parse("+").unwrap();
    w.execute(&c).unwrap();
    // the walls' section's example is puck_rooms' own
    let walls = doc
        .split("```ron\nwalls: [\n")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .unwrap();
    let puck = std::fs::read_to_string("scenes/puck_rooms.ron").unwrap();
    let flat = |t: &str| t.split_whitespace().collect::<String>();
    assert!(flat(&puck).contains(&flat(walls)), "{walls}");
}

#[test]
fn puck_rooms14_arm7x5_three_rooms_and_arm7_continuous_expand_to_the_scenes_they_replaced() {
    same_as_before("puck_rooms14");
    same_as_before("arm7x5");
    same_as_before("three_rooms");
    same_as_before("arm7_continuous");
}

/// A scene built in code with a chain: `validate` checks what it
/// generates (an error names it, without a position), the validated scene builds
/// it, `to_ron` writes the chain, which reads back expanded and executes
/// the same.
#[test]
fn a_scene_built_in_code_with_shorthands_validates_builds_and_writes() {
    let arm = Scene::builtin("arm7").unwrap();
    let mut short = arm.to_spec();
    let WorldSpec::Physics(p) = &mut short.world else {
        panic!()
    };
    let mut chain = e3d::scene::ChainSpec::new(7, 0.25, 0.04);
    chain.mass = Some(e3d::scene::Each::All(0.1));
    chain.friction = 1.0;
    chain.limits = Some((-2.5, 2.5));
    chain.damping = e3d::scene::Each::List(vec![0.5, 0.3, 0.15, 0.08, 0.04, 0.02, 0.01]);
    p.bodies.clear();
    p.joints.clear();
    p.chains.push(chain);
    short.validate().unwrap();
    let text = short.to_ron();
    assert!(text.contains("chains: ["), "{text}");
    assert_eq!(Scene::parse(&text, "short.ron").unwrap(), arm);
    let mut expanded = short.clone();
    expanded.expand().unwrap();
    assert_eq!(expanded, *arm.spec());
    let c = arm.command_space().parse("-++++--").unwrap();
    let a = arm.build().execute(&c).unwrap();
    let b = short.validate().unwrap().build().execute(&c).unwrap();
    assert_eq!(a, b);
    // a generated body's mistake, named
    let WorldSpec::Physics(p) = &mut short.world else {
        panic!()
    };
    p.chains[0].mass = Some(e3d::scene::Each::All(-1.0));
    let e = short.validate().unwrap_err().to_string();
    assert_eq!(
        e,
        "<scene arm7>: field `mass`: expected body `link1`: a mass > 0 in kg, found -1 (generated by chains[0])"
    );
}
