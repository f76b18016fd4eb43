//! A physics scene as an MJCF model in the x-y plane (`e3d scene export
//! --mjcf`, Python's `Scene.to_mjcf`).

use super::{COM_SITE, DEPTH, DRAG, EFFECT_SITE, ORIGIN_SITE, THIN};
use crate::scene::physics::{BodyKind, BodySpec, JointSpec, PhysicsSpec, ShapeSpec};
use crate::scene::valid::{Resolved, ResolvedProbe, ResolvedValue};
use crate::scene::{Scene, WorldSpec};
use std::fmt::Write;

/// The period of a bouncing contact's spring, in MuJoCo steps, over 2 pi:
/// a stiffer one is under-resolved and bounces less than asked
/// (docs/physics.md, the cross-check).
const RESTITUTION_STEPS: f64 = 4.0;

/// What the MJCF model of a scene cannot reproduce exactly, written at the
/// top of every exported file.
const CAVEATS: &str = "\
What does not map exactly:
- Contacts. Rapier solves contacts as (nearly) hard constraints with its
  friction model; MuJoCo's contacts are soft (solref, solimp) and let
  bodies overlap a little. Friction: Rapier takes the mean of a pair's
  coefficients, MuJoCo the larger; torsional and rolling friction are 0
  here. Restitution e > 0 becomes a bouncing contact spring (solref
  = -stiffness -damping: natural frequency 1 / (4 timesteps), damping
  ratio -ln e / sqrt(pi^2 + ln^2 e)); MuJoCo mixes two geoms' solref
  where Rapier takes the mean of their restitutions.
  Shapes are prisms: boxes get a half-thickness of 0.1 m along z; segments
  and polylines (fixed walls) become capsules of radius 1 mm.
- Joint limits. e3d's limits are inelastic stops (a joint reaching one
  stops there); MuJoCo's are soft. Each limit gets solreflimit = (2
  timesteps, damping ratio 1), the stiffest critically damped limit
  MuJoCo allows: close to a stop, not the same.
- Body damping. linear_damping and angular_damping are mapped only on a
  free body or the root of a free-floating chain, as the damping of its
  planar joints (c m on the slides, c I on the hinge: Rapier decays a
  speed by 1 / (1 + dt c) per step, MuJoCo by 1 / (1 + h c) per step of
  h = dt / substeps); on the other links of a free-floating chain they
  are not mapped.
- Impulses. An Impulse (J, N s) is a force J / timestep on the body's
  centre of mass during the first MuJoCo step of its phase.
- Numbers. Rapier computes in f32, MuJoCo in f64. Masses and inertias are
  those Rapier uses (parry2d's, from the shape and mass or density).
- Drag. A body's `drag` is e3d's linear law, not MuJoCo's fluid model: it
  is written as the custom numeric e3d_drag_<body> (along, across, turn),
  for a replay to apply as the body's xfrc_applied (the notes above say
  how, in a scene with drag).
- Not exported: start contexts (the model starts from the bodies as the
  scene lists them), noise, symmetry, max_speed, fast_rotation.";

/// The MJCF model of a physics scene (`None` for a grid scene): every body
/// with its shape, mass and inertia as Rapier gives them, its joints
/// (hinges and slides, limits, damping, position motors), gravity, the time
/// step, and actuators for every action, with the table of what each
/// symbol does (`<custom>`) so that a command replays. The file's comments
/// say how to replay a command and what cannot be mapped exactly
/// (`docs/mjcf.md`).
///
/// ```
/// let scene = e3d::Scene::builtin("arm_push").unwrap();
/// let xml = e3d::scene::mjcf::to_mjcf(&scene).unwrap();
/// assert!(xml.contains("<joint name=\"j1\" type=\"hinge\""));
/// assert!(e3d::scene::mjcf::to_mjcf(&e3d::Scene::builtin("two_rooms").unwrap()).is_none());
/// ```
pub fn to_mjcf(scene: &Scene) -> Option<String> {
    let WorldSpec::Physics(p) = &scene.spec().world else {
        return None;
    };
    let x = Export::new(scene, p);
    let mut out = String::new();
    x.write(&mut out);
    Some(out)
}

