//! The Python module `aqua`: scenes, runs returned as numpy arrays, and a coupling interface
//! in the create → init → step → close style of mooring codes.
//!
//! ```python
//! import aqua
//! scene = aqua.Scene.load("examples/mooring-chain.toml")
//! scene.check()                       # list of diagnostics (dicts); raises aqua.AquaError
//! res = scene.run(out="out/chain")    # res.summary["chain_fairlead_reaction"], res.positions
//!                                     # res.extremes["chain_fairlead_reaction"]["max"]
//! sim = aqua.Coupling(scene)
//! f0 = sim.init()                     # {"chain/fairlead": array (1, 3)} at equilibrium
//! f = sim.step(0.0, 0.1, {"chain/fairlead": [100.1, 0.0, -5.0]})
//! sim.close()
//! ```
//!
//! The coupling (bodies, tensions mid-run, save/restore, retry) is in `coupling.rs`;
//! docs/guide/coupling.md is its guide.
//!
//! Errors carry the message `aqua` prints after "error: ". Their class tells the cause:
//! `aqua.InputError` for a mistake in the scene, `aqua.SolveError` for a solve that failed,
//! both subclasses of `aqua.AquaError`, which the other failures (files, coupling calls) raise.

use aqua_sim::{Frame, Observer, SimError};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};

create_exception!(
    aqua,
    AquaError,
    PyException,
    "An invalid scene or a failed computation; the message is the one `aqua` prints."
);

create_exception!(
    aqua,
    InputError,
    AquaError,
    "A mistake in the scene: a key, value or name that is not valid (`aqua` exits with 2)."
);

create_exception!(
    aqua,
    SolveError,
    AquaError,
    "A solve that failed: static equilibrium not reached, a time integrator that could not \
     start, a dynamic step that failed, or values that are not finite."
);

mod coupling;

