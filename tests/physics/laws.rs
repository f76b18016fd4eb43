//! Physics laws, checked on every kind of body and joint the scene format
//! offers: impulse and momentum, momentum of a free chain under internal
//! torques, damping decay, energy of an undamped pendulum, the small-angle
//! period, free fall, motors' settled angles and positions, joint limits
//! and a slider's travel under a known force. Each law has its tolerance;
//! `docs/physics.md` lists them with the errors measured (run this file
//! with `-- --nocapture` to print them).

use e3d::world::Motion;
use e3d::Scene;

/// Parses a scene written in a test.
fn scene(text: &str) -> Scene {
    Scene::parse(text, "law.ron").unwrap_or_else(|e| panic!("{e}"))
}

/// The whole motion of `command` (symbols) on `scene`.
fn motion(scene: &Scene, command: &str) -> Motion {
    let mut world = scene.physics_world().expect("a physics scene");
    let c = scene.command_space().parse(command).unwrap();
    world.motion(&c).unwrap()
}

/// Mass and moment of inertia (about the centre, as docs/physics.md
/// says e3d gives it) of every body, in the scene's order (fixed bodies:
/// 0).
fn inertia(scene: &Scene) -> Vec<(f64, f64)> {
    let e3d::scene::WorldSpec::Physics(p) = &scene.spec().world else {
        panic!("a physics scene")
    };
    p.bodies
        .iter()
        .map(|b| {
            if b.kind != e3d::scene::physics::BodyKind::Dynamic {
                return (0.0, 0.0);
            }
            let m = b.mass_kg();
            let i = b.inertia_kg_m2().expect("a body with an area");
            (m, i)
        })
        .collect()
}

/// Total linear momentum (N·s) of frame `k`.
fn momentum(m: &Motion, mass: &[(f64, f64)], k: usize) -> [f64; 2] {
    let f = &m.frames[k];
    let mut p = [0.0; 2];
    for (v, (mi, _)) in f.velocities.iter().zip(mass) {
        p[0] += mi * v[0];
        p[1] += mi * v[1];
    }
    p
}

/// Centre of mass of frame `k`.
fn centre_of_mass(m: &Motion, mass: &[(f64, f64)], k: usize) -> [f64; 2] {
    let f = &m.frames[k];
    let (mut c, mut total) = ([0.0; 2], 0.0);
    for (pose, (mi, _)) in f.poses.iter().zip(mass) {
        c[0] += mi * pose.position[0];
        c[1] += mi * pose.position[1];
        total += mi;
    }
    [c[0] / total, c[1] / total]
}

fn body(m: &Motion, name: &str) -> usize {
    m.bodies.iter().position(|b| b == name).unwrap()
}

/// A free-floating chain of four links (link1 the root, no joint to
/// ground), a torque on each joint, no gravity: with `contacts`, the
/// links fold onto each other (non-adjacent links touch).
fn free_chain(collide: bool, extra: &str) -> String {
    format!(
        r#"Scene(
    name: "free_chain",
    world: Physics(
        bodies: [
            (name: "link1", shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (0.2, 0.0), collide: {collide} {extra}),
            (name: "link2", shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (0.6, 0.0), collide: {collide} {extra}),
            (name: "link3", shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (1.0, 0.0), collide: {collide} {extra}),
            (name: "link4", shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (1.4, 0.0), collide: {collide} {extra}),
        ],
        joints: [
            (name: "j2", parent: "link1", child: "link2", parent_anchor: (0.2, 0.0), child_anchor: (-0.2, 0.0)),
            (name: "j3", parent: "link2", child: "link3", parent_anchor: (0.2, 0.0), child_anchor: (-0.2, 0.0)),
            (name: "j4", parent: "link3", child: "link4", parent_anchor: (0.2, 0.0), child_anchor: (-0.2, 0.0)),
        ],
        schedule: Simultaneous(push: 1.0, settle: 2.0),
        effect: (body: "link4", grid: (rows: 4, cols: 4, min: (-2.0, -2.0), max: (2.0, 2.0))),
    ),
    command: Slots([
        (alphabet: [(symbol: '0', action: Idle), (symbol: '+', action: Torque(joint: "j2", torque: 1.5))]),
        (alphabet: [(symbol: '0', action: Idle), (symbol: '+', action: Torque(joint: "j3", torque: 1.5))]),
        (alphabet: [(symbol: '0', action: Idle), (symbol: '+', action: Torque(joint: "j4", torque: 1.5))]),
    ]),
)"#
    )
}

