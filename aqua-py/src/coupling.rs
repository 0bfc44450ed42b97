//! `aqua.Coupling`: the `[[prescribed]]` node groups of a scene driven from Python, MoorDyn
//! style — `init()`, `step(t, dt, points, bodies)`, `close()` — with rigid bodies, the
//! structure's tensions and positions mid-run, save/restore and retry of a failed step
//! (docs/guide/coupling.md).

use crate::{AquaError, Scene, err};
use aqua_sim::coupling::{BodyTarget, Forces, Target};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Mutex;

/// Drives the `[[prescribed]]` node groups of a scene from Python.
///
/// Points: positions are absolute [m], one row per node of the group ((3,) for one node); a
/// value may also be a dict with `position`, `velocity` and `acceleration` (a missing velocity
/// is the backward difference of the positions, and then a missing acceleration that of the
/// velocities). Bodies (`add_body`): a pose [x, y, z, roll, pitch, yaw] [m, rad] or a dict
/// with `pose`, `velocity` [u, v, w, ωx, ωy, ωz] and `acceleration`. Each call may take its
/// own dt; the solver steps with the scene's `analysis.dynamic.dt` (else the first call's)
/// and lands on t + dt. A step that fails raises `aqua.SolveError` and leaves the coupling at
/// t, to be called again with a smaller dt. Returned: the structure's forces on each group's
/// nodes [N], {name: array (n_nodes, 3)}, and on each body {name: [Fx, Fy, Fz, Mx, My, Mz]}
/// [N, N·m] about its reference point.
#[pyclass(module = "aqua", frozen)]
pub(crate) struct Coupling {
    inner: Mutex<Option<aqua_sim::Coupling>>,
    names: Vec<String>,
}

/// A saved coupling state (`Coupling.save()`), for `Coupling.restore(state)`.
#[pyclass(module = "aqua", frozen)]
pub(crate) struct CouplingState {
    inner: aqua_sim::coupling::CouplingState,
}

#[pymethods]
impl CouplingState {
    /// The model time of the state [s].
    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }
}

fn value_error(msg: String) -> PyErr {
    pyo3::exceptions::PyValueError::new_err(msg)
}

fn rows(obj: &Bound<'_, PyAny>) -> PyResult<Vec<[f64; 3]>> {
    let three = |v: Vec<f64>| -> PyResult<[f64; 3]> {
        <[f64; 3]>::try_from(v.as_slice())
            .map_err(|_| value_error(format!("a position has 3 coordinates, got {}", v.len())))
    };
    if let Ok(v) = obj.extract::<Vec<f64>>() {
        return Ok(vec![three(v)?]);
    }
    obj.extract::<Vec<Vec<f64>>>()?
        .into_iter()
        .map(three)
        .collect()
}

fn target(obj: &Bound<'_, PyAny>) -> PyResult<Target> {
    if let Ok(d) = obj.cast::<PyDict>() {
        let get = |k: &str| -> PyResult<Option<Vec<[f64; 3]>>> {
            d.get_item(k)?.map(|v| rows(&v)).transpose()
        };
        return Ok(Target {
            position: get("position")?
                .ok_or_else(|| value_error("a target dict needs \"position\"".into()))?,
            velocity: get("velocity")?,
            acceleration: get("acceleration")?,
        });
    }
    Ok(Target {
        position: rows(obj)?,
        ..Target::default()
    })
}

fn six(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 6]> {
    let v: Vec<f64> = obj.extract()?;
    <[f64; 6]>::try_from(v.as_slice())
        .map_err(|_| value_error(format!("a body {what} has 6 components, got {}", v.len())))
}

fn body_target(obj: &Bound<'_, PyAny>) -> PyResult<BodyTarget> {
    if let Ok(d) = obj.cast::<PyDict>() {
        let get = |k: &str| -> PyResult<Option<[f64; 6]>> {
            d.get_item(k)?.map(|v| six(&v, k)).transpose()
        };
        return Ok(BodyTarget {
            pose: get("pose")?.ok_or_else(|| value_error("a body dict needs \"pose\"".into()))?,
            velocity: get("velocity")?,
            acceleration: get("acceleration")?,
        });
    }
    Ok(BodyTarget {
        pose: six(obj, "pose")?,
        ..BodyTarget::default()
    })
}

