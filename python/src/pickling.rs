//! Pickling of the result classes (`Outcome`, `BatchOutcome`, `Motion`,
//! `SessionRecord`, `SessionBatch`, `EpisodeRecord`): `__reduce__` gives
//! `(cls._from_state, (state,))`, `state` a tuple of every field as Python
//! holds it (numpy arrays pickle themselves), and `_from_state` takes the
//! fields back in the same order, checking each one's type. So the results
//! cross process boundaries (multiprocessing, joblib) and `copy.deepcopy`
//! works on them.

use pyo3::conversion::FromPyObjectOwned;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use pyo3::PyTypeInfo;

/// The state of a pickled object, one item per field (see the module).
macro_rules! state {
    ($py:expr; $($field:expr),* $(,)?) => {{
        use pyo3::IntoPyObjectExt;
        vec![$(($field).into_bound_py_any($py)?),*]
    }};
}
pub(crate) use state;

/// `(cls._from_state, (state,))`, what `__reduce__` returns.
pub(crate) fn reduce<'py, T: PyTypeInfo>(
    py: Python<'py>,
    state: Vec<Bound<'py, PyAny>>,
) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyTuple>,))> {
    let from_state = py.get_type::<T>().getattr("_from_state")?;
    Ok((from_state, (PyTuple::new(py, state)?,)))
}

/// Reads a pickled state's fields in order.
pub(crate) struct Fields<'a, 'py> {
    items: &'a Bound<'py, PyTuple>,
    next: usize,
    class: &'static str,
}

impl<'a, 'py> Fields<'a, 'py> {
    /// The fields of `class`, which has `len` of them.
    pub(crate) fn of(
        items: &'a Bound<'py, PyTuple>,
        class: &'static str,
        len: usize,
    ) -> PyResult<Self> {
        if items.len() != len {
            return Err(PyTypeError::new_err(format!(
                "{class}._from_state: expected a state of {len} fields (what pickling an {class} gives), found {}",
                items.len()
            )));
        }
        Ok(Fields {
            items,
            next: 0,
            class,
        })
    }

    /// The next field.
    pub(crate) fn take<T: FromPyObjectOwned<'py>>(&mut self) -> PyResult<T> {
        let i = self.next;
        self.next += 1;
        let item = self.items.get_item(i)?;
        item.extract::<T>().map_err(|e| {
            let e: PyErr = e.into();
            PyTypeError::new_err(format!("{}._from_state: field {i}: {e}", self.class))
        })
    }
}
