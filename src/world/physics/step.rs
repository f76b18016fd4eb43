//! Running commands: applying the actions of each slot, stepping Rapier
//! (with the gating of far joint limits), and the guards that report a
//! blown-up simulation as [`WorldError::Diverged`].

use super::{v2, Act, Cmd, PhysicsWorld, Probe, Sets, ValueAct, MAX_ROTATION_PER_STEP};
use crate::command::Command;
use crate::effect::wrap_angle;
use crate::world::{Outcome, WorldError};
use rapier2d::math::Real;
use rapier2d::math::Vector;
use rapier2d::prelude::{
    JointAxesMask, Multibody, MultibodyJointSet, MultibodyLink, RigidBodyHandle,
};

impl Act {
    /// The act times `k`: its torque, impulse, force or joint target.
    fn scaled(mut self, k: Real) -> Act {
        match &mut self {
            Act::Idle => {}
            Act::Torque { torque: x, .. } | Act::Target { angle: x, .. } => *x *= k,
            Act::Impulse { impulse: x, .. } | Act::Force { force: x, .. } => *x *= k,
        }
        self
    }
}

impl ValueAct {
    /// The act of the value `v`.
    fn at(self, v: f64) -> Act {
        match self {
            ValueAct::Scaled(act) => act.scaled(v as Real),
            ValueAct::Heading { body, impulse } => Act::Impulse {
                body,
                impulse: v2((impulse * v.cos(), impulse * v.sin())),
            },
        }
    }
}

/// The multibody of which the body `child` is a link, and the link's id
/// (`None`: the body is no multibody link).
pub(super) fn multibody_mut(
    mbs: &mut MultibodyJointSet,
    child: RigidBodyHandle,
) -> Option<(&mut Multibody, usize)> {
    let link = *mbs.rigid_body_link(child)?;
    Some((mbs.get_multibody_mut(link.multibody)?, link.id))
}

/// The multibody link of the body `child`, to change its joint.
fn link_mut(mbs: &mut MultibodyJointSet, child: RigidBodyHandle) -> Option<&mut MultibodyLink> {
    let (mb, id) = multibody_mut(mbs, child)?;
    mb.link_mut(id)
}

impl PhysicsWorld {
    pub(super) fn tracked_position_in(&self, sets: &Sets, copy: usize) -> [f64; 2] {
        let p = sets.bodies[self.copies[copy].tracked]
            .position()
            .transform_point(self.tracked_point);
        [p.x as f64, p.y as f64]
    }

    /// The layout point and effect of copy `copy` in `sets` now: the
    /// features the probes read, binned (see [`Binning::locate`](crate::effect::Binning::locate)).
    pub(super) fn located_in(&self, sets: &Sets, copy: usize) -> ([f64; 2], usize) {
        let replica = &self.copies[copy];
        let mut values = [0.0f64; 16];
        let mut many = Vec::new();
        let n = self.binning.arity();
        let out: &mut [f64] = if n <= values.len() {
            &mut values[..n]
        } else {
            many.resize(n, 0.0);
            &mut many
        };
        let mut at = 0;
        for probe in &replica.probes {
            match *probe {
                Probe::Centre(ref bodies) => {
                    let (mut c, mut total) = ([0.0f64; 2], 0.0);
                    for &(b, m) in bodies {
                        let p = sets.bodies[b].center_of_mass();
                        c[0] += m * p.x as f64;
                        c[1] += m * p.y as f64;
                        total += m;
                    }
                    out[at] = c[0] / total;
                    out[at + 1] = c[1] / total;
                    at += 2;
                }
                Probe::Point { body, point, frame } => {
                    let mut p = sets.bodies[body].position().transform_point(point);
                    if let Some(f) = frame {
                        p = sets.bodies[f].position().inverse_transform_point(p);
                    }
                    out[at] = p.x as f64;
                    out[at + 1] = p.y as f64;
                    at += 2;
                }
                Probe::Joint(k) => {
                    out[at] = replica.joints[k].coordinate(&sets.bodies).0;
                    at += 1;
                }
                Probe::Angle(b) => {
                    out[at] = wrap_angle(sets.bodies[b].rotation().angle() as f64);
                    at += 1;
                }
            }
        }
        self.binning.locate(out)
    }

