//! A command's whole motion (`World.trace`) as a `Motion`
//! (python/e3d/_results.py).

use crate::outcome::outcome_to_py;
use crate::record::result_class;
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

pub(crate) fn motion_to_py(
    py: Python<'_>,
    command: String,
    m: e3d::world::Motion,
) -> PyResult<Py<PyAny>> {
    let (f, b, j) = (m.frames.len(), m.bodies.len(), m.joints.len());
    let table = |cols: usize, value: &dyn Fn(&e3d::world::Frame, usize) -> f64| {
        let mut a = Array2::<f64>::zeros((f, cols));
        for (r, frame) in m.frames.iter().enumerate() {
            for c in 0..cols {
                a[[r, c]] = value(frame, c);
            }
        }
        a.into_pyarray(py)
    };
    let time: Vec<f64> = m.frames.iter().map(|fr| fr.time).collect();
    let fields = (
        command,
        m.bodies.clone(),
        m.joints.clone(),
        time.into_pyarray(py),
        table(b, &|fr, c| fr.poses[c].position[0]),
        table(b, &|fr, c| fr.poses[c].position[1]),
        table(b, &|fr, c| fr.poses[c].angle),
        table(b, &|fr, c| fr.velocities[c][0]),
        table(b, &|fr, c| fr.velocities[c][1]),
        table(b, &|fr, c| fr.velocities[c][2]),
    );
    let more = (
        table(j, &|fr, c| fr.joint_angles[c]),
        table(j, &|fr, c| fr.joint_velocities[c]),
        outcome_to_py(py, &m.outcome)?,
    );
    let state = fields.into_pyobject(py)?.add(more.into_pyobject(py)?)?;
    let class = result_class(py, "Motion")?;
    Ok(class.call1(state.cast_into::<PyTuple>()?)?.unbind())
}
