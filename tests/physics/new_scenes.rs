//! The canonical scenes of issue 25: arm_push (an arm pushing a puck, the
//! puck's cell as the effect) and swimmer (a free-floating chain). Their
//! numbers are those of docs/scenes.md.

use e3d::scene::{CommandSpec, Scene, WorldSpec};
use e3d::world::OutcomeTable;

fn cell(scene: &Scene, effect: usize) -> (usize, usize) {
    let g = scene.effect_grid();
    (effect / g.cols, effect % g.cols)
}

/// The commands (as text) ending in `cell`, and the number of cells reached.
fn reach(scene: &Scene, target: (usize, usize)) -> (Vec<String>, usize) {
    let table = OutcomeTable::build_scene(scene).unwrap();
    let space = scene.command_space();
    let hits = (0..table.len() as u64)
        .filter(|&i| cell(scene, table.get(i).effect) == target)
        .map(|i| space.format(&space.command_at(i)))
        .collect();
    (hits, table.reachable_effects())
}

fn template_of_three_joints(scene: &Scene) {
    assert_eq!(scene.spec().slots, Some(6));
    let CommandSpec::Slots(slots) = &scene.spec().command else {
        panic!("{}: a template loads as Slots", scene.spec().name)
    };
    let names: Vec<&str> = slots.iter().map(|s| s.name.as_deref().unwrap()).collect();
    assert_eq!(names, ["j1", "j2", "j3", "j1", "j2", "j3"]);
    assert_eq!(scene.command_space().num_commands(), Some(729));
}

#[test]
fn arm_push_moves_the_puck_to_its_reward_cell_rarely() {
    let s = Scene::builtin("arm_push").unwrap();
    assert_eq!(s, Scene::load("scenes/arm_push.ron").unwrap());
    template_of_three_joints(&s);
    let WorldSpec::Physics(p) = &s.spec().world else {
        panic!("physics")
    };
    assert_eq!(p.effect.body, "puck");
    assert_eq!(p.joints.len(), 3);
    assert_eq!(s.num_effects(), 144);
    assert_eq!(s.spec().steps_per_command(), Some(240));
    assert_eq!(s.spec().reward.cells, [(2, 3)]);
    // the puck starts in (4, 8); untouched by `------`
    let mut w = s.build();
    let c = s.command_space().parse("------").unwrap();
    assert_eq!(cell(&s, w.execute(&c).unwrap().effect), (4, 8));
    let (hits, reached) = reach(&s, (2, 3));
    assert_eq!(reached, 18);
    assert_eq!(
        hits,
        ["--+++-", "--+++0", "--++++", "0-+++-", "0-+++0", "0-++++"]
    );
}

#[test]
fn the_swimmer_is_free_floating_and_reorients_itself() {
    let s = Scene::builtin("swimmer").unwrap();
    assert_eq!(s, Scene::load("scenes/swimmer.ron").unwrap());
    template_of_three_joints(&s);
    let WorldSpec::Physics(p) = &s.spec().world else {
        panic!("physics")
    };
    // four capsule links, three joints between them, none on the ground
    assert_eq!(p.bodies.len(), 4);
    assert!(p
        .bodies
        .iter()
        .all(|b| matches!(b.shape, e3d::scene::physics::ShapeSpec::Capsule { .. })));
    assert_eq!(p.joints.len(), 3);
    assert!(p.joints.iter().all(|j| j.parent != "ground"));
    assert_eq!(s.num_effects(), 144);
    assert_eq!(s.spec().steps_per_command(), Some(300));
    // a free chain keeps its momentum (built of impulse joints): its end
    // reaches 7 cells, the farthest (4, 7) by 13 commands
    let (hits, reached) = reach(&s, (4, 7));
    assert_eq!(reached, 7);
    assert_eq!(hits.len(), 13);
    assert!(hits.iter().any(|h| h == "+++0++"), "{hits:?}");
    // the centre of mass stays where it was (internal torques only)
    let mut world = s.physics_world().unwrap();
    let c = s.command_space().parse("++++++").unwrap();
    let m = world.motion(&c).unwrap();
    // equal links, symmetric about their origins: the mean of the origins
    let com = |f: &e3d::world::Frame| {
        let n = f.poses.len() as f64;
        (
            f.poses.iter().map(|b| b.position[0]).sum::<f64>() / n,
            f.poses.iter().map(|b| b.position[1]).sum::<f64>() / n,
        )
    };
    let (a, b) = (com(&m.frames[0]), com(m.frames.last().unwrap()));
    assert!(
        (a.0 - b.0).abs() < 1e-3 && (a.1 - b.1).abs() < 1e-3,
        "{a:?} {b:?}"
    );
}