/// What one actuator drives.
#[derive(Debug, Clone, PartialEq)]
enum Drive {
    /// A joint's position motor (`Target`).
    Position(usize),
    /// A torque on a joint (`Torque`).
    Torque(usize),
    /// A force on a body along world axis 0 (x) or 1 (y) (`Force`, `Impulse`).
    Force(usize, usize),
}

/// How a symbol's controls act (the first number of its `<numeric>`).
#[derive(Debug, Clone, Copy)]
enum Mode {
    /// Held during the slot's phase, then 0.
    Held = 1,
    /// A set point, kept until another.
    SetPoint = 2,
    /// During the first MuJoCo step of the phase only.
    Impulse = 3,
}

/// The controls of one action: (how they act, actuator, value).
type Controls = Vec<(Mode, usize, f64)>;

/// A scene on its way to MJCF.
struct Export<'a> {
    scene: &'a Scene,
    p: &'a PhysicsSpec,
    /// MuJoCo steps per e3d step.
    substeps: usize,
    /// MuJoCo's time step.
    h: f64,
    /// Per body: the joint whose child it is.
    parent_joint: Vec<Option<usize>>,
    /// The actuators, in order, with their control range.
    actuators: Vec<(Drive, (f64, f64))>,
}

impl<'a> Export<'a> {
    fn new(scene: &'a Scene, p: &'a PhysicsSpec) -> Export<'a> {
        let links = scene.links();
        let substeps = p.solver_iterations.unwrap_or(4).max(1);
        let mut parent_joint = vec![None; p.bodies.len()];
        for (k, &(_, child)) in links.joints.iter().enumerate() {
            parent_joint[child] = Some(k);
        }
        let mut x = Export {
            scene,
            p,
            substeps,
            h: p.dt / substeps as f64,
            parent_joint,
            actuators: Vec::new(),
        };
        // every joint with a motor holds it (a set point of 0 at first)
        for (k, j) in p.joints.iter().enumerate() {
            if j.motor.is_some() {
                x.actuators.push((Drive::Position(k), (0.0, 0.0)));
            }
        }
        for (_, controls) in x.symbol_controls() {
            x.widen(&controls);
        }
        for (slot, v) in links.values.iter().enumerate() {
            let (lo, hi) = scene.values().map_or((0.0, 0.0), |s| s.range(slot));
            for (_, controls) in [(lo, x.value_controls(v, lo)), (hi, x.value_controls(v, hi))] {
                x.widen(&controls);
            }
        }
        x
    }

    /// The actuator of `drive`, added if new.
    fn actuator(&mut self, drive: Drive) -> usize {
        match self.actuators.iter().position(|(d, _)| *d == drive) {
            Some(i) => i,
            None => {
                self.actuators.push((drive, (0.0, 0.0)));
                self.actuators.len() - 1
            }
        }
    }

    /// Widens the control ranges to hold `controls`.
    fn widen(&mut self, controls: &[(Mode, usize, f64)]) {
        for &(_, a, v) in controls {
            let r = &mut self.actuators[a].1;
            *r = (r.0.min(v), r.1.max(v));
        }
    }

    /// The controls of one action: (how they act, actuator, value).
    fn controls(&mut self, action: &Resolved) -> Vec<(Mode, usize, f64)> {
        let force = |x: &mut Self, body, f: (f64, f64), mode| {
            let mut c = Vec::new();
            for (axis, v) in [f.0, f.1].into_iter().enumerate() {
                if v != 0.0 {
                    c.push((mode, x.actuator(Drive::Force(body, axis)), v));
                }
            }
            c
        };
        match *action {
            Resolved::Idle => Vec::new(),
            Resolved::Torque { joint, torque } => {
                vec![(Mode::Held, self.actuator(Drive::Torque(joint)), torque)]
            }
            Resolved::Force { body, force: f } => force(self, body, f, Mode::Held),
            Resolved::Impulse { body, impulse } => {
                let j = (impulse.0 / self.h, impulse.1 / self.h);
                force(self, body, j, Mode::Impulse)
            }
            Resolved::Target { joint, angle, .. } => {
                vec![(Mode::SetPoint, self.actuator(Drive::Position(joint)), angle)]
            }
        }
    }

    /// The controls of every symbol: per slot and symbol, in order.
    fn symbol_controls(&mut self) -> Vec<((usize, usize), Controls)> {
        if self.scene.values().is_some() {
            return Vec::new();
        }
        let links = self.scene.links();
        let sizes: Vec<usize> = self.scene.spec().slots().map(|a| a.len()).collect();
        let mut at = 0;
        let mut out = Vec::new();
        for (slot, &n) in sizes.iter().enumerate() {
            for k in 0..n {
                out.push(((slot, k), self.controls(&links.symbols[at + k])));
            }
            at += n;
        }
        out
    }

    /// The controls of the value `v` of a continuous slot.
    fn value_controls(&mut self, value: &ResolvedValue, v: f64) -> Vec<(Mode, usize, f64)> {
        match value {
            ResolvedValue::Scaled(a) => {
                let mut c = self.controls(a);
                for x in &mut c {
                    x.2 *= v;
                }
                c
            }
            ResolvedValue::Heading { body, impulse } => {
                let (s, c) = v.sin_cos();
                self.controls(&Resolved::Impulse {
                    body: *body,
                    impulse: (impulse * c, impulse * s),
                })
            }
        }
    }

    /// The name of actuator `a`.
    fn actuator_name(&self, a: usize) -> String {
        let p = self.p;
        match self.actuators[a].0 {
            Drive::Position(k) => format!("{}_target", p.joints[k].name),
            Drive::Torque(k) => format!("{}_torque", p.joints[k].name),
            Drive::Force(b, axis) => format!("{}_f{}", p.bodies[b].name, ["x", "y"][axis]),
        }
    }

    fn write(&self, out: &mut String) {
        let p = self.p;
        let spec = self.scene.spec();
        let mut head = format!(
            "MJCF model of the e3d scene `{}`, written by `e3d scene export`.\n",
            spec.name
        );
        self.write_notes(&mut head);
        let _ = writeln!(out, "<!-- {}\n{CAVEATS}\n-->", comment(&head));
        let _ = writeln!(out, "<mujoco model=\"{}\">", attr(&spec.name));
        out.push_str(
            "  <compiler angle=\"radian\" inertiafromgeom=\"false\" autolimits=\"true\"/>\n",
        );
        let _ = writeln!(
            out,
            "  <option timestep=\"{}\" gravity=\"{} {} 0\" integrator=\"implicitfast\"/>",
            num(self.h),
            num(p.gravity.0),
            num(p.gravity.1)
        );
        out.push_str("  <worldbody>\n");
        let _ = writeln!(out, "    <site name=\"{ORIGIN_SITE}\"/>");
        for i in 0..p.bodies.len() {
            let top = match self.parent_joint[i] {
                None => true,
                Some(k) => self.scene.links().joints[k].0.is_none(),
            };
            if top {
                self.write_body(out, i, 2);
            }
        }
        out.push_str("  </worldbody>\n");
        self.write_contacts(out);
        self.write_actuators(out);
        self.write_custom(out);
        out.push_str("</mujoco>\n");
    }

    /// The schedule and the table of actions, in words.
    fn write_notes(&self, out: &mut String) {
        let p = self.p;
        let (phase, settle, together) = p.schedule.steps(p.dt);
        let _ = writeln!(
            out,
            "\nUnits: metres, kilograms, seconds, radians; the scene's plane is x-y.\n\
             One e3d step (dt = {} s) is {} MuJoCo steps (timestep = dt / {}, e3d's\n\
             solver iterations are substeps).",
            num(p.dt),
            self.substeps,
            self.substeps
        );
        let per = phase * self.substeps as u64;
        let tail = settle * self.substeps as u64;
        if together {
            let _ = writeln!(
                out,
                "A command: every slot acts together for {per} MuJoCo steps, then {tail} steps with no input."
            );
        } else {
            let _ = writeln!(
                out,
                "A command: slot i acts at the start of phase i; each phase is {per} MuJoCo steps;\n\
                 then {tail} steps with no input."
            );
        }
        out.push_str(
            "Replaying a symbol (the custom numeric `e3d_s<slot>_<symbol index>`, data: mode\n\
             then pairs of actuator index and control): mode 1 holds the controls during\n\
             the phase and sets them back to 0 after it; mode 2 sets a position actuator's\n\
             control, kept until another; mode 3 is an impulse, the controls during the\n\
             phase's first MuJoCo step only. Controls of slots acting together add up.\n\
             A continuous slot (`e3d_s<slot>_value`) gives the controls of the value 1,\n\
             times the value; mode 4 (data: 4, actuator x, actuator y, J) is an impulse\n\
             of J in the direction of the value (radians). `e3d_schedule`: whether the\n\
             slots act together (1) or in turn (0), MuJoCo steps per phase, after the\n\
             last phase, and per e3d step.\n",
        );
        if p.bodies.iter().any(|b| b.drag.is_some()) {
            out.push_str(
                "Drag (`e3d_drag_<body>`, data: along, across, turn, in N s/m and N m s/rad):\n\
                 at the start of each e3d step (every `substeps` MuJoCo steps), with u the\n\
                 body's local x axis in the world, n its normal, v the velocity of its centre\n\
                 of mass and w its spin, set the body's xfrc_applied (world frame, at the\n\
                 centre of mass) to the force -(along (v.u) u + across (v.n) n) and the\n\
                 torque -turn w about z, and hold it for those MuJoCo steps.\n",
            );
        }
        let sizes: Vec<usize> = self.scene.spec().slots().map(|a| a.len()).collect();
        let links = self.scene.links();
        if self.scene.values().is_none() {
            let mut at = 0;
            for (slot, alphabet) in self.scene.spec().slots().enumerate() {
                let words: Vec<String> = alphabet
                    .iter()
                    .zip(&links.symbols[at..])
                    .map(|(s, a)| format!("`{}` {}", s.symbol, self.say(a)))
                    .collect();
                let _ = writeln!(out, "slot {slot}: {}", words.join(", "));
                at += sizes[slot];
            }
        }
    }

    /// An action in words, with its actuators.
    fn say(&self, a: &Resolved) -> String {
        let p = self.p;
        match *a {
            Resolved::Idle => "nothing".into(),
            Resolved::Torque { joint, torque } => {
                format!("{} N m on {}_torque", num(torque), p.joints[joint].name)
            }
            Resolved::Force { body, force } => format!(
                "force ({}, {}) N on {}_fx, _fy",
                num(force.0),
                num(force.1),
                p.bodies[body].name
            ),
            Resolved::Impulse { body, impulse } => format!(
                "impulse ({}, {}) N s on {}_fx, _fy",
                num(impulse.0),
                num(impulse.1),
                p.bodies[body].name
            ),
            Resolved::Target { joint, angle, .. } => {
                format!(
                    "set point {} on {}_target",
                    num(angle),
                    p.joints[joint].name
                )
            }
        }
    }

    fn write_body(&self, out: &mut String, i: usize, depth: usize) {
        let p = self.p;
        let links = self.scene.links();
        let b = &p.bodies[i];
        let pad = "  ".repeat(depth);
        let parent = self.parent_joint[i].and_then(|k| links.joints[k].0);
        let (pos, angle) = match parent {
            Some(q) => relative(&p.bodies[q], b),
            None => (b.position, b.angle),
        };
        let _ = writeln!(
            out,
            "{pad}<body name=\"{}\" pos=\"{} {} 0\" euler=\"0 0 {}\">",
            attr(&b.name),
            num(pos.0),
            num(pos.1),
            num(angle)
        );
        let inner = format!("{pad}  ");
        let mass = MassProps::of(b);
        match self.parent_joint[i] {
            Some(k) => self.write_joint(out, &inner, k),
            None if b.kind == BodyKind::Dynamic => {
                let m = mass.mass;
                let damp = |c: f64, x: f64| {
                    if c > 0.0 {
                        format!(" damping=\"{}\"", num(c * x))
                    } else {
                        String::new()
                    }
                };
                for (axis, dir) in [("x", "1 0 0"), ("y", "0 1 0")] {
                    let _ = writeln!(
                        out,
                        "{inner}<joint name=\"{}_{axis}\" type=\"slide\" axis=\"{dir}\"{}/>",
                        attr(&b.name),
                        damp(b.linear_damping, m)
                    );
                }
                if !b.lock_rotation {
                    let _ = writeln!(
                        out,
                        "{inner}<joint name=\"{}_rz\" type=\"hinge\" axis=\"0 0 1\"{}/>",
                        attr(&b.name),
                        damp(b.angular_damping, mass.inertia)
                    );
                }
            }
            None => {}
        }
        if b.kind == BodyKind::Dynamic {
            // MuJoCo needs a positive inertia; a body without area has none
            let inertia = if mass.inertia > 0.0 {
                mass.inertia
            } else {
                1e-9
            };
            let _ = writeln!(
                out,
                "{inner}<inertial pos=\"{} {} 0\" mass=\"{}\" diaginertia=\"{i} {i} {i}\"/>",
                num(mass.com.0),
                num(mass.com.1),
                num(mass.mass),
                i = num(inertia)
            );
        }
        self.write_geoms(out, &inner, b);
        for (f, probe) in links.probes.iter().enumerate() {
            if let ResolvedProbe::Point { body, point, .. } = probe {
                if *body == i {
                    let _ = writeln!(
                        out,
                        "{inner}<site name=\"{EFFECT_SITE}{f}\" pos=\"{} {} 0\"/>",
                        num(point.0),
                        num(point.1)
                    );
                }
            }
        }
        if self
            .actuators
            .iter()
            .any(|(d, _)| matches!(d, Drive::Force(body, _) if *body == i))
        {
            let _ = writeln!(
                out,
                "{inner}<site name=\"{}{COM_SITE}\" pos=\"{} {} 0\"/>",
                attr(&b.name),
                num(mass.com.0),
                num(mass.com.1)
            );
        }
        for (c, pj) in self.parent_joint.iter().enumerate() {
            if pj.is_some_and(|k| links.joints[k].0 == Some(i)) {
                self.write_body(out, c, depth + 1);
            }
        }
        let _ = writeln!(out, "{pad}</body>");
    }

    fn write_joint(&self, out: &mut String, pad: &str, k: usize) {
        let j: &JointSpec = &self.p.joints[k];
        let (parent, child) = self.scene.links().joints[k];
        let parent_angle = parent.map_or(0.0, |q| self.p.bodies[q].angle);
        let offset = self.p.bodies[child].angle - parent_angle;
        let (kind, axis) = match j.axis() {
            None => ("hinge", (0.0, 0.0, 1.0)),
            Some((x, y)) => {
                // the axis in the child's frame
                let (s, c) = (-offset).sin_cos();
                ("slide", (c * x - s * y, s * x + c * y, 0.0))
            }
        };
        let mut extra = String::new();
        if let Some((lo, hi)) = j.limits {
            let _ = write!(
                extra,
                " range=\"{} {}\" solreflimit=\"{} 1\"",
                num(lo),
                num(hi),
                num(2.0 * self.h)
            );
        }
        if j.damping > 0.0 {
            let _ = write!(extra, " damping=\"{}\"", num(j.damping));
        }
        let _ = writeln!(
            out,
            "{pad}<joint name=\"{}\" type=\"{kind}\" pos=\"{} {} 0\" axis=\"{} {} {}\"{extra}/>",
            attr(&j.name),
            num(j.child_anchor.0),
            num(j.child_anchor.1),
            num(axis.0),
            num(axis.1),
            num(axis.2)
        );
    }

    /// A geom's contact `solref` for restitution `e`: without it, (2
    /// timesteps, damping ratio 1), the stiffest critically damped contact;
    /// with it, MuJoCo's direct form `-stiffness -damping` of a spring of
    /// natural frequency 1 / (4 timesteps) whose damping ratio
    /// `-ln e / sqrt(pi² + ln² e)` gives a damped spring's half-period
    /// bounce `e`.
    fn solref(&self, e: f64) -> String {
        if e <= 0.0 {
            return format!("{} 1", num(2.0 * self.h));
        }
        let w = 1.0 / (RESTITUTION_STEPS * self.h);
        let ratio = -e.ln() / (std::f64::consts::PI.powi(2) + e.ln().powi(2)).sqrt();
        format!("{} {}", num(-w * w), num(-2.0 * ratio * w))
    }

    fn write_geoms(&self, out: &mut String, pad: &str, b: &BodySpec) {
        let mut common = format!(" friction=\"{} 0 0\"", num(b.friction));
        let _ = write!(common, " solref=\"{}\"", self.solref(b.restitution));
        if !b.collide {
            common.push_str(" contype=\"0\" conaffinity=\"0\"");
        }
        let name = attr(&b.name);
        let capsule = |out: &mut String, n: &str, a: (f64, f64), c: (f64, f64), r: f64| {
            let _ = writeln!(
                out,
                "{pad}<geom name=\"{n}\" type=\"capsule\" fromto=\"{} {} 0 {} {} 0\" size=\"{}\"{common}/>",
                num(a.0),
                num(a.1),
                num(c.0),
                num(c.1),
                num(r)
            );
        };
        match &b.shape {
            ShapeSpec::Ball { radius } => {
                let _ = writeln!(
                    out,
                    "{pad}<geom name=\"{name}\" type=\"sphere\" size=\"{}\"{common}/>",
                    num(*radius)
                );
            }
            ShapeSpec::Cuboid { width, height } => {
                let _ = writeln!(
                    out,
                    "{pad}<geom name=\"{name}\" type=\"box\" size=\"{} {} {}\"{common}/>",
                    num(width / 2.0),
                    num(height / 2.0),
                    num(DEPTH)
                );
            }
            ShapeSpec::Capsule { a, b, radius } => capsule(out, &name, *a, *b, *radius),
            ShapeSpec::Segment { a, b } => capsule(out, &name, *a, *b, THIN),
            ShapeSpec::Polyline { points } => {
                for (k, w) in points.windows(2).enumerate() {
                    capsule(out, &format!("{name}_{k}"), w[0], w[1], THIN);
                }
            }
        }
    }

    /// Contact pairs for the joints whose bodies collide (`contacts: true`):
    /// MuJoCo leaves a body and its parent out otherwise.
    fn write_contacts(&self, out: &mut String) {
        let p = self.p;
        let pairs: Vec<(usize, usize)> = (p.joints.iter().zip(&self.scene.links().joints))
            .filter(|(j, _)| j.contacts)
            .filter_map(|(_, &(parent, child))| Some((parent?, child)))
            .filter(|&(a, c)| p.bodies[a].collide && p.bodies[c].collide)
            .collect();
        if pairs.is_empty() {
            return;
        }
        out.push_str("  <contact>\n");
        for (a, c) in pairs {
            for g1 in geom_names(&p.bodies[a]) {
                for g2 in geom_names(&p.bodies[c]) {
                    let _ = writeln!(out, "    <pair geom1=\"{g1}\" geom2=\"{g2}\"/>");
                }
            }
        }
        out.push_str("  </contact>\n");
    }

    fn write_actuators(&self, out: &mut String) {
        if self.actuators.is_empty() {
            return;
        }
        let p = self.p;
        out.push_str("  <actuator>\n");
        for (a, (drive, (lo, hi))) in self.actuators.iter().enumerate() {
            let name = attr(&self.actuator_name(a));
            let range = if lo < hi {
                format!(" ctrlrange=\"{} {}\"", num(*lo), num(*hi))
            } else {
                String::new()
            };
            let _ = match *drive {
                Drive::Position(k) => {
                    let m = p.joints[k].motor.expect("a position actuator's joint has a motor");
                    writeln!(
                        out,
                        "    <position name=\"{name}\" joint=\"{}\" kp=\"{}\" kv=\"{}\"{range}/>",
                        attr(&p.joints[k].name),
                        num(m.stiffness),
                        num(m.damping)
                    )
                }
                Drive::Torque(k) => writeln!(
                    out,
                    "    <motor name=\"{name}\" joint=\"{}\"{range}/>",
                    attr(&p.joints[k].name)
                ),
                Drive::Force(b, axis) => writeln!(
                    out,
                    "    <motor name=\"{name}\" site=\"{}{COM_SITE}\" refsite=\"{ORIGIN_SITE}\" gear=\"{}\"{range}/>",
                    attr(&p.bodies[b].name),
                    ["1 0 0 0 0 0", "0 1 0 0 0 0"][axis]
                ),
            };
        }
        out.push_str("  </actuator>\n");
    }

    /// The schedule and the controls of every symbol, as MuJoCo custom
    /// numerics (the model's `numeric_data`).
    fn write_custom(&self, out: &mut String) {
        let p = self.p;
        let (phase, settle, together) = p.schedule.steps(p.dt);
        let s = self.substeps as u64;
        out.push_str("  <custom>\n");
        let _ = writeln!(
            out,
            "    <numeric name=\"e3d_schedule\" data=\"{} {} {} {s}\"/>",
            u8::from(together),
            phase * s,
            settle * s
        );
        let mut x = Export {
            scene: self.scene,
            p,
            substeps: self.substeps,
            h: self.h,
            parent_joint: self.parent_joint.clone(),
            actuators: self.actuators.clone(),
        };
        let data = |mode: Option<Mode>, c: &[(Mode, usize, f64)]| {
            let mut d = mode.map_or(0, |m| m as u8).to_string();
            for (_, a, v) in c {
                let _ = write!(d, " {a} {}", num(*v));
            }
            d
        };
        for b in &p.bodies {
            if let Some(d) = b.drag {
                let _ = writeln!(
                    out,
                    "    <numeric name=\"{DRAG}{}\" data=\"{} {} {}\"/>",
                    attr(&b.name),
                    num(d.along),
                    num(d.across),
                    num(d.turn)
                );
            }
        }
        for ((slot, k), c) in x.symbol_controls() {
            let _ = writeln!(
                out,
                "    <numeric name=\"e3d_s{slot}_{k}\" data=\"{}\"/>",
                data(c.first().map(|c| c.0), &c)
            );
        }
        for (slot, v) in self.scene.links().values.iter().enumerate() {
            let d = match v {
                ResolvedValue::Heading { body, impulse } => format!(
                    "4 {} {} {}",
                    x.actuator(Drive::Force(*body, 0)),
                    x.actuator(Drive::Force(*body, 1)),
                    num(*impulse)
                ),
                ResolvedValue::Scaled(a) => {
                    let c = x.controls(a);
                    data(c.first().map(|c| c.0), &c)
                }
            };
            let _ = writeln!(
                out,
                "    <numeric name=\"e3d_s{slot}_value\" data=\"{d}\"/>"
            );
        }
        out.push_str("  </custom>\n");
    }
}

