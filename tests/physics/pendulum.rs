//! Pendulums: the small-oscillation period, and joint position targets.

use e3d::world::PhysicsWorld;
use e3d::{Scene, World};

/// A rod of length 1 m, width 0.02 m and 1 kg hanging from the ground at
/// the origin, started `theta0` rad off the vertical, no damping.
fn pendulum(theta0: f64) -> Scene {
    let a = -std::f64::consts::FRAC_PI_2 + theta0;
    let (x, y) = (0.5 * a.cos(), 0.5 * a.sin());
    let text = format!(
        r#"Scene(
    name: "pendulum",
    world: Physics(
        gravity: (0.0, -9.81),
        bodies: [(name: "rod", shape: Cuboid(width: 1.0, height: 0.02), mass: 1.0,
                  position: ({x}, {y}), angle: {a})],
        joints: [(name: "pivot", parent: "ground", child: "rod", child_anchor: (-0.5, 0.0))],
        schedule: Simultaneous(push: 0.016666666666666666, settle: 10.0),
        effect: (body: "rod", point: (0.5, 0.0),
                 grid: (rows: 4, cols: 4, min: (-1.0, -1.0), max: (1.0, 1.0))),
    ),
    command: Repeat(slots: 1, alphabet: [(symbol: '0', action: Idle)]),
)"#
    );
    Scene::parse(&text, "pendulum.ron").unwrap()
}

fn world(scene: &Scene) -> PhysicsWorld {
    scene.physics_world().expect("a physics scene")
}

#[test]
fn the_small_oscillation_period_is_two_pi_sqrt_i_over_mgd() {
    // I about the pivot: m (L² + w²) / 12 + m (L/2)², d = L/2.
    let (m, l, w, g) = (1.0f64, 1.0f64, 0.02f64, 9.81f64);
    let i = m * (l * l + w * w) / 12.0 + m * (l / 2.0).powi(2);
    let expected = 2.0 * std::f64::consts::PI * (i / (m * g * l / 2.0)).sqrt();
    let scene = pendulum(0.05);
    let mut wd = world(&scene);
    let c = wd.command_space().parse("0").unwrap();
    let t = wd.trace(&c).unwrap();
    // the times the tip crosses x = 0 going right (linear interpolation)
    let dt = 1.0 / 60.0;
    let mut ups = Vec::new();
    for (k, p) in t.points.windows(2).enumerate() {
        if p[0][0] < 0.0 && p[1][0] >= 0.0 {
            ups.push((k as f64 + p[0][0] / (p[0][0] - p[1][0])) * dt);
        }
    }
    assert!(ups.len() >= 4, "{} crossings", ups.len());
    let period = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
    // Symplectic Euler keeps the energy bounded and changes the period of a
    // linear oscillator by a factor 1 + (omega dt)² / 24 + ...: with omega
    // = 3.84 rad/s and dt = 1/60, 1.7e-4. The amplitude of 0.05 rad adds
    // theta0² / 16 = 1.6e-4, the crossing interpolation about (omega dt)² /
    // 8 / cycles. 1% leaves room for all of it; we also check 0.2%.
    let rel = (period - expected).abs() / expected;
    eprintln!(
        "period {period:.5} s, expected {expected:.5} s, {rel:.2e} relative, {} crossings",
        ups.len()
    );
    assert!(rel < 0.01, "period {period}, expected {expected}");
    assert!(rel < 0.002, "period {period}, expected {expected}");
}

#[test]
fn an_undamped_pendulum_keeps_its_amplitude() {
    // no damping (a joint's damping defaults to 0, not to Rapier's 0.1):
    // after 10 s the swing still reaches about its start angle
    let scene = pendulum(0.2);
    let mut wd = world(&scene);
    let t = wd.trace(&wd.command_space().parse("0").unwrap()).unwrap();
    let last_swing = t.points[t.points.len() - 120..]
        .iter()
        .map(|p| p[0].abs())
        .fold(0.0, f64::max);
    let first = 0.2f64.sin();
    assert!(
        (last_swing - first).abs() / first < 0.05,
        "{last_swing} vs {first}"
    );
}

