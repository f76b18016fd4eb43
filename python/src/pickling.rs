//! Pickling of the result classes (`Outcome`, `BatchOutcome`, `Motion`,
//! `SessionRecord`, `SessionBatch`, `EpisodeRecord`): `__reduce__` gives
//! `(cls._from_state, (state,))`, `state` a tuple of every field as Python
//! holds it (numpy arrays pickle themselves; an effect grid as a dict, a
//! `Motion`'s outcome as an `Outcome`), and `_from_state` takes the fields
//! back in the same order, checking each one's type. [`pickled`] writes
//! both ways from one list of the fields. So the results
//! cross process boundaries (multiprocessing, joblib) and `copy.deepcopy`
//! works on them.

use pyo3::conversion::FromPyObjectOwned;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyList, PyTuple};
use pyo3::PyTypeInfo;

/// What `__reduce__` returns: `(cls._from_state, (state,))`.
pub(crate) type Reduced<'py> = PyResult<(Bound<'py, PyAny>, (Bound<'py, PyTuple>,))>;

/// Pickling for a class of `fields` (each a Python value, or a type that
/// converts to and from one: see the module), in a plain `impl` block:
/// `pickle_reduce` (what `__reduce__` returns) and `pickle_from` (what
/// `_from_state` returns), the fields listed once for both ways and their
/// number counted from the list.
macro_rules! pickled {
    ($ty:ident, $class:literal { $($field:ident),* $(,)? }) => {
        impl $ty {
            /// `(cls._from_state, (fields,))`, every field in the list's order.
            fn pickle_reduce<'py>(&self, py: Python<'py>) -> $crate::pickling::Reduced<'py> {
                use pyo3::IntoPyObjectExt;
                let state = vec![$((&self.$field).into_bound_py_any(py)?),*];
                $crate::pickling::reduce::<Self>(py, state)
            }

            /// Whether `other` holds the same values field by field
            /// ([`same`](crate::pickling::same)): `__eq__` (`Outcome`
            /// compares its four numbers itself).
            #[allow(dead_code)]
            fn pickle_eq(&self, py: Python<'_>, other: &Self) -> PyResult<bool> {
                let (_, (a,)) = self.pickle_reduce(py)?;
                let (_, (b,)) = other.pickle_reduce(py)?;
                $crate::pickling::same(a.as_any(), b.as_any())
            }

            /// The object of a state `pickle_reduce` gave, each field's type
            /// checked.
            /// `self` with every array it holds read-only (numpy's
            /// `writeable` flag off, also inside its lists and dicts): a
            /// result handed to Python cannot be changed through a getter
            /// (`batch.metrics['normalized_entropy'][0] = 99` changed the
            /// batch). `np.array(a)` is a writable copy.
            #[allow(dead_code)]
            pub(crate) fn frozen(self, py: Python<'_>) -> PyResult<Self> {
                let (_, (state,)) = self.pickle_reduce(py)?;
                $crate::pickling::freeze(state.as_any())?;
                Ok(self)
            }

            fn pickle_from(state: &Bound<'_, pyo3::types::PyTuple>) -> PyResult<Self> {
                let names: &[&str] = &[$(stringify!($field)),*];
                let mut f = $crate::pickling::Fields::of(state, $class, names.len())?;
                Ok($ty { $($field: f.take()?),* })
            }
        }
    };
}
pub(crate) use pickled;

/// Makes every numpy array in `obj` read-only: `obj` itself, the items of
/// a list or tuple, the values of a dict, recursively (a result's arrays,
/// see `frozen`). Anything else is left as it is.
pub(crate) fn freeze(obj: &Bound<'_, PyAny>) -> PyResult<()> {
    if obj.cast::<numpy::PyUntypedArray>().is_ok() {
        obj.call_method1("setflags", (false,))?;
    } else if let Ok(t) = obj.cast::<PyTuple>() {
        for item in t.iter() {
            freeze(&item)?;
        }
    } else if let Ok(l) = obj.cast::<PyList>() {
        for item in l.iter() {
            freeze(&item)?;
        }
    } else if let Ok(d) = obj.cast::<PyDict>() {
        for (_, v) in d.iter() {
            freeze(&v)?;
        }
    }
    Ok(())
}

/// Whether two values of pickled states are the same: numpy arrays of the
/// same dtype and shape and equal values (NaN equal to NaN), dicts key by
/// key, lists and tuples item by item, floats equal or both NaN, anything
/// else by `==`. So a result equals its pickled copy and the same session
/// run again, whose metrics may hold NaN (none) and whose arrays `==`
/// compares element by element.
pub(crate) fn same(a: &Bound<'_, PyAny>, b: &Bound<'_, PyAny>) -> PyResult<bool> {
    let np = a.py().import("numpy")?;
    same_in(&np, &np.getattr("ndarray")?, a, b)
}

/// [`same`], with numpy and its `ndarray` type looked up once.
fn same_in(
    np: &Bound<'_, PyModule>,
    ndarray: &Bound<'_, PyAny>,
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
) -> PyResult<bool> {
    let py = a.py();
    match (a.is_instance(ndarray)?, b.is_instance(ndarray)?) {
        (true, true) => {
            let dtype = a.getattr("dtype")?;
            if !dtype.eq(b.getattr("dtype")?)? {
                return Ok(false);
            }
            let kind: String = dtype.getattr("kind")?.extract()?;
            let kw = PyDict::new(py);
            kw.set_item("equal_nan", matches!(kind.as_str(), "f" | "c"))?;
            return np
                .call_method("array_equal", (a, b), Some(&kw))?
                .is_truthy();
        }
        (false, false) => {}
        _ => return Ok(false),
    }
    if let (Ok(x), Ok(y)) = (a.cast::<PyDict>(), b.cast::<PyDict>()) {
        if x.len() != y.len() {
            return Ok(false);
        }
        for (k, v) in x.iter() {
            match y.get_item(&k)? {
                Some(w) if same_in(np, ndarray, &v, &w)? => {}
                _ => return Ok(false),
            }
        }
        return Ok(true);
    }
    if let (Some(x), Some(y)) = (items(a), items(b)) {
        if x.len() != y.len() {
            return Ok(false);
        }
        for (v, w) in x.iter().zip(&y) {
            if !same_in(np, ndarray, v, w)? {
                return Ok(false);
            }
        }
        return Ok(true);
    }
    if let (Ok(x), Ok(y)) = (a.cast::<PyFloat>(), b.cast::<PyFloat>()) {
        let (x, y) = (x.value(), y.value());
        return Ok(x == y || (x.is_nan() && y.is_nan()));
    }
    a.eq(b)
}

/// The items of a list or a tuple (`None`: neither).
fn items<'py>(o: &Bound<'py, PyAny>) -> Option<Vec<Bound<'py, PyAny>>> {
    if let Ok(l) = o.cast::<PyList>() {
        return Some(l.iter().collect());
    }
    o.cast::<PyTuple>().ok().map(|t| t.iter().collect())
}

/// `(cls._from_state, (state,))`, what `__reduce__` returns.
pub(crate) fn reduce<'py, T: PyTypeInfo>(
    py: Python<'py>,
    state: Vec<Bound<'py, PyAny>>,
) -> Reduced<'py> {
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
