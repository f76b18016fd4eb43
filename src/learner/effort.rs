//! The effort of a command, read from its scene's actions: what
//! MAP-Elites' elites and the `qd_score` measure.

use super::state::ensure;
use crate::command::Command;
use crate::scene::{Action, CommandSpec, Scene, ValueAction};
use serde::{Deserialize, Serialize};

/// The effort of a command (docs/algorithms.md, "Effort"): the sum over
/// its slots of the size of the slot's action, in the action's own unit
/// ([`Effort::size`]: `|torque|`, the norm of an impulse or a force,
/// `|angle|` of a set point, the length of a grid move, 0 for `Idle`).
/// On a continuous slot the size of the action of the value `v` is
/// `scale * |v| + fixed` ([`ValueEffort`]).
///
/// The **effort quality** of a command is `1 - effort / max`, `max` the
/// largest effort of a command ([`max`](Self::max)): in `[0, 1]`, 1 for a
/// command at rest. Where every command has the same effort
/// ([`varies`](Self::varies) is false: the puck and grid scenes) the
/// quality says nothing, and no `qd_score` is reported.
///
/// ```
/// use e3d::learner::Effort;
/// use e3d::Scene;
/// let arm = Scene::builtin("arm7").unwrap();
/// let e = Effort::of_scene(&arm);
/// let c = arm.command_space().parse("+0-0000").unwrap(); // j1 +1.8, j3 -0.75 N·m
/// assert!((e.of(&c).unwrap() - 2.55).abs() < 1e-12);
/// assert!((e.max() - 4.62).abs() < 1e-12);
/// assert!((e.quality(&c).unwrap() - (1.0 - 2.55 / 4.62)).abs() < 1e-12);
/// assert!(e.varies());
/// assert!(!Effort::of_scene(&Scene::builtin("three_rooms").unwrap()).varies());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Effort {
    /// Per slot, the size of each of its symbols' actions (alphabet order).
    Symbols(Vec<Vec<f64>>),
    /// Per slot, the size of the action of a value.
    Values(Vec<ValueEffort>),
}

/// The size of the action of a continuous slot's value `v`:
/// `scale * |v| + fixed`, with `|v| <= bound`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ValueEffort {
    /// The size of the value 1: 1 for a torque or a set point, the norm
    /// of the direction of an impulse or a force, 0 for a heading.
    pub scale: f64,
    /// The size whatever the value: a heading's impulse, else 0.
    pub fixed: f64,
    /// The largest `|v|` of the slot's range.
    pub bound: f64,
}

impl ValueEffort {
    /// The effort of the continuous slot `range` whose value does `action`.
    pub fn of(action: &ValueAction, range: (f64, f64)) -> ValueEffort {
        let (scale, fixed) = match action {
            ValueAction::Torque { .. } | ValueAction::Target { .. } => (1.0, 0.0),
            ValueAction::Impulse { direction, .. } | ValueAction::Force { direction, .. } => {
                (direction.0.hypot(direction.1), 0.0)
            }
            ValueAction::Heading { impulse, .. } => (0.0, impulse.abs()),
        };
        let bound = f64::max(range.0.abs(), range.1.abs());
        ValueEffort {
            scale,
            fixed,
            bound,
        }
    }

    fn at(&self, v: f64) -> f64 {
        self.scale * v.abs() + self.fixed
    }

    fn max(&self) -> f64 {
        self.at(self.bound)
    }
}

/// A command whose [`Effort`] can be measured: a command of symbols
/// (`[u8]`, [`Command`]) or of values (`[f64]`); `()` has none.
pub trait Effortful {
    /// Its effort under `effort`, if `effort` measures its kind of command
    /// and its slots.
    fn effort(&self, effort: &Effort) -> Option<f64>;
}

impl Effortful for [u8] {
    fn effort(&self, effort: &Effort) -> Option<f64> {
        match effort {
            Effort::Symbols(sizes) if sizes.len() == self.len() => {
                let size = |(&s, slot): (&u8, &Vec<f64>)| slot.get(s as usize).copied();
                self.iter().zip(sizes).map(size).sum()
            }
            _ => None,
        }
    }
}

impl Effortful for [f64] {
    fn effort(&self, effort: &Effort) -> Option<f64> {
        match effort {
            Effort::Values(slots) if slots.len() == self.len() => {
                Some(self.iter().zip(slots).map(|(&v, s)| s.at(v)).sum())
            }
            _ => None,
        }
    }
}

