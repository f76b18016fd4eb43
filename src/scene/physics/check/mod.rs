//! The validation of a physics world: every body, joint, action, the
//! schedule and the effect, with an error that names the field, the value
//! and what was expected.

mod action;
mod body;
mod context_poses;
mod contexts;
mod joint;
mod noise;
mod symmetry;

use super::limits::*;
use super::{PhysicsSpec, Schedule, MAX_STEPS};
use crate::effect::{Binning, EffectGrid, Feature};
use crate::scene::overlap::{first_overlap, OVERLAP_TOLERANCE};
use crate::scene::{Invalid, SceneSpec};
use std::collections::HashMap;

/// `"name"`, the text that anchors an error on a named item.
fn quoted(name: &str) -> String {
    format!("\"{name}\"")
}

/// Names for a message: joined by commas, or `none`.
fn listed(names: &[&str]) -> String {
    match names {
        [] => "none".into(),
        _ => names.join(", "),
    }
}

fn finite2(p: (f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

/// The name of a body or joint (`what`): not empty, one the name check
/// passes, not a `duplicate`; its anchor (`"name"`) and its `who` for
/// messages (`body `name``).
fn check_name(what: &str, name: &str, duplicate: bool) -> Result<(String, String), Invalid> {
    let at = quoted(name);
    if name.trim().is_empty() {
        return Err(Invalid::new("name", format!("a non-empty {what} name")));
    }
    crate::text::check_name(name)
        .map_err(|e| Invalid::at("name", Some(&at), &format!("{what}: {e}")))?;
    if what == "body" && name == super::GROUND {
        return Err(Invalid::at(
            "name",
            Some(&at),
            "a body name other than `ground` (it stands for the fixed world frame)",
        ));
    }
    if duplicate {
        let twice = format!("distinct {what} names, but `{name}` is used twice");
        return Err(Invalid::at("name", Some(&at), &twice).nth(1));
    }
    Ok((at, format!("{what} `{name}`")))
}

impl PhysicsSpec {
    /// Checks the whole world, part by part, in a fixed order (the first
    /// fault is reported): the world's own numbers, the bodies, the joints,
    /// the schedule, the effect, the symbols' actions, the continuous
    /// slots' actions, the symmetry, and bodies overlapping at the start.
    pub(crate) fn validate(&self, scene: &SceneSpec) -> Result<(), Invalid> {
        self.check_world_numbers()?;
        self.check_counts()?;
        // names to indices: linear in the number of bodies and joints
        let index = self.check_bodies()?;
        let position = |name: &str| index.get(name).copied();
        self.check_joints(&position)?;
        // fields that Rapier would silently ignore on some kinds of body
        for b in &self.bodies {
            self.check_body_kind(b)?;
        }
        self.check_schedule(scene)?;
        self.check_effect()?;
        self.check_symbol_actions(scene, &position)?;
        self.check_value_actions(scene, &position)?;
        if let Some(sym) = self.symmetry {
            sym.validate(self, scene)?;
        }
        self.check_contexts()?;
        self.check_noise()?;
        self.check_overlap()?;
        self.check_context_overlaps()
    }

    /// Gravity, `dt`, `solver_iterations` and `max_speed`.
    fn check_world_numbers(&self) -> Result<(), Invalid> {
        let g = self.gravity;
        if !finite2(g) {
            return Err(Invalid::new("gravity", "finite numbers (m/s²)"));
        }
        for c in [g.0, g.1] {
            let bound = Bound::magnitude(MAX_GRAVITY, "m/s²");
            On::WORLD.number("gravity", "components", c, bound)?;
        }
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= 1.0) {
            return Err(Invalid::new(
                "dt",
                format!("a time step in (0, 1] seconds, found {}", self.dt),
            ));
        }
        if let Some(n) = self.solver_iterations.filter(|n| !(1..=1000).contains(n)) {
            return Err(Invalid::new(
                "solver_iterations",
                format!("between 1 and 1000 iterations, found {n}"),
            ));
        }
        if !(self.max_speed > 0.0 && in_range(self.max_speed, MIN_MAGNITUDE, MAX_SPEED, false)) {
            return Err(Invalid::new(
                "max_speed",
                format!(
                    "a speed in [1.2e-38, {MAX_SPEED}] m/s (Rapier caps speeds at 400 m/s, silently), found {}",
                    show(self.max_speed)
                ),
            ));
        }
        Ok(())
    }

    /// At least one body, at most [`MAX_BODIES`] bodies and [`MAX_JOINTS`]
    /// joints.
    fn check_counts(&self) -> Result<(), Invalid> {
        if self.bodies.is_empty() {
            return Err(Invalid::new("bodies", "at least one body"));
        }
        if self.bodies.len() > MAX_BODIES {
            return Err(Invalid::new(
                "bodies",
                format!("at most {MAX_BODIES} bodies, found {}", self.bodies.len()),
            ));
        }
        if self.joints.len() > MAX_JOINTS {
            return Err(Invalid::new(
                "joints",
                format!("at most {MAX_JOINTS} joints, found {}", self.joints.len()),
            ));
        }
        Ok(())
    }

    /// Every body in order; returns the index of each body's name (its
    /// first occurrence).
    fn check_bodies(&self) -> Result<HashMap<&str, usize>, Invalid> {
        let mut index: HashMap<&str, usize> = HashMap::with_capacity(self.bodies.len());
        for (i, b) in self.bodies.iter().enumerate() {
            let first = *index.entry(b.name.as_str()).or_insert(i);
            self.validate_body(b, first != i)?;
        }
        Ok(index)
    }

    /// The schedule's durations: finite, whole numbers of steps, at least
    /// one step of action, at most [`MAX_STEPS`] steps per command.
    fn check_schedule(&self, scene: &SceneSpec) -> Result<(), Invalid> {
        let (field, values) = match self.schedule {
            Schedule::Sequential { phase, settle } => ("phase", [phase, settle]),
            Schedule::Simultaneous { push, settle } => ("push", [push, settle]),
        };
        for (f, v) in [(field, values[0]), ("settle", values[1])] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Invalid::new(
                    f,
                    format!("a duration >= 0 in seconds, found {v}"),
                ));
            }
            let durations = Bound::range(0.0, MAX_STEPS as f64, "s");
            On::WORLD.number(f, "a duration", v, durations)?;
            let steps = v / self.dt;
            if (steps - steps.round()).abs() > 1e-6 * steps.max(1.0) {
                return Err(Invalid::new(
                    f,
                    format!(
                        "a whole number of time steps ({v} s / dt {} = {steps:.4} steps)",
                        self.dt
                    ),
                ));
            }
        }
        let (phase, _, _) = self.schedule.steps(self.dt);
        if phase == 0 {
            return Err(Invalid::new(
                field,
                "at least one time step in which the slots act",
            ));
        }
        let n = scene.slots().count();
        let total = self.schedule.total_steps(self.dt, n);
        if total > MAX_STEPS {
            return Err(Invalid::new(
                field,
                format!("at most {MAX_STEPS} steps per command, found {total}"),
            ));
        }
        Ok(())
    }

    /// The effect: the short form (a known body, a finite point, a valid grid)
    /// or a list of features, each checked, with a valid number of effects.
    fn check_effect(&self) -> Result<(), Invalid> {
        let e = &self.effect;
        if e.features.is_empty() {
            let Some(grid) = &e.grid else {
                return Err(Invalid::new(
                    "effect",
                    "an effect: `body` and `grid` (one tracked point), or `features: [...]` (see docs/scenes.md, \"Effects\")",
                ));
            };
            if e.body.is_empty() {
                return Err(Invalid::new(
                    "grid",
                    "the effect's tracked body beside its grid: `body: \"NAME\"`",
                ));
            }
            self.known_body("body", &e.body, "the effect's tracked point")?;
            check_point(e.point, None)?;
            return check_grid(grid, None);
        }
        if !e.body.is_empty() || e.grid.is_some() || e.point != (0.0, 0.0) {
            return Err(Invalid::new(
                "features",
                "either `features` or the short form (`body`, `point`, `grid`) in the effect, not both: move the tracked point into the list as `Point(body: ..., point: ..., grid: ...)`",
            ));
        }
        for (k, f) in e.features.iter().enumerate() {
            self.check_feature(k, f)?;
        }
        let axes: Vec<_> = e.features.iter().map(Feature::axis).collect();
        let valid = "features whose product has a valid number of effects";
        Binning::new(axes)
            .map(drop)
            .map_err(|e| Invalid::new("features", format!("{valid}: {e}")))
    }

    /// Feature `k` of the effect's list.
    fn check_feature(&self, k: usize, f: &Feature) -> Result<(), Invalid> {
        let within = |v: Invalid| v.within("features", k);
        match f {
            Feature::Point {
                body,
                point,
                frame,
                grid,
            } => {
                self.known_body("body", body, "the effect's point")?;
                if let Some(fr) = frame {
                    self.known_body("frame", fr, "the frame of the effect's point")?;
                    if fr == body {
                        return Err(within(Invalid::new(
                            "frame",
                            format!("a frame other than the point's own body `{body}` (a point does not move in its own frame)"),
                        )));
                    }
                }
                check_point(*point, Some(k))?;
                check_grid(grid, Some(k))
            }
            Feature::Joint { joint, bins, range } => {
                let at = quoted(joint);
                let on = On::new(Some(&at), "the effect's joint");
                let j = self.known_joint(joint, &|what| on.bad("joint", what))?;
                check_line(*bins, *range, j.kind.unit(), k)
            }
            Feature::Angle { body, bins, range } => {
                self.known_body("body", body, "the effect's angle")?;
                check_line(*bins, *range, "rad", k)
            }
            Feature::Centre { bodies, grid } => {
                for (i, b) in bodies.iter().enumerate() {
                    self.known_body("bodies", b, "the effect's centre of mass")?;
                    let bad = |what: String| Err(within(Invalid::new("bodies", what)));
                    if bodies[..i].contains(b) {
                        return bad(format!(
                            "each body once in the centre's `bodies`, but `{b}` is twice"
                        ));
                    }
                    if self
                        .body(b)
                        .is_some_and(|s| s.kind != super::BodyKind::Dynamic)
                    {
                        return bad(format!(
                            "dynamic bodies in the centre's `bodies`, but `{b}` never moves"
                        ));
                    }
                }
                if bodies.is_empty() {
                    return Err(within(Invalid::new(
                        "bodies",
                        "the bodies whose centre of mass is the feature: `bodies: [\"NAME\", ...]`",
                    )));
                }
                check_grid(grid, Some(k))
            }
        }
    }
    /// No two bodies in one another at the start: Rapier would push them
    /// apart explosively before the first command.
    fn check_overlap(&self) -> Result<(), Invalid> {
        let Some((i, j, depth)) = first_overlap(self) else {
            return Ok(());
        };
        let (a, b) = (&self.bodies[i], &self.bodies[j]);
        Err(Invalid::at(
            "position",
            Some(&quoted(&b.name)),
            &format!(
                "body `{}`: a start pose where it does not overlap `{}` ({:?} and {:?} overlap by {} m; at most {} m, touching, is allowed)",
                b.name,
                a.name,
                b.kind,
                a.kind,
                show(depth),
                OVERLAP_TOLERANCE
            ),
        ))
    }

    pub(super) fn body_names(&self) -> String {
        self.bodies
            .iter()
            .map(|b| b.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// `Ok` when body `name` exists; else the failure at `field`.
    fn known_body(&self, field: &str, name: &str, whose: &str) -> Result<(), Invalid> {
        match self.body(name) {
            Some(_) => Ok(()),
            None => Err(self.unknown_body(field, name, whose)),
        }
    }

    pub(super) fn unknown_body(&self, field: &str, name: &str, whose: &str) -> Invalid {
        let names: Vec<&str> = self.bodies.iter().map(|b| b.name.as_str()).collect();
        Invalid::at(
            field,
            Some(&quoted(name)),
            &format!(
                "{whose}: a known body{}, but there is no body `{name}`{}; bodies: {}",
                if field == "parent" {
                    " or `ground`"
                } else {
                    ""
                },
                crate::scene::error::did_you_mean(name, &names),
                names.join(", ")
            ),
        )
    }
}

/// A failure placed in feature `k` of the effect's list, if given.
fn in_feature(k: Option<usize>) -> impl Fn(Invalid) -> Invalid + Copy {
    move |v| Invalid {
        within: k.map(|k| ("features", k)),
        ..v
    }
}

/// A tracked point: finite, within [`MAX_LENGTH`]; in feature `k` of the
/// effect's list, if given.
fn check_point(p: (f64, f64), k: Option<usize>) -> Result<(), Invalid> {
    let place = in_feature(k);
    if !finite2(p) {
        return Err(place(Invalid::new(
            "point",
            "a tracked point with finite coordinates",
        )));
    }
    let on = On::new(None, "the tracked point");
    for c in [p.0, p.1] {
        on.number("point", "coordinates", c, COORDINATES)
            .map_err(place)?;
    }
    Ok(())
}

/// An effect grid: valid, its corners within [`MAX_LENGTH`].
fn check_grid(grid: &EffectGrid, k: Option<usize>) -> Result<(), Invalid> {
    let place = in_feature(k);
    grid.validate()
        .map_err(|e| place(Invalid::new("grid", format!("a valid grid: {e}"))))?;
    let on = On::new(None, "the effect grid");
    for &c in grid.min.iter().chain(&grid.max) {
        on.number("grid", "corners", c, COORDINATES)
            .map_err(place)?;
    }
    Ok(())
}

/// A number's binning in feature `k`: at least one bin (and at most
/// [`MAX_EFFECTS`](crate::effect::MAX_EFFECTS)), a finite `range` with
/// `min < max`.
fn check_line(bins: usize, (lo, hi): (f64, f64), unit: &str, k: usize) -> Result<(), Invalid> {
    let place = |v: Invalid| v.within("features", k);
    if bins == 0 || bins > crate::effect::MAX_EFFECTS {
        return Err(place(Invalid::new(
            "bins",
            format!(
                "between 1 and {} bins, found {bins}",
                crate::effect::MAX_EFFECTS
            ),
        )));
    }
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(place(Invalid::new(
            "range",
            format!(
                "a range (min, max) of finite numbers with min < max, in {unit}, found ({}, {})",
                show(lo),
                show(hi)
            ),
        )));
    }
    if let Err(e) = crate::effect::check_bins(bins, lo, hi) {
        return Err(place(Invalid::new("range", format!("{e} (in {unit})"))));
    }
    Ok(())
}
