//! A learner's tables by name: what [`LearnerState::tables`] shows of a
//! learner's state (Q, the policy, the effect model `p`, the target `p*`,
//! counts, ...) and what [`LearnerState::set_table`] replaces, checked.
//!
//! Every table is an array of floats with a shape, row-major:
//!
//! - a table per slot (`q`, `policy`) has the shape `(slots, k)`, `k` the
//!   largest alphabet; the entries past a shorter slot's alphabet are NaN
//!   (and are ignored when the table is written);
//! - a table per effect (`p`, `target`, `counts`) has the shape `(effects,)`;
//! - a contextual learner's tables have one more axis in front, the
//!   context: `(contexts, slots, k)`, `(contexts, effects)`; tables over
//!   whole commands (`reference`, Q-learning's `q`) are `(contexts,
//!   commands)`, in the order of [`CommandSpace::index_of`](crate::command::CommandSpace::index_of).
//!
//! ```
//! use e3d::learner::state::tables::StateTable;
//! use e3d::{Params, Target};
//! use e3d::command::CommandSpace;
//! use e3d::learner::{E3d, LearnerState};
//! let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
//! let mut l = E3d::new(&space, 3, &Params::TASK1, &Target::Uniform).unwrap();
//! let names: Vec<&str> = l.tables().iter().map(|t| t.name).collect();
//! assert_eq!(names, ["q", "policy", "p", "target"]);
//! l.set_table("target", &[2.0, 1.0, 1.0]).unwrap(); // weights, normalised
//! let target = l.tables().into_iter().find(|t| t.name == "target").unwrap();
//! assert!((target.values[0] - 0.5).abs() < 1e-15);
//! assert!(l.set_table("q", &[0.0, f64::NAN, 0.0, 0.0]).is_err()); // not finite
//! ```
//!
//! [`LearnerState::tables`]: super::LearnerState::tables
//! [`LearnerState::set_table`]: super::LearnerState::set_table

use crate::effect::{EffectModel, Target};
use crate::learner::LearnerError;

/// One table of a learner's state: its name, its shape, its values
/// (row-major) and whether [`set_table`](super::LearnerState::set_table)
/// can replace it.
#[derive(Debug, Clone, PartialEq)]
pub struct StateTable {
    /// `"q"`, `"policy"`, `"p"`, `"target"`, `"counts"`, ...
    pub name: &'static str,
    /// The length of each axis.
    pub shape: Vec<usize>,
    /// The values, row-major (`shape`'s product of them).
    pub values: Vec<f64>,
    /// Whether the table can be written.
    pub writable: bool,
}

impl StateTable {
    /// A table of one row per slot, `(slots, k)` (`k` the largest of
    /// `sizes`), the entries past a slot's alphabet NaN.
    pub(crate) fn slots(
        name: &'static str,
        writable: bool,
        sizes: &[usize],
        row: impl Fn(usize) -> Vec<f64>,
    ) -> StateTable {
        let k = sizes.iter().copied().max().unwrap_or(0);
        let mut values = Vec::with_capacity(sizes.len() * k);
        for s in 0..sizes.len() {
            let r = row(s);
            values.extend_from_slice(&r);
            values.resize((s + 1) * k, f64::NAN);
        }
        StateTable {
            name,
            shape: vec![sizes.len(), k],
            values,
            writable,
        }
    }

    /// A table of one axis.
    pub(crate) fn vector(name: &'static str, writable: bool, values: Vec<f64>) -> StateTable {
        StateTable {
            name,
            shape: vec![values.len()],
            values,
            writable,
        }
    }

    /// The tables of several contexts (each context's learner gives the
    /// same tables), with the context as a new first axis.
    pub(crate) fn stack(per_context: Vec<Vec<StateTable>>) -> Vec<StateTable> {
        let n = per_context.len();
        let mut out: Vec<StateTable> = Vec::new();
        for (c, tables) in per_context.into_iter().enumerate() {
            for (i, t) in tables.into_iter().enumerate() {
                if c == 0 {
                    let mut shape = vec![n];
                    shape.extend_from_slice(&t.shape);
                    let mut values = Vec::with_capacity(n * t.values.len());
                    values.extend_from_slice(&t.values);
                    out.push(StateTable { shape, values, ..t });
                } else {
                    out[i].values.extend_from_slice(&t.values);
                }
            }
        }
        out
    }
}

/// The error for a table `name` that `tables` (a learner of kind `kind`)
/// does not have, or cannot write.
pub(crate) fn no_table(kind: &str, name: &str, tables: &[StateTable]) -> LearnerError {
    if tables.iter().any(|t| t.name == name) {
        return LearnerError::State(format!("table `{name}` of a `{kind}` learner is read-only"));
    }
    let names: Vec<&str> = tables.iter().map(|t| t.name).collect();
    LearnerError::State(format!(
        "a `{kind}` learner has no table `{name}` (its tables: {})",
        if names.is_empty() {
            "none".to_string()
        } else {
            names.join(", ")
        }
    ))
}