/// The largest drift of the centre of mass (m) and of the momentum (N·s)
/// over a motion of a system at rest at the start.
fn drift(m: &Motion, mass: &[(f64, f64)]) -> (f64, f64) {
    let c0 = centre_of_mass(m, mass, 0);
    let (mut dc, mut dp) = (0.0f64, 0.0f64);
    for k in 0..m.frames.len() {
        let c = centre_of_mass(m, mass, k);
        dc = dc.max((c[0] - c0[0]).hypot(c[1] - c0[1]));
        let p = momentum(m, mass, k);
        dp = dp.max(p[0].hypot(p[1]));
    }
    (dc, dp)
}

/// Internal torques on a free chain whose links never touch: the centre
/// of mass stays where it is and the momentum stays 0.
#[test]
fn a_free_chain_keeps_its_momentum_without_contacts() {
    let s = scene(&free_chain(false, ""));
    let mass = inertia(&s);
    for command in ["+00", "0+0", "++0", "+++", "0++"] {
        let m = motion(&s, command);
        let (dc, dp) = drift(&m, &mass);
        println!("law free chain, no contacts, {command}: centre of mass moved {dc:.3e} m, |p| up to {dp:.3e} N·s");
        assert!(dc < 1e-4, "{command}: the centre of mass moved {dc} m");
        assert!(dp < 1e-4, "{command}: momentum {dp} N·s");
    }
}

/// Internal torques that fold a free chain onto itself (non-adjacent
/// links touch): contacts are internal forces too, so the centre of mass
/// stays where it is.
#[test]
fn a_free_chain_keeps_its_momentum_through_self_contact() {
    let s = scene(&free_chain(true, ""));
    let mass = inertia(&s);
    let mut touched = 0;
    for command in ["+00", "0+0", "++0", "+++", "0++", "+0+"] {
        let mut world = s.physics_world().unwrap();
        let c = s.command_space().parse(command).unwrap();
        touched += usize::from(world.inspect(&c).unwrap().contact_steps > 0);
        let m = motion(&s, command);
        let (dc, dp) = drift(&m, &mass);
        println!("law free chain, self-contact, {command}: centre of mass moved {dc:.3e} m, |p| up to {dp:.3e} N·s");
        assert!(dc < 1e-3, "{command}: the centre of mass moved {dc} m");
        assert!(dp < 1e-3, "{command}: momentum {dp} N·s");
    }
    assert!(touched >= 2, "only {touched} commands made links touch");
}

/// One body or link hit by `Impulse(impulse: J)` at the start: the whole
/// system's momentum changes by exactly J in one step (no gravity, no
/// other body to push against). An impulse on a link of a chain hung on
/// `ground` is refused at load (tests/physics/audit.rs).
fn impulse_scene(kind: &str) -> (String, &'static str) {
    let (bodies, joints, target) = match kind {
        // a free body
        "free" => (
            r#"(name: "puck", shape: Ball(radius: 0.2), mass: 2.0, position: (0.0, 0.0))"#,
            "",
            "puck",
        ),
        // the root of a free-floating chain, and a link of it
        "free_root" | "free_link" => (
            r#"(name: "link1", shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (0.2, 0.0)),
               (name: "link2", shape: Cuboid(width: 0.4, height: 0.08), mass: 0.5, position: (0.6, 0.0))"#,
            r#"(name: "j2", parent: "link1", child: "link2", parent_anchor: (0.2, 0.0), child_anchor: (-0.2, 0.0))"#,
            if kind == "free_root" {
                "link1"
            } else {
                "link2"
            },
        ),
        k => panic!("no body kind {k}"),
    };
    (
        format!(
            r#"Scene(
    name: "impulse_{kind}",
    world: Physics(
        bodies: [{bodies}],
        joints: [{joints}],
        schedule: Simultaneous(push: 0.1, settle: 0.0),
        effect: (body: "{target}", grid: (rows: 2, cols: 2, min: (-3.0, -3.0), max: (3.0, 3.0))),
    ),
    command: Slots([
        (alphabet: [(symbol: 'x', action: Impulse(body: "{target}", impulse: (0.3, 0.7)))]),
    ]),
)"#
        ),
        target,
    )
}