/// An attribute set on a raised exception: its name and a text or a number (None if neither).
type Attribute = (&'static str, Option<String>, Option<f64>);

/// The Python exception for an aqua-sim error, chosen by its variant (not by its message).
/// An `InputError` carries `file`, `key` and `value` (None when not known); a `SolveError` of
/// a time step carries `reason` (the kind of failure, as run.json's `step_control.reasons`
/// names it) and `time` [s], and of a static solve `reason` and `load_factor`.
pub(crate) fn err(e: SimError) -> PyErr {
    let msg = e.chain();
    let (py_err, attrs): (PyErr, Vec<Attribute>) = match &e {
        SimError::Input(ie) => (
            InputError::new_err(msg),
            vec![
                (
                    "file",
                    ie.file.as_ref().map(|p| p.display().to_string()),
                    None,
                ),
                ("key", ie.key.clone(), None),
                ("value", ie.value.clone(), None),
            ],
        ),
        SimError::Model { .. } => (
            InputError::new_err(msg),
            vec![
                ("file", None, None),
                ("key", None, None),
                ("value", None, None),
            ],
        ),
        SimError::Dynamic(fe) | SimError::Static { source: fe, .. } => {
            let mut attrs = vec![("reason", None, None), ("time", None, None)];
            match fe.as_ref() {
                aqua_fem::FemError::StepFailed(f) => {
                    attrs = vec![
                        ("reason", Some(f.reason.kind().to_string()), None),
                        ("time", None, Some(f.t)),
                    ];
                }
                aqua_fem::FemError::StaticFailed(f) => {
                    attrs = vec![
                        ("reason", Some(f.reason.kind().to_string()), None),
                        ("load_factor", None, Some(f.load_factor)),
                    ];
                }
                _ => {}
            }
            (SolveError::new_err(msg), attrs)
        }
        SimError::StartDynamic(..) | SimError::NonFinite(_) => (
            SolveError::new_err(msg),
            vec![("reason", None, None), ("time", None, None)],
        ),
        SimError::Io { .. }
        | SimError::Plot { .. }
        | SimError::Output(_)
        | SimError::Coupling(_) => (AquaError::new_err(msg), Vec::new()),
    };
    Python::attach(|py| {
        let v = py_err.value(py);
        for (name, text, number) in attrs {
            let _ = match (text, number) {
                (Some(t), _) => v.setattr(name, t),
                (None, Some(x)) => v.setattr(name, x),
                (None, None) => v.setattr(name, py.None()),
            };
        }
    });
    py_err
}

/// A scene: the TOML file's contents, type-checked.
#[pyclass(module = "aqua", frozen)]
pub(crate) struct Scene {
    pub(crate) inner: aqua_sim::Scene,
}

#[pymethods]
impl Scene {
    /// Reads a scene file.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        aqua_sim::read_scene(aqua_sim::SceneInput::File(&path), &[])
            .map(|inner| Self { inner })
            .map_err(err)
    }

    /// A scene from a dict with the TOML file's structure; `path` names it in messages and
    /// relative gmsh files are found next to it.
    #[staticmethod]
    #[pyo3(signature = (d, path = "scene.toml"))]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyDict>, path: &str) -> PyResult<Self> {
        let json: String = py.import("json")?.call_method1("dumps", (d,))?.extract()?;
        let value: serde_json::Value =
            serde_json::from_str(&json).map_err(|e| InputError::new_err(format!("{path}: {e}")))?;
        let text = toml::to_string(&value)
            .map_err(|e| InputError::new_err(format!("{path}: not a scene table: {e}")))?;
        aqua_sim::read_scene(
            aqua_sim::SceneInput::Text {
                text: &text,
                path: Path::new(path),
            },
            &[],
        )
        .map(|inner| Self { inner })
        .map_err(err)
    }

    /// The scene name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// Validates the scene as `aqua check` does; returns the diagnostics as dicts with
    /// `code`, `severity`, `location`, `message`.
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let scene = self.inner.clone();
        let report = py
            .detach(|| {
                let prep = aqua_sim::prepare(aqua_sim::PrepareOptions::scene(scene))?;
                aqua_sim::check::report(&prep)
            })
            .map_err(err)?;
        report
            .warnings
            .iter()
            .map(|d| {
                let dict = PyDict::new(py);
                dict.set_item("code", d.code)?;
                dict.set_item(
                    "severity",
                    match d.severity {
                        aqua_sim::Severity::Note => "note",
                        aqua_sim::Severity::Warning => "warning",
                    },
                )?;
                dict.set_item("location", &d.location)?;
                dict.set_item("message", &d.message)?;
                Ok(dict)
            })
            .collect()
    }

    /// Runs the scene (statics and/or dynamics as its `[analysis]` says). With `out`, writes
    /// the same files as `aqua run --out`. Returns the output steps as numpy arrays.
    #[pyo3(signature = (out = None))]
    fn run(&self, py: Python<'_>, out: Option<PathBuf>) -> PyResult<Results> {
        let scene = self.inner.clone();
        py.detach(|| run_scene(scene, out))
            .map_err(err)?
            .ok_or_else(|| {
                pyo3::exceptions::PyKeyboardInterrupt::new_err(
                    "run interrupted; the output steps written so far are kept",
                )
            })
    }

    fn __repr__(&self) -> String {
        format!("Scene({:?})", self.inner.name)
    }
}

/// Collects every output step in memory.
#[derive(Default)]
struct Collect {
    rows: Vec<Vec<f64>>,
    /// Positions of the model's nodes per output step: the mesh's nodes, then a rod's twist
    /// carriers ([`Results`] keeps the mesh's).
    positions: Vec<Vec<[f64; 3]>>,
    tensions: Vec<f64>,
}

impl Observer for Collect {
    fn frame(&mut self, f: &Frame<'_>) -> aqua_sim::Result<()> {
        self.rows.push(f.row.values());
        self.positions.push(f.state.x.clone());
        self.tensions.extend(&f.outputs.tension);
        Ok(())
    }

    /// Ctrl-C in Python stops the run after the current step (`run` then raises
    /// KeyboardInterrupt).
    fn stop_requested(&self) -> bool {
        Python::attach(|py| py.check_signals().is_err())
    }
}

