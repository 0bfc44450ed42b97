//! The one place where aqua-sim calls aqua-fem's solvers: static equilibrium
//! ([`static_equilibrium`]) and the time integrators behind one [`Stepper`] trait
//! ([`start_integrator`]). The run loop and the coupling both come through here.

use crate::error::{Result, SimError};
use crate::plan::Integrator;
use crate::provider::WaterLoads;
use aqua_fem::{
    BodyPose, DynamicSolver, Energies, ExplicitSolver, FemError, LinearSolverStats, Model, Outputs,
    Snapshot, State, StaticControl, StaticProgress, StaticSettings, StaticSolution, StepControl,
    StepReport, solve_static_from,
};
use aqua_mesh::{Mesh, ObjectKind};

/// Static equilibrium of the model under the water loads (docs/theory/fem.md#static-solver).
/// `progress` sees every Newton iteration and may stop the solve, which then returns the
/// last accepted state with `report.interrupted`.
/// A failure names the scene objects of the nodes it is about (`mesh` is the model's mesh).
pub fn static_equilibrium(
    model: &Model,
    mesh: &Mesh,
    loads: &mut WaterLoads,
    settings: &StaticSettings,
    progress: &mut dyn FnMut(&StaticProgress) -> StaticControl,
) -> Result<StaticSolution> {
    static_equilibrium_from(model, mesh, loads, settings, None, progress)
}

/// [`static_equilibrium`] from the node positions `start` [m] (`None`: as built), e.g. a
/// coarser mesh's equilibrium carried to this one (crate::mesh_sequence).
pub(crate) fn static_equilibrium_from(
    model: &Model,
    mesh: &Mesh,
    loads: &mut WaterLoads,
    settings: &StaticSettings,
    start: Option<&[[f64; 3]]>,
    progress: &mut dyn FnMut(&StaticProgress) -> StaticControl,
) -> Result<StaticSolution> {
    solve_static_from(model, loads, settings, start, progress).map_err(|e| {
        let nodes: Vec<usize> = match &e {
            FemError::Drifting { nodes, .. }
            | FemError::Unconstrained { nodes, .. }
            | FemError::Sinking { nodes, .. } => nodes.clone(),
            FemError::StaticFailed(f) => vec![f.worst_node],
            _ => Vec::new(),
        };
        SimError::Static {
            parts: part_names(mesh, &nodes),
            source: Box::new(e),
        }
    })
}

/// " (part: line 'm1', buoy 'b')": the objects owning `nodes`, in mesh order, at most six
/// named; "" if none.
pub(crate) fn part_names(mesh: &Mesh, nodes: &[usize]) -> String {
    let mut objects: Vec<usize> = nodes
        .iter()
        .filter_map(|&i| mesh.node_owner.get(i).map(|o| o.0 as usize))
        .collect();
    objects.sort_unstable();
    objects.dedup();
    let names: Vec<String> = objects
        .iter()
        .filter_map(|&o| mesh.objects.get(o))
        .map(|o| format!("{} '{}'", object_kind(&o.kind), o.name))
        .collect();
    match names.len() {
        0 => String::new(),
        1..=6 => format!(" (part: {})", names.join(", ")),
        k => format!(
            " (part: {} and {} more objects)",
            names[..6].join(", "),
            k - 6
        ),
    }
}

fn object_kind(k: &ObjectKind) -> &'static str {
    match k {
        ObjectKind::Cage(_) => "cage",
        ObjectKind::Panel => "panel",
        ObjectKind::Line => "line",
        ObjectKind::Gmsh => "mesh",
        ObjectKind::Buoy => "buoy",
        ObjectKind::Frame => "farm frame",
        ObjectKind::Body => "body",
    }
}