/// Δp = J on a free body, on the root of a free-floating chain and on a
/// link of it (the whole chain's momentum), after the impulse's step.
#[test]
fn an_impulse_changes_momentum_by_exactly_j() {
    for kind in ["free", "free_root", "free_link"] {
        let (text, _) = impulse_scene(kind);
        let s = scene(&text);
        let mass = inertia(&s);
        let m = motion(&s, "x");
        let p = momentum(&m, &mass, 1);
        let err = (p[0] - 0.3).hypot(p[1] - 0.7);
        println!("law impulse {kind}: p after one step ({:.6}, {:.6}) N·s for J (0.3, 0.7), error {err:.2e} N·s", p[0], p[1]);
        assert!(err < 1e-4, "{kind}: momentum {p:?} after J = (0.3, 0.7)");
        // and it keeps it (no force acts after the impulse)
        let last = m.frames.len() - 1;
        let q = momentum(&m, &mass, last);
        assert!(
            (q[0] - 0.3).hypot(q[1] - 0.7) < 1e-4,
            "{kind}: {q:?} at the end"
        );
    }
}

/// A body whose `linear_damping` is c and `angular_damping` d, set moving:
/// each step divides its speed by 1 + c dt (spin: 1 + d dt), as
/// docs/scenes.md says; so after n steps v0 / (1 + c dt)^n.
fn damped(kind: &str) -> String {
    let (bodies, joints, target) = match kind {
        "free" => (
            r#"(name: "puck", shape: Ball(radius: 0.2), mass: 1.0, linear_damping: 1.5, angular_damping: 0.8)"#,
            "",
            "puck",
        ),
        "free_root" => (
            r#"(name: "link1", shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (0.2, 0.0), linear_damping: 1.5, angular_damping: 0.8),
               (name: "link2", shape: Cuboid(width: 0.4, height: 0.08), mass: 1.0, position: (0.6, 0.0), linear_damping: 1.5, angular_damping: 0.8)"#,
            r#"(name: "j2", parent: "link1", child: "link2", parent_anchor: (0.2, 0.0), child_anchor: (-0.2, 0.0))"#,
            "link1",
        ),
        k => panic!("no kind {k}"),
    };
    format!(
        r#"Scene(
    name: "damped_{kind}",
    world: Physics(
        bodies: [{bodies}],
        joints: [{joints}],
        schedule: Simultaneous(push: 0.016666666666666666, settle: 1.0),
        effect: (body: "{target}", grid: (rows: 2, cols: 2, min: (-3.0, -3.0), max: (3.0, 3.0))),
    ),
    command: Slots([
        (alphabet: [(symbol: 'x', action: Impulse(body: "{target}", impulse: (1.0, 0.0)))]),
    ]),
)"#
    )
}

/// The documented damping decay on a free body: v_n = v_1 / (1 + c dt)^(n-1).
#[test]
fn damping_divides_the_speed_by_one_plus_c_dt_each_step() {
    let s = scene(&damped("free"));
    let m = motion(&s, "x");
    let dt: f64 = 1.0 / 60.0;
    let v1 = m.frames[1].velocities[0][0];
    let mut worst = 0.0f64;
    for n in 1..m.frames.len() {
        let expected = v1 / (1.0 + 1.5 * dt).powi(n as i32 - 1);
        let v = m.frames[n].velocities[0][0];
        worst = worst.max((v / expected - 1.0).abs());
    }
    println!(
        "law damping free: worst relative error of v_n against v_1 / (1 + c dt)^(n-1): {worst:.2e}"
    );
    assert!(worst < 1e-5, "relative error {worst}");
}

/// A free-floating chain with `linear_damping` on its links: the chain's
/// momentum decays as documented for the links' damping (its centre of
/// mass glides like a free body of that damping).
#[test]
fn damping_slows_a_free_chain_as_documented() {
    let s = scene(&damped("free_root"));
    let mass = inertia(&s);
    let m = motion(&s, "x");
    let dt: f64 = 1.0 / 60.0;
    let p1 = momentum(&m, &mass, 1)[0];
    let n = m.frames.len() - 1;
    let pn = momentum(&m, &mass, n)[0];
    let expected = p1 / (1.0 + 1.5 * dt).powi(n as i32 - 1);
    let err = (pn / expected - 1.0).abs();
    println!("law damping free chain: p after {n} steps {pn:.6} for {expected:.6}, relative error {err:.2e}");
    assert!(err < 1e-3, "momentum {pn}, expected {expected}");
}