    /// The outcome of copy `copy` in `sets` now.
    pub(super) fn outcome_in(&self, sets: &Sets, copy: usize) -> Outcome {
        let (point, effect) = self.located_in(sets, copy);
        Outcome {
            effect,
            reward: self.reward[effect],
            point,
        }
    }

    pub(super) fn diverged(&self, command: Cmd<'_>, reason: String) -> WorldError {
        WorldError::Diverged {
            scene: self.scene.clone(),
            command: self.describe(command),
            reason,
        }
    }

    /// A command as written: its symbols, or its values.
    pub(super) fn describe(&self, command: Cmd<'_>) -> String {
        match (command, &self.values) {
            (Cmd::Symbols(c), _) => self.space.format(c),
            (Cmd::Values(v), Some(space)) => space.format(v),
            (Cmd::Values(v), None) => format!("{v:?}"),
        }
    }

    /// `Ok` if `command` fits this world.
    pub(super) fn check(&self, command: Cmd<'_>) -> Result<(), WorldError> {
        let (command, reason) = match (command, &self.values) {
            (Cmd::Symbols(c), None) => return crate::world::check_command(&self.space, c),
            (Cmd::Symbols(c), Some(_)) => (
                c.to_string(),
                format!(
                    "scene `{}` takes values, not symbols: its slots are continuous (execute_values)",
                    self.scene
                ),
            ),
            (Cmd::Values(v), Some(space)) => match space.check(v) {
                Ok(()) => return Ok(()),
                Err(e) => (space.format(v), e.to_string()),
            },
            (Cmd::Values(v), None) => (
                format!("{v:?}"),
                format!(
                    "scene `{}` takes symbols, not values: its slots are not continuous",
                    self.scene
                ),
            ),
        };
        Err(WorldError::BadCommand { command, reason })
    }

    /// Starts the actions of one slot.
    fn apply(&mut self, act: Act) {
        let bodies = &mut self.sets.bodies;
        match act {
            Act::Idle => {}
            Act::Torque {
                child,
                parent,
                torque,
            } => {
                bodies[child].add_torque(torque, true);
                if let Some(p) = parent {
                    bodies[p].add_torque(-torque, true);
                }
            }
            Act::Impulse { body, impulse } => bodies[body].apply_impulse(impulse, true),
            Act::Force { body, force } => bodies[body].add_force(force, true),
            Act::Target {
                child,
                impulse,
                axis,
                angle,
                stiffness,
                damping,
            } => {
                let data = match impulse {
                    Some(h) => self
                        .sets
                        .impulse_joints
                        .get_mut(h, true)
                        .map(|j| &mut j.data),
                    None => {
                        link_mut(&mut self.sets.multibody_joints, child).map(|l| &mut l.joint.data)
                    }
                };
                if let Some(data) = data {
                    data.set_motor_position(axis, angle, stiffness, damping);
                }
            }
        }
    }

    /// Starts the actions of slot `slot` of `command` on copy `copy`
    /// (times the slot's drawn factor in a noisy world).
    fn apply_slot(&mut self, copy: usize, command: Cmd<'_>, slot: usize) {
        let act = match command {
            Cmd::Symbols(c) => self.copies[copy].acts[self.offset[slot] + c.symbols[slot] as usize],
            Cmd::Values(v) => self.copies[copy].value_acts[slot].at(v[slot]),
        };
        let act = match &self.noise {
            Some(n) => act.scaled(n.factor(copy, self.space.num_slots(), slot)),
            None => act,
        };
        self.apply(act);
    }

    /// Removes every held force and torque (of every copy).
    fn release(&mut self) {
        for r in &self.copies {
            for (h, _) in &r.dynamic {
                let b = &mut self.sets.bodies[*h];
                b.reset_forces(false);
                b.reset_torques(false);
            }
        }
    }

