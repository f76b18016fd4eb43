//! `Outcome` and `BatchOutcome` (python/e3d/_results.py): what executing
//! one command, or a batch, gives back.

use crate::record::result_class;
use numpy::IntoPyArray;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

/// One command's outcome as an `Outcome`.
pub(crate) fn outcome_to_py(py: Python<'_>, o: &e3d::Outcome) -> PyResult<Py<PyAny>> {
    let fields = (o.effect, o.reward, o.point[0], o.point[1]);
    Ok(result_class(py, "Outcome")?.call1(fields)?.unbind())
}

/// Outcomes as a `BatchOutcome` of numpy arrays, one entry per command.
pub(crate) fn batch_to_py(py: Python<'_>, out: &[e3d::Outcome]) -> PyResult<Py<PyAny>> {
    let effect: Vec<i64> = out.iter().map(|o| o.effect as i64).collect();
    let column = |f: fn(&e3d::Outcome) -> f64| out.iter().map(f).collect::<Vec<f64>>();
    let fields = (
        effect.into_pyarray(py),
        column(|o| o.reward).into_pyarray(py),
        column(|o| o.point[0]).into_pyarray(py),
        column(|o| o.point[1]).into_pyarray(py),
    );
    Ok(result_class(py, "BatchOutcome")?.call1(fields)?.unbind())
}

/// The fields of an `Outcome` (`what` names it in the `TypeError` for
/// anything else).
pub(crate) fn outcome_of(o: &Bound<'_, PyAny>, what: &str) -> PyResult<e3d::Outcome> {
    if !o.is_instance(&result_class(o.py(), "Outcome")?)? {
        return Err(PyTypeError::new_err(format!(
            "{what}, found {}",
            crate::errors::type_name(o)
        )));
    }
    Ok(e3d::Outcome {
        effect: o.getattr("effect")?.extract()?,
        reward: o.getattr("reward")?.extract()?,
        point: [o.getattr("x")?.extract()?, o.getattr("y")?.extract()?],
    })
}
