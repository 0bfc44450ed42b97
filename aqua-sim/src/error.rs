//! Errors of aqua-sim: typed, with the library error that caused them kept as `source`, so the
//! binary (or the Python module) turns them into text once, at the edge.

use std::path::PathBuf;
use thiserror::Error;

/// A library error met while turning a scene into a model: the crates below keep their own
/// types, wrapped here without losing them.
#[derive(Debug, Error)]
pub enum ModelError {
    /// Structural model (aqua-fem).
    #[error(transparent)]
    Fem(#[from] aqua_fem::FemError),
    /// Water loads (aqua-hydro).
    #[error(transparent)]
    Hydro(#[from] aqua_hydro::HydroError),
    /// Geometry (aqua-mesh).
    #[error(transparent)]
    Mesh(#[from] aqua_mesh::MeshError),
    /// Sea (aqua-env).
    #[error(transparent)]
    Env(#[from] aqua_env::EnvError),
}

/// Everything that can stop a scene from being checked, run or coupled.
///
/// [`SimError::is_input`] tells a mistake in the input (the `aqua` binary exits with 2) from a
/// computation that failed (exit 1). The full message is the error followed by its sources,
/// joined by ": " ([`SimError::chain`]).
#[derive(Debug, Error)]
pub enum SimError {
    /// A mistake in the scene: the message names the file, line, section, key and value, and
    /// what would be valid; the fields give them to a program.
    #[error(transparent)]
    Input(InputError),
    /// A library rejected a value of the scene; `at` names the file and the place in it.
    #[error("{at}")]
    Model {
        /// File and place ("scene.toml: line 12: [[point]] #1").
        at: String,
        /// What the library said.
        #[source]
        source: Box<ModelError>,
    },
    /// A file could not be read or written.
    #[error("{what} {}", path.display())]
    Io {
        /// What was being done ("creating", "writing", …).
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A picture could not be drawn or written.
    #[error("drawing {}: {message}", path.display())]
    Plot {
        /// The PNG file.
        path: PathBuf,
        /// What the plotting library said.
        message: String,
    },
    /// An output file (VTK series) could not be written.
    #[error("writing the output series")]
    Output(#[source] Box<aqua_mesh::MeshError>),
    /// A value to be written was not finite (the step is not written).
    #[error("{0}")]
    NonFinite(String),
    /// The static solve failed.
    #[error("static equilibrium failed{parts}")]
    Static {
        /// The scene objects the failure is about (" (part: line 'm1', buoy 'b')"), or "".
        parts: String,
        /// What the solver said.
        #[source]
        source: Box<aqua_fem::FemError>,
    },
    /// A time integrator could not start.
    #[error("starting the {0} solver")]
    StartDynamic(&'static str, #[source] Box<aqua_fem::FemError>),
    /// A dynamic step failed.
    #[error("dynamic run failed")]
    Dynamic(#[source] Box<aqua_fem::FemError>),
    /// A coupling call did not fit the coupled model (unknown node, wrong time, closed).
    #[error("coupling: {0}")]
    Coupling(String),
}

/// A mistake in the input, for a person (its message) and for a program (where and what).
#[derive(Debug, Clone, PartialEq, Default, Error)]
#[error("{message}")]
pub struct InputError {
    /// The whole message, as `aqua` prints it after "error: ".
    pub message: String,
    /// The scene file, when known.
    pub file: Option<PathBuf>,
    /// The dotted key at fault (e.g. `analysis.dynamic.theta`), when known.
    pub key: Option<String>,
    /// The value given, as written, when known.
    pub value: Option<String>,
}

impl SimError {
    /// An input error with a ready message.
    pub fn input(msg: impl Into<String>) -> Self {
        Self::Input(InputError {
            message: msg.into(),
            ..InputError::default()
        })
    }

    /// An input error about `key` = `value` in `file`, with its message (which names them).
    pub fn invalid(
        file: impl Into<PathBuf>,
        key: impl Into<String>,
        value: impl ToString,
        message: impl Into<String>,
    ) -> Self {
        Self::Input(InputError {
            message: message.into(),
            file: Some(file.into()),
            key: Some(key.into()),
            value: Some(value.to_string()),
        })
    }

    /// A library error at a place in the scene.
    pub fn at(at: impl Into<String>, source: impl Into<ModelError>) -> Self {
        Self::Model {
            at: at.into(),
            source: Box::new(source.into()),
        }
    }

    /// True for mistakes in the input (scene, files named by it), false for failed
    /// computations and I/O of the outputs.
    pub fn is_input(&self) -> bool {
        matches!(self, Self::Input(_) | Self::Model { .. })
    }

    /// The message followed by every source, joined by ": " (what `aqua` prints after
    /// "error: ", and what a Python exception carries).
    pub fn chain(&self) -> String {
        let mut s = self.to_string();
        let mut src = std::error::Error::source(self);
        while let Some(e) = src {
            s.push_str(": ");
            s.push_str(&e.to_string());
            src = e.source();
        }
        s
    }
}

/// Result with [`SimError`].
pub type Result<T, E = SimError> = std::result::Result<T, E>;
