//! Commands in: strings, lists or numpy arrays, checked against a
//! scene's command space.

use e3d::command::CommandSpace;
use e3d::command::ValueSpace;
use e3d::Command;
use numpy::ndarray::{Array2, ArrayView2};
use numpy::{
    PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyList, PyString, PyTuple};

/// Checks one row of symbols against the space (wide enough for any
/// integer dtype's values, uint64 included, to be named as they are).
pub(crate) fn check_row(space: &CommandSpace, row: usize, symbols: &[i128]) -> PyResult<Command> {
    let mut out = Vec::with_capacity(symbols.len());
    for (slot, (&s, k)) in symbols.iter().zip(space.sizes()).enumerate() {
        if s < 0 || s >= k as i128 {
            let alphabet: String = space.alphabet(slot).iter().collect();
            return Err(PyValueError::new_err(format!(
                "row {row}: symbol {s} at slot {slot} is out of range: slot {slot} has {k} symbols ({alphabet}), indices 0 to {}",
                k - 1
            )));
        }
        out.push(s as u8);
    }
    Ok(Command::new(out))
}

pub(crate) fn check_view(space: &CommandSpace, view: ArrayView2<'_, u8>) -> PyResult<Vec<Command>> {
    let sizes: Vec<usize> = space.sizes().collect();
    let mut out = Vec::with_capacity(view.nrows());
    for (i, row) in view.rows().into_iter().enumerate() {
        let symbols: Vec<u8> = row.iter().copied().collect();
        if symbols.iter().zip(&sizes).any(|(&s, &k)| s as usize >= k) {
            // the message names the first symbol out of range
            let wide: Vec<i128> = symbols.iter().map(|&s| s as i128).collect();
            check_row(space, i, &wide)?;
        }
        out.push(Command::new(symbols));
    }
    Ok(out)
}

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
    let array = untyped_array(py, obj)?;
    check_array(space, &array, ndim)?;
    array_commands(py, space, &array, ndim)
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

/// Refuses an array that is not `ndim` dimensions of rows of `slots`
/// values (with `ndim == 2`, at least one row); `what` says what is
/// expected.
fn check_shape(
    array: &Bound<'_, PyUntypedArray>,
    ndim: usize,
    slots: usize,
    what: &str,
) -> PyResult<()> {
    let shape = array.shape().to_vec();
    if ndim == 2 && array.len() == 0 {
        // `[]` and an array of shape (0, slots) alike
        return Err(PyValueError::new_err(format!(
            "commands: an empty batch (shape {shape:?}); expected at least one command, {what}"
        )));
    }
    if array.ndim() != ndim {
        return Err(PyValueError::new_err(format!(
            "expected {what}, found an array of {} dimension(s), shape {shape:?}",
            array.ndim()
        )));
    }
    if shape[ndim - 1] != slots {
        return Err(PyValueError::new_err(format!(
            "expected {what}, found shape {shape:?}: the scene's commands have {slots} slots"
        )));
    }
    Ok(())
}

/// `obj` as a numpy array: itself, or `numpy.asarray(obj)`.
fn untyped_array<'py>(
    py: Python<'py>,
    obj: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    Ok(match obj.cast::<PyUntypedArray>() {
        Ok(a) => a.clone(),
        Err(_) => {
            let np = py.import("numpy")?;
            let a = np.call_method1("asarray", (obj,)).map_err(|e| {
                PyValueError::new_err(format!(
                    "expected commands as an integer array, a command string or a list of them: {e}"
                ))
            })?;
            a.cast_into::<PyUntypedArray>()
                .map_err(|e| PyValueError::new_err(e.to_string()))?
        }
    })
}

/// Checks that `array` holds commands of `space`: `ndim` dimensions (with
/// `ndim == 2`, at least one row), a row as long as the slots, integers.
fn check_array(
    space: &CommandSpace,
    array: &Bound<'_, PyUntypedArray>,
    ndim: usize,
) -> PyResult<()> {
    let what = if ndim == 1 {
        format!("one command, an array of shape [{}]", space.num_slots())
    } else {
        format!(
            "an array of shape [N, {}] (one command per row)",
            space.num_slots()
        )
    };
    check_shape(array, ndim, space.num_slots(), &what)?;
    let dtype = array.dtype();
    let kind = dtype.kind();
    if kind != b'u' && kind != b'i' {
        return Err(PyValueError::new_err(format!(
            "expected an integer array of symbol indices (dtype uint8, as Scene.parse returns), found dtype {}",
            dtype.str()?
        )));
    }
    Ok(())
}

/// The commands of an integer array `check_array` accepted, each row
/// checked against the slots' alphabets: a uint8 array read in place,
/// another dtype through int64.
fn array_commands(
    py: Python<'_>,
    space: &CommandSpace,
    array: &Bound<'_, PyUntypedArray>,
    ndim: usize,
) -> PyResult<Vec<Command>> {
    let rows = if ndim == 1 { 1 } else { array.shape()[0] };
    if array.dtype().is_equiv_to(&numpy::dtype::<u8>(py)) {
        let a = array.cast::<PyArrayDyn<u8>>()?.readonly();
        let view = a.as_array();
        if let Ok(v) = view.view().into_shape_with_order((rows, space.num_slots())) {
            return check_view(space, v);
        }
        // a layout that is not C-contiguous (a transposed or reversed
        // view): copied in logical order
        let flat: Vec<u8> = view.iter().copied().collect();
        let owned = Array2::from_shape_vec((rows, space.num_slots()), flat).expect("same size");
        return check_view(space, owned.view());
    }
    // an unsigned dtype through uint64, a signed one through int64: no
    // value wraps round (2^63 would read as a negative symbol)
    let flat: Vec<i128> = if array.dtype().kind() == b'u' {
        let wide = array.call_method1("astype", ("uint64",))?;
        let a = wide.cast::<PyArrayDyn<u64>>()?.readonly();
        a.as_array().iter().map(|&s| s as i128).collect()
    } else {
        let wide = array.call_method1("astype", ("int64",))?;
        let a = wide.cast::<PyArrayDyn<i64>>()?.readonly();
        a.as_array().iter().map(|&s| s as i128).collect()
    };
    flat.chunks(space.num_slots().max(1))
        .take(rows)
        .enumerate()
        .map(|(i, r)| check_row(space, i, r))
        .collect()
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
    let n = space.num_slots();
    let np = py.import("numpy")?;
    let array = np
        .call_method1("asarray", (obj, "float64"))
        .map_err(|e| {
            PyValueError::new_err(format!(
                "expected continuous commands as a float array, a string of values or a list of them: {e}"
            ))
        })?
        .cast_into::<PyUntypedArray>()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let what = if ndim == 1 {
        format!("one command, an array of shape [{n}] (one value per slot)")
    } else {
        format!("an array of shape [N, {n}] (one command of values per row)")
    };
    check_shape(&array, ndim, n, &what)?;
    let a = array.cast::<PyArrayDyn<f64>>()?.readonly();
    let flat: Vec<f64> = a.as_array().iter().copied().collect();
    flat.chunks(n)
        .enumerate()
        .map(|(row, values)| {
            space.check(values).map_err(|e| {
                PyValueError::new_err(if ndim == 2 {
                    format!("row {row}: {e}")
                } else {
                    e.to_string()
                })
            })?;
            Ok(values.to_vec())
        })
        .collect()
}
