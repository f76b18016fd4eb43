//! Mirror symmetry (`symmetry: FlipY` in arm7.ron): of each pair of
//! mirror-image commands only one is simulated, the other's outcome is its
//! reflection. The simulated half is Rapier's own result, bit for bit; the
//! reflected half agrees with Rapier in effect on at least 99% of arm7's
//! commands (2185 of 2187 measured).

use e3d::scene::{PhysicsSpec, Symmetry, WorldSpec};
use e3d::{OutcomeTable, Scene, World};

/// arm7 as shipped (with its symmetry) or without it (Rapier's own outcome
/// of every command).
fn arm7(symmetric: bool) -> Scene {
    let mut s = Scene::builtin("arm7").unwrap().to_spec();
    let WorldSpec::Physics(p) = &mut s.world else {
        panic!("arm7 is a physics scene")
    };
    assert_eq!(p.symmetry, Some(Symmetry::FlipY));
    if !symmetric {
        p.symmetry = None;
    }
    s.validate().unwrap()
}

fn spec(s: &Scene) -> &PhysicsSpec {
    match &s.spec().world {
        WorldSpec::Physics(p) => p,
        _ => unreachable!(),
    }
}

/// How many commands have the same effect in both tables.
fn equal_effects(a: &OutcomeTable, b: &OutcomeTable) -> usize {
    a.outcomes()
        .zip(b.outcomes())
        .filter(|(x, y)| x.effect == y.effect)
        .count()
}

#[test]
fn arm7_simulates_one_command_of_each_mirror_pair() {
    let scene = arm7(true);
    let w = scene.physics_world().unwrap();
    let space = scene.command_space();
    let twins: Vec<_> = space
        .iter()
        .filter_map(|c| w.twin(&c).map(|t| (c, t)))
        .collect();
    // 2187 = 1 command that is its own mirror image + 2 x 1093
    assert_eq!(twins.len(), 1093);
    for (c, t) in &twins {
        // '-' is 0, '0' is 1, '+' is 2: the mirror image swaps - and +
        assert!(c.symbols.iter().zip(&t.symbols).all(|(&a, &b)| a + b == 2));
        assert!(space.index_of(t) < space.index_of(c));
        assert!(w.twin(t).is_none(), "a twin is simulated itself");
    }
    assert!(w.twin(&space.parse("0000000").unwrap()).is_none());
    // without the symmetry, every command is simulated
    let plain = arm7(false);
    let w = plain.physics_world().unwrap();
    assert!(space.iter().all(|c| w.twin(&c).is_none()));
}

#[test]
fn a_mirrored_outcome_is_the_reflection_of_its_simulated_twin() {
    let (sym, plain) = (arm7(true), arm7(false));
    let mut ws = sym.physics_world().unwrap();
    let mut wp = plain.physics_world().unwrap();
    let space = sym.command_space();
    let grid = sym.effect_grid();
    for text in ["+--0+-+", "+++++++", "0+-0000", "+----+-", "00000+0"] {
        let c = space.parse(text).unwrap();
        let t = ws.twin(&c).unwrap_or_else(|| panic!("{text} has a twin"));
        let o = ws.execute(&c).unwrap();
        let ot = ws.execute(&t).unwrap();
        // the twin is Rapier's own result, bit for bit
        assert_eq!(ot, wp.execute(&t).unwrap(), "{text}");
        assert_eq!(o.point, [ot.point[0], -ot.point[1]], "{text}");
        assert_eq!(o.effect, grid.effect_of(o.point));
        assert_eq!(o.reward, sym.reward_table()[o.effect]);
        // a trace agrees with execute: the twin's trace, reflected
        let tr = ws.trace(&c).unwrap();
        assert_eq!(tr.outcome, o, "{text}");
        assert_eq!(*tr.points.last().unwrap(), o.point, "{text}");
        let plain_tr = wp.trace(&t).unwrap();
        assert_eq!(
            tr.points[60],
            [plain_tr.points[60][0], -plain_tr.points[60][1]]
        );
        let (a, b) = (tr.poses[6], plain_tr.poses[6]);
        assert_eq!(a.position, [b.position[0], -b.position[1]]);
        assert!((a.angle + b.angle).abs() < 1e-12, "{} {}", a.angle, b.angle);
    }
    // a batch gives what execute gives
    let cmds: Vec<_> = ["+--0+-+", "-++0-+-", "0000000"]
        .iter()
        .map(|t| space.parse(t).unwrap())
        .collect();
    let mut out = Vec::new();
    ws.execute_batch(&cmds, &mut out);
    for (c, r) in cmds.iter().zip(out) {
        assert_eq!(r.unwrap(), ws.execute(c).unwrap());
    }
}

#[test]
fn the_mirrored_table_is_the_world_and_keeps_99_percent_of_rapiers_effects() {
    let (sym, plain) = (arm7(true), arm7(false));
    let mirrored = OutcomeTable::build_scene(&sym).unwrap();
    let rapier = OutcomeTable::build_scene(&plain).unwrap();
    assert_eq!(mirrored.len(), 2187);
    // the table holds what the world executes, command by command
    let space = sym.command_space();
    let mut w = sym.build();
    for i in (0..2187).step_by(13) {
        assert_eq!(
            w.execute(&space.command_at(i)).unwrap(),
            *mirrored.get(i),
            "{i}"
        );
    }
    // the simulated half is Rapier's own result
    let probe = sym.physics_world().unwrap();
    let simulated = (0..2187u64).filter(|&i| probe.twin(&space.command_at(i)).is_none());
    for i in simulated {
        assert_eq!(mirrored.get(i), rapier.get(i), "{i}");
    }
    let equal = equal_effects(&mirrored, &rapier);
    println!("arm7 mirrored: {equal} of 2187 effects equal to Rapier's");
    assert!(equal * 100 >= 2187 * 99, "{equal} of 2187 effects equal");
    // the cells reached and the reward cell's commands are the same
    let reached = |t: &OutcomeTable| -> Vec<usize> {
        let c = t.effect_counts();
        (0..c.len()).filter(|&e| c[e] > 0).collect()
    };
    assert_eq!(reached(&mirrored), reached(&rapier));
    assert_eq!(reached(&mirrored).len(), 68);
    let rewarded = |t: &OutcomeTable| t.outcomes().filter(|o| o.reward > 0.0).count();
    assert_eq!((rewarded(&mirrored), rewarded(&rapier)), (5, 5));
}

