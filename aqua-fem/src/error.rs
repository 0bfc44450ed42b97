//! Typed errors of the structural model and its solvers.

use crate::failure::{FailureReason, SchemeKind};
use std::sync::Arc;
use thiserror::Error;

/// Everything that can go wrong while building a model or solving it.
///
/// Messages name the offending parameter, its value and what would be valid, or, for solver
/// failures, the time, the node with the largest residual and the residual history.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FemError {
    /// A parameter is out of its valid range.
    #[error("invalid {what} = {value}: {valid}")]
    InvalidParameter {
        /// Name of the parameter (and where it belongs, e.g. `element 3 unstretched_length`).
        what: String,
        /// The value that was given.
        value: f64,
        /// What would be valid.
        valid: String,
    },
    /// A node index does not exist.
    #[error("{what}: node {node} does not exist (the model has {n_nodes} nodes)")]
    UnknownNode {
        /// Where the index was used.
        what: String,
        /// The bad index.
        node: usize,
        /// Number of nodes in the model.
        n_nodes: usize,
    },
    /// The mesh coordinates (U, V) of a net triangle's corners span no area: the triangle
    /// holds no twines and its twine vectors are undefined (docs/theory/fem.md#net-triangle).
    #[error(
        "net triangle {triangle} (nodes {}-{}-{}): its mesh coordinates (U, V) = {uv:?} span \
         an area of {area:.3e} mesh cells; the (U, V) corners must not lie on one line",
        nodes[0],
        nodes[1],
        nodes[2]
    )]
    DegenerateNetTriangle {
        /// Index the triangle would have had.
        triangle: usize,
        /// Its nodes.
        nodes: [usize; 3],
        /// The mesh coordinates given.
        uv: [[f64; 2]; 3],
        /// Their signed area in (U, V).
        area: f64,
    },
    /// Structurally bad model (duplicate constraint, unattached node, empty model, ...).
    #[error("invalid model: {0}")]
    InvalidModel(String),
    /// A rigid body's input is out of range (docs/theory/fem.md#rigid-bodies).
    #[error("rigid body '{body}': invalid {key} = {value}: {valid}")]
    RigidBody {
        /// The body's name.
        body: String,
        /// The offending key (`mass [kg]`, `inertia [kg m^2]`, `points`, ...).
        key: String,
        /// The value that was given.
        value: String,
        /// What would be valid.
        valid: String,
    },
    /// The explicit solver was given a model with rigid bodies: their rotational inertia is a
    /// full 3×3 block that its lumped (diagonal) mass cannot hold.
    #[error(
        "rigid body '{body}': the explicit solver cannot integrate rigid bodies (their \
         rotational inertia is a full 3x3 block); use the implicit DynamicSolver (HHT-alpha or \
         the midpoint rule)"
    )]
    RigidBodyNeedsImplicit {
        /// The first body's name.
        body: String,
    },
    /// A connected part of the structure is held by nothing (no fixed/prescribed node, no
    /// seabed contact, no restoring load): the static problem is singular.
    #[error(
        "the part of the structure containing node {first_node} ({n_nodes} nodes) has no fixed or \
         prescribed node, no seabed contact and no restoring load: it is free-floating and the \
         static problem is singular; fix a node or add a support"
    )]
    Unconstrained {
        /// Lowest node index of the free component.
        first_node: usize,
        /// Number of nodes in the component.
        n_nodes: usize,
        /// Every node of the component (for naming it).
        nodes: Vec<usize>,
    },
    /// A connected part with no node fixed in x (or in y) carries loads with a resultant
    /// along that axis at the as-built position. Nothing else holds a part horizontally in
    /// statics (seabed contact and buoyancy act vertically, statics has no seabed friction):
    /// it has no static equilibrium, the loads carry it away.
    #[error(
        "the part of the structure containing node {first_node} ({n_nodes} nodes) has no node \
         fixed in {free_dirs}, and nothing else holds it along {free_dirs} in statics (seabed \
         contact and buoyancy act vertically; statics has no seabed friction), but the loads on \
         it push it horizontally with [{:.4e}, {:.4e}] N: it has no static equilibrium and \
         would drift away; anchor it (fix a node, e.g. a line's `fixed = [\"anchor\"]`) or \
         attach it to a held part",
        force[0],
        force[1]
    )]
    Drifting {
        /// Lowest node index of the part.
        first_node: usize,
        /// Number of nodes in the part.
        n_nodes: usize,
        /// The free horizontal directions ("x", "y" or "x and y").
        free_dirs: String,
        /// Horizontal resultant of the external loads on the part [N].
        force: [f64; 2],
        /// Every node of the part (for naming it).
        nodes: Vec<usize>,
    },
    /// A connected part with no node fixed in z and no seabed contact whose weight (with the
    /// point forces) exceeds the largest buoyancy the water can give it, fully submerged:
    /// nothing can hold it up, it sinks without end.
    #[error(
        "the part of the structure containing node {first_node} ({n_nodes} nodes) would sink: \
         its weight, {weight:.4e} N, is more than the buoyancy it has fully submerged, \
         {buoyancy:.4e} N, and nothing else holds it up (no node fixed in z, no seabed contact \
         to rest on); fix a node in z, hang it from a float or a held part, lighten it or give \
         it more buoyancy"
    )]
    Sinking {
        /// Lowest node index of the part.
        first_node: usize,
        /// Number of nodes in the part.
        n_nodes: usize,
        /// Downward resultant of its weights and point forces [N].
        weight: f64,
        /// Its largest buoyancy (every member fully submerged) [N].
        buoyancy: f64,
        /// Every node of the part (for naming it).
        nodes: Vec<usize>,
    },
    /// The load provider reported an error, or its loads were unusable.
    #[error("load provider, element {element}: {error}")]
    Load {
        /// Load element index (usize::MAX when not element specific).
        element: usize,
        /// The provider's error, its type kept ([`LoadError::inner`]).
        error: LoadError,
    },
    /// The static solver failed.
    #[error(transparent)]
    StaticFailed(Box<StaticFailure>),
    /// A dynamic step failed down to the minimum step.
    #[error(transparent)]
    StepFailed(Box<StepFailure>),
    /// The sparse factorisation failed or the system is singular.
    #[error("linear solve failed: {0}")]
    Linear(String),
    /// A non-finite number appeared.
    #[error("non-finite value in {0}")]
    NonFinite(String),
}

