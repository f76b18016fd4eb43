//! `Motion`: the whole motion of one command (`World.trace`).

use crate::outcome::PyOutcome;
use crate::pickling::{pickled, Reduced};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

/// The whole motion of one command (`World.trace`), one row a frame (the
/// start, then every step): `time` (float64 `[F]`, seconds), per body
/// (`bodies`, the scene's order, fixed ones included) `x`, `y`, `angle`,
/// `vx`, `vy`, `omega` (float64 `[F, bodies]`), per joint (`joints`)
/// `joint_angle` (the child's rotation relative to its parent, 0 at the
/// start pose, radians in (-pi, pi]) and `joint_velocity` (float64
/// `[F, joints]`), and the command's `outcome`. `columns()` gives the
/// same as a dict of the CSV columns of `e3d scene exec --trace`.
#[pyclass(module = "e3d", name = "Motion", frozen, get_all)]
pub(crate) struct PyMotion {
    command: String,
    bodies: Vec<String>,
    joints: Vec<String>,
    time: Py<PyArray1<f64>>,
    x: Py<numpy::PyArray2<f64>>,
    y: Py<numpy::PyArray2<f64>>,
    angle: Py<numpy::PyArray2<f64>>,
    vx: Py<numpy::PyArray2<f64>>,
    vy: Py<numpy::PyArray2<f64>>,
    omega: Py<numpy::PyArray2<f64>>,
    joint_angle: Py<numpy::PyArray2<f64>>,
    joint_velocity: Py<numpy::PyArray2<f64>>,
    outcome: PyOutcome,
}

#[pymethods]
impl PyMotion {
    /// Equal when every field is (arrays value by value, NaN equal to
    /// NaN): a pickled copy, or the same work run again.
    fn __eq__(&self, py: Python<'_>, other: PyRef<'_, Self>) -> PyResult<bool> {
        self.pickle_eq(py, &other)
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> Reduced<'py> {
        self.pickle_reduce(py)
    }
    #[staticmethod]
    fn _from_state(state: &Bound<'_, PyTuple>) -> PyResult<Self> {
        let m = Self::pickle_from(state)?;
        m.check_shapes(state.py())?;
        m.frozen(state.py())
    }

    /// The number of frames (the start and every step).
    fn __len__(&self, py: Python<'_>) -> usize {
        self.time.bind(py).len()
    }

    /// The columns of `e3d scene exec --trace FILE.csv`, in its order:
    /// `step` (int64), `time`, then per body `NAME.x`, `NAME.y`,
    /// `NAME.angle`, `NAME.vx`, `NAME.vy`, `NAME.omega`, then per joint
    /// `NAME.angle`, `NAME.velocity` (float64 arrays `[F]`).
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        let frames = self.time.bind(py).len();
        let steps: Vec<i64> = (0..frames as i64).collect();
        out.set_item("step", steps.into_pyarray(py))?;
        out.set_item("time", self.time.bind(py).call_method0("copy")?)?;
        let per_body = [
            ("x", &self.x),
            ("y", &self.y),
            ("angle", &self.angle),
            ("vx", &self.vx),
            ("vy", &self.vy),
            ("omega", &self.omega),
        ];
        for (b, name) in self.bodies.iter().enumerate() {
            for (field, a) in &per_body {
                let col = a.bind(py).readonly().as_array().column(b).to_owned();
                out.set_item(format!("{name}.{field}"), col.into_pyarray(py))?;
            }
        }
        for (j, name) in self.joints.iter().enumerate() {
            for (field, a) in [
                ("angle", &self.joint_angle),
                ("velocity", &self.joint_velocity),
            ] {
                let col = a.bind(py).readonly().as_array().column(j).to_owned();
                out.set_item(format!("{name}.{field}"), col.into_pyarray(py))?;
            }
        }
        Ok(out)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "Motion(command={:?}, {} frames, {} bodies, {} joints)",
            self.command,
            self.time.bind(py).len(),
            self.bodies.len(),
            self.joints.len()
        )
    }
}

pub(crate) fn motion_to_py(
    py: Python<'_>,
    command: String,
    m: e3d::world::Motion,
) -> PyResult<PyMotion> {
    let (f, b, j) = (m.frames.len(), m.bodies.len(), m.joints.len());
    let table = |cols: usize, value: &dyn Fn(&e3d::world::Frame, usize) -> f64| {
        let mut a = Array2::<f64>::zeros((f, cols));
        for (r, frame) in m.frames.iter().enumerate() {
            for c in 0..cols {
                a[[r, c]] = value(frame, c);
            }
        }
        a.into_pyarray(py).unbind()
    };
    let time: Vec<f64> = m.frames.iter().map(|fr| fr.time).collect();
    let o = m.outcome;
    PyMotion {
        command,
        time: time.into_pyarray(py).unbind(),
        x: table(b, &|fr, c| fr.poses[c].position[0]),
        y: table(b, &|fr, c| fr.poses[c].position[1]),
        angle: table(b, &|fr, c| fr.poses[c].angle),
        vx: table(b, &|fr, c| fr.velocities[c][0]),
        vy: table(b, &|fr, c| fr.velocities[c][1]),
        omega: table(b, &|fr, c| fr.velocities[c][2]),
        joint_angle: table(j, &|fr, c| fr.joint_angles[c]),
        joint_velocity: table(j, &|fr, c| fr.joint_velocities[c]),
        bodies: m.bodies,
        joints: m.joints,
        outcome: o.into(),
    }
    .frozen(py)
}

impl PyMotion {
    /// Refuses a state whose arrays are not `[frames, bodies]` and
    /// `[frames, joints]` (the columns would index past them).
    fn check_shapes(&self, py: Python<'_>) -> PyResult<()> {
        use numpy::PyUntypedArrayMethods;
        let frames = self.time.bind(py).len();
        let per_body = [
            &self.x,
            &self.y,
            &self.angle,
            &self.vx,
            &self.vy,
            &self.omega,
        ];
        let per_joint = [&self.joint_angle, &self.joint_velocity];
        let fits = per_body
            .iter()
            .all(|a| a.bind(py).shape() == [frames, self.bodies.len()])
            && per_joint
                .iter()
                .all(|a| a.bind(py).shape() == [frames, self.joints.len()]);
        if !fits {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "Motion: not a pickled state: arrays of {frames} frames x {} bodies and x {} joints expected",
                self.bodies.len(),
                self.joints.len()
            )));
        }
        Ok(())
    }
}

pickled!(PyMotion, "Motion" {
    command, bodies, joints, time, x, y, angle, vx, vy, omega, joint_angle, joint_velocity, outcome,
});