/// What the run loop needs of a time integrator (HHT-α or explicit).
pub trait Stepper {
    /// True once the end time is reached.
    fn is_finished(&self) -> bool;
    /// One step (HHT-α may halve it, both land on output times).
    fn step(&mut self, loads: &mut WaterLoads) -> aqua_fem::Result<StepReport>;
    /// The current state.
    fn state(&self) -> &State;
    /// Tensions, reactions, … of the current state.
    fn outputs(&self) -> &Outputs;
    /// Warnings of starting the integrator (a reduced explicit step, …).
    fn warnings(&self) -> Vec<String>;
    /// The pose of every rigid body in the current state, in the model's order (explicit
    /// schemes refuse models with rigid bodies: none).
    fn body_poses(&self) -> Vec<BodyPose> {
        Vec::new()
    }
    /// What the step control did (HHT-α; explicit schemes keep a fixed step).
    fn step_control(&self) -> Option<StepControl> {
        None
    }
    /// The energy ledger (HHT-α and the midpoint rule).
    fn energies(&self) -> Option<Energies> {
        None
    }
    /// Counters of the implicit schemes' linear solves (factorisations, kept factors, …).
    fn linear_solver_stats(&self) -> Option<LinearSolverStats> {
        None
    }
    /// Moves the end time to `t_end` [s] (a coupling's call; a failed step may be retried).
    fn extend_to(&mut self, t_end: f64) -> aqua_fem::Result<()>;
    /// The integrator's state for [`Stepper::restore`] (implicit schemes only); the next
    /// step factorises afresh, as after a restore.
    fn save(&mut self) -> Option<Snapshot> {
        None
    }
    /// The integrator's state, leaving its kept factorisation in use.
    fn checkpoint(&self) -> Option<Snapshot> {
        None
    }
    /// Puts back a state of [`Stepper::save`].
    fn restore(&mut self, snapshot: &Snapshot) -> aqua_fem::Result<()> {
        let _ = snapshot;
        Err(FemError::InvalidModel(
            "save and restore need an implicit scheme (HHT-α or the midpoint rule)".into(),
        ))
    }
}

impl Stepper for DynamicSolver<'_> {
    fn is_finished(&self) -> bool {
        DynamicSolver::is_finished(self)
    }
    fn step(&mut self, loads: &mut WaterLoads) -> aqua_fem::Result<StepReport> {
        DynamicSolver::step(self, loads)
    }
    fn state(&self) -> &State {
        DynamicSolver::state(self)
    }
    fn outputs(&self) -> &Outputs {
        DynamicSolver::outputs(self)
    }
    fn warnings(&self) -> Vec<String> {
        Vec::new()
    }
    fn body_poses(&self) -> Vec<BodyPose> {
        DynamicSolver::body_poses(self)
    }
    fn step_control(&self) -> Option<StepControl> {
        Some(DynamicSolver::step_control(self).clone())
    }
    fn energies(&self) -> Option<Energies> {
        Some(DynamicSolver::energies(self))
    }
    fn linear_solver_stats(&self) -> Option<LinearSolverStats> {
        Some(DynamicSolver::linear_solver_stats(self))
    }
    fn extend_to(&mut self, t_end: f64) -> aqua_fem::Result<()> {
        DynamicSolver::extend_to(self, t_end)
    }
    fn save(&mut self) -> Option<Snapshot> {
        Some(DynamicSolver::save(self))
    }
    fn checkpoint(&self) -> Option<Snapshot> {
        Some(DynamicSolver::checkpoint(self))
    }
    fn restore(&mut self, snapshot: &Snapshot) -> aqua_fem::Result<()> {
        DynamicSolver::restore(self, snapshot)
    }
}

impl Stepper for ExplicitSolver<'_> {
    fn is_finished(&self) -> bool {
        ExplicitSolver::is_finished(self)
    }
    fn step(&mut self, loads: &mut WaterLoads) -> aqua_fem::Result<StepReport> {
        ExplicitSolver::step(self, loads)
    }
    fn state(&self) -> &State {
        ExplicitSolver::state(self)
    }
    fn outputs(&self) -> &Outputs {
        ExplicitSolver::outputs(self)
    }
    fn warnings(&self) -> Vec<String> {
        ExplicitSolver::warnings(self).to_vec()
    }
    fn extend_to(&mut self, t_end: f64) -> aqua_fem::Result<()> {
        ExplicitSolver::extend_to(self, t_end)
    }
}

/// Starts the integrator from `initial` (the static state) or from rest as built.
pub fn start_integrator<'m>(
    model: &'m Model,
    integrator: &Integrator,
    initial: Option<&State>,
    loads: &mut WaterLoads,
) -> Result<Box<dyn Stepper + 'm>> {
    Ok(match integrator {
        Integrator::Hht(s) => Box::new(
            DynamicSolver::new(model, s.clone(), initial, loads)
                .map_err(|e| SimError::StartDynamic("dynamic", Box::new(e)))?,
        ),
        Integrator::Explicit(s) => Box::new(
            ExplicitSolver::new(model, s.clone(), initial, loads)
                .map_err(|e| SimError::StartDynamic("explicit", Box::new(e)))?,
        ),
    })
}
