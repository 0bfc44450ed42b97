//! Settings, progress and report of the static solver (scene keys of `[analysis.static]`).

use crate::error::{Result, invalid};
use crate::state::{Outputs, State};
use serde::{Deserialize, Serialize};

/// Settings of the static solver (scene keys of `[analysis.static]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StaticSettings {
    /// Relative force tolerance ε_r (‖r‖₂ ≤ ε_r·F_ref). Default 1e-6.
    pub tol: f64,
    /// Newton iterations (factorisations) per load increment. Default 500.
    pub max_iter: usize,
    /// Initial number of load increments (Δs0 = 1/load_steps). Default 1: the full load at
    /// once, halved only if that solve fails.
    pub load_steps: usize,
    /// Smallest load increment before failing. Default 1e-4.
    pub min_load_step: f64,
    /// Initial Levenberg–Marquardt damping μ0, relative to Σ EA/L0 at each node (0: start
    /// undamped). Default 1e-3. μ then adapts; it does not change the answer.
    pub stabilisation: f64,
    /// Backtracking along a rejected step on the energy merit before μ is raised. Default true
    /// (the reference cage needs 121 iterations with it, 362 without;
    /// docs/theory/fem.md#static-solver).
    pub line_search: bool,
    /// Watchdog: a full step that the merit rejects is taken on trial and kept if, after the
    /// next step, the merit at the first iterate has fallen. Default true
    /// (docs/theory/fem.md#watchdog).
    pub watchdog: bool,
    /// Levenberg–Marquardt damping on the line elements' stretch (and a tenth of the nodal
    /// Σ EA/L0) instead of the nodal Σ EA/L0: a cage drifting on its bridles is then hardly
    /// damped. Default false: it halves the full-scale farm's statics but costs a slack-bottom
    /// cage 3.4× more iterations (docs/theory/fem.md#stretch-damping).
    pub stretch_damping: bool,
    /// Time at which loads and prescribed offsets are evaluated [s]. Default 0.
    pub time: f64,
    /// Form missing water-load position derivatives by finite differences. Default true.
    pub fd_position_jacobian: bool,
    /// Coarser meshes solved first, each the start of the next (mesh sequencing): 0 (default)
    /// starts from the as-built geometry, k solves the scene with its nets' element length
    /// doubled k times first. Read by the scene runner (aqua-sim), which builds the coarser
    /// models; the solver itself takes a start shape (`solve_static_from`;
    /// docs/theory/fem.md#mesh-sequencing). At most `MAX_MESH_SEQUENCE`.
    pub mesh_sequence: usize,
}

/// Largest `mesh_sequence`: 2⁴ = 16 times the element length is coarser than any net needs.
pub const MAX_MESH_SEQUENCE: usize = 4;

impl Default for StaticSettings {
    fn default() -> Self {
        Self {
            tol: 1e-6,
            max_iter: 500,
            load_steps: 1,
            min_load_step: 1e-4,
            stabilisation: 1e-3,
            line_search: true,
            watchdog: true,
            stretch_damping: false,
            time: 0.0,
            fd_position_jacobian: true,
            mesh_sequence: 0,
        }
    }
}

impl StaticSettings {
    pub(super) fn validate(&self) -> Result<()> {
        if !(self.tol.is_finite() && self.tol > 0.0 && self.tol < 1.0) {
            return Err(invalid("static tol", self.tol, "0 < tol < 1"));
        }
        if self.max_iter == 0 {
            return Err(invalid("static max_iter", 0.0, ">= 1"));
        }
        if self.load_steps == 0 {
            return Err(invalid("static load_steps", 0.0, ">= 1"));
        }
        if !(self.min_load_step > 0.0 && self.min_load_step <= 1.0) {
            return Err(invalid(
                "static min_load_step",
                self.min_load_step,
                "0 < value <= 1",
            ));
        }
        if !(self.stabilisation.is_finite() && self.stabilisation >= 0.0) {
            return Err(invalid("static stabilisation", self.stabilisation, ">= 0"));
        }
        if self.mesh_sequence > MAX_MESH_SEQUENCE {
            return Err(invalid(
                "static mesh_sequence",
                self.mesh_sequence as f64,
                format!("0 ..= {MAX_MESH_SEQUENCE}"),
            ));
        }
        if !self.time.is_finite() {
            return Err(invalid("static time [s]", self.time, "finite"));
        }
        Ok(())
    }
}

/// What the static solve did.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct StaticReport {
    /// Accepted load increments, the re-solves after a wake change included.
    pub increments: usize,
    /// Rejected (halved) increments.
    pub rejected_increments: usize,
    /// Total Newton iterations (factorisations).
    pub iterations: usize,
    /// Iterations whose step the merit rejected (μ raised, refactorised).
    pub rejected_steps: usize,
    /// Steps accepted only after backtracking.
    pub backtracked_steps: usize,
    /// ‖r‖/F_ref per iteration of the last Newton solve.
    pub last_residual_history: Vec<f64>,
    /// Final ‖r‖/F_ref.
    pub relative_residual: f64,
    /// Round-off level of ‖r‖ relative to F_ref at the solution: the solver stops there even
    /// if `tol` asks for less.
    pub noise_level: f64,
    /// Reference force F_ref [N].
    pub f_ref: f64,
    /// ‖r‖/F_ref at every Newton iterate of every increment, in order.
    pub residual_history: Vec<f64>,
    /// The observer stopped the solve: the state is the last accepted one, not an equilibrium.
    pub interrupted: bool,
    /// Load factor s of the returned state (1 = full load; below 1 only when the solve was
    /// interrupted during load continuation).
    pub load_factor: f64,
    /// Warnings (logged by the caller).
    pub warnings: Vec<String>,
    /// Parts and interface DOFs of the block solve that factorised the systems, if the
    /// model's partition was used (docs/theory/fem.md#block-solve).
    #[serde(default)]
    pub block_solve: Option<(usize, usize)>,
}

/// One Newton iteration of the static solve, as reported to an observer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticProgress {
    /// Load factor being solved for (1 = full load).
    pub load_factor: f64,
    /// Levenberg–Marquardt damping μ of the next step.
    pub damping: f64,
    /// Newton iterations so far.
    pub iteration: usize,
    /// ‖r‖/F_ref at this iterate.
    pub relative_residual: f64,
}

/// What an observer tells the static solver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StaticControl {
    /// Go on.
    Continue,
    /// Stop now and return the last accepted state with `report.interrupted`.
    Stop,
}

/// Result of a static solve.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    /// Equilibrium state (v = a = 0).
    pub state: State,
    /// Tensions, strains, reactions, ...
    pub outputs: Outputs,
    /// Solver statistics.
    pub report: StaticReport,
}

impl StaticSolution {
    /// The pose of every rigid body at the equilibrium, in the order of
    /// [`Model::rigid_bodies`](crate::Model::rigid_bodies): statics takes a body's rotation
    /// vector about its as-built axes, R = exp([ψ]×) (docs/theory/fem.md#rigid-bodies).
    pub fn body_poses(&self, model: &crate::Model) -> Vec<crate::rigid_body::BodyPose> {
        let frames = vec![crate::rigid_body::BodyFrame::default(); model.rigid_bodies().len()];
        crate::system::body_poses_with(model, &frames, &self.state.x, &self.state.v)
    }
}
