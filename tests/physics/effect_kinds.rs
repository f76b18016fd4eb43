//! Effects of several kinds in scene files: a joint's angle, a slider's
//! position, a body's angle, a point in another body's frame, and their
//! products, each binned against values computed by hand on a tiny scene;
//! and the mistakes the loader refuses in them, with line and column.

use e3d::{Scene, World};

/// A tiny world without gravity: a hinge and a slider each driven to a
/// set point by a stiff motor, a free body turned by 2 rad, and two free
/// bodies a point of one is seen from. `EFFECT` is replaced by the
/// features under test.
const TINY: &str = r#"Scene(
    name: "tiny",
    world: Physics(
        bodies: [
            (name: "arm", shape: Cuboid(width: 0.4, height: 0.05), mass: 0.5, position: (0.2, 0.0), collide: false),
            (name: "cart", shape: Cuboid(width: 0.2, height: 0.1), mass: 0.5, position: (0.0, 2.0), collide: false),
            (name: "spun", shape: Ball(radius: 0.1), mass: 1.0, position: (-2.0, -2.0), angle: 2.0),
            (name: "hand", shape: Ball(radius: 0.1), mass: 1.0, position: (1.0, 1.0), angle: 1.5707963267948966),
            (name: "puck", shape: Ball(radius: 0.1), mass: 1.0, position: (0.5, 2.5)),
        ],
        joints: [
            (name: "hinge", parent: "ground", child: "arm", child_anchor: (-0.2, 0.0),
             motor: (stiffness: 20.0, damping: 2.0)),
            (name: "rail", parent: "ground", child: "cart", parent_anchor: (0.0, 2.0),
             kind: Prismatic(axis: (1.0, 0.0)), motor: (stiffness: 40.0, damping: 8.0)),
        ],
        schedule: Simultaneous(push: 4.0, settle: 0.0),
        effect: (features: [EFFECT]),
    ),
    command: Slots([
        (alphabet: [(symbol: 'h', action: Target(joint: "hinge", angle: 0.3))]),
        (alphabet: [(symbol: 's', action: Target(joint: "rail", position: 0.5))]),
    ]),
)"#;

fn tiny(effect: &str) -> String {
    TINY.replace("EFFECT", effect)
}

/// The effect and layout point of the one command `hs`.
fn outcome(effect: &str) -> (usize, [f64; 2], usize) {
    let scene = Scene::parse(&tiny(effect), "tiny.ron").unwrap();
    let mut world = scene.build();
    let c = world.command_space().parse("hs").unwrap();
    let o = world.execute(&c).unwrap();
    (o.effect, o.point, world.num_effects())
}

fn error(effect: &str) -> String {
    match Scene::parse(&tiny(effect), "tiny.ron") {
        Ok(_) => panic!("accepted: {effect}"),
        Err(e) => e.to_string(),
    }
}

const HINGE: &str = r#"Joint(joint: "hinge", bins: 4, range: (-1.0, 1.0))"#;
const RAIL: &str = r#"Joint(joint: "rail", bins: 5, range: (-1.0, 1.0))"#;
const SPUN: &str =
    r#"Angle(body: "spun", bins: 8, range: (-3.141592653589793, 3.141592653589793))"#;
const SEEN: &str = r#"Point(body: "puck", frame: "hand", grid: (rows: 4, cols: 4, min: (-2.0, -2.0), max: (2.0, 2.0)))"#;

#[test]
fn a_joints_angle_is_binned_on_its_strip() {
    // the hinge settles at its set point 0.3 rad: bin floor((0.3 + 1) / 0.5) = 2
    let (e, p, n) = outcome(HINGE);
    assert_eq!((e, n), (2, 4));
    assert!((p[0] - 0.3).abs() < 0.02, "{p:?}");
    assert_eq!(p[1], 0.5);
}

