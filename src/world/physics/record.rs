//! Recording what a command does: the tracked point's path, every body's
//! pose and velocity and every joint's angle step by step, and statistics
//! for diagnostics.

use super::{Cmd, PhysicsWorld, Sets};
use crate::command::Command;
use crate::scene::Symmetry;
use crate::world::{Outcome, WorldError};

/// The pose of one body, for pictures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyPose {
    /// The position of the body's origin `(x, y)`, metres.
    pub position: [f64; 2],
    /// The angle in radians.
    pub angle: f64,
}

/// What [`PhysicsWorld::trace`] records.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    /// The tracked point at the start and after every step.
    pub points: Vec<[f64; 2]>,
    /// The terminal pose of every body of the scene, in the scene's order.
    pub poses: Vec<BodyPose>,
    /// The outcome (as [`World::execute`](crate::World::execute) returns it).
    pub outcome: Outcome,
}

/// The whole motion of one command, step by step (see
/// [`PhysicsWorld::motion`]): every body's pose and velocity and every
/// joint's angle and angular velocity, at the start and after each step.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// The scene's bodies, in its order (fixed ones included).
    pub bodies: Vec<String>,
    /// The scene's joints, in its order.
    pub joints: Vec<String>,
    /// The start (time 0) and every step after it.
    pub frames: Vec<Frame>,
    /// The outcome (as [`World::execute`](crate::World::execute) returns it).
    pub outcome: Outcome,
}

/// One instant of a [`Motion`].
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Seconds since the start of the command.
    pub time: f64,
    /// The pose of each body, in [`Motion::bodies`]' order.
    pub poses: Vec<BodyPose>,
    /// Each body's velocity: `(vx, vy)` m/s and the angular velocity rad/s.
    pub velocities: Vec<[f64; 3]>,
    /// Each joint's angle (the child's rotation relative to the parent,
    /// 0 at the start pose, radians in `(-pi, pi]`), in
    /// [`Motion::joints`]' order.
    pub joint_angles: Vec<f64>,
    /// Each joint's angular velocity (child's minus parent's), rad/s.
    pub joint_velocities: Vec<f64>,
}

impl Motion {
    /// Writes the motion as CSV, one row per frame: `step,time`, then per
    /// body `NAME.x,NAME.y,NAME.angle,NAME.vx,NAME.vy,NAME.omega`, then per
    /// joint `NAME.angle,NAME.velocity`; with `command`, a leading
    /// `command` column holding it (and `header` false: rows only, for
    /// several commands in one file).
    pub fn write_csv(
        &self,
        mut out: impl std::io::Write,
        command: Option<&str>,
        header: bool,
    ) -> std::io::Result<()> {
        if header {
            let body = ["x", "y", "angle", "vx", "vy", "omega"];
            let cols: Vec<String> = (command.map(|_| "command".to_string()).into_iter())
                .chain(["step".into(), "time".into()])
                .chain(
                    self.bodies
                        .iter()
                        .flat_map(|b| body.map(|f| format!("{b}.{f}"))),
                )
                .chain(
                    (self.joints.iter())
                        .flat_map(|j| [format!("{j}.angle"), format!("{j}.velocity")]),
                )
                .collect();
            writeln!(out, "{}", cols.join(","))?;
        }
        for (k, f) in self.frames.iter().enumerate() {
            Self::write_csv_row(&mut out, command, k, f)?;
        }
        Ok(())
    }

    /// One row of [`write_csv`](Self::write_csv): frame `k`.
    pub fn write_csv_row(
        mut out: impl std::io::Write,
        command: Option<&str>,
        k: usize,
        f: &Frame,
    ) -> std::io::Result<()> {
        let mut row = String::new();
        if let Some(c) = command {
            row.push_str(c);
            row.push(',');
        }
        row.push_str(&format!("{k},{}", f.time));
        for (p, v) in f.poses.iter().zip(&f.velocities) {
            for x in [p.position[0], p.position[1], p.angle, v[0], v[1], v[2]] {
                row.push_str(&format!(",{x}"));
            }
        }
        for (a, w) in f.joint_angles.iter().zip(&f.joint_velocities) {
            row.push_str(&format!(",{a},{w}"));
        }
        writeln!(out, "{row}")
    }
}