    /// Switches off, for the coming step, the limits of the joints that
    /// cannot reach them during it, and on again those of the others.
    ///
    /// Why this changes no result: Rapier rebuilds a multibody joint's
    /// limit constraint at every substep whatever the joint's position, and
    /// one whose joint is inside its limits has impulse bounds `[0, 0]`, so
    /// it never changes a velocity (`v + 0 = v`). It still costs a solve
    /// with the multibody's LU factorisation at every substep, about 14% of
    /// an arm7 rollout. A joint further than [`LIMIT_GATE_MARGIN`] plus four
    /// steps of its current speed from both limits keeps its limit off for
    /// one step. Joints with a motor are left alone (Rapier's motor
    /// constraint reads the limits too).
    ///
    /// The margin is an assumption about how far a joint can move within
    /// one step, so it is checked: after the step, a joint whose limit was
    /// off and which moved more than half the margin sets `gate_missed`,
    /// and the command is run again with every limit on
    /// ([`run_copies`](Self::run_copies)). Every table of the shipped
    /// scenes is byte-identical with and without the gating.
    fn gate_limits(&mut self) {
        if !self.gate_limits {
            return;
        }
        let dt = self.params.dt as f64;
        let total: usize = self.copies.iter().map(|c| c.joints.len()).sum();
        self.gated_angles.resize(total, f64::NAN);
        let mbs = &mut self.sets.multibody_joints;
        let joints = self.copies.iter().flat_map(|c| &c.joints);
        for (j, gated) in joints.zip(&mut self.gated_angles) {
            *gated = f64::NAN;
            let Some((lo, hi)) = j.limits else { continue };
            if j.slider.is_some() {
                continue;
            }
            let Some((mb, id)) = multibody_mut(mbs, j.child) else {
                continue;
            };
            let Some(l) = mb.link(id) else { continue };
            if !l.joint().data.motor_axes.is_empty() {
                continue;
            }
            // a revolute joint's angle is its angular coordinate
            let q = l.joint().coords()[2] as f64;
            let w = mb.generalized_velocity()[l.assembly_id()] as f64;
            let margin = self.gate_margin + self.gate_speed_steps * w.abs() * dt;
            let near = q - lo < margin || hi - q < margin;
            let Some(l) = mb.link_mut(id) else {
                continue;
            };
            let axes = &mut l.joint.data.limit_axes;
            if near {
                axes.insert(JointAxesMask::ANG_X);
            } else {
                axes.remove(JointAxesMask::ANG_X);
                *gated = q;
            }
        }
    }

    /// After a step: whether a joint whose limit was off moved more than
    /// half of [`LIMIT_GATE_MARGIN`] (see [`gate_limits`](Self::gate_limits)).
    fn check_gated(&mut self) {
        if !self.gate_limits || self.gate_missed {
            return;
        }
        let mbs = &self.sets.multibody_joints;
        let joints = self.copies.iter().flat_map(|c| &c.joints);
        for (j, &q0) in joints.zip(&self.gated_angles) {
            if q0.is_nan() {
                continue;
            }
            let moved = mbs
                .rigid_body_link(j.child)
                .and_then(|link| mbs.get_multibody(link.multibody)?.link(link.id))
                .map(|l| (l.joint().coords()[2] as f64 - q0).abs());
            if !moved.is_some_and(|m| m <= 0.5 * self.gate_margin) {
                self.gate_missed = true;
                return;
            }
        }
    }

    /// One Rapier step of the whole world, far limits gated.
    fn pipeline_step(&mut self) {
        self.gate_limits();
        let s = &mut self.sets;
        self.pipeline.step(
            self.gravity,
            &self.params,
            &mut s.islands,
            &mut s.broad_phase,
            &mut s.narrow_phase,
            &mut s.bodies,
            &mut s.colliders,
            &mut s.impulse_joints,
            &mut s.multibody_joints,
            &mut s.soft_bodies,
            &mut s.ccd,
            &(),
            &(),
        );
        self.check_gated();
    }