#[test]
fn a_sliders_position_is_binned_on_its_strip() {
    // the cart settles at 0.5 m along the rail: bin floor((0.5 + 1) / 0.4) = 3
    let (e, p, n) = outcome(RAIL);
    assert_eq!((e, n), (3, 5));
    assert!((p[0] - 0.5).abs() < 0.02, "{p:?}");
}

#[test]
fn a_bodys_angle_is_binned_on_its_strip() {
    // the free body keeps its start angle 2 rad: bin floor((2 + pi) / (pi / 4)) = 6
    let (e, p, n) = outcome(SPUN);
    assert_eq!((e, n), (6, 8));
    assert!((p[0] - 2.0).abs() < 1e-6, "{p:?}");
}

#[test]
fn a_point_in_another_bodys_frame_is_binned_on_its_grid() {
    // the puck (0.5, 2.5) seen from the hand at (1, 1) turned by 90°:
    // (-0.5, 1.5) turned back by 90° is (1.5, 0.5): column
    // floor((1.5 + 2) / 1) = 3, row floor((2 - 0.5) / 1) = 1, effect 1 * 4 + 3
    let (e, p, n) = outcome(SEEN);
    assert_eq!((e, n), (7, 16));
    assert!(
        (p[0] - 1.5).abs() < 1e-5 && (p[1] - 0.5).abs() < 1e-5,
        "{p:?}"
    );
}

#[test]
fn two_numbers_make_a_grid_the_first_down_the_rows() {
    // hinge bin 2 of 4 is row 4 - 1 - 2 = 1 (its largest value in row 0);
    // rail bin 3 of 5 is column 3: effect 1 * 5 + 3
    let (e, p, n) = outcome(&format!("{HINGE}, {RAIL}"));
    assert_eq!((e, n), (8, 20));
    // the layout point is (rail, hinge)
    assert!(
        (p[0] - 0.5).abs() < 0.02 && (p[1] - 0.3).abs() < 0.02,
        "{p:?}"
    );
}

#[test]
fn other_products_are_nested_blocks() {
    // the angle's strip (1 x 8) by the point's grid (4 x 4): 4 x 32 cells;
    // angle bin 6, point cell (1, 3): row 0 * 4 + 1, column 6 * 4 + 3
    let (e, _, n) = outcome(&format!("{SPUN}, {SEEN}"));
    assert_eq!(n, 128);
    assert_eq!(e, 32 + 27);
    // three features: the hinge (1 x 4) first, then the angle and the point
    let (e, _, n) = outcome(&format!("{HINGE}, {SPUN}, {SEEN}"));
    assert_eq!(n, 4 * 8 * 16);
    // row 0 * 1 * 4 + 1; column (2 * 8 + 6) * 4 + 3
    assert_eq!(e, 4 * 8 * 4 + (2 * 8 + 6) * 4 + 3);
}

#[test]
fn a_single_world_point_feature_is_the_short_form() {
    let long =
        r#"Point(body: "puck", grid: (rows: 4, cols: 4, min: (-2.0, -2.0), max: (2.0, 2.0)))"#;
    // (0.5, 2.5): column floor(2.5 / 1) = 2, row 0 (above the grid)
    let (e, p, n) = outcome(long);
    assert_eq!((e, n), (2, 16));
    assert!((p[0] - 0.5).abs() < 1e-6 && (p[1] - 2.5).abs() < 1e-6);
    let short = tiny("").replace(
        "effect: (features: [])",
        r#"effect: (body: "puck", grid: (rows: 4, cols: 4, min: (-2.0, -2.0), max: (2.0, 2.0)))"#,
    );
    let scene = Scene::parse(&short, "tiny.ron").unwrap();
    let mut world = scene.build();
    let c = world.command_space().parse("hs").unwrap();
    let o = world.execute(&c).unwrap();
    assert_eq!((o.effect, o.point), (e, p));
}