/// A body's mass, centre of mass (local) and inertia about it, as Rapier
/// computes them (parry2d, f32).
pub(crate) struct MassProps {
    pub mass: f64,
    pub com: (f64, f64),
    pub inertia: f64,
}

impl MassProps {
    /// The mass properties Rapier gives body `b`
    /// ([`BodySpec::mass_properties`]), or, without area, its `mass`
    /// alone.
    pub(crate) fn of(b: &BodySpec) -> MassProps {
        match b.mass_properties() {
            Some(mp) => MassProps {
                mass: mp.mass() as f64,
                com: (mp.local_com.x as f64, mp.local_com.y as f64),
                inertia: mp.principal_inertia() as f64,
            },
            None => MassProps {
                mass: b.mass_kg(),
                com: (0.0, 0.0),
                inertia: 0.0,
            },
        }
    }
}

/// The pose of body `c` in the frame of body `p`.
fn relative(p: &BodySpec, c: &BodySpec) -> ((f64, f64), f64) {
    let (dx, dy) = (c.position.0 - p.position.0, c.position.1 - p.position.1);
    let (s, co) = (-p.angle).sin_cos();
    ((co * dx - s * dy, s * dx + co * dy), c.angle - p.angle)
}

/// The names of body `b`'s geoms.
fn geom_names(b: &BodySpec) -> Vec<String> {
    match &b.shape {
        ShapeSpec::Polyline { points } => (0..points.len().saturating_sub(1))
            .map(|k| format!("{}_{k}", attr(&b.name)))
            .collect(),
        _ => vec![attr(&b.name)],
    }
}

/// A number as MJCF writes it: the shortest text that reads back the same
/// f64 (or f32 widened), `0` for zero.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    // an f32 widened prints as its f32 text
    let f = x as f32;
    if f as f64 == x {
        return f.to_string();
    }
    x.to_string()
}

/// `s` escaped for an XML attribute.
fn attr(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `s` safe inside an XML comment (no `--`).
fn comment(s: &str) -> String {
    let mut t = s.to_string();
    while t.contains("--") {
        t = t.replace("--", "- -");
    }
    t
}