/// A pendulum: a ball of radius `r` hung `l` below a ground hinge by its
/// anchor, started `a0` rad off vertical, gravity 9.81, undamped.
fn pendulum(l: f64, r: f64, a0: f64, seconds: f64) -> String {
    let (x, y) = (l * a0.sin(), -l * a0.cos());
    // the anchor in the ball's frame (the ball's angle is 0): from its
    // centre to the hinge
    let (ax, ay) = (-x, -y);
    format!(
        r#"Scene(
    name: "pendulum",
    world: Physics(
        gravity: (0.0, -9.81),
        bodies: [(name: "bob", shape: Ball(radius: {r}), mass: 1.0, position: ({x}, {y}), collide: false)],
        joints: [(name: "hinge", parent: "ground", child: "bob", child_anchor: ({ax}, {ay}))],
        schedule: Simultaneous(push: 0.016666666666666666, settle: {settle}),
        effect: (body: "bob", grid: (rows: 2, cols: 2, min: (-3.0, -3.0), max: (3.0, 3.0))),
    ),
    command: Slots([(alphabet: [(symbol: '0', action: Idle)])]),
)"#,
        settle = seconds - 1.0 / 60.0
    )
}

/// Energy (kinetic + potential) of an undamped pendulum over 10 s.
#[test]
fn an_undamped_pendulum_keeps_its_energy_for_ten_seconds() {
    let s = scene(&pendulum(1.0, 0.05, 0.5, 10.0));
    let mass = inertia(&s);
    let m = motion(&s, "0");
    let energy = |k: usize| {
        let f = &m.frames[k];
        let (mi, ii) = mass[0];
        let v = f.velocities[0];
        0.5 * mi * (v[0] * v[0] + v[1] * v[1])
            + 0.5 * ii * v[2] * v[2]
            + mi * 9.81 * f.poses[0].position[1]
    };
    let e0 = energy(0);
    // the swing's scale: the potential energy between the lowest and the
    // start height
    let scale = 1.0 * 9.81 * 1.0 * (1.0 - 0.5f64.cos());
    let worst = (0..m.frames.len())
        .map(|k| (energy(k) - e0).abs())
        .fold(0.0, f64::max);
    let end = energy(m.frames.len() - 1) - e0;
    println!(
        "law pendulum energy over 10 s: worst |E - E0| {worst:.3e} J, at the end {end:.3e} J, of a swing of {scale:.4} J ({:.2}% worst)",
        100.0 * worst / scale
    );
    assert!(worst < 0.02 * scale, "energy drift {worst} J of {scale} J");
}

/// The small-angle period of a pendulum of length 1 m against 2π√(L/g)
/// (a ball of radius 0.02 m: its own inertia lengthens the period by
/// (1 + r²/(2L²))^½ - 1 = 1e-4).
#[test]
fn a_small_swing_has_the_period_of_the_ideal_pendulum() {
    let l = 1.0;
    let s = scene(&pendulum(l, 0.02, 0.05, 10.0));
    let m = motion(&s, "0");
    let x: Vec<f64> = m.frames.iter().map(|f| f.poses[0].position[0]).collect();
    // upward zero crossings of x, linearly interpolated
    let mut crossings = Vec::new();
    for k in 1..x.len() {
        if x[k - 1] < 0.0 && x[k] >= 0.0 {
            crossings.push((k - 1) as f64 + x[k - 1] / (x[k - 1] - x[k]));
        }
    }
    assert!(crossings.len() >= 4, "{} crossings", crossings.len());
    let dt: f64 = 1.0 / 60.0;
    let n = crossings.len() - 1;
    let period = (crossings[n] - crossings[0]) * dt / n as f64;
    let ideal = std::f64::consts::TAU * (l / 9.81f64).sqrt();
    let err = period / ideal - 1.0;
    println!("law pendulum period: {period:.5} s over {n} periods, 2π√(L/g) = {ideal:.5} s, relative error {err:.2e}");
    assert!(err.abs() < 2e-3, "period {period} s, ideal {ideal} s");
}

