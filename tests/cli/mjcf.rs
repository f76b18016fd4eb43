//! `e3d scene export --mjcf` and `e3d scene import`: every shipped physics
//! scene exports to MJCF that the import reads back into the same bodies and
//! joints; the reacher's MJCF imports into the shipped scene; what lies
//! outside the planar subset is refused with its line and column.

use crate::common::{e3d, stdout_of, temp_path};
use e3d::scene::mjcf::{import::from_mjcf, to_mjcf};
use e3d::scene::physics::{BodyKind, PhysicsSpec, ShapeSpec};
use e3d::scene::{Scene, WorldSpec, BUILTIN};

fn physics(spec: &e3d::SceneSpec) -> &PhysicsSpec {
    match &spec.world {
        WorldSpec::Physics(p) => p,
        WorldSpec::Grid(_) => panic!("a physics scene"),
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * a.abs().max(b.abs()).max(1.0)
}

/// The bodies and joints of `b` (imported) are those of `a`, as far as
/// MJCF carries them (a kinematic body comes back fixed; restitution and
/// the damping of a free-floating chain's links are not exported).
fn assert_same_world(a: &PhysicsSpec, b: &PhysicsSpec, scene: &str) {
    assert_eq!(a.bodies.len(), b.bodies.len(), "{scene}");
    assert!(close(a.dt, b.dt) && a.gravity == b.gravity, "{scene}");
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        let at = format!("{scene}: body {}", x.name);
        assert_eq!(x.name, y.name, "{at}");
        assert_eq!(x.shape, y.shape, "{at}");
        assert_eq!(x.collide, y.collide, "{at}");
        assert!(close(x.friction, y.friction), "{at}");
        assert!(
            close(x.position.0, y.position.0) && close(x.position.1, y.position.1),
            "{at}: {:?} {:?}",
            x.position,
            y.position
        );
        assert!(close(x.angle, y.angle), "{at}");
        let moves = x.kind == BodyKind::Dynamic;
        assert_eq!(moves, y.kind == BodyKind::Dynamic, "{at}");
        if moves {
            assert!(
                close(x.mass_kg(), y.mass_kg()),
                "{at}: {} {}",
                x.mass_kg(),
                y.mass_kg()
            );
            assert_eq!(x.lock_rotation, y.lock_rotation, "{at}");
            // drag travels as the custom numeric e3d_drag_<body>
            assert_eq!(x.drag, y.drag, "{at}");
            if !a.joints.iter().any(|j| j.child == x.name) {
                assert!(close(x.linear_damping, y.linear_damping), "{at}");
            }
        }
    }
    assert_eq!(a.joints.len(), b.joints.len(), "{scene}");
    for (x, y) in a.joints.iter().zip(&b.joints) {
        let at = format!("{scene}: joint {}", x.name);
        assert_eq!(
            (&x.name, &x.parent, &x.child),
            (&y.name, &y.parent, &y.child),
            "{at}"
        );
        assert_eq!(x.child_anchor, y.child_anchor, "{at}");
        assert!(
            close(x.parent_anchor.0, y.parent_anchor.0)
                && close(x.parent_anchor.1, y.parent_anchor.1),
            "{at}"
        );
        assert_eq!(x.limits, y.limits, "{at}");
        assert_eq!(x.damping, y.damping, "{at}");
        assert_eq!(x.motor, y.motor, "{at}");
        assert_eq!(x.contacts, y.contacts, "{at}");
        match (x.axis(), y.axis()) {
            (None, None) => {}
            (Some(p), Some(q)) => assert!(close(p.0, q.0) && close(p.1, q.1), "{at}"),
            _ => panic!("{at}: kinds differ"),
        }
    }
}