/// Checks that `values` holds `len` finite numbers, for table `name`.
pub(crate) fn check_len(name: &str, values: &[f64], len: usize) -> Result<(), LearnerError> {
    if values.len() != len {
        return Err(LearnerError::State(format!(
            "table `{name}`: {} values given, expected {len}",
            values.len()
        )));
    }
    Ok(())
}

/// The rows of a table per slot (`(slots, k)` laid out as
/// [`StateTable::slots`]) cut to each slot's alphabet, checked finite
/// (`probs`: each row > 0 and summing to 1 within 1e-9).
pub(crate) fn slot_rows<'a>(
    name: &str,
    values: &'a [f64],
    sizes: &[usize],
    probs: bool,
) -> Result<Vec<&'a [f64]>, LearnerError> {
    let k = sizes.iter().copied().max().unwrap_or(0);
    check_len(name, values, sizes.len() * k)?;
    let mut rows = Vec::with_capacity(sizes.len());
    for (s, &n) in sizes.iter().enumerate() {
        let row = &values[s * k..s * k + n];
        if let Some(v) = row.iter().find(|v| !v.is_finite()) {
            return Err(LearnerError::State(format!(
                "table `{name}`, slot {s}: {v} is not a finite number"
            )));
        }
        let total: f64 = row.iter().sum();
        if probs && (row.iter().any(|&p| p <= 0.0) || (total - 1.0).abs() > 1e-9) {
            return Err(LearnerError::State(format!(
                "table `{name}`, slot {s}: expected probabilities > 0 summing to 1, found {row:?}"
            )));
        }
        rows.push(row);
    }
    Ok(rows)
}

/// The rows a written table `q` or `policy` gives Q (laid out as
/// [`StateTable::slots`], checked); a policy's as `log(p) / beta`
/// (softmax gives `p` back: it is unchanged by a constant added to a
/// slot's Q). `None` if `name` is neither.
pub(crate) fn q_rows(
    name: &str,
    values: &[f64],
    sizes: &[usize],
    beta: f64,
) -> Result<Option<Vec<Vec<f64>>>, LearnerError> {
    if name != "q" && name != "policy" {
        return Ok(None);
    }
    let rows = slot_rows(name, values, sizes, name == "policy")?.into_iter();
    Ok(Some(if name == "q" {
        rows.map(<[f64]>::to_vec).collect()
    } else {
        rows.map(|r| r.iter().map(|p| p.ln() / beta).collect())
            .collect()
    }))
}

/// The tables `p` (the effect model) and `target` (`p*`, from its logs),
/// both writable.
pub(crate) fn model_tables(model: &EffectModel, log_target: &[f64]) -> [StateTable; 2] {
    [
        StateTable::vector("p", true, model.probs()),
        StateTable::vector("target", true, target_of(log_target)),
    ]
}

/// Writes the table `p` (with `model`'s rate) or `target` (weights `>= 0`,
/// normalised); `Ok(false)` if `name` is neither.
pub(crate) fn set_model_table(
    name: &str,
    values: &[f64],
    model: &mut EffectModel,
    log_target: &mut Vec<f64>,
) -> Result<bool, LearnerError> {
    match name {
        "p" => {
            check_len("p", values, model.num_effects())?;
            *model = EffectModel::from_probs(values, model.eta())
                .map_err(|e| LearnerError::State(format!("table `p`: {e}")))?;
        }
        "target" => *log_target = log_target_of(values, model.num_effects())?,
        _ => return Ok(false),
    }
    Ok(true)
}

/// The target's logs from written weights (`>= 0`, normalised).
pub(crate) fn log_target_of(values: &[f64], effects: usize) -> Result<Vec<f64>, LearnerError> {
    check_len("target", values, effects)?;
    Target::Weights(values.to_vec())
        .log_probs(effects)
        .map_err(|e| LearnerError::State(format!("table `target`: {e}")))
}

/// The target `p*` from its logs.
pub(crate) fn target_of(log_target: &[f64]) -> Vec<f64> {
    log_target.iter().map(|v| v.exp()).collect()
}

/// Counts from written values: integers >= 0.
pub(crate) fn counts_of(values: &[f64], effects: usize) -> Result<Vec<u64>, LearnerError> {
    check_len("counts", values, effects)?;
    values
        .iter()
        .map(|&v| {
            if v.is_finite() && v >= 0.0 && v.fract() == 0.0 && v < 2f64.powi(53) {
                Ok(v as u64)
            } else {
                Err(LearnerError::State(format!(
                    "table `counts`: {v} is not an integer >= 0"
                )))
            }
        })
        .collect()
}