impl Coupling {
    fn with<T>(
        &self,
        f: impl FnOnce(&mut aqua_sim::Coupling) -> aqua_sim::Result<T>,
    ) -> PyResult<T> {
        let mut guard = self.inner.lock().map_err(|_| {
            AquaError::new_err("coupling: a previous call panicked; create a new Coupling")
        })?;
        let c = guard
            .as_mut()
            .ok_or_else(|| AquaError::new_err("coupling: the coupling is closed"))?;
        f(c).map_err(err)
    }

    /// The returned dict: forces per point, wrenches per body.
    fn forces<'py>(&self, py: Python<'py>, f: Forces) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let wrenches = self.with(|c| {
            (0..c.bodies().len())
                .map(|b| Ok((c.bodies()[b].name.clone(), c.body_wrench(b, &f)?)))
                .collect::<aqua_sim::Result<Vec<_>>>()
        })?;
        for (name, rows) in self.names.iter().zip(f) {
            let n = rows.len();
            let a = PyArray1::from_vec(py, rows.into_iter().flatten().collect());
            d.set_item(name, a.reshape([n, 3])?)?;
        }
        for (name, w) in wrenches {
            d.set_item(name, PyArray1::from_vec(py, w.to_vec()))?;
        }
        Ok(d)
    }
}

#[pymethods]
impl Coupling {
    /// Builds the scene (a `Scene` or a path) with its `[[prescribed]]` nodes driven from
    /// Python; with `out`, writes the files of `aqua run` but `run.json` there (a
    /// `summary.csv` row per step call, the ParaView series, `extremes.csv` at `close`).
    #[new]
    #[pyo3(signature = (scene, out = None))]
    fn new(py: Python<'_>, scene: &Bound<'_, PyAny>, out: Option<PathBuf>) -> PyResult<Self> {
        let scene = match scene.cast::<Scene>() {
            Ok(s) => s.get().inner.clone(),
            Err(_) => aqua_sim::read_scene(
                aqua_sim::SceneInput::File(&scene.extract::<PathBuf>()?),
                &[],
            )
            .map_err(err)?,
        };
        let c = py
            .detach(|| {
                let mut c = aqua_sim::Coupling::new(scene)?;
                if let Some(dir) = &out {
                    c.write_to(dir)?;
                }
                Ok(c)
            })
            .map_err(err)?;
        let names = c.points().iter().map(|p| p.name.clone()).collect();
        Ok(Self {
            inner: Mutex::new(Some(c)),
            names,
        })
    }

    /// Names of the coupled node groups.
    #[getter]
    fn points(&self) -> Vec<String> {
        self.names.clone()
    }

    /// Puts the named points on a rigid body whose reference point is built at `origin` [m];
    /// `step(..., bodies={name: pose})` then moves them with it, and the returned dict holds
    /// the body's force and moment [Fx, Fy, Fz, Mx, My, Mz] about that point.
    #[pyo3(signature = (name, points, origin = [0.0, 0.0, 0.0]))]
    fn add_body(&self, name: &str, points: Vec<String>, origin: [f64; 3]) -> PyResult<()> {
        let refs: Vec<&str> = points.iter().map(String::as_str).collect();
        self.with(|c| c.add_body(name, &refs, origin).map(|_| ()))
    }

    /// Names of the coupled bodies.
    #[getter]
    fn bodies(&self) -> PyResult<Vec<String>> {
        self.with(|c| Ok(c.bodies().iter().map(|b| b.name.clone()).collect()))
    }

    /// Model time [s]: the end of the last step that succeeded.
    #[getter]
    fn time(&self) -> PyResult<f64> {
        self.with(|c| Ok(c.time()))
    }