#[test]
fn every_shipped_physics_scene_exports_and_imports_back() {
    let (mut n, mut drags) = (0, 0);
    for (name, _) in BUILTIN {
        let scene = Scene::builtin(name).unwrap();
        let Some(xml) = to_mjcf(&scene) else {
            assert!(matches!(scene.spec().world, WorldSpec::Grid(_)), "{name}");
            continue;
        };
        let walls = physics(scene.spec()).bodies.iter().any(|b| {
            matches!(
                b.shape,
                ShapeSpec::Segment { .. } | ShapeSpec::Polyline { .. }
            )
        });
        if walls {
            // segments and polylines export as thin capsules, a polyline as
            // several in one body: outside what the import reads
            let e = from_mjcf(&xml, &format!("{name}.xml")).unwrap_err();
            assert!(e.message.contains("a second geom"), "{name}: {e}");
            continue;
        }
        let imported =
            from_mjcf(&xml, &format!("{name}.xml")).unwrap_or_else(|e| panic!("{name}: {e}"));
        // what the import writes loads with the scene loader
        let text = imported.to_ron(&format!("{name}.xml"));
        let back = Scene::parse(&text, "imported.ron").unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_same_world(physics(scene.spec()), physics(back.spec()), name);
        drags += physics(back.spec())
            .bodies
            .iter()
            .filter(|b| b.drag.is_some())
            .count();
        n += 1;
    }
    assert_eq!(n, 13);
    // swimmer_drag's four links came back with their drag
    assert_eq!(drags, 4);
}

