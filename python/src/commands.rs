//! Commands in: strings parsed by the library, arrays collected by
//! `e3d._args.symbols` / `values` (shapes, dtypes, the message naming the
//! row and slot at fault), each checked against a scene's command space.

use e3d::command::CommandSpace;
use e3d::command::ValueSpace;
use e3d::Command;
use numpy::{PyArray2, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyList, PyString, PyTuple};

/// Commands from a Python object: a command string, a list of command
/// strings, or an integer array (numpy, or anything `numpy.asarray` takes)
/// of shape `[slots]` (`ndim == 1`) or `[N, slots]` (`ndim == 2`).
pub(crate) fn commands_from(
    py: Python<'_>,
    space: &CommandSpace,
    obj: &Bound<'_, PyAny>,
    ndim: usize,
) -> PyResult<Vec<Command>> {
    if let Some(parsed) = texts(obj, ndim, |t| space.parse(t).map_err(|e| e.to_string()))? {
        return Ok(parsed);
    }
    if let Some(commands) = in_place(space, obj, ndim) {
        return Ok(commands);
    }
    let sizes: Vec<usize> = space.sizes().collect();
    let alphabets: Vec<String> = (0..sizes.len())
        .map(|s| space.alphabet(s).iter().collect())
        .collect();
    let args = py.import("e3d._args")?;
    let a = args.call_method1("symbols", (sizes, alphabets, obj, ndim))?;
    let a = a.cast_into::<PyArray2<u8>>()?;
    let a = a.readonly();
    let rows = a.as_array();
    Ok(rows
        .rows()
        .into_iter()
        .map(|r| Command::new(r.to_vec()))
        .collect())
}

/// The commands of a C-contiguous uint8 array of the right shape whose
/// symbols are all in range (the common case, read without a call into
/// Python); None for anything else.
fn in_place(space: &CommandSpace, obj: &Bound<'_, PyAny>, ndim: usize) -> Option<Vec<Command>> {
    let a = obj.cast::<PyArrayDyn<u8>>().ok()?.readonly();
    let slots = space.num_slots();
    if a.ndim() != ndim || a.shape()[ndim - 1] != slots || a.len() == 0 {
        return None;
    }
    let sizes: Vec<usize> = space.sizes().collect();
    let fits = |r: &[u8]| r.iter().zip(&sizes).all(|(&s, &k)| usize::from(s) < k);
    let rows = a.as_slice().ok()?.chunks(slots);
    rows.map(|r| fits(r).then(|| Command::new(r.to_vec())))
        .collect()
}

/// Commands given as text: one string, or (with `ndim == 2`) a non-empty
/// list or tuple of strings, each read by `parse`; None for anything else.
fn texts<T>(
    obj: &Bound<'_, PyAny>,
    ndim: usize,
    parse: impl Fn(&str) -> Result<T, String>,
) -> PyResult<Option<Vec<T>>> {
    let one = |s: &Bound<'_, PyAny>| -> PyResult<T> {
        parse(&s.cast::<PyString>()?.to_cow()?).map_err(PyValueError::new_err)
    };
    if obj.is_instance_of::<PyString>() {
        return Ok(Some(vec![one(obj)?]));
    }
    if ndim == 2 && (obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>()) {
        let items: Vec<Bound<'_, PyAny>> = obj.try_iter()?.collect::<PyResult<_>>()?;
        if !items.is_empty() && items.iter().all(|i| i.is_instance_of::<PyString>()) {
            return items.iter().map(one).collect::<PyResult<_>>().map(Some);
        }
    }
    Ok(None)
}

/// Continuous commands from a Python object: a string of values
/// (`"1.8, -1.2, 0, ..."`, as `e3d scene exec` takes them), a list of such
/// strings, or a float array (anything `numpy.asarray` takes) of shape
/// `[slots]` (`ndim == 1`) or `[N, slots]` (`ndim == 2`). Each row is
/// checked against the slots' ranges (`ValueError` naming the row).
pub(crate) fn values_from(
    py: Python<'_>,
    space: &ValueSpace,
    obj: &Bound<'_, PyAny>,
    ndim: usize,
) -> PyResult<Vec<Vec<f64>>> {
    if let Some(parsed) = texts(obj, ndim, |t| space.parse(t).map_err(|e| e.to_string()))? {
        return Ok(parsed);
    }
    let args = py.import("e3d._args")?;
    let a = args.call_method1("values", (space.num_slots(), obj, ndim))?;
    let a = a.cast_into::<PyArray2<f64>>()?;
    let a = a.readonly();
    let rows = a.as_array();
    let rows = rows.rows().into_iter().enumerate();
    rows.map(|(row, values)| {
        let values = values.to_vec();
        space.check(&values).map_err(|e| {
            PyValueError::new_err(if ndim == 2 {
                format!("row {row}: {e}")
            } else {
                e.to_string()
            })
        })?;
        Ok(values)
    })
    .collect()
}