    /// The copies Rapier quarantined during the last step, with the number
    /// of bodies and colliders of each (`None`: nothing quarantined).
    fn quarantined(&self) -> Option<Vec<(usize, usize)>> {
        let q = self.pipeline.quarantine();
        if q.bodies().is_empty() && q.colliders().is_empty() {
            return None;
        }
        let mut per_copy = vec![(0usize, 0usize); self.copies.len()];
        let copy_of = |h: RigidBodyHandle| -> Option<usize> {
            let c = *self.copy_of_body.get(h.into_raw_parts().0 as usize)?;
            (c != u32::MAX).then_some(c as usize)
        };
        // a body or collider of no known copy counts against every copy
        let mut charge = |c: Option<usize>, body: bool| {
            let all = 0..per_copy.len();
            for p in &mut per_copy[c.map_or(all, |c| c..c + 1)] {
                *if body { &mut p.0 } else { &mut p.1 } += 1;
            }
        };
        for &h in q.bodies() {
            charge(copy_of(h), true);
        }
        for &c in q.colliders() {
            charge(
                self.sets
                    .colliders
                    .get(c)
                    .and_then(|c| c.parent())
                    .and_then(copy_of),
                false,
            );
        }
        Some(per_copy)
    }

    /// Why copy `copy` counts as blown up after a step, if it does.
    fn blown_up(&self, copy: usize) -> Option<String> {
        let dt = self.params.dt as f64;
        for &(h, fast) in &self.copies[copy].dynamic {
            let b = &self.sets.bodies[h];
            let t = b.translation();
            let v = b.linvel();
            let w = b.angvel() as f64;
            if !(t.x.is_finite()
                && t.y.is_finite()
                && v.x.is_finite()
                && v.y.is_finite()
                && w.is_finite())
            {
                return Some("a body's pose or velocity is not finite".into());
            }
            // squared speeds first: `hypot` at every step of every body
            // costs a few per cent of a puck's rollout
            let (vx, vy) = (v.x as f64, v.y as f64);
            if vx * vx + vy * vy > self.max_speed * self.max_speed && vx.hypot(vy) > self.max_speed
            {
                let speed = vx.hypot(vy);
                return Some(format!(
                    "a body moves at {speed:.1} m/s, above the scene's max_speed {} m/s",
                    self.max_speed
                ));
            }
            if !fast && w.abs() * dt >= 0.99 * MAX_ROTATION_PER_STEP {
                return Some(format!(
                    "a body spins at {:.1} rad/s, Rapier's cap of 45° per step: its rotation would be silently clamped (give it `fast_rotation: true` or a smaller dt)",
                    w.abs()
                ));
            }
        }
        None
    }

    /// Adds to the held forces of the first `n` copies' bodies with drag
    /// their drag at the current velocities ([`DragSpec::force`](crate::scene::physics::DragSpec::force)),
    /// for one step; keeps the forces and torques they held before in
    /// `held_forces`.
    fn add_drag(&mut self, n: usize) {
        self.held_forces.clear();
        for r in &self.copies[..n] {
            for (h, d) in &r.drag {
                let b = &mut self.sets.bodies[*h];
                self.held_forces.push((b.user_force(), b.user_torque()));
                let v = b.linvel();
                let ((fx, fy), t) = d.force(
                    b.rotation().angle() as f64,
                    (v.x as f64, v.y as f64),
                    b.angvel() as f64,
                );
                b.add_force(Vector::new(fx as Real, fy as Real), false);
                b.add_torque(t as Real, false);
            }
        }
    }

    /// Gives the bodies with drag back the forces they held before
    /// [`add_drag`](Self::add_drag).
    fn remove_drag(&mut self, n: usize) {
        let bodies = self.copies[..n].iter().flat_map(|r| &r.drag);
        for ((h, _), &(f, t)) in bodies.zip(&self.held_forces) {
            let b = &mut self.sets.bodies[*h];
            b.reset_forces(false);
            b.reset_torques(false);
            b.add_force(f, false);
            b.add_torque(t, false);
        }
    }