#[test]
fn drag_is_written_as_a_numeric_and_a_moving_body_is_needed_to_read_it() {
    let xml = stdout_of(&["scene", "export", "--mjcf", "swimmer_drag"]);
    assert!(
        xml.contains(r#"<numeric name="e3d_drag_link3" data="0.02 0.5 0"/>"#),
        "{xml}"
    );
    assert!(
        xml.contains("set the body's xfrc_applied (world frame, at the"),
        "{xml}"
    );
    // a drag numeric naming a fixed body is refused with its line
    let bad = xml.replace("e3d_drag_link3", "e3d_drag_wall_south");
    let e = from_mjcf(&bad, "bad.xml").unwrap_err();
    assert!(
        e.message.contains("there is no moving body `wall_south`"),
        "{e}"
    );
    let line = bad
        .lines()
        .position(|l| l.contains("e3d_drag_wall_south"))
        .unwrap()
        + 1;
    assert_eq!(e.line as usize, line, "{e}");
    let bad = xml.replace(r#"data="0.02 0.5 0""#, r#"data="0.02 0.5""#);
    let e = from_mjcf(&bad, "bad.xml").unwrap_err();
    assert!(
        e.message
            .contains("expected 3 numbers (along, across, turn)"),
        "{e}"
    );
}

#[test]
fn the_export_writes_what_rapier_uses() {
    let xml = stdout_of(&["scene", "export", "--mjcf", "arm_push"]);
    // link1: a 0.4 x 0.05 box of 0.5 kg, I = m (w² + h²) / 12 in f32
    assert!(xml.contains(r#"<inertial pos="0 0 0" mass="0.5" diaginertia="0.006770834 0.006770834 0.006770834"/>"#), "{xml}");
    assert!(xml.contains(r#"<joint name="j1" type="hinge" pos="-0.2 0 0" axis="0 0 1" range="-2 2" solreflimit="0.008333333333333333 1" damping="0.05"/>"#));
    assert!(
        xml.contains(r#"<position name="j1_target" joint="j1" kp="8" kv="2.5" ctrlrange="-1 1"/>"#)
    );
    // the puck: a free body in the plane, its damping on its slides (c m, m in f32)
    assert!(xml.contains(
        r#"<joint name="puck_x" type="slide" axis="1 0 0" damping="0.6000000089406967"/>"#
    ));
    // without restitution, a critically damped contact; the puck's 0.3, a
    // spring of natural frequency 1 / (4 timesteps) = 60 rad/s (stiffness
    // 3600) with damping ratio -ln 0.3 / sqrt(pi² + ln² 0.3) = 0.3579
    assert!(
        xml.contains(r#"friction="0.5 0 0" solref="0.008333333333333333 1"#),
        "{xml}"
    );
    assert!(xml.contains(r#"solref="-3600 -42.942855660398""#), "{xml}");
    assert!(xml.contains(r#"<numeric name="e3d_schedule" data="0 120 240 4"/>"#));
    assert!(xml.contains(r#"<numeric name="e3d_s0_2" data="2 0 1"/>"#));
    assert!(xml.contains("What does not map exactly"));
    // cart_pole: a slide on ground, forces on the cart's centre of mass
    let xml = stdout_of(&["scene", "export", "--mjcf", "cart_pole"]);
    assert!(
        xml.contains(r#"type="slide" pos="0 0 0" axis="1 0 0" range="-1.5 1.5""#),
        "{xml}"
    );
    assert!(xml.contains(r#"<motor name="cart_fx" site="cart_com" refsite="e3d_origin" gear="1 0 0 0 0 0" ctrlrange="-4 4"/>"#));
    let out = e3d(&["scene", "export", "--mjcf", "two_rooms"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("is a grid"));
}

#[test]
fn the_reacher_imports_into_the_shipped_scene() {
    let out = temp_path("mjcf").with_extension("ron");
    stdout_of(&[
        "scene",
        "import",
        "scenes/mjcf/reacher.xml",
        "--out",
        out.to_str().unwrap(),
    ]);
    let imported = Scene::load(&out).unwrap();
    let shipped = Scene::builtin("reacher").unwrap();
    assert_eq!(physics(imported.spec()), physics(shipped.spec()));
    assert_eq!(imported.spec().command, shipped.spec().command);
    assert_eq!(imported.command_space().num_commands(), Some(729));
    // and back: the shipped scene's export imports to the same world
    let xml = to_mjcf(&shipped).unwrap();
    let again = from_mjcf(&xml, "reacher.xml").unwrap();
    assert_same_world(physics(shipped.spec()), physics(&again.spec), "reacher");
    let _ = std::fs::remove_file(out);
}

#[test]
fn what_lies_outside_the_subset_is_refused_with_its_line() {
    let arm = |body: &str, extra: &str| {
        format!(
            "<mujoco>\n  <compiler angle=\"radian\"/>\n{extra}  <worldbody>\n    <body name=\"a\">\n      <joint name=\"j\"/>\n{body}    </body>\n  </worldbody>\n  <actuator>\n    <motor joint=\"j\" ctrlrange=\"-1 1\"/>\n  </actuator>\n</mujoco>\n"
        )
    };
    let geom = "      <geom type=\"sphere\" size=\"0.1\" mass=\"1\"/>\n";
    if let Err(e) = from_mjcf(&arm(geom, ""), "ok.xml") {
        panic!("{e}");
    }
    let cases: [(String, &str); 8] = [
        (
            arm(
                "      <geom type=\"cylinder\" size=\"0.1 0.1\" mass=\"1\"/>\n",
                "",
            ),
            "x.xml:6:7: geom type \"cylinder\": e3d reads sphere, box and capsule",
        ),
        (
            arm(geom, "  <default/>\n"),
            "x.xml:3:3: <default> is outside the planar subset",
        ),
        (
            arm(&format!("{geom}      <freejoint/>\n"), ""),
            "x.xml:7:7: <freejoint> moves in 3D",
        ),
        (
            arm(
                "      <geom type=\"capsule\" size=\"0.1 0.2\" mass=\"1\"/>\n",
                "",
            ),
            "x.xml:6:7: a capsule needs fromto",
        ),
        (
            arm(geom, "").replace("<joint name=\"j\"/>", "<joint name=\"j\" axis=\"1 0 0\"/>"),
            "x.xml:5:7: a hinge turns about z",
        ),
        (
            arm(geom, "").replace("<joint name=\"j\"/>", "<joint name=\"j\" stiffness=\"3\"/>"),
            "x.xml:5:7: <joint stiffness=...> is outside the planar subset",
        ),
        (
            arm(geom, "").replace(
                "<motor joint=\"j\" ctrlrange=\"-1 1\"/>",
                "<velocity joint=\"j\"/>",
            ),
            "x.xml:10:5: <velocity> actuators are outside the subset",
        ),
        (
            arm(&format!("{geom}{geom}"), ""),
            "x.xml:7:7: a second geom in body `a`",
        ),
    ];
    for (text, expected) in cases {
        let e = from_mjcf(&text, "x.xml").unwrap_err().to_string();
        assert!(e.starts_with(expected), "{e}\nexpected: {expected}");
    }
    // through the command line: the file, line and column, exit code 2
    let bad = temp_path("bad").with_extension("xml");
    std::fs::write(
        &bad,
        arm("      <geom type=\"plane\" size=\"1 1 1\"/>\n", ""),
    )
    .unwrap();
    let out = e3d(&["scene", "import", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(".xml:6:7: geom type \"plane\""), "{err}");
    let _ = std::fs::remove_file(bad);
}