/// What happened during one command, for diagnostics (see
/// [`PhysicsWorld::inspect`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunStats {
    /// The outcome (as [`World::execute`](crate::World::execute) returns it).
    pub outcome: Outcome,
    /// The largest linear speed of a dynamic body, m/s.
    pub max_speed: f64,
    /// The largest angular speed of a dynamic body, rad/s.
    pub max_spin: f64,
    /// Steps during which two dynamic bodies touch (jointed neighbours
    /// never do unless their joint has `contacts: true`).
    pub contact_steps: u64,
    /// Steps during which a dynamic body touches a body that is not
    /// dynamic: a fixed or kinematic body, a wall.
    pub fixed_contact_steps: u64,
    /// Steps during which some joint is within 0.01 rad of a limit (or
    /// beyond it: limits are slightly compliant).
    pub limit_steps: u64,
}

impl PhysicsWorld {
    /// Executes `command` and records the tracked point after every step
    /// and the terminal pose of every body (for pictures).
    ///
    /// With a [`Symmetry`](crate::scene::Symmetry), a command whose [`twin`](Self::twin) is
    /// simulated in its place gets the twin's trace, reflected.
    pub fn trace(&mut self, command: &Command) -> Result<Trace, WorldError> {
        self.trace_of(Cmd::Symbols(command))
    }

    /// [`trace`](Self::trace) of a continuous command.
    pub fn trace_values(&mut self, values: &[f64]) -> Result<Trace, WorldError> {
        self.trace_of(Cmd::Values(values))
    }

    fn trace_of(&mut self, command: Cmd<'_>) -> Result<Trace, WorldError> {
        let mut points = vec![self.tracked_position_in(&self.pristine, 0)];
        let outcome = self.run_one(command, false, |w| {
            points.push(w.tracked_position_in(&w.sets, 0))
        })?;
        let mut poses = self.frame_of(&self.sets, 0.0).poses;
        if let Some(sym) = self.reflected_by(command) {
            points[1..].iter_mut().for_each(|p| *p = sym.reflect(*p));
            poses.iter_mut().for_each(|p| reflect_pose(&sym, p));
        }
        Ok(Trace {
            points,
            poses,
            outcome,
        })
    }

    /// The symmetry the records of `command` are reflected by: its
    /// scene's, when its [`twin`](Self::twin) is simulated in its place.
    fn reflected_by(&self, command: Cmd<'_>) -> Option<Symmetry> {
        self.twin_of(command)?;
        self.mirror.as_ref().map(|(sym, _)| *sym)
    }

    /// Executes `command` and records its whole motion ([`Motion`]): every
    /// body's pose and velocity, every joint's angle and angular velocity,
    /// with the time, at the start and after every step. The outcome is
    /// [`World::execute`](crate::World::execute)'s; with a [`Symmetry`](crate::scene::Symmetry), a command whose
    /// [`twin`](Self::twin) is simulated in its place gets the twin's
    /// motion, reflected.
    ///
    /// ```
    /// use e3d::Scene;
    /// let scene = Scene::builtin("arm7").unwrap();
    /// let mut world = scene.physics_world().unwrap();
    /// let c = scene.command_space().parse("+0-0+0-").unwrap();
    /// let m = world.motion(&c).unwrap();
    /// assert_eq!(m.frames.len(), 121); // the start and 120 steps
    /// assert_eq!(m.joints.len(), 7);
    /// assert!(m.frames[15].joint_angles[0] > 0.0); // joint 1 pushed by +t
    /// ```
    pub fn motion(&mut self, command: &Command) -> Result<Motion, WorldError> {
        self.motion_of(Cmd::Symbols(command))
    }

    /// [`motion`](Self::motion) of a continuous command.
    pub fn motion_values(&mut self, values: &[f64]) -> Result<Motion, WorldError> {
        self.motion_of(Cmd::Values(values))
    }

    fn motion_of(&mut self, command: Cmd<'_>) -> Result<Motion, WorldError> {
        let mut frames = Vec::new();
        let mut m = self.motion_each_of(command, &mut |_, f| frames.push(f))?;
        m.frames = frames;
        Ok(m)
    }

    /// [`motion`](Self::motion) frame by frame, in memory that does not
    /// grow with the steps: `each(k, frame)` gets frame `k` (0: the
    /// start) as soon as it is computed, and the [`Motion`] returned holds
    /// no frame. `e3d scene exec --trace` streams frames this way, and
    /// `e3d scene render --animate` keeps only those it draws.
    pub fn motion_each(
        &mut self,
        command: &Command,
        each: &mut dyn FnMut(usize, Frame),
    ) -> Result<Motion, WorldError> {
        self.motion_each_of(Cmd::Symbols(command), each)
    }