    /// One step, then the checks of the copies still running (`failed[c]`
    /// is `None`); a copy that blows up gets its error in `failed`.
    /// Returns whether some copy is still running.
    fn step(&mut self, commands: &[Cmd<'_>], failed: &mut [Option<WorldError>]) -> bool {
        self.add_drag(commands.len());
        self.pipeline_step();
        if !self.held_forces.is_empty() {
            self.remove_drag(commands.len());
        }
        if let Some(q) = self.quarantined() {
            for (c, &(bodies, colliders)) in q.iter().enumerate().take(commands.len()) {
                if failed[c].is_none() && bodies + colliders > 0 {
                    failed[c] = Some(self.diverged(
                        commands[c],
                        format!(
                            "Rapier quarantined {bodies} bod(ies) and {colliders} collider(s) whose state became non-finite"
                        ),
                    ));
                }
            }
        }
        let mut running = false;
        for c in 0..commands.len() {
            if failed[c].is_none() {
                match self.blown_up(c) {
                    Some(reason) => failed[c] = Some(self.diverged(commands[c], reason)),
                    None => running = true,
                }
            }
        }
        running
    }

    /// Runs `commands` (at most one per copy; copy `c` runs `commands[c]`,
    /// copies without a command are switched off for the run:
    /// [`idle_copies`](Self::idle_copies)) from the pristine state, calling
    /// `each_step` after every step, and appends one result per command to
    /// `out`.
    ///
    /// `fast` is the path of `execute`: limits far from their joints are
    /// left out of steps ([`gate_limits`](Self::gate_limits)); if a joint
    /// then moves further than the gating assumes, the commands are run
    /// again with every limit on, so the results are always those of
    /// Rapier with every limit. A single command also starts from the
    /// deepest phase-end state kept of its prefix ([`prefix`](super::prefix)),
    /// so `each_step` sees only the steps simulated. Traces are not `fast`:
    /// every limit on, every step simulated, `each_step` sees each once.
    pub(super) fn run_copies(
        &mut self,
        commands: &[Cmd<'_>],
        out: &mut Vec<Result<Outcome, WorldError>>,
        fast: bool,
        each_step: impl FnMut(&Self),
    ) {
        let configured = self.gate_limits;
        self.gate_limits = configured && fast;
        self.gate_missed = false;
        let start = out.len();
        // the command whose prefixes are reused and kept, if any
        let prefixed = match commands {
            [Cmd::Symbols(c)] if fast && self.prefixes.depth() > 0 => Some(&c.symbols[..]),
            _ => None,
        };
        self.run_copies_once(commands, out, prefixed, each_step);
        if self.gate_missed {
            out.truncate(start);
            self.gate_limits = false;
            self.run_copies_once(commands, out, prefixed, |_| {});
        }
        self.gate_limits = configured;
    }

    /// Switches off the bodies of the copies from `n` on, which have no
    /// command this run: Rapier leaves a disabled body out of every stage
    /// of its step, so a batch of `n` commands costs a world of `n` copies,
    /// not of all of them. The next run's restore switches them on again.
    fn idle_copies(&mut self, n: usize) {
        for r in &self.copies[n..] {
            for &h in &r.handles {
                let b = &mut self.sets.bodies[h];
                if !b.is_fixed() {
                    b.set_enabled(false);
                }
            }
        }
    }

    /// Notes the state now as the end of phase `phase` of `symbols`, for
    /// the commands that share that prefix. A snapshot holds every limit
    /// on (gating left some out of the last step), as a run from the
    /// pristine state has them, so that it continues a gated or an ungated
    /// run alike.
    fn note_prefix(&mut self, symbols: &[u8], phase: usize) {
        if !self.prefixes.wants(symbols, phase + 1) {
            return;
        }
        let mut sets = self.sets.clone();
        let joints = self.copies.iter().flat_map(|c| &c.joints);
        for (j, q0) in joints.zip(&self.gated_angles) {
            if q0.is_nan() {
                continue;
            }
            if let Some(l) = link_mut(&mut sets.multibody_joints, j.child) {
                l.joint.data.limit_axes.insert(JointAxesMask::ANG_X);
            }
        }
        self.prefixes.note(symbols, phase + 1, sets);
    }

    /// [`run_copies`](Self::run_copies) once, with the gating as set,
    /// reusing and keeping the phase-end states of `prefixed`'s prefixes.
    fn run_copies_once(
        &mut self,
        commands: &[Cmd<'_>],
        out: &mut Vec<Result<Outcome, WorldError>>,
        prefixed: Option<&[u8]>,
        mut each_step: impl FnMut(&Self),
    ) {
        let n = commands.len();
        assert!(n <= self.copies.len(), "more commands than copies");
        let mut failed: Vec<Option<WorldError>> =
            commands.iter().map(|&c| self.check(c).err()).collect();
        let prefixed = prefixed.filter(|_| failed[0].is_none());
        // the deepest phase-end state kept of the prefixes of `prefixed`
        // (see [`prefix`](super::prefix)), else the pristine one
        let first = match prefixed.and_then(|s| self.prefixes.deepest(s)) {
            Some((k, sets)) => {
                self.sets.restore(sets);
                k
            }
            None => {
                self.sets.restore(&self.pristine);
                0
            }
        };
        self.idle_copies(n);
        self.draw_noise(n);
        let slots = self.space.num_slots();
        let mut running = failed.iter().any(Option::is_none);
        // one phase with every slot (simultaneous) or one phase per slot
        // (sequential): apply the phase's slots, step, release
        let (phases, width) = if self.together {
            (1, slots)
        } else {
            (slots, 1)
        };
        for phase in first..phases {
            for (c, &command) in commands.iter().enumerate() {
                if failed[c].is_none() {
                    for slot in phase * width..(phase + 1) * width {
                        self.apply_slot(c, command, slot);
                    }
                }
            }
            for _ in 0..self.phase_steps {
                if !running {
                    break;
                }
                running = self.step(commands, &mut failed);
                each_step(self);
            }
            self.release();
            if let Some(symbols) = prefixed.filter(|_| running) {
                self.note_prefix(symbols, phase);
            }
        }
        for _ in 0..self.settle_steps {
            if !running {
                break;
            }
            running = self.step(commands, &mut failed);
            each_step(self);
        }
        if prefixed.is_some() {
            // a missed gate reruns the command ungated: keep that run's
            let missed = self.gate_limits && self.gate_missed;
            self.prefixes.settle(failed[0].is_none() && !missed);
        }
        for (c, f) in failed.into_iter().enumerate() {
            out.push(match f {
                Some(e) => Err(e),
                None => Ok(self.outcome_in(&self.sets, c)),
            });
        }
    }

    /// The mirror image of `command` simulated in its place, if any (see
    /// [`twin`](Self::twin)); never for values.
    pub(super) fn twin_of(&self, command: Cmd<'_>) -> Option<Command> {
        match command {
            Cmd::Symbols(c) => self.twin(c),
            Cmd::Values(_) => None,
        }
    }

    /// Runs `commands` (any number) from the pristine state, up to
    /// [`num_copies`](Self::num_copies) at once, calling `each_step` after
    /// every step simulated (`fast`: the path of `execute`, see
    /// [`run_copies`](Self::run_copies)), and appends one result per
    /// command to `out`, in order. A command with a [`twin`](Self::twin)
    /// runs as its twin and gets the reflected outcome (`each_step` sees
    /// the twin's steps).
    pub(super) fn run(
        &mut self,
        commands: &[Cmd<'_>],
        out: &mut Vec<Result<Outcome, WorldError>>,
        fast: bool,
        mut each_step: impl FnMut(&Self),
    ) {
        out.reserve(commands.len());
        let start = out.len();
        let twins: Vec<Option<Command>> = commands.iter().map(|&c| self.twin_of(c)).collect();
        let runs = commands.iter().zip(&twins);
        let runs: Vec<Cmd<'_>> = runs
            .map(|(&c, t)| t.as_ref().map_or(c, Cmd::Symbols))
            .collect();
        let keys = self.noise.as_mut().map(|n| n.take_keys(commands.len()));
        for (b, batch) in runs.chunks(self.copies.len()).enumerate() {
            if let (Some(n), Some(keys)) = (&mut self.noise, &keys) {
                n.set_batch(&keys[b * self.copies.len()..][..batch.len()]);
            }
            self.run_copies(batch, out, fast, &mut each_step);
        }
        for (k, (c, t)) in commands.iter().zip(&twins).enumerate() {
            if let (Cmd::Symbols(c), Some(t)) = (c, t) {
                let r = std::mem::replace(&mut out[start + k], Err(WorldError::Stopped));
                out[start + k] = self.mirrored_result(c, t, r);
            }
        }
    }

    /// [`run`](Self::run) of one command: its result.
    pub(super) fn run_one(
        &mut self,
        command: Cmd<'_>,
        fast: bool,
        each_step: impl FnMut(&Self),
    ) -> Result<Outcome, WorldError> {
        let mut out = Vec::with_capacity(1);
        self.run(&[command], &mut out, fast, each_step);
        out.pop().expect("one result per command")
    }

    /// Executes a continuous command open loop from the start state: slot
    /// `i` acts with the value `values[i]` (see
    /// [`ValueAction`](crate::scene::ValueAction)), on the scene's
    /// schedule. The same values always give the same bits. A scene of
    /// symbols, a wrong number of values or a value outside its range is a
    /// [`WorldError::BadCommand`].
    ///
    /// ```
    /// use e3d::Scene;
    /// let scene = Scene::builtin("arm7_continuous").unwrap();
    /// let mut world = scene.physics_world().unwrap();
    /// let space = world.value_space().unwrap().clone();
    /// let v = space.parse("1.8, -1.2, 0.75, 0, 0, 0, 0").unwrap();
    /// let a = world.execute_values(&v).unwrap();
    /// assert_eq!(world.execute_values(&v).unwrap(), a);
    /// assert!(world.execute_values(&[2.0; 7]).is_err()); // 2 > 1.8 on slot 0
    /// ```
    pub fn execute_values(&mut self, values: &[f64]) -> Result<Outcome, WorldError> {
        self.run_one(Cmd::Values(values), true, |_| {})
    }

    /// Executes continuous commands (any number), up to
    /// [`num_copies`](Self::num_copies) at once, and appends one result per
    /// command to `out`, in order: each the one
    /// [`execute_values`](Self::execute_values) gives on a world of one
    /// copy (up to the copies' contact order, as for
    /// [`execute_batch`](Self::execute_batch)).
    pub fn execute_values_batch(
        &mut self,
        commands: &[Vec<f64>],
        out: &mut Vec<Result<Outcome, WorldError>>,
    ) {
        let commands: Vec<Cmd<'_>> = commands.iter().map(|v| Cmd::Values(v)).collect();
        self.run(&commands, out, true, |_| {})
    }

    /// Executes `commands` (any number), up to [`num_copies`](Self::num_copies)
    /// at once, and appends one result per command to `out`, in order (a
    /// last run of fewer commands than copies simulates only those). Each
    /// result is the one [`World::execute`](crate::World::execute) gives for that command; a
    /// command that blows up fails alone, the others of its batch go on.
    /// With a [`Symmetry`](crate::scene::Symmetry), a command with a [`twin`](Self::twin) runs as
    /// its twin.
    pub fn execute_batch(
        &mut self,
        commands: &[Command],
        out: &mut Vec<Result<Outcome, WorldError>>,
    ) {
        let commands: Vec<Cmd<'_>> = commands.iter().map(Cmd::Symbols).collect();
        self.run(&commands, out, true, |_| {})
    }
}
