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
    let (WorldSpec::Physics(n), WorldSpec::Physics(o)) = (&new.world, &old.world) else {
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
    assert_eq!(new.to_ron(), old.to_ron(), "{name}");
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