/// Free fall: a ball dropped from rest under gravity g. Rapier integrates
/// semi-implicitly (velocity first) in 4 substeps of h = dt / 4 per step
/// (its solver iterations), so after n steps, m = 4n substeps,
/// y = y0 - g h² m(m+1)/2; the continuous y0 - g t²/2 is lower by
/// g h t / 2.
#[test]
fn free_fall_follows_the_semi_implicit_law() {
    let text = r#"Scene(
    name: "fall",
    world: Physics(
        gravity: (0.0, -9.81),
        bodies: [(name: "ball", shape: Ball(radius: 0.1), mass: 1.0, position: (0.0, 10.0))],
        schedule: Simultaneous(push: 0.016666666666666666, settle: 0.9833333333333333),
        effect: (body: "ball", grid: (rows: 2, cols: 2, min: (-3.0, -3.0), max: (3.0, 30.0))),
    ),
    command: Slots([(alphabet: [(symbol: '0', action: Idle)])]),
)"#;
    let s = scene(text);
    let m = motion(&s, "0");
    let dt: f64 = 1.0 / 60.0;
    let (mut worst, mut worst_continuous) = (0.0f64, 0.0f64);
    for (n, f) in m.frames.iter().enumerate() {
        let n = n as f64;
        let y = f.poses[0].position[1];
        let (h, m) = (dt / 4.0, 4.0 * n);
        let discrete = 10.0 - 9.81 * h * h * m * (m + 1.0) / 2.0;
        let t = n * dt;
        let continuous = 10.0 - 9.81 * t * t / 2.0;
        worst = worst.max((y - discrete).abs());
        worst_continuous = worst_continuous.max((y - continuous).abs());
        let v = f.velocities[0][1];
        assert!((v + 9.81 * t).abs() < 1e-4, "v {v} at {t} s");
    }
    println!("law free fall over 1 s: |y - semi-implicit| up to {worst:.2e} m, |y - continuous| up to {worst_continuous:.3e} m (g h t / 2 = {:.3e} m)", 9.81 * dt / 8.0);
    assert!(worst < 1e-5, "{worst} m from the semi-implicit law");
    assert!(worst_continuous <= 9.81 * dt / 8.0 + 1e-5);
}

/// A hinge with a position motor, `Target(angle: 0.5)`, no gravity: the
/// joint settles at 0.5 rad.
#[test]
fn a_motor_settles_at_its_target_angle() {
    let text = r#"Scene(
    name: "motor",
    world: Physics(
        bodies: [(name: "arm", shape: Cuboid(width: 0.5, height: 0.05), mass: 0.5, position: (0.25, 0.0))],
        joints: [(name: "j", parent: "ground", child: "arm", child_anchor: (-0.25, 0.0),
                  motor: (stiffness: 5.0, damping: 0.5))],
        schedule: Simultaneous(push: 0.5, settle: 4.5),
        effect: (body: "arm", grid: (rows: 2, cols: 2, min: (-3.0, -3.0), max: (3.0, 3.0))),
    ),
    command: Slots([(alphabet: [(symbol: 't', action: Target(joint: "j", angle: 0.5)),
                                (symbol: 'u', action: Target(joint: "j", angle: -1.2))])]),
)"#;
    let s = scene(text);
    for (command, target) in [("t", 0.5), ("u", -1.2)] {
        let m = motion(&s, command);
        let a = m.frames.last().unwrap().joint_angles[0];
        println!(
            "law motor angle: settled at {a:.6} rad for a target {target} rad, error {:.2e}",
            a - target
        );
        assert!((a - target).abs() < 1e-3, "settled at {a}, target {target}");
    }
}

/// A hinge with limits (-0.4, 0.3) pushed by a torque far beyond them: the
/// joint never goes more than 0.03 rad past a limit (Rapier's limits are
/// slightly soft: the overshoot is about a substep of the speed at
/// impact) and ends at it.
#[test]
fn joint_limits_hold() {
    let text = r#"Scene(
    name: "limits",
    world: Physics(
        bodies: [(name: "arm", shape: Cuboid(width: 0.5, height: 0.05), mass: 0.5, position: (0.25, 0.0))],
        joints: [(name: "j", parent: "ground", child: "arm", child_anchor: (-0.25, 0.0),
                  limits: (-0.4, 0.3), damping: 0.05)],
        schedule: Simultaneous(push: 2.0, settle: 0.0),
        effect: (body: "arm", grid: (rows: 2, cols: 2, min: (-3.0, -3.0), max: (3.0, 3.0))),
    ),
    command: Slots([(alphabet: [(symbol: '+', action: Torque(joint: "j", torque: 2.0)),
                                (symbol: '-', action: Torque(joint: "j", torque: -2.0))])]),
)"#;
    let s = scene(text);
    for (command, limit) in [("+", 0.3), ("-", -0.4)] {
        let m = motion(&s, command);
        let past = m
            .frames
            .iter()
            .map(|f| (f.joint_angles[0].abs() - f64::abs(limit)).max(0.0))
            .fold(0.0, f64::max);
        let end = m.frames.last().unwrap().joint_angles[0];
        println!("law limits: {command} went at most {past:.2e} rad past {limit}, ends {:.2e} rad from it", end - limit);
        assert!(past < 0.03, "{past} rad past the limit");
        assert!((end - limit).abs() < 0.01, "ends at {end}");
    }
}

