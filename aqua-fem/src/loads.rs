//! The load-provider trait: everything the water does arrives through it
//! (docs/theory/fem.md#loads).

use crate::error::LoadError;

/// Most nodes a load element may have (point = 1, line = 2, triangle = 3, quad = 4).
pub const MAX_LOAD_NODES: usize = 4;
/// Size of a local load-element Jacobian (3·MAX_LOAD_NODES).
pub const MAX_LOAD_DOFS: usize = 3 * MAX_LOAD_NODES;

/// Which derivatives the solver wants from a call.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Want {
    /// ∂f/∂v wanted.
    pub dfdv: bool,
    /// ∂f/∂x wanted.
    pub dfdx: bool,
}

/// Output buffer of one load element, owned by the solver and reused for every call (no
/// allocation). Before each call the solver zeroes `force` and `added_mass` of the element's
/// nodes and clears both `has_*` flags.
///
/// Local ordering: node i of the element (as listed by
/// [`LoadProvider::element_nodes`]), component k → local DOF 3i + k.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementLoad {
    /// Force on each node of the element [N] (structure's equation of motion sense: pushes
    /// the structure).
    pub force: [[f64; 3]; MAX_LOAD_NODES],
    /// Added-mass 3×3 block per node [kg], row-major; the solver adds it to M.
    pub added_mass: [[[f64; 3]; 3]; MAX_LOAD_NODES],
    /// ∂f_{3i+k}/∂v_{3j+l} [N·s/m]; valid only if `has_dfdv` (then every entry of the leading
    /// 3n×3n block must be written).
    pub dfdv: [[f64; MAX_LOAD_DOFS]; MAX_LOAD_DOFS],
    /// Set by the provider when it filled `dfdv`.
    pub has_dfdv: bool,
    /// ∂f_{3i+k}/∂x_{3j+l} [N/m]; valid only if `has_dfdx`.
    pub dfdx: [[f64; MAX_LOAD_DOFS]; MAX_LOAD_DOFS],
    /// Set by the provider when it filled `dfdx`.
    pub has_dfdx: bool,
}

impl Default for ElementLoad {
    fn default() -> Self {
        Self {
            force: [[0.0; 3]; MAX_LOAD_NODES],
            added_mass: [[[0.0; 3]; 3]; MAX_LOAD_NODES],
            dfdv: [[0.0; MAX_LOAD_DOFS]; MAX_LOAD_DOFS],
            has_dfdv: false,
            dfdx: [[0.0; MAX_LOAD_DOFS]; MAX_LOAD_DOFS],
            has_dfdx: false,
        }
    }
}

impl ElementLoad {
    pub(crate) fn reset(&mut self, n: usize) {
        for i in 0..n {
            self.force[i] = [0.0; 3];
            self.added_mass[i] = [[0.0; 3]; 3];
        }
        self.has_dfdv = false;
        self.has_dfdx = false;
    }
}

/// External (water) loads on the structure, evaluated at the current Newton iterate.
///
/// The provider declares its *load elements* (sets of 1–4 nodes: points, lines, panels);
/// the set is fixed for a run, so the solver can build the sparse pattern once. At every
/// evaluation the solver calls [`prepare`](Self::prepare) once with the full state (for
/// global work such as wake factors), then [`element_load`](Self::element_load) for each
/// element, possibly in parallel, with the element's node positions and velocities. The
/// provider writes into the solver-owned [`ElementLoad`] buffer.
///
/// Derivatives: ∂f/∂v is needed in dynamics and ∂f/∂x in statics (and optionally dynamics);
/// if the provider does not set `has_dfdv`/`has_dfdx` when asked, the solver forms them by
/// element-local central differences (perturbation 1e-7·max(l, 1 m) in x, 1e-7·max(|v|, 1 m/s)
/// in v), calling `element_load` again with perturbed local states.
///
/// Conventions: forces in N on the structure; `t` in s; positions m; velocities m/s.
pub trait LoadProvider: Sync {
    /// Number of load elements.
    fn n_elements(&self) -> usize;
    /// Node indices of load element `e` (1 to [`MAX_LOAD_NODES`] distinct nodes).
    fn element_nodes(&self, e: usize) -> &[usize];
    /// Called once per evaluation before the element loop, with all node positions and
    /// velocities.
    fn prepare(&mut self, t: f64, x: &[[f64; 3]], v: &[[f64; 3]]) -> Result<(), LoadError> {
        let _ = (t, x, v);
        Ok(())
    }
    /// Called with an accepted state: before each time step, when a static solve has
    /// converged, and once in each full-load static solve before the first wake re-solve, at
    /// the first iterate with ‖r‖ ≤ 0.1·F_ref (the solve then goes on with the changed loads).
    /// The place for load data that must stay fixed between these calls because it changes
    /// discontinuously with the geometry (which elements lie in a wake). Returns true if the
    /// loads changed (any wake factor by more than the provider's tolerance, not only a
    /// change of membership); a converged static solve is then repeated from its equilibrium,
    /// and after five such re-solves the loads are frozen and solved once more
    /// (docs/theory/fem.md#static-solver).
    fn accept_state(&mut self, t: f64, x: &[[f64; 3]]) -> Result<bool, LoadError> {
        let _ = (t, x);
        Ok(false)
    }
    /// Fills `out` for element `e` with node positions `x` and velocities `v` (slices of the
    /// element's node count, in the order of `element_nodes`).
    fn element_load(
        &self,
        e: usize,
        t: f64,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        want: Want,
        out: &mut ElementLoad,
    ) -> Result<(), LoadError>;
    /// Adds to `lift` the largest buoyancy [N] the provider can exert on each node: with
    /// every member fully submerged. Returns false (the default) if the provider cannot tell;
    /// statics then does not check whether a part free in z is held up
    /// ([`crate::FemError::Sinking`]). Drag and lift of a current are not counted.
    fn max_buoyancy(&self, lift: &mut [f64]) -> bool {
        let _ = lift;
        false
    }

    /// Marks nodes on which the provider exerts a position-dependent *vertical* restoring
    /// force (buoyancy that changes with the draft), so that a part held only by such loads
    /// is not reported as unsupported. Statics assumes that no provider load restores
    /// horizontally: a part with no node fixed in x (or y) whose loads push it along x (or
    /// y) is reported as drifting ([`crate::FemError::Drifting`]).
    fn mark_restoring_nodes(&self, held: &mut [bool]) {
        let _ = held;
    }
}

/// No external loads (structure in air / vacuum).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NoLoads;

impl LoadProvider for NoLoads {
    fn n_elements(&self) -> usize {
        0
    }
    fn element_nodes(&self, _e: usize) -> &[usize] {
        &[]
    }
    fn element_load(
        &self,
        _e: usize,
        _t: f64,
        _x: &[[f64; 3]],
        _v: &[[f64; 3]],
        _want: Want,
        _out: &mut ElementLoad,
    ) -> Result<(), LoadError> {
        Ok(())
    }
}

/// [`LoadProvider::accept_state`] with its error as a [`FemError::Load`](crate::FemError).
pub(crate) fn accept_state<P: LoadProvider + ?Sized>(
    provider: &mut P,
    t: f64,
    x: &[[f64; 3]],
) -> crate::Result<bool> {
    provider
        .accept_state(t, x)
        .map_err(|e| crate::FemError::Load {
            element: usize::MAX,
            error: e,
        })
}