impl Effortful for Command {
    fn effort(&self, effort: &Effort) -> Option<f64> {
        self.symbols[..].effort(effort)
    }
}

impl Effortful for Vec<f64> {
    fn effort(&self, effort: &Effort) -> Option<f64> {
        self[..].effort(effort)
    }
}

impl Effortful for () {
    fn effort(&self, _: &Effort) -> Option<f64> {
        None
    }
}

impl Effort {
    /// The effort of `scene`'s commands, from the actions of its slots.
    pub fn of_scene(scene: &Scene) -> Effort {
        let spec = scene.spec();
        match &spec.command {
            CommandSpec::Continuous(slots) => Effort::Values(
                (slots.iter())
                    .map(|s| ValueEffort::of(&s.action, s.range))
                    .collect(),
            ),
            _ => Effort::Symbols(
                (spec.slots())
                    .map(|a| a.iter().map(|s| Effort::size(&s.action)).collect())
                    .collect(),
            ),
        }
    }

    /// The size of an action: 0 for `Idle`, the length of a grid `Move`
    /// (cells), `|torque|` (N·m), the norm of an `Impulse` (N·s) or a
    /// `Force` (N), `|angle|` of a `Target` (its set point from the start
    /// pose: radians, or metres for a slider).
    ///
    /// ```
    /// use e3d::learner::Effort;
    /// use e3d::scene::Action;
    /// let kick = Action::Impulse { body: "puck".into(), impulse: (0.6, -0.8) };
    /// assert_eq!(Effort::size(&kick), 1.0);
    /// assert_eq!(Effort::size(&Action::Move { drow: 0, dcol: -1 }), 1.0);
    /// assert_eq!(Effort::size(&Action::Idle), 0.0);
    /// ```
    pub fn size(action: &Action) -> f64 {
        match action {
            Action::Idle => 0.0,
            Action::Move { drow, dcol } => f64::from(*drow).hypot(f64::from(*dcol)),
            Action::Torque { torque, .. } => torque.abs(),
            Action::Impulse {
                impulse: (x, y), ..
            }
            | Action::Force { force: (x, y), .. } => x.hypot(*y),
            Action::Target { angle, .. } => angle.abs(),
        }
    }

    /// The effort of `command` (see [`Effort`]), `None` if this effort
    /// does not measure its kind or its number of slots.
    pub fn of<C: Effortful + ?Sized>(&self, command: &C) -> Option<f64> {
        command.effort(self)
    }

    /// The largest effort of a command: the sum over slots of the largest
    /// size of the slot's actions.
    pub fn max(&self) -> f64 {
        self.bounds().1
    }

    /// The least and the largest effort of a command.
    fn bounds(&self) -> (f64, f64) {
        let ends = |s: &[f64]| {
            let lo = s.iter().copied().fold(f64::INFINITY, f64::min);
            (lo, s.iter().copied().fold(0.0, f64::max))
        };
        let per_slot: Vec<(f64, f64)> = match self {
            Effort::Symbols(sizes) => sizes.iter().map(|s| ends(s)).collect(),
            Effort::Values(slots) => slots.iter().map(|s| (s.fixed, s.max())).collect(),
        };
        per_slot
            .iter()
            .fold((0.0, 0.0), |(lo, hi), (a, b)| (lo + a, hi + b))
    }

    /// Whether commands differ in effort (the least effort is below the
    /// largest): else every command has the same quality, and the
    /// `qd_score` says nothing.
    pub fn varies(&self) -> bool {
        let (lo, hi) = self.bounds();
        lo < hi
    }

    /// The effort quality of `command`: `1 - effort / max`, in `[0, 1]`
    /// (1 when [`max`](Self::max) is 0).
    pub fn quality<C: Effortful + ?Sized>(&self, command: &C) -> Option<f64> {
        let e = command.effort(self)?;
        let max = self.max();
        Some(if max > 0.0 { 1.0 - e / max } else { 1.0 })
    }

    pub(super) fn check(&self) -> Result<(), String> {
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        let fine = match self {
            Effort::Symbols(v) => {
                !v.is_empty() && v.iter().all(|s| !s.is_empty() && s.iter().all(|&x| ok(x)))
            }
            Effort::Values(v) => {
                !v.is_empty() && v.iter().all(|s| ok(s.scale) && ok(s.fixed) && ok(s.bound))
            }
        };
        ensure(fine, || {
            format!("an effort of no slot, or of sizes not finite and >= 0: {self:?}")
        })
    }
}