    fn motion_each_of(
        &mut self,
        command: Cmd<'_>,
        each: &mut dyn FnMut(usize, Frame),
    ) -> Result<Motion, WorldError> {
        let dt = self.dt;
        let mirror = self.reflected_by(command);
        let reflect = move |mut f: Frame| {
            if let Some(sym) = mirror {
                for (p, v) in f.poses.iter_mut().zip(&mut f.velocities) {
                    reflect_pose(&sym, p);
                    let [vx, vy] = sym.reflect([v[0], v[1]]);
                    *v = [vx, vy, -v[2]];
                }
                // a mirror turns every relative rotation the other way
                for a in f.joint_angles.iter_mut().chain(&mut f.joint_velocities) {
                    *a = -*a;
                }
            }
            f
        };
        each(0, reflect(self.frame_of(&self.pristine, 0.0)));
        let mut k = 0;
        let outcome = self.run_one(command, false, |w| {
            k += 1;
            each(k, reflect(w.frame_of(&w.sets, k as f64 * dt)));
        })?;
        Ok(Motion {
            bodies: self.body_names.clone(),
            joints: self.joint_names.clone(),
            frames: Vec::new(),
            outcome,
        })
    }

    /// The state of copy 0 in `sets`, at time `time`.
    pub(super) fn frame_of(&self, sets: &Sets, time: f64) -> Frame {
        let bodies = &sets.bodies;
        let (poses, velocities) = (self.copies[0].handles.iter())
            .map(|&h| {
                let (b, p) = (&bodies[h], bodies[h].position());
                let pose = BodyPose {
                    position: [p.translation.x as f64, p.translation.y as f64],
                    angle: p.rotation.angle() as f64,
                };
                (
                    pose,
                    [b.linvel().x as f64, b.linvel().y as f64, b.angvel() as f64],
                )
            })
            .unzip();
        let joints = self.copies[0].joints.iter();
        let (joint_angles, joint_velocities) = joints.map(|j| j.coordinate(bodies)).unzip();
        Frame {
            time,
            poses,
            velocities,
            joint_angles,
            joint_velocities,
        }
    }

    /// The total kinetic energy (J) of the dynamic bodies at the end of
    /// each step of `command` (for tests of energy conservation).
    pub fn kinetic_energy_trace(&mut self, command: &Command) -> Result<Vec<f64>, WorldError> {
        let mut e = Vec::new();
        self.run_one(Cmd::Symbols(command), false, |w| {
            e.push(
                w.copies[0]
                    .dynamic
                    .iter()
                    .map(|(h, _)| w.sets.bodies[*h].kinetic_energy() as f64)
                    .sum(),
            )
        })?;
        Ok(e)
    }

    /// Executes `command` and reports speeds, contacts between dynamic
    /// bodies and with fixed ones, and joints at their limits (for diagnostics and docs).
    pub fn inspect(&mut self, command: &Command) -> Result<RunStats, WorldError> {
        let mut s = RunStats {
            outcome: Outcome {
                effect: 0,
                reward: 0.0,
                point: [0.0; 2],
            },
            max_speed: 0.0,
            max_spin: 0.0,
            contact_steps: 0,
            fixed_contact_steps: 0,
            limit_steps: 0,
        };
        s.outcome = self.run_one(Cmd::Symbols(command), false, |w| {
            let bodies = &w.sets.bodies;
            for (h, _) in &w.copies[0].dynamic {
                let b = &bodies[*h];
                s.max_speed = s.max_speed.max((b.linvel().length()) as f64);
                s.max_spin = s.max_spin.max((b.angvel() as f64).abs());
            }
            let dynamic = |c: rapier2d::prelude::ColliderHandle| {
                w.sets.colliders[c]
                    .parent()
                    .is_some_and(|h| bodies[h].is_dynamic())
            };
            // the touching pairs' kinds: (dynamic, dynamic) and (dynamic, not)
            let pairs = || {
                (w.sets.narrow_phase.contact_pairs())
                    .filter(|p| p.has_any_active_contact())
                    .map(|p| (dynamic(p.collider1), dynamic(p.collider2)))
            };
            s.contact_steps += u64::from(pairs().any(|(a, b)| a && b));
            s.fixed_contact_steps += u64::from(pairs().any(|(a, b)| a != b));
            let at_limit = w.copies[0].joints.iter().any(|j| {
                let (a, _) = j.coordinate(bodies);
                j.limits
                    .is_some_and(|(lo, hi)| a <= lo + 0.01 || a >= hi - 0.01)
            });
            s.limit_steps += u64::from(at_limit);
        })?;
        Ok(s)
    }
}

/// `pose` reflected by `sym`.
fn reflect_pose(sym: &Symmetry, pose: &mut BodyPose) {
    pose.position = sym.reflect(pose.position);
    pose.angle = sym.reflect_angle(pose.angle);
}