/// A slider (prismatic joint) along `axis` from `parent` (`ground` or a
/// free body), its child a 2 kg cart; `extra` adds fields to the joint.
fn slider(parent: &str, axis: (f64, f64), extra: &str, settle: f64) -> String {
    let base = if parent == "ground" {
        String::new()
    } else {
        format!(
            r#"(name: "{parent}", shape: Cuboid(width: 0.6, height: 0.1), mass: 3.0, position: (0.0, 0.0), collide: false),"#
        )
    };
    format!(
        r#"Scene(
    name: "slider",
    world: Physics(
        bodies: [
            {base}
            (name: "cart", shape: Cuboid(width: 0.3, height: 0.2), mass: 2.0, position: (0.0, 0.0), collide: false),
        ],
        joints: [(name: "s", parent: "{parent}", child: "cart", kind: Prismatic(axis: ({ax}, {ay})) {extra})],
        schedule: Simultaneous(push: 1.0, settle: {settle}),
        effect: (body: "cart", grid: (rows: 2, cols: 2, min: (-3.0, -3.0), max: (3.0, 3.0))),
    ),
    command: Slots([(alphabet: [
        (symbol: 'f', action: Force(body: "cart", force: (3.0, 4.0))),
        (symbol: '0', action: Idle),
    ])]),
)"#,
        ax = axis.0,
        ay = axis.1
    )
}

/// A slider on ground along x: a force (3, 4) N on its 2 kg cart for 1 s
/// moves it F_x t² / (2 m) = 0.75 m along the axis (lengthened by h / t,
/// h = dt / 4, by the semi-implicit substeps, as in free fall) and not at
/// all across it; along the axis (0.6, 0.8), the force's part along it
/// (5 N) moves it 1.25 m.
#[test]
fn a_slider_travels_as_the_force_along_its_axis_says() {
    for (axis, along) in [((1.0, 0.0), 3.0), ((0.6, 0.8), 5.0)] {
        let s = scene(&slider("ground", axis, "", 0.0));
        let m = motion(&s, "f");
        let f = m.frames.last().unwrap();
        let cart = body(&m, "cart");
        let [x, y] = f.poses[cart].position;
        let n = f64::hypot(axis.0, axis.1);
        let (ux, uy) = (axis.0 / n, axis.1 / n);
        let travel = x * ux + y * uy;
        let across = (-x * uy + y * ux).abs();
        // F (t² + h t) / (2 m), t = 1 s: semi-implicit substeps of h = dt / 4
        let h = 1.0 / 240.0;
        let expected = along * (1.0 + h) / 2.0 / 2.0;
        let err = travel / expected - 1.0;
        println!("law slider travel, axis {axis:?}: {travel:.6} m for F t²/(2m) = {expected} m (relative error {err:.2e}), {across:.2e} m across, joint position {:.6} m, angle {:.2e} rad", f.joint_angles[0], f.poses[cart].angle);
        assert!(err.abs() < 1e-4, "travel {travel} m, expected {expected} m");
        assert!(across < 1e-4, "{across} m across the axis");
        assert!(f.poses[cart].angle.abs() < 1e-4, "the cart turned");
        assert!(
            (f.joint_angles[0] - travel).abs() < 1e-4,
            "the joint's position"
        );
    }
}

/// A slider between two free bodies (a free-floating tree): the force on
/// the cart acts on the pair (the joint passes on what it does not let
/// slide), so the pair's momentum after 1 s is F t = (3, 4) N·s.
#[test]
fn a_slider_between_free_bodies_conserves_momentum() {
    let s = scene(&slider("base", (1.0, 0.0), "", 0.0));
    let mass = inertia(&s);
    let m = motion(&s, "f");
    let last = m.frames.len() - 1;
    let p = momentum(&m, &mass, last);
    let err = (p[0] - 3.0).hypot(p[1] - 4.0);
    println!(
        "law slider between free bodies: momentum ({:.6}, {:.6}) N·s for F t = (3, 4), error {err:.2e}",
        p[0], p[1]
    );
    assert!(err < 1e-3, "momentum {p:?}");
}