#[test]
fn targets_move_the_arm_of_pendulum3_and_idle_keeps_it_hanging() {
    let scene = Scene::load("scenes/pendulum3.ron").unwrap();
    let mut w = scene.build();
    let mut at = |c: &str| {
        w.execute(&w.command_space().parse(c).unwrap())
            .unwrap()
            .point
    };
    // no target: the motors hold the hanging pose
    let rest = at("ccc");
    assert!(
        rest[0].abs() < 1e-4 && (rest[1] + 0.9).abs() < 1e-3,
        "{rest:?}"
    );
    // the shoulder swings the whole arm to the right (positive angle:
    // counter-clockwise from hanging); gravity makes it sag below the target
    let right = at("ecc");
    assert!(right[0] > 0.6 && right[1] > -0.4, "{right:?}");
    let left = at("acc");
    assert!(
        (left[0] + right[0]).abs() < 1e-3 && (left[1] - right[1]).abs() < 1e-3,
        "{left:?} mirrors {right:?}"
    );
    // 125 commands reach many cells
    let space = w.command_space().clone();
    let mut cells = std::collections::BTreeSet::new();
    for c in space.iter() {
        cells.insert(w.execute(&c).unwrap().effect);
    }
    assert!(cells.len() >= 20, "{} cells", cells.len());
}

#[test]
fn joint_damping_decays_the_spin_at_rate_b_over_i() {
    // A rod on a pivot, no gravity, joint damping b = 0.05 N*m*s/rad, I =
    // 1/3 kg m² about the pivot: once the torque stops, omega decays as
    // e^(-b t / I) and the kinetic energy as e^(-2 b t / I). The multibody
    // damping is implicit, omega_{k+1} = omega_k / (1 + b dt / I) per step:
    // after 60 steps (1/(1+0.0025))^120 = 0.7408 for the energy against
    // e^-0.3 = 0.7408 continuous (the two differ by 3.7e-4 relative).
    let text = r#"Scene(
    name: "spin",
    world: Physics(
        bodies: [(name: "rod", shape: Cuboid(width: 1.0, height: 0.02), mass: 1.0, position: (0.5, 0.0))],
        joints: [(name: "pivot", parent: "ground", child: "rod", child_anchor: (-0.5, 0.0), damping: 0.05)],
        schedule: Simultaneous(push: 0.1, settle: 1.1),
        effect: (body: "rod", grid: (rows: 2, cols: 2, min: (-1.0, -1.0), max: (1.0, 1.0))),
    ),
    command: Repeat(slots: 1, alphabet: [(symbol: 'T', action: Torque(joint: "pivot", torque: 1.0))]),
)"#;
    let scene = Scene::parse(text, "spin.ron").unwrap();
    let mut w = world(&scene);
    let e = w
        .kinetic_energy_trace(&w.command_space().parse("T").unwrap())
        .unwrap();
    let i = (1.0 + 0.02f64 * 0.02) / 12.0 + 0.25;
    // Rapier computes a multibody's accelerations from the forces present
    // at the end of the previous step: a torque acts one solver substep
    // late (1/4 step with the default 4 iterations). Its whole impulse
    // arrives, 1 N*m x 0.1 s, but the last quarter step of it lands in the
    // first step after the push: we start counting one step later.
    let omega = (2.0 * e[6] / i).sqrt();
    let expected_omega = 0.1 / i * (1.0 / (1.0 + 0.05 / 60.0 / i)).powf(3.75);
    assert!(
        (omega - expected_omega).abs() / expected_omega < 0.01,
        "{omega} vs {expected_omega}"
    );
    let ratio = e[6 + 60] / e[6];
    let continuous = (-2.0 * 0.05 * 1.0 / i).exp();
    let implicit = (1.0 / (1.0 + 0.05 / 60.0 / i)).powi(120);
    eprintln!(
        "energy ratio over 1 s: {ratio:.6}, implicit {implicit:.6}, continuous {continuous:.6}"
    );
    assert!(
        (ratio - implicit).abs() / implicit < 1e-3,
        "{ratio} vs {implicit}"
    );
    assert!(
        (ratio - continuous).abs() / continuous < 0.01,
        "{ratio} vs {continuous}"
    );
}