/// Error returned by a [`crate::LoadProvider`]: the provider's own error, boxed with its type,
/// so a caller can downcast it ([`LoadError::inner`]) and act on the cause.
#[derive(Debug, Error, Clone)]
#[error(transparent)]
pub struct LoadError(Arc<dyn std::error::Error + Send + Sync + 'static>);

impl LoadError {
    /// Wraps a provider's error.
    pub fn new(error: impl std::error::Error + Send + Sync + 'static) -> Self {
        Self(Arc::new(error))
    }

    /// An error that is only a message.
    pub fn msg(message: impl Into<String>) -> Self {
        Self(Arc::new(Message(message.into())))
    }

    /// The provider's error, for `downcast_ref`.
    pub fn inner(&self) -> &(dyn std::error::Error + Send + Sync + 'static) {
        &*self.0
    }
}

impl PartialEq for LoadError {
    /// Equal when the messages are: the boxed errors need not be comparable.
    fn eq(&self, other: &Self) -> bool {
        self.to_string() == other.to_string()
    }
}

/// A [`LoadError`] that is only a message.
#[derive(Debug, Error)]
#[error("{0}")]
struct Message(String);

/// Result alias of this crate.
pub type Result<T, E = FemError> = std::result::Result<T, E>;

pub(crate) fn invalid(what: impl Into<String>, value: f64, valid: impl Into<String>) -> FemError {
    FemError::InvalidParameter {
        what: what.into(),
        value,
        valid: valid.into(),
    }
}

/// The last values of a residual history (‖r‖/F_ref per iteration), 3 digits each: a failure
/// message stays a few lines long however many iterations ran.
fn brief(history: &[f64]) -> String {
    const SHOWN: usize = 8;
    let tail: Vec<String> = history
        .iter()
        .skip(history.len().saturating_sub(SHOWN))
        .map(|r| format!("{r:.3e}"))
        .collect();
    if history.len() > SHOWN {
        format!(
            "(last {SHOWN} of {} iterations) [..., {}]",
            history.len(),
            tail.join(", ")
        )
    } else {
        format!("[{}]", tail.join(", "))
    }
}

/// Details of a static solver failure.
#[derive(Debug, Error, Clone, PartialEq)]
#[error(
    "static solve failed at load factor {load_factor:.4} (increment {increment:.2e} < minimum \
         {min_increment:.2e}): {reason}; worst node {worst_node} at {worst_position:?} with \
         residual {worst_residual:.4e} N (F_ref = {f_ref:.4e} N); residual history {}. \
         Hints: {}",
    brief(.history),
    .reason.hint(SchemeKind::Statics)
)]
pub struct StaticFailure {
    /// Load factor that could not be reached.
    pub load_factor: f64,
    /// Last attempted increment.
    pub increment: f64,
    /// Minimum allowed increment.
    pub min_increment: f64,
    /// Why the last attempt failed.
    pub reason: FailureReason,
    /// Node with the largest residual.
    pub worst_node: usize,
    /// Its position [m].
    pub worst_position: [f64; 3],
    /// Its residual norm [N].
    pub worst_residual: f64,
    /// Reference force [N].
    pub f_ref: f64,
    /// ‖r‖/F_ref per iteration of the last attempt.
    pub history: Vec<f64>,
}

/// Details of a dynamic step failure.
#[derive(Debug, Error, Clone, PartialEq)]
#[error(
    "dynamic step failed at t = {t:.6} s with dt = {dt:.3e} s < dt_min = {dt_min:.3e} s: \
         {reason}; worst node {worst_node} at {worst_position:?} with residual \
         {worst_residual:.4e} N; most strained element {max_strain_element} (strain \
         {max_strain:.4e}), most compressed element {min_strain_element} (strain \
         {min_strain:.4e}); residual history {}. Hints: {}",
    brief(.history),
    .reason.hint(*.scheme)
)]
pub struct StepFailure {
    /// Time of the last converged state [s].
    pub t: f64,
    /// Step that failed [s].
    pub dt: f64,
    /// Minimum step [s].
    pub dt_min: f64,
    /// Why the last attempt failed.
    pub reason: FailureReason,
    /// Node with the largest residual.
    pub worst_node: usize,
    /// Its position [m].
    pub worst_position: [f64; 3],
    /// Its residual norm [N].
    pub worst_residual: f64,
    /// Element with the largest strain.
    pub max_strain_element: usize,
    /// Its strain.
    pub max_strain: f64,
    /// Element with the smallest strain.
    pub min_strain_element: usize,
    /// Its strain.
    pub min_strain: f64,
    /// ‖r‖/F_ref per iteration of the last attempt.
    pub history: Vec<f64>,
    /// The scheme that failed: the hint names only what it can change (HHT-α's `alpha`, the
    /// midpoint rule's `theta`).
    pub scheme: SchemeKind,
}
