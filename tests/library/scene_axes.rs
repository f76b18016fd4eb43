//! Scene fields set by path (`Scene::with_paths`, `scene::path::set_path`)
//! and sweeps over them (`SweepSpec::axes`).

use e3d::scene::WorldSpec;
use e3d::sweep::{Sweep, SweepSpec, Values};
use e3d::Scene;

#[test]
fn paths_set_fields_of_the_scene_and_are_checked_as_a_file() {
    let puck = Scene::builtin("puck_rooms").unwrap();
    let heavy = puck
        .with_paths([
            ("bodies.puck.mass", 2.5.into()),
            ("world.bodies[6].linear_damping", 3.into()),
        ])
        .unwrap();
    let WorldSpec::Physics(p) = &heavy.spec().world else {
        panic!()
    };
    let b = p.bodies.iter().find(|b| b.name == "puck").unwrap();
    assert_eq!((b.mass, b.linear_damping), (Some(2.5), 3.0));
    // a section the scene leaves out is created
    let noisy = puck
        .with_paths([("noise.actions.Gaussian.sd", 0.05.into())])
        .unwrap();
    let WorldSpec::Physics(p) = &noisy.spec().world else {
        panic!()
    };
    assert!(p.active_noise().is_some());
    // the short names of Python's `with_`: `slots` checks the count
    let rooms = Scene::builtin("two_rooms").unwrap();
    let six = rooms
        .with_paths([("command.slots", 6.into()), ("slots", 6.into())])
        .unwrap();
    assert_eq!(six.command_space().num_slots(), 6);
    let e = rooms
        .with_paths([("slots", 6.into())])
        .unwrap_err()
        .to_string();
    assert!(e.contains("slots"), "{e}");
    for (path, expected) in [
        ("bodies.puck.mas", "field `bodies.puck.mas`: expected unknown field `mas`, expected one of `name`, `kind`, `shape`"),
        ("joints.j1.damping", "field `joints.j1.damping`: expected no item named `j1`; the names: "),
        ("bodies.9.mass", "field `bodies.9.mass`: expected index 9: the list has 7 items"),
        ("bodies..mass", "field `bodies..mass`: expected expected dot-separated names"),
    ] {
        let e = puck.with_paths([(path, 1.0.into())]).unwrap_err().to_string();
        assert!(e.starts_with(&format!("<scene puck_rooms>: {expected}")), "{path}: {e}");
    }
}

#[test]
fn a_sweep_over_scene_fields_runs_each_derived_scene() {
    let spec = SweepSpec::new(["two_rooms"], ["e3d", "uniform"], 2, 200)
        .with_axis("command.slots", Values::list([5.0, 7.0]))
        .with_seed(3);
    let text = spec.to_ron();
    assert!(
        text.contains("    axes: {\n        \"command.slots\": [5.0, 7.0],\n    },\n"),
        "{text}"
    );
    assert_eq!(SweepSpec::parse(&text, "axes.ron").unwrap(), spec);
    let sweep = Sweep::new(spec).unwrap();
    assert_eq!(
        (
            sweep.scenes().len(),
            sweep.cells().len(),
            sweep.num_sessions()
        ),
        (2, 4, 8)
    );
    let slots: Vec<usize> = sweep
        .scenes()
        .iter()
        .map(|s| s.command_space().num_slots())
        .collect();
    assert_eq!(slots, [5, 7]);
    assert_eq!(sweep.cells()[2].axes, [7.0]);
    assert_eq!(
        sweep.identity(&sweep.cells()[3], 1),
        "scene=two_rooms;learner=uniform;use_reward=true;alpha=-;beta=-;lambda=-;eta=-;epsilon=-;command.slots=7;session=1"
    );
    assert!(sweep
        .results_header()
        .contains(",epsilon,command.slots,session,seed,"));
    let results = sweep.run(2).unwrap();
    assert_eq!(results, sweep.run(1).unwrap());
    // 5 moves reach fewer cells than 7
    let distinct = |cell: usize| {
        results
            .iter()
            .filter(|r| r.session.cell == cell)
            .map(|r| r.values[3].unwrap())
            .sum::<f64>()
    };
    assert!(distinct(1) < distinct(3), "{} {}", distinct(1), distinct(3));
}