#[test]
fn ill_formed_features_are_refused_with_line_and_column() {
    let line = tiny("")
        .lines()
        .position(|l| l.contains("effect:"))
        .unwrap()
        + 1;
    let cases = [
        (
            r#"Joint(joint: "elbow", bins: 4, range: (-1.0, 1.0))"#,
            "no joint `elbow`",
        ),
        (
            r#"Angle(body: "pole", bins: 4, range: (-1.0, 1.0))"#,
            "no body `pole`",
        ),
        (
            r#"Point(body: "puck", frame: "palm", grid: (rows: 2, cols: 2, min: (0.0, 0.0), max: (1.0, 1.0)))"#,
            "no body `palm`",
        ),
        (
            r#"Joint(joint: "hinge", bins: 0, range: (-1.0, 1.0))"#,
            "between 1 and 1048576 bins, found 0",
        ),
        (
            r#"Joint(joint: "hinge", bins: 3, range: (1.0, -1.0))"#,
            "min < max, in rad, found (1, -1)",
        ),
        (
            r#"Joint(joint: "rail", bins: 3, range: (0.5, 0.5))"#,
            "min < max, in m, found (0.5, 0.5)",
        ),
        (
            r#"Point(body: "puck", grid: (rows: 0, cols: 2, min: (0.0, 0.0), max: (1.0, 1.0)))"#,
            "at least one cell",
        ),
        (
            r#"Point(body: "puck", frame: "puck", grid: (rows: 2, cols: 2, min: (0.0, 0.0), max: (1.0, 1.0)))"#,
            "a frame other than the point's own body",
        ),
    ];
    for (f, want) in cases {
        let e = error(f);
        assert!(e.contains(want), "{f}: {e}");
        assert!(
            e.starts_with(&format!("tiny.ron:{line}:")),
            "{f}: not on the effect's line {line}: {e}"
        );
    }
    // an unknown feature field is a syntax error at its place
    let e = error(r#"Joint(joint: "hinge", bins: 3, range: (-1.0, 1.0), unit: "rad")"#);
    assert!(
        e.starts_with(&format!("tiny.ron:{line}:")) && e.contains("unit"),
        "{e}"
    );
    // both forms, or neither
    let both = tiny(HINGE).replace("effect: (features:", r#"effect: (body: "puck", features:"#);
    let e = Scene::parse(&both, "tiny.ron").unwrap_err().to_string();
    assert!(e.contains("either `features` or the short form"), "{e}");
    let none = tiny("").replace("effect: (features: [])", "effect: ()");
    let e = Scene::parse(&none, "tiny.ron").unwrap_err().to_string();
    assert!(e.contains("`body` and `grid`"), "{e}");
    // a product of too many effects
    let e = error(&format!(
        "{}, {}",
        r#"Joint(joint: "hinge", bins: 2000, range: (-1.0, 1.0))"#,
        r#"Joint(joint: "rail", bins: 2000, range: (-1.0, 1.0))"#
    ));
    assert!(e.contains("at most 1048576 cells"), "{e}");
}

#[test]
fn a_symmetry_is_refused_for_effects_it_cannot_reflect() {
    let text = tiny(HINGE).replace("schedule:", "symmetry: FlipY,\n        schedule:");
    let e = Scene::parse(&text, "tiny.ron").unwrap_err().to_string();
    assert!(e.contains("no symmetry with this effect"), "{e}");
}

#[test]
fn cart_pole_bins_its_start_in_the_middle_cell() {
    let scene = Scene::builtin("cart_pole").unwrap();
    assert_eq!(scene.num_effects(), 63);
    let world = scene.physics_world().unwrap();
    // angle 0 (row 4 of 9), position 0 (column 3 of 7)
    assert_eq!(world.start().1, 4 * 7 + 3);
    let mut world = scene.build();
    // five pushes to the right: the cart ends right of the middle
    let c = world.command_space().parse(">>>>>").unwrap();
    let o = world.execute(&c).unwrap();
    assert!(o.effect % 7 > 3, "{o:?}");
    assert!(o.point[0] > 0.2, "{o:?}");
}
