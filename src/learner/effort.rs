//! The effort of a command, which MAP-Elites' elites and the `qd_score`
//! measure.

use super::state::ensure;
use crate::command::{Command, CommandSpace, ValueSpace};
use serde::{Deserialize, Serialize};

/// The effort of a command, from which MAP-Elites' elites and the
/// `qd_score` are measured (docs/algorithms.md, "MAP-Elites").
///
/// - symbols: the number of slots whose symbol is not the slot's neutral
///   symbol `'0'` (the scenes' `Idle`; a slot without `'0'` always counts);
/// - values: the sum over slots of `|v| / max(|min|, |max|)` of the slot's
///   range.
///
/// Either is in `[0, n]`, `n` the slots; the **effort quality** of a
/// command is `1 - effort / n`, in `[0, 1]` (1: a command at rest).
///
/// ```
/// use e3d::learner::Effort;
/// use e3d::command::{CommandSpace, ValueSpace};
/// let space = CommandSpace::repeat(4, &['-', '0', '+']).unwrap();
/// let e = Effort::of_symbols(&space);
/// let c = space.parse("0+0-").unwrap();
/// assert_eq!(e.of(&c.symbols[..]), Some(2.0));
/// assert_eq!(e.quality(&c.symbols[..]), Some(0.5));
/// let v = Effort::of_values(&ValueSpace::new(vec![(-2.0, 1.0); 2]).unwrap());
/// assert_eq!(v.of(&[1.0, -2.0][..]), Some(1.5));
/// assert_eq!(v.of(&c.symbols[..]), None); // not a command of values
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Effort {
    /// Per slot, the index of its neutral symbol `'0'`, if it has one.
    Symbols(Vec<Option<u8>>),
    /// Per slot, the largest `|v|` of its range.
    Values(Vec<f64>),
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
            Effort::Symbols(neutral) if neutral.len() == self.len() => Some(
                self.iter()
                    .zip(neutral)
                    .filter(|&(&s, &n)| Some(s) != n)
                    .count() as f64,
            ),
            _ => None,
        }
    }
}

impl Effortful for [f64] {
    fn effort(&self, effort: &Effort) -> Option<f64> {
        match effort {
            Effort::Values(scale) if scale.len() == self.len() => {
                Some(self.iter().zip(scale).map(|(v, s)| (v / s).abs()).sum())
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
    /// The effort of commands of `space`: `'0'` is each slot's neutral
    /// symbol.
    pub fn of_symbols(space: &CommandSpace) -> Effort {
        let neutral = |s: usize| space.alphabet(s).iter().position(|&c| c == '0');
        Effort::Symbols(
            (0..space.num_slots())
                .map(|s| neutral(s).map(|i| i as u8))
                .collect(),
        )
    }

    /// The effort of commands of values of `space`.
    pub fn of_values(space: &ValueSpace) -> Effort {
        let big = |&(lo, hi): &(f64, f64)| f64::max(lo.abs(), hi.abs());
        Effort::Values(space.ranges().iter().map(big).collect())
    }

    /// The effort of `command` (see [`Effort`]), `None` if this effort
    /// does not measure its kind or its number of slots.
    pub fn of<C: Effortful + ?Sized>(&self, command: &C) -> Option<f64> {
        command.effort(self)
    }

    /// The effort quality of `command`: `1 - effort / slots`, in `[0, 1]`.
    pub fn quality<C: Effortful + ?Sized>(&self, command: &C) -> Option<f64> {
        let n = match self {
            Effort::Symbols(v) => v.len(),
            Effort::Values(v) => v.len(),
        };
        Some(1.0 - command.effort(self)? / n.max(1) as f64)
    }

    pub(super) fn check(&self) -> Result<(), String> {
        let ok = match self {
            Effort::Symbols(v) => !v.is_empty(),
            Effort::Values(v) => !v.is_empty() && v.iter().all(|s| s.is_finite() && *s > 0.0),
        };
        ensure(ok, || {
            format!("an effort of no slot or of scales <= 0: {self:?}")
        })
    }
}
