//! The arguments of `Learner.learn` and `propose`: the command, its
//! outcome (an `Outcome`, or an effect, a reward and a terminal point) and
//! the context, each checked against the learner's shape.

use crate::errors::{finite_arg, usize_arg};
use crate::outcome::outcome_of;
use e3d::learner::state::StateShape;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

/// `learn`'s `effect` (an integer >= 0; its range is checked with the
/// command) and `reward` (a finite number).
pub(crate) fn effect_reward(
    effect: &Bound<'_, PyAny>,
    reward: &Bound<'_, PyAny>,
) -> PyResult<(usize, f64)> {
    Ok((
        usize_arg(effect, "effect", 0)?,
        finite_arg(reward, "reward")?,
    ))
}

/// A context in `[0, n)`.
pub(crate) fn context_arg(obj: &Bound<'_, PyAny>, n: usize, name: &str) -> PyResult<usize> {
    let c = usize_arg(obj, name, 0)?;
    if c >= n {
        return Err(PyValueError::new_err(format!(
            "{name} {c}: expected a context in [0, {n})"
        )));
    }
    Ok(c)
}

/// The command and outcome of a free learner's `learn`: `(command,
/// outcome)` or `(command, effect, reward)` with `point=` or not, and
/// whether a terminal point was given.
pub(crate) fn free_outcome<'py>(
    args: &Bound<'py, PyTuple>,
    point: Option<&Bound<'py, PyAny>>,
    shape: &StateShape,
) -> PyResult<(Bound<'py, PyAny>, e3d::Outcome, bool)> {
    let usage = "learn(command, outcome) or learn(command, effect, reward, point=None)";
    let point = point.filter(|p| !p.is_none()).cloned();
    let (command, o, point) = match args.len() {
        2 => {
            let what = format!("outcome: expected an e3d.Outcome ({usage})");
            let o = outcome_of(&args.get_item(1)?, &what)?;
            if point.is_some() {
                return Err(PyTypeError::new_err(format!(
                    "point: an Outcome holds its point ({usage})"
                )));
            }
            let mut checked = check_effect(o.effect, o.reward, shape)?;
            checked.point = o.point;
            return Ok((args.get_item(0)?, checked, true));
        }
        3 => {
            let (effect, reward) = effect_reward(&args.get_item(1)?, &args.get_item(2)?)?;
            (
                args.get_item(0)?,
                check_effect(effect, reward, shape)?,
                point,
            )
        }
        _ => return Err(PyTypeError::new_err(usage)),
    };
    let Some(p) = point else {
        return Ok((command, o, false));
    };
    let xy: (f64, f64) = p.extract().map_err(|_| {
        PyTypeError::new_err("point: expected the terminal point (x, y), two numbers")
    })?;
    if !(xy.0.is_finite() && xy.1.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "point = ({}, {}): expected finite numbers",
            xy.0, xy.1
        )));
    }
    Ok((
        command,
        e3d::Outcome {
            point: [xy.0, xy.1],
            ..o
        },
        true,
    ))
}

/// The outcome of `effect` and `reward`, the effect checked.
pub(crate) fn check_effect(
    effect: usize,
    reward: f64,
    shape: &StateShape,
) -> PyResult<e3d::Outcome> {
    if let Some(n) = shape.effects.filter(|&n| effect >= n) {
        return Err(PyValueError::new_err(format!(
            "effect {effect}: expected an effect in [0, {n})"
        )));
    }
    Ok(e3d::Outcome {
        effect,
        reward,
        point: [0.0, 0.0],
    })
}

pub(crate) fn bad_command(shape: &StateShape) -> PyErr {
    PyValueError::new_err(format!(
        "command: expected one symbol index per slot, within the alphabet sizes {:?} (0: a value)",
        shape.sizes
    ))
}

/// A command of symbol indices, checked against `shape`.
pub(crate) fn symbols_of(command: &Bound<'_, PyAny>, shape: &StateShape) -> PyResult<Vec<u8>> {
    let symbols: Vec<u8> = command.extract().map_err(|_| bad_command(shape))?;
    let fits = symbols.len() == shape.sizes.len()
        && symbols
            .iter()
            .zip(&shape.sizes)
            .all(|(&a, &k)| usize::from(a) < k);
    if !fits {
        return Err(bad_command(shape));
    }
    Ok(symbols)
}