    /// Static equilibrium (as-built state for a dynamic-only scene); returns the forces.
    fn init<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let f = py.detach(|| self.with(|c| c.init()))?;
        self.forces(py, f)
    }

    /// Advances from t to t + dt with the given points and bodies where they are at t + dt;
    /// the others stay. Returns the forces at t + dt. A failed step raises `aqua.SolveError`
    /// and leaves the coupling at t.
    #[pyo3(signature = (t, dt, targets = None, bodies = None))]
    fn step<'py>(
        &self,
        py: Python<'py>,
        t: f64,
        dt: f64,
        targets: Option<&Bound<'py, PyDict>>,
        bodies: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut points = Vec::new();
        for (k, v) in targets.into_iter().flat_map(|d| d.iter()) {
            let name: String = k.extract()?;
            let i = self.with(|c| c.point(&name))?;
            points.push((i, target(&v)?));
        }
        let mut moved = Vec::new();
        for (k, v) in bodies.into_iter().flat_map(|d| d.iter()) {
            let name: String = k.extract()?;
            let b = self.with(|c| c.body(&name))?;
            moved.push((b, body_target(&v)?));
        }
        let f = py.detach(|| self.with(|c| c.step(t, dt, &points, &moved)))?;
        self.forces(py, f)
    }

    /// Positions of the mesh nodes [m], (n_nodes, 3), in mesh node order (the node indices of
    /// `elements`).
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let x = self.with(|c| c.positions())?;
        let n = x.len();
        let a = PyArray1::from_vec(py, x.into_iter().flatten().collect());
        Ok(a.reshape([n, 3])?.into_any())
    }

    /// Tension of every cable element [N] at the current state, (n_elements,), in the order
    /// of `elements`.
    fn tensions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let t = py.detach(|| self.with(|c| c.tensions()))?;
        Ok(PyArray1::from_vec(py, t))
    }

    /// The node pair of every cable element, (n_elements, 2).
    #[getter]
    fn elements<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let e = self.with(|c| Ok(c.elements().elements.clone()))?;
        let n = e.len();
        let a = PyArray1::from_vec(py, e.into_iter().flatten().collect::<Vec<usize>>());
        Ok(a.reshape([n, 2])?.into_any())
    }

    /// The elements of each group, {"object/group": array of element indices}.
    #[getter]
    fn groups<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let table = self.with(|c| Ok(c.elements().clone()))?;
        let d = PyDict::new(py);
        for (g, name) in table.group_names.iter().enumerate() {
            let idx: Vec<usize> = (0..table.groups.len())
                .filter(|&e| table.groups[e] == g)
                .collect();
            if !idx.is_empty() {
                d.set_item(name, PyArray1::from_vec(py, idx))?;
            }
        }
        Ok(d)
    }

    /// The whole state, for `restore`: the steps after a restore repeat those after the save
    /// bit for bit.
    fn save(&self, py: Python<'_>) -> PyResult<CouplingState> {
        let inner = py.detach(|| self.with(|c| c.save()))?;
        Ok(CouplingState { inner })
    }

    /// Puts back a state of `save`.
    fn restore(&self, py: Python<'_>, state: &CouplingState) -> PyResult<()> {
        py.detach(|| self.with(|c| c.restore(&state.inner)))
    }

    /// Writes the remaining files (with `out`) and stops the solver; later calls raise.
    fn close(&self) -> PyResult<()> {
        let mut guard = self
            .inner
            .lock()
            .map_err(|_| AquaError::new_err("coupling: a previous call panicked"))?;
        match guard.take() {
            Some(mut c) => c.close().map_err(err),
            None => Ok(()),
        }
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    fn __exit__(
        &self,
        _t: &Bound<'_, PyAny>,
        _v: &Bound<'_, PyAny>,
        _tb: &Bound<'_, PyAny>,
    ) -> PyResult<bool> {
        self.close()?;
        Ok(false)
    }
}