/// Runs a scene as `aqua run` does (the same files with `out`); `None` when Ctrl-C stopped it.
fn run_scene(scene: aqua_sim::Scene, out: Option<PathBuf>) -> aqua_sim::Result<Option<Results>> {
    let mut c = Collect::default();
    let options = aqua_sim::RunOptions {
        scene: aqua_sim::PrepareOptions::scene(scene),
        out: out.as_deref(),
    };
    let outcome = aqua_sim::run_scene(options, &mut c)?;
    outcome.result?;
    let (prep, record) = (&outcome.prepared, &outcome.record);
    if record.ending == aqua_sim::Ending::Interrupted {
        return Ok(None);
    }
    let np = prep.built.mesh.nodes.len();
    Ok(Some(Results {
        columns: aqua_sim::SummaryRow::columns(&prep.built),
        rows: c.rows,
        positions: c
            .positions
            .iter()
            .flat_map(|x| x[..np].iter().flatten().copied())
            .collect(),
        tensions: c.tensions,
        n_nodes: prep.built.mesh.nodes.len(),
        n_elements: prep.built.model.elements().len(),
        status: record.ending.as_str().to_string(),
        extremes: record
            .extremes
            .as_ref()
            .map(|e| {
                e.table()
                    .into_iter()
                    .map(|(c, x)| (c.to_string(), [x.max, x.t_max, x.min, x.t_min]))
                    .collect()
            })
            .unwrap_or_default(),
    }))
}

/// The output steps of a run.
#[pyclass(module = "aqua", frozen)]
struct Results {
    columns: Vec<String>,
    rows: Vec<Vec<f64>>,
    positions: Vec<f64>,
    tensions: Vec<f64>,
    n_nodes: usize,
    n_elements: usize,
    status: String,
    /// Per load column: max, t_max, min, t_min over every accepted step.
    extremes: Vec<(String, [f64; 4])>,
}

#[pymethods]
impl Results {
    /// `summary.csv` column names.
    #[getter]
    fn columns(&self) -> Vec<String> {
        self.columns.clone()
    }

    /// How the run ended ("completed").
    #[getter]
    fn status(&self) -> String {
        self.status.clone()
    }

    /// Times of the output steps [s].
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, "t")
    }

    /// The load extremes over every accepted step (as `extremes.csv`):
    /// {column: {"max", "t_max", "min", "t_min"}}.
    #[getter]
    fn extremes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, v) in &self.extremes {
            let e = PyDict::new(py);
            for (k, x) in ["max", "t_max", "min", "t_min"].into_iter().zip(*v) {
                e.set_item(k, x)?;
            }
            d.set_item(name, e)?;
        }
        Ok(d)
    }

    /// The summary columns by name: {name: array (n_steps,)}.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for name in &self.columns {
            d.set_item(name, self.column(py, name)?)?;
        }
        Ok(d)
    }

    /// One summary column (n_steps,).
    fn column<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let k = self.columns.iter().position(|c| c == name).ok_or_else(|| {
            pyo3::exceptions::PyKeyError::new_err(format!(
                "{name}: no such column; columns: {}",
                self.columns.join(", ")
            ))
        })?;
        Ok(PyArray1::from_vec(
            py,
            self.rows.iter().map(|r| r[k]).collect(),
        ))
    }

    /// Node positions [m], (n_steps, n_nodes, 3).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let a = PyArray1::from_vec(py, self.positions.clone());
        Ok(a.reshape([self.rows.len(), self.n_nodes, 3])?.into_any())
    }

    /// Element tensions [N], (n_steps, n_elements).
    #[getter]
    fn tensions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let a = PyArray1::from_vec(py, self.tensions.clone());
        Ok(a.reshape([self.rows.len(), self.n_elements])?.into_any())
    }

    fn __len__(&self) -> usize {
        self.rows.len()
    }
}

/// The `aqua` module.
#[pymodule(name = "aqua")]
fn aqua_py(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Scene>()?;
    m.add_class::<Results>()?;
    m.add_class::<coupling::Coupling>()?;
    m.add_class::<coupling::CouplingState>()?;
    m.add("AquaError", m.py().get_type::<AquaError>())?;
    m.add("InputError", m.py().get_type::<InputError>())?;
    m.add("SolveError", m.py().get_type::<SolveError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