/// A slider's position motor settles at its target (no gravity), on
/// ground (a multibody) and between free bodies (an impulse joint).
#[test]
fn a_slider_motor_settles_at_its_target_position() {
    for parent in ["ground", "base"] {
        let text = slider(
            parent,
            (1.0, 0.0),
            ", motor: (stiffness: 20.0, damping: 8.0), damping: 1.0",
            5.0,
        )
        .replace(
            "(symbol: '0', action: Idle)",
            "(symbol: 't', action: Target(joint: \"s\", position: 0.4))",
        );
        let s = scene(&text);
        let m = motion(&s, "t");
        let q = m.frames.last().unwrap().joint_angles[0];
        println!(
            "law slider motor ({parent}): settled at {q:.6} m for a target 0.4 m, error {:.2e}",
            q - 0.4
        );
        assert!((q - 0.4).abs() < 1e-3, "{parent}: settled at {q}");
    }
}

/// A slider's limits hold against a force far beyond them.
#[test]
fn slider_limits_hold() {
    for parent in ["ground", "base"] {
        let s = scene(&slider(parent, (1.0, 0.0), ", limits: (-0.1, 0.2)", 1.0));
        let m = motion(&s, "f");
        let past = m
            .frames
            .iter()
            .map(|f| f.joint_angles[0] - 0.2)
            .fold(f64::MIN, f64::max);
        let end = m.frames.last().unwrap().joint_angles[0];
        println!("law slider limits ({parent}): at most {past:.2e} m past 0.2, ends at {end:.6} m");
        assert!(past < 0.01, "{parent}: {past} m past the limit");
        assert!((end - 0.2).abs() < 0.01, "{parent}: ends at {end}");
    }
}

/// A torque `t` held on a body pinned at its centre of mass spins it up
/// by `t dt / I` per step: the inertia e3d documents (`BodySpec::inertia_kg_m2`,
/// parry2d's formulas) is the one Rapier uses, for every shape with an
/// area and for an `inertia:` set by hand.
#[test]
fn a_torque_spins_a_body_as_its_documented_inertia_says() {
    let shapes = [
        "Ball(radius: 0.2), mass: 2.0",
        "Cuboid(width: 0.5, height: 0.1), mass: 1.5",
        "Capsule(a: (-0.3, 0.0), b: (0.3, 0.0), radius: 0.05), mass: 0.4",
        "Capsule(a: (-0.1, 0.0), b: (0.3, 0.1), radius: 0.1), density: 3.0",
        "Capsule(a: (-0.3, 0.0), b: (0.3, 0.0), radius: 0.05), mass: 0.4, inertia: 0.02",
    ];
    for shape in shapes {
        // `Torque` acts through a joint: a hinge to ground at the centre
        // of mass, which carries no torque
        let text = format!(
            r#"Scene(
    name: "spin",
    world: Physics(
        bodies: [(name: "b", shape: {shape}, collide: false)],
        joints: [(name: "pin", parent: "ground", child: "b", parent_anchor: ({cx}, {cy}), child_anchor: ({cx}, {cy}))],
        schedule: Simultaneous(push: 1.0, settle: 0.0),
        effect: (body: "b", grid: (rows: 2, cols: 2, min: (-3.0, -3.0), max: (3.0, 3.0))),
    ),
    command: Slots([(alphabet: [(symbol: 'x', action: Torque(joint: "pin", torque: 0.01))])]),
)"#,
            cx = centre(shape).0,
            cy = centre(shape).1,
        );
        let s = scene(&text);
        let (_, i) = inertia(&s)[0];
        let m = motion(&s, "x");
        // the spin-up per step (the first step gives 3/4 of it: Rapier
        // applies the torque from its second substep of four)
        let w = m.frames[31].velocities[0][2] - m.frames[30].velocities[0][2];
        let expected = 0.01 / 60.0 / i;
        let err = (w / expected - 1.0).abs();
        println!("law inertia {shape}: I = {i:.6e} kg·m², Δω per step {w:.6e} for {expected:.6e} rad/s, relative error {err:.1e}");
        assert!(
            err < 1e-4,
            "{shape}: ω {w} rad/s, expected {expected} from I = {i}"
        );
    }
}