#[test]
fn pendulum3_has_the_symmetry_flip_x_and_it_keeps_its_effects() {
    // pendulum3 hangs along -y under gravity: x -> -x leaves it unchanged
    // (its links point down, angle -pi/2; targets come in pairs +-a). It
    // does not declare it (125 commands cost nothing); declared here, the
    // loader accepts it and the reflected outcomes agree with Rapier's.
    let text = std::fs::read_to_string("scenes/pendulum3.ron").unwrap();
    let from = "schedule: Simultaneous(push: 1.0, settle: 1.0),";
    assert_eq!(text.matches(from).count(), 1);
    let sym = Scene::parse(
        &text.replacen(from, &format!("{from} symmetry: FlipX,"), 1),
        "p.ron",
    )
    .expect("pendulum3 has the symmetry FlipX");
    let plain = Scene::builtin("pendulum3").unwrap();
    let (a, b) = (
        OutcomeTable::build_scene(&sym).unwrap(),
        OutcomeTable::build_scene(&plain).unwrap(),
    );
    assert_eq!(OutcomeTable::simulated_commands(&sym), Some(63));
    let equal = equal_effects(&a, &b);
    println!("pendulum3 with FlipX: {equal} of 125 effects equal to Rapier's");
    assert!(equal * 100 >= 125 * 99, "{equal} of 125 effects equal");
    // a reflected trace: the hand's pose is the mirror image of its twin's
    let mut w = sym.physics_world().unwrap();
    let space = sym.command_space();
    let c = space.parse("ddc").unwrap();
    let t = w.twin(&c).expect("ddc is answered by its mirror image bbc");
    assert_eq!(space.format(&t), "bbc");
    let (tc, tt) = (w.trace(&c).unwrap(), w.trace(&t).unwrap());
    let (pc, pt) = (tc.poses[2], tt.poses[2]);
    assert_eq!(pc.position, [-pt.position[0], pt.position[1]]);
    // the same angle, up to a whole turn
    let turn = (pc.angle - (std::f64::consts::PI - pt.angle)).rem_euclid(std::f64::consts::TAU);
    let near = turn.min(std::f64::consts::TAU - turn);
    assert!(near < 1e-9, "{} {}", pc.angle, pt.angle);
    // and a scene that does not have the symmetry is refused
    let bad = text.replacen(from, &format!("{from} symmetry: FlipY,"), 1);
    let e = Scene::parse(&bad, "p.ron").unwrap_err().to_string();
    assert!(
        e.contains("symmetry FlipY: gravity along the mirror line"),
        "{e}"
    );
}

#[test]
fn a_symmetric_puck_table_batches_its_simulated_half_and_matches_execute() {
    // one moving body: copies are exact, so the table runs the simulated
    // half 32 at a time; it must still equal `execute` of every command
    let text = r#"Scene(
        name: "puck_mirror",
        world: Physics(
            bodies: [
                (name: "wall", kind: Fixed, shape: Cuboid(width: 0.2, height: 4.0), position: (2.5, 0.0), restitution: 0.5),
                (name: "puck", shape: Ball(radius: 0.2), mass: 1.0, linear_damping: 1.5, friction: 0.0, restitution: 0.5, lock_rotation: true),
            ],
            schedule: Sequential(phase: 0.5, settle: 0.5),
            effect: (body: "puck", grid: (rows: 4, cols: 4, min: (-1.0, -2.0), max: (3.0, 2.0))),
            symmetry: FlipY,
        ),
        command: Repeat(slots: 4, alphabet: [
            (symbol: 'U', action: Impulse(body: "puck", impulse: (1.0, 0.6))),
            (symbol: 'R', action: Impulse(body: "puck", impulse: (1.2, 0.0))),
            (symbol: 'D', action: Impulse(body: "puck", impulse: (1.0, -0.6))),
        ]),
    )"#;
    let scene = Scene::parse(text, "puck_mirror.ron").unwrap();
    assert!(spec(&scene).copies_are_exact());
    assert_eq!(OutcomeTable::simulated_commands(&scene), Some(41));
    let table = OutcomeTable::build_scene(&scene).unwrap();
    let one_by_one = OutcomeTable::build(&mut scene.build()).unwrap();
    assert!(table.outcomes().eq(one_by_one.outcomes()));
    // the mirror images really are reflected: U... ends below the axis
    // where D... ends above it, and the puck hits the wall on some
    let space = scene.command_space();
    let (up, down) = (space.parse("UUUU").unwrap(), space.parse("DDDD").unwrap());
    let (u, d) = (table.lookup(&up).unwrap(), table.lookup(&down).unwrap());
    assert_eq!(u.point, [d.point[0], -d.point[1]]);
    assert!(u.point[1] > 0.5, "{:?}", u.point);
    assert!(
        table.outcomes().any(|o| o.point[0] > 2.0),
        "the wall is reached"
    );
}
