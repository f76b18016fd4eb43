//! Whole motions: every body's pose and velocity, every joint's angle and
//! velocity, per step, from the library and from `scene exec --trace`.

use e3d::{Scene, World};

#[test]
fn a_motion_ends_where_the_command_does_and_mirrors_exactly() {
    let scene = Scene::builtin("arm7").unwrap();
    let space = scene.command_space();
    let mut world = scene.physics_world().unwrap();
    let c = space.parse("+-0+0-+").unwrap();
    let image = space.parse("-+0-0+-").unwrap();
    let m = world.motion(&c).unwrap();
    assert_eq!(m.outcome, scene.build().execute(&c).unwrap());
    assert_eq!(m.frames.len(), 121);
    assert_eq!(m.bodies.len(), 7); // the links: the base is the fixed ground
    assert_eq!(m.joints.len(), 7);
    assert_eq!(m.frames[120].time, 120.0 / 60.0);
    // the start: at rest, every joint at 0
    assert!(m.frames[0].joint_angles.iter().all(|&a| a == 0.0));
    assert!(m.frames[0].velocities.iter().all(|v| *v == [0.0; 3]));
    // the last frame's poses are those the trace keeps
    let trace = world.trace(&c).unwrap();
    assert_eq!(m.frames[120].poses, trace.poses);
    // joint 1's velocity is the first link's angular velocity (its parent
    // is the ground), joint 2's the second's minus the first's
    let f = &m.frames[10];
    assert_eq!(f.joint_velocities[0], f.velocities[0][2]);
    assert_eq!(
        f.joint_velocities[1],
        f.velocities[1][2] - f.velocities[0][2]
    );
    assert!(f.joint_velocities[0] > 0.0, "pushed by +t");
    // the mirror image's motion: every joint turned the other way, bit for bit
    let mi = world.motion(&image).unwrap();
    for (a, b) in m.frames.iter().zip(&mi.frames) {
        let neg: Vec<f64> = a.joint_angles.iter().map(|x| -x).collect();
        assert_eq!(b.joint_angles, neg);
        let ys: Vec<f64> = a.poses.iter().map(|p| -p.position[1]).collect();
        let yi: Vec<f64> = b.poses.iter().map(|p| p.position[1]).collect();
        assert_eq!(yi, ys);
    }
    assert!(Scene::builtin("two_rooms")
        .unwrap()
        .physics_world()
        .is_none());
}

#[test]
fn scene_exec_trace_writes_every_frame_of_every_command() {
    let dir = std::env::temp_dir().join(format!("e3d-motion-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("motion.csv");
    let e3d = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_e3d"))
            .args(args)
            .output()
            .unwrap()
    };
    let cmds = ["SEEEEES", "NNNNNNN"];
    let traced = e3d(&[
        "scene",
        "exec",
        "puck_rooms",
        "--trace",
        file.to_str().unwrap(),
        cmds[0],
        cmds[1],
    ]);
    assert!(traced.status.success(), "{traced:?}");
    let plain = e3d(&["scene", "exec", "puck_rooms", cmds[0], cmds[1]]);
    assert_eq!(traced.stdout, plain.stdout);
    let csv = std::fs::read_to_string(&file).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    // a header, then 541 frames (the start and 540 steps) per command
    assert_eq!(lines.len(), 1 + 2 * 541);
    assert!(lines[0].starts_with("command,step,time,"), "{}", lines[0]);
    assert!(lines[0].contains("puck.x,puck.y,puck.angle,puck.vx,puck.vy,puck.omega"));
    assert!(lines[1].starts_with("SEEEEES,0,0,"));
    assert!(lines[542].starts_with("NNNNNNN,0,0,"));
    // the puck's last position is the row's terminal point
    let header: Vec<&str> = lines[0].split(',').collect();
    let x = header.iter().position(|&h| h == "puck.x").unwrap();
    let last: Vec<&str> = lines[541].split(',').collect();
    let row = String::from_utf8(plain.stdout).unwrap();
    let row: Vec<&str> = row.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(last[x], row[3]);
    assert_eq!(last[x + 1], row[4]);
    // a grid has no motion: refused, nothing written
    let grid = e3d(&[
        "scene",
        "exec",
        "two_rooms",
        "--trace",
        dir.join("g.csv").to_str().unwrap(),
        "EEEEEEE",
    ]);
    assert_eq!(grid.status.code(), Some(2));
    assert!(!dir.join("g.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