/// The centre of a capsule written in a shape string of the test above.
fn centre(shape: &str) -> (f64, f64) {
    let n: Vec<f64> = shape
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .filter_map(|t| t.parse().ok())
        .collect();
    if shape.starts_with("Capsule") {
        ((n[0] + n[2]) / 2.0, (n[1] + n[3]) / 2.0)
    } else {
        (0.0, 0.0)
    }
}

/// The shipped `swimmer_drag` scene with its drag, or without (`drag:
/// false`).
fn swimmer(drag: bool) -> Scene {
    let s = Scene::builtin("swimmer_drag").unwrap();
    if drag {
        return s;
    }
    let mut spec = s.spec().clone();
    let e3d::scene::WorldSpec::Physics(p) = &mut spec.world else {
        panic!("a physics scene")
    };
    for b in &mut p.bodies {
        b.drag = None;
    }
    spec.validate().unwrap()
}

/// The drag force and torque on each body in frame `k` (as
/// `DragSpec::force` computes it), and the bodies' drags.
fn drag_force(s: &Scene, m: &Motion, k: usize) -> [f64; 2] {
    let e3d::scene::WorldSpec::Physics(p) = &s.spec().world else {
        panic!("a physics scene")
    };
    let f = &m.frames[k];
    let mut total = [0.0; 2];
    for (b, (pose, v)) in p.bodies.iter().zip(f.poses.iter().zip(&f.velocities)) {
        if let Some(d) = b.drag {
            let (force, _) = d.force(pose.angle, (v[0], v[1]), v[2]);
            total[0] += force.0;
            total[1] += force.1;
        }
    }
    total
}

/// The swimmer in water: internal torques on a free chain with
/// anisotropic drag, in a walled box it never touches. At every step
/// its momentum changes by the drag impulse and nothing else (Σ F dt of
/// the drag at the step's start), and it moves: its centre of mass ends
/// centimetres from where it started. Without drag the same commands
/// leave the momentum 0 and the centre of mass where it was.
#[test]
fn a_swimmer_moves_by_drag_alone_and_its_momentum_changes_by_the_drag_impulses() {
    let dt = 1.0 / 60.0;
    let (wet, dry) = (swimmer(true), swimmer(false));
    let (mass, dry_mass) = (inertia(&wet), inertia(&dry));
    let mut farthest = 0.0f64;
    for command in ["+++000", "+-+-+-", "0+0-+0", "++--++", "-0+0-0"] {
        let mut world = wet.physics_world().unwrap();
        let c = wet.command_space().parse(command).unwrap();
        assert_eq!(
            world.inspect(&c).unwrap().contact_steps,
            0,
            "{command} touched something"
        );
        let m = motion(&wet, command);
        let (mut worst, mut largest) = (0.0f64, 0.0f64);
        for k in 0..m.frames.len() - 1 {
            let (p0, p1) = (momentum(&m, &mass, k), momentum(&m, &mass, k + 1));
            let f = drag_force(&wet, &m, k);
            let err = (p1[0] - p0[0] - f[0] * dt).hypot(p1[1] - p0[1] - f[1] * dt);
            worst = worst.max(err);
            largest = largest.max((f[0] * dt).hypot(f[1] * dt));
        }
        let (c0, c1) = (
            centre_of_mass(&m, &mass, 0),
            centre_of_mass(&m, &mass, m.frames.len() - 1),
        );
        let moved = (c1[0] - c0[0]).hypot(c1[1] - c0[1]);
        farthest = farthest.max(moved);
        println!("law swimmer {command}: |Δp - drag impulse| up to {worst:.2e} N·s (drag impulses up to {largest:.2e} N·s); centre of mass moved {moved:.4} m");
        assert!(
            worst < 1e-3 * largest.max(1e-6) + 1e-7,
            "{command}: Δp off the drag impulse by {worst} N·s"
        );
        let dry_motion = motion(&dry, command);
        let (dc, dp) = drift(&dry_motion, &dry_mass);
        println!("law swimmer {command} without drag: centre of mass moved {dc:.2e} m, |p| up to {dp:.2e} N·s");
        assert!(
            dc < 1e-4 && dp < 1e-4,
            "{command} without drag: moved {dc} m, p {dp}"
        );
    }
    assert!(farthest > 0.05, "the swimmer moved at most {farthest} m");
}
