//! The run loop of a scene: statics and/or dynamics with any integrator, an output frame
//! (state, outputs, wake, summary row) at every output step, and a record of how it ended.
//!
//! What to do with the frames (files, arrays, a progress bar) is the caller's, through an
//! [`Observer`]; a stop request is honoured between steps and leaves every frame already
//! delivered complete.

use crate::design::DynamicWatch;
use crate::diagnostic::Diagnostic;
use crate::error::{Result, SimError};
use crate::extremes::Extremes;
use crate::plan::{Integrator, Prepared};
use crate::post::{SummaryRow, net_force_and_wake, total_volume};
use crate::provider::WaterLoads;
use crate::scene::AnalysisKind;
use crate::solvers::{Stepper, start_integrator, static_equilibrium_from};
use aqua_env::Phase;
use aqua_fem::{
    BodyPose, Energies, LinearSolverStats, Model, Outputs, State, StaticControl, StaticProgress,
    StepControl, StepReport,
};
use aqua_hydro::assembly::LoadAssembly;
use std::time::Instant;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Ending {
    /// Reached the end.
    #[default]
    Completed,
    /// Stopped on request (Ctrl-C).
    Interrupted,
    /// A solve failed.
    Failed,
}

impl Ending {
    /// "completed", "interrupted" or "failed".
    pub fn as_str(self) -> &'static str {
        match self {
            Ending::Completed => "completed",
            Ending::Interrupted => "interrupted",
            Ending::Failed => "failed",
        }
    }
}

/// Counters and timing of a run (`run.json`).
#[derive(Debug, Clone, Default)]
pub struct RunRecord {
    /// Wall time of the whole run [s].
    pub wall: f64,
    /// Wall time of the dynamic phase [s].
    pub dyn_wall: f64,
    /// Dynamic steps.
    pub steps: usize,
    /// Newton iterations of the dynamic steps.
    pub iterations: usize,
    /// Newton iterations of the static solve.
    pub static_iterations: usize,
    /// Newton iterations of the coarser static solves of a mesh sequence, coarsest first
    /// (`analysis.static.mesh_sequence`; empty without one).
    pub static_sequence_iterations: Vec<usize>,
    /// ‖r‖/F_ref of every static Newton iterate.
    pub static_residuals: Vec<f64>,
    /// Load factor of the static state written (1 = full load; below 1 only when the solve
    /// was interrupted during load continuation); `None` without a static solve.
    pub static_load_factor: Option<f64>,
    /// Whether the static state written is a converged equilibrium (false when the solve was
    /// interrupted: step 0 is then the last accepted iterate); `None` without a static solve.
    pub static_converged: Option<bool>,
    /// ‖r‖/F_ref of the static state written; `None` without a static solve.
    pub static_relative_residual: Option<f64>,
    /// Parts and interface DOFs of the static solve's block solve, if one served
    /// (docs/theory/fem.md#block-solve).
    pub static_block_solve: Option<(usize, usize)>,
    /// How it ended.
    pub ending: Ending,
    /// Output frames delivered.
    pub frames: usize,
    /// The last summary row.
    pub last: Option<SummaryRow>,
    /// Extremes of the load columns over every accepted step (crate::extremes), also of an
    /// interrupted or failed run (what it reached).
    pub extremes: Option<Extremes>,
    /// Step halvings and regrowths of the dynamic phase (HHT-α).
    pub step_control: Option<StepControl>,
    /// The reaction of each `[[line]]`'s supported anchor after every accepted dynamic step
    /// [N] (empty for a free anchor), for [`step_ripple_warning`].
    pub anchor_reactions: Vec<Vec<f64>>,
    /// The energy ledger at the end of the dynamic phase (implicit schemes).
    pub energies: Option<Energies>,
    /// Counters of the dynamic phase's linear solves (implicit schemes).
    pub linear_solver: Option<LinearSolverStats>,
}

impl RunRecord {
    /// Keeps the integrator's step control and energy ledger.
    fn keep_ledgers(&mut self, solver: &dyn Stepper) {
        self.step_control = solver.step_control();
        if let Some(c) = self.step_control.as_mut() {
            c.step_ripple = Some(c.step_ripple());
        }
        self.energies = solver.energies();
        self.linear_solver = solver.linear_solver_stats();
    }
}

/// One output step.
#[derive(Debug)]
pub struct Frame<'a> {
    /// The state.
    pub state: &'a State,
    /// Tensions, strains, reactions, hydro forces.
    pub outputs: &'a Outputs,
    /// Wake factor per VTK cell (lines, then panels).
    pub wake: &'a [f64],
    /// The summary row.
    pub row: &'a SummaryRow,
    /// This output step is also a step of the ParaView series (every
    /// `analysis.dynamic.paraview_interval`; [`crate::plan::Plan::paraview_step`]).
    pub paraview: bool,
}

/// What the caller does with a run as it goes. Every method has a do-nothing default.
pub trait Observer {
    /// A diagnostic (the load models' fit ranges, the solvers' warnings).
    fn diagnostic(&mut self, _d: &Diagnostic) {}
    /// The static solve starts.
    fn static_started(&mut self) {}
    /// A static Newton iteration (load factor, iteration, residual); `stop_requested` is
    /// polled right after, so a stop takes effect within one iteration.
    fn static_progress(&mut self, _p: &StaticProgress) {}
    /// The dynamic phase starts and will run to `t_end` [s].
    fn dynamics_started(&mut self, _t_end: f64) {}
    /// A dynamic step was accepted (`steps` so far).
    fn step_done(&mut self, _report: &StepReport, _steps: usize) {}
    /// An output step; an error stops the run.
    fn frame(&mut self, _frame: &Frame<'_>) -> Result<()> {
        Ok(())
    }
    /// True to stop after the current step (polled between steps).
    fn stop_requested(&self) -> bool {
        false
    }
}

/// A scene ready to run: the model, its water loads and the undeformed net volume.
#[derive(Debug)]
pub struct Simulation<'p> {
    prep: &'p Prepared,
    loads: WaterLoads,
    volume0: f64,
    diagnostics: Vec<Diagnostic>,
    /// Floaters and nets checked at every dynamic step (docs/theory/farm.md#design-warnings).
    watch: DynamicWatch,
}

/// The water loads of a prepared scene, and the load models' warnings.
pub fn water_loads(prep: &Prepared, phase: Phase) -> Result<(WaterLoads, Vec<Diagnostic>)> {
    let built = &prep.built;
    let file = || prep.scene.path.display().to_string();
    let mut assembly = LoadAssembly::new(
        built.sea.clone(),
        built.model.n_nodes(),
        built.elements.clone(),
    )
    .map_err(|e| SimError::at(file(), e))?;
    assembly
        .set_cage_wake(built.cage_wake.clone())
        .map_err(|e| SimError::at(file(), e))?;
    let diagnostics = Diagnostic::warnings("hydro/model", "water loads", assembly.warnings());
    Ok((
        WaterLoads::new(assembly, phase, &built.elements),
        diagnostics,
    ))
}

impl<'p> Simulation<'p> {
    /// Sets up the water loads of a prepared scene.
    pub fn new(prep: &'p Prepared) -> Result<Self> {
        if let Some(p) = prep
            .scene
            .prescribed
            .iter()
            .find(|p| p.value.motion == crate::scene::MotionKind::Coupled)
        {
            return Err(SimError::input(format!(
                "{}: line {}: [[prescribed]] nodes = \"{}\": motion = \"coupled\" is driven \
                 step by step from Python (aqua.Coupling); a run needs motion = \"constant\", \
                 \"ramp\", \"sine\" or \"table\"",
                prep.scene.path.display(),
                p.line,
                p.value.nodes
            )));
        }
        let (loads, diagnostics) = water_loads(prep, Phase::Static)?;
        let volume0 = total_volume(&prep.built, prep.built.model.nodes());
        Ok(Self {
            prep,
            loads,
            volume0,
            diagnostics,
            watch: DynamicWatch::new(&prep.built.design),
        })
    }

    /// Warnings of setting up the water loads.
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.diagnostics
    }

    /// Runs the plan to its end, a stop request or a failure; the record says which.
    pub fn run(&mut self, obs: &mut dyn Observer) -> (RunRecord, Result<()>) {
        let t0 = Instant::now();
        let mut record = RunRecord::default();
        let result = self.solve(obs, &mut record);
        record.wall = t0.elapsed().as_secs_f64();
        if result.is_err() && record.ending == Ending::Completed {
            record.ending = Ending::Failed;
        }
        (record, result)
    }

    fn solve(&mut self, obs: &mut dyn Observer, record: &mut RunRecord) -> Result<()> {
        let prep = self.prep;
        let model = &prep.built.model;
        let plan = &prep.plan;
        record.extremes = Some(Extremes::new(&prep.built));
        self.loads.phase = Phase::Static;
        let mut initial: Option<State> = None;
        if plan.kind != AnalysisKind::Dynamic {
            obs.static_started();
            let mut progress = |p: &StaticProgress| {
                obs.static_progress(p);
                if obs.stop_requested() {
                    StaticControl::Stop
                } else {
                    StaticControl::Continue
                }
            };
            // A mesh sequence first, if asked for (docs/theory/fem.md#mesh-sequencing).
            let seq = if plan.statics.mesh_sequence > 0 {
                crate::mesh_sequence::sequenced_start(prep, &mut progress)?
            } else {
                Default::default()
            };
            let stat = static_equilibrium_from(
                model,
                &prep.built.mesh,
                &mut self.loads,
                &plan.statics,
                seq.start.as_deref(),
                &mut progress,
            )?;
            for d in Diagnostic::warnings("fem/statics", "statics", &seq.warnings) {
                obs.diagnostic(&d);
            }
            record.static_sequence_iterations = seq.iterations;
            for d in Diagnostic::warnings("fem/statics", "statics", &stat.report.warnings) {
                obs.diagnostic(&d);
            }
            record.static_iterations = stat.report.iterations;
            record.static_residuals = stat.report.residual_history.clone();
            record.static_load_factor = Some(stat.report.load_factor);
            record.static_converged = Some(!stat.report.interrupted);
            record.static_relative_residual = Some(stat.report.relative_residual);
            record.static_block_solve = stat.report.block_solve;
            let poses = stat.body_poses(model);
            self.observe(record, &stat.state, &stat.outputs, &poses);
            if let Some(e) = record.extremes.as_mut() {
                // The equilibrium is its own load case: the first dynamic step replaces it.
                e.until_next();
            }
            self.frame(
                obs,
                record,
                &stat.state,
                &stat.outputs,
                &poses,
                stat.report.iterations,
                0.0,
            )?;
            if stat.report.interrupted {
                // The last accepted (not converged) state is step 0 of the output.
                record.ending = Ending::Interrupted;
                return Ok(());
            }
            // Design checks of the equilibrium (docs/theory/farm.md#design-warnings).
            for d in prep.built.design.at_equilibrium(&stat.state.x) {
                obs.diagnostic(&d);
            }
            initial = Some(stat.state);
        }
        let Some(integrator) = &plan.dynamics else {
            return Ok(());
        };
        self.loads.phase = Phase::Dynamic;
        let t_dyn = Instant::now();
        let result = match start_integrator(model, integrator, initial.as_ref(), &mut self.loads) {
            Ok(mut solver) => {
                for d in Diagnostic::warnings("fem/explicit", "dynamics", &solver.warnings()) {
                    obs.diagnostic(&d);
                }
                obs.dynamics_started(plan.t_end);
                let r = self.drive(solver.as_mut(), obs, record, initial.is_none());
                for d in self.watch.diagnostics(&prep.built.design) {
                    obs.diagnostic(&d);
                }
                if let Some(d) = energy_guard_warning(integrator, record) {
                    obs.diagnostic(&d);
                }
                if let Some(d) = time_step_warning(record, model) {
                    obs.diagnostic(&d);
                }
                if let Some(d) = step_ripple_warning(integrator, record, model, &prep.built) {
                    obs.diagnostic(&d);
                }
                if let Some(d) = seabed_contact_warning(integrator, record, model) {
                    obs.diagnostic(&d);
                }
                if let Some(d) = extremes_warning(record, &prep.built.group_names) {
                    obs.diagnostic(&d);
                }
                if let Some(d) = snap_warning(record, model) {
                    obs.diagnostic(&d);
                }
                if let Some(d) = peak_snap_warning(record, model) {
                    obs.diagnostic(&d);
                }
                if let Some(d) = support_snap_warning(record, &prep.built) {
                    obs.diagnostic(&d);
                }
                if let Some(d) = snap_ringing_warning(integrator, record, model) {
                    obs.diagnostic(&d);
                }
                r
            }
            Err(e) => Err(e),
        };
        record.dyn_wall = t_dyn.elapsed().as_secs_f64();
        result
    }

    /// Steps to the end (or a stop request), delivering every output step. A failed step
    /// ends the loop with its error; the frames already delivered stay.
    fn drive(
        &mut self,
        solver: &mut dyn Stepper,
        obs: &mut dyn Observer,
        record: &mut RunRecord,
        write_initial: bool,
    ) -> Result<()> {
        if write_initial {
            let poses = solver.body_poses();
            self.observe(record, solver.state(), solver.outputs(), &poses);
            self.frame(
                obs,
                record,
                solver.state(),
                solver.outputs(),
                &poses,
                0,
                0.0,
            )?;
        }
        while !solver.is_finished() {
            if obs.stop_requested() {
                record.ending = Ending::Interrupted;
                record.keep_ledgers(solver);
                return Ok(());
            }
            let report = solver.step(&mut self.loads).map_err(|e| {
                record.keep_ledgers(solver);
                SimError::Dynamic(Box::new(e))
            })?;
            record.steps += 1;
            record.iterations += report.iterations;
            let built = &self.prep.built;
            let t = solver.state().t;
            self.watch
                .step(&built.design, &solver.state().x, t, |x, y| {
                    built.sea.elevation(x, y, t, Phase::Dynamic)
                });
            let poses = solver.body_poses();
            self.observe(record, solver.state(), solver.outputs(), &poses);
            obs.step_done(&report, record.steps);
            if report.output_time {
                self.frame(
                    obs,
                    record,
                    solver.state(),
                    solver.outputs(),
                    &poses,
                    report.iterations,
                    report.dt,
                )?;
            }
        }
        record.keep_ledgers(solver);
        Ok(())
    }

    /// Adds an accepted state to the run's extremes (every step, not only output steps).
    fn observe(
        &self,
        record: &mut RunRecord,
        state: &State,
        outputs: &Outputs,
        poses: &[BodyPose],
    ) {
        if let Some(e) = record.extremes.as_mut() {
            e.observe(&self.prep.built, &self.loads, state, outputs, poses);
        }
        // The supported anchors' reactions over every dynamic step, for their step ripple
        // (docs/theory/fem.md#step-ripple-indicator).
        if self.loads.phase == Phase::Dynamic {
            let ends = &self.prep.built.line_ends;
            record.anchor_reactions.resize(ends.len(), Vec::new());
            for (series, l) in record.anchor_reactions.iter_mut().zip(ends) {
                if l.supported[0] {
                    let r = outputs.reaction[l.anchor];
                    series.push((r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt());
                }
            }
        }
    }

    /// Post-processes a state and hands it to the observer.
    fn frame(
        &self,
        obs: &mut dyn Observer,
        record: &mut RunRecord,
        state: &State,
        outputs: &Outputs,
        poses: &[BodyPose],
        iterations: usize,
        dt: f64,
    ) -> Result<()> {
        let built = &self.prep.built;
        let (net_force, wake) = net_force_and_wake(built, &self.loads, state);
        let row = SummaryRow::of_state(
            built,
            state,
            outputs,
            poses,
            net_force,
            self.volume0,
            iterations,
            dt,
        );
        obs.frame(&Frame {
            state,
            outputs,
            wake: &wake,
            row: &row,
            paraview: self.prep.plan.paraview_step(record.frames),
        })?;
        record.frames += 1;
        record.last = Some(row);
        Ok(())
    }
}

/// Estimated peak-tension error from the time step above which a run warns (1 %).
pub const PEAK_TENSION_ERROR_WARNING: f64 = 0.01;

/// A warning when the peak element tension changed so much within single steps that its
/// extremes are under-resolved: the estimate of [`StepControl::peak_tension_resolution`] above
/// 1 % (docs/theory/fem.md#time-step-error-indicator). It names the element group whose member
/// carried the peak at that step, so that a snap of a slack line is not read as an error of
/// the loaded lines.
fn time_step_warning(record: &RunRecord, model: &Model) -> Option<Diagnostic> {
    let res = record.step_control.as_ref()?.peak_tension_resolution();
    if res.error <= PEAK_TENSION_ERROR_WARNING {
        return None;
    }
    let group = res
        .element
        .and_then(|e| model.groups().iter().find(|g| g.elements.contains(&e)))
        .map(|g| g.name.as_str());
    let (within, snap) = match group {
        Some(g) => (
            format!(", in `{g}`"),
            format!(
                " (if `{g}` is a slack member that snaps taut within single steps, its peak may \
                 not converge with `dt` at all: docs/theory/fem.md#choice-of-the-default-scheme)"
            ),
        ),
        None => (String::new(), String::new()),
    };
    Some(Diagnostic::warning(
        "fem/time-step",
        "dynamics",
        format!(
            "near its largest values the peak tension changed by up to {:.3} N within one step \
             (range {:.3} … {:.3} N){within}: \
             tension extremes at this time step are uncertain by about {:.1} % \
             (docs/theory/fem.md#time-step-error-indicator); halve `dt` or compare with \
             `aqua study --vary dt=...`{snap}",
            res.jump,
            res.range[0],
            res.range[1],
            100.0 * res.error
        ),
    ))
}

/// Step-to-step ripple near the top of a tension series (RMS, relative to its largest value)
/// above which a run warns (docs/theory/fem.md#step-ripple-indicator).
pub const STEP_RIPPLE_WARNING: f64 = 0.01;

/// A warning when the peak element tension or a supported anchor's reaction carries a
/// step-to-step oscillation near its top: [`aqua_fem::StepRipple::ripple`] of the peak tension
/// or of an anchor's reaction series above [`STEP_RIPPLE_WARNING`]
/// (docs/theory/fem.md#step-ripple-indicator). It names the element group whose member carried
/// the peak at the largest alternation, and the line of the anchor with the largest ripple.
fn step_ripple_warning(
    integrator: &Integrator,
    record: &RunRecord,
    model: &Model,
    built: &crate::build::Built,
) -> Option<Diagnostic> {
    let scheme = match integrator {
        Integrator::Hht(s) if s.midpoint => format!("the midpoint rule with θ = {}", s.theta),
        Integrator::Hht(s) => format!("HHT-α (α = {})", s.alpha),
        _ => "this scheme".to_string(),
    };
    let mut what = Vec::new();
    if let Some(r) = record
        .step_control
        .as_ref()
        .and_then(|c| c.step_ripple)
        .filter(|r| r.ripple > STEP_RIPPLE_WARNING)
    {
        let within = r
            .element
            .and_then(|e| model.groups().iter().find(|g| g.elements.contains(&e)))
            .map_or_else(String::new, |g| format!(", in `{}`", g.name));
        what.push(format!(
            "the largest tension carries one of {:.1} % RMS (up to {:.1} % over {} steps \
             near its top{within})",
            100.0 * r.ripple,
            100.0 * r.largest,
            r.windows
        ));
    }
    let anchor = record
        .anchor_reactions
        .iter()
        .zip(&built.line_ends)
        .map(|(series, l)| (aqua_fem::dynamics::step_ripple(series, &[]), &l.name))
        .filter(|(r, _)| r.ripple > STEP_RIPPLE_WARNING)
        .max_by(|a, b| a.0.ripple.total_cmp(&b.0.ripple));
    if let Some((r, name)) = anchor {
        what.push(format!(
            "the anchor reaction of `{name}` carries one of {:.1} % RMS (up to {:.1} % over {} steps \
             near its top)",
            100.0 * r.ripple,
            100.0 * r.largest,
            r.windows
        ));
    }
    if what.is_empty() {
        return None;
    }
    Some(Diagnostic::warning(
        "fem/step-ripple",
        "dynamics",
        format!(
            "tension extremes at this time step are uncertain by about the step-to-step \
             oscillation they carry near their top with {scheme}: {} \
             (docs/theory/fem.md#step-ripple-indicator); the extremes over every step may lie \
             several times that above a converged run; HHT-α damps the midpoint rule's, and \
             where the member named is slack and snaps taut within single steps its peak may \
             not converge with `dt` at all (docs/theory/fem.md#choice-of-the-default-scheme)",
            what.join(", and ")
        ),
    ))
}

/// A warning when landings and lift-offs on the seabed excite its contact at a frequency the
/// scheme damps at this step: [`aqua_fem::ContactResolution::loss`] above
/// [`aqua_fem::CONTACT_LOSS_WARNING`] (docs/theory/fem.md#seabed-contact-resolution).
/// It names the element group of the node with the largest loss.
fn seabed_contact_warning(
    integrator: &Integrator,
    record: &RunRecord,
    model: &Model,
) -> Option<Diagnostic> {
    let c = record.step_control.as_ref()?.seabed_contact?;
    if c.impacts == 0 || c.loss <= aqua_fem::CONTACT_LOSS_WARNING {
        return None;
    }
    let node = match model
        .elements()
        .iter()
        .position(|e| e.a == c.node || e.b == c.node)
        .and_then(|e| model.groups().iter().find(|g| g.elements.contains(&e)))
    {
        Some(g) => format!("node {} of `{}`", c.node, g.name),
        None => format!("node {}", c.node),
    };
    let scheme = match integrator {
        Integrator::Hht(s) if s.midpoint => format!("the midpoint rule with θ = {}", s.theta),
        Integrator::Hht(s) => format!("HHT-α (α = {})", s.alpha),
        _ => return None,
    };
    Some(Diagnostic::warning(
        "fem/seabed-contact",
        "dynamics",
        format!(
            "anchor and touchdown tension extremes may be up to {:.1} % low: {} landings and \
             lift-offs on the seabed (e.g. {node}) excite its contact at ω_c = {:.0} rad/s, \
             which {scheme} does not resolve at dt = {} s (ω_c·dt = {:.2}: it removes that \
             share of a contact oscillation per contact period; \
             docs/theory/fem.md#seabed-contact-resolution); dt ≤ {:.2e} s resolves it, \
             and `scheme = \"midpoint\"` with θ = ½ does not damp it (its time-step \
             check then judges the step)",
            100.0 * c.loss,
            c.impacts,
            c.omega,
            c.dt,
            c.omega * c.dt,
            c.resolving_dt,
        ),
    ))
}

/// A warning when a slack element snapped taut within a single step that does not resolve the
/// snap, and the snap's estimated tension lies above the largest tension the run computed:
/// [`aqua_fem::SnapResolution::excess`] above [`aqua_fem::SNAP_EXCESS_WARNING`]
/// (docs/theory/fem.md#snap-resolution). It names the element group that snapped.
fn snap_warning(record: &RunRecord, model: &Model) -> Option<Diagnostic> {
    let s = record.step_control.as_ref()?.snaps.as_ref()?;
    if s.excess <= aqua_fem::SNAP_EXCESS_WARNING {
        return None;
    }
    let group = group_label(model, s.group);
    Some(Diagnostic::warning(
        "fem/snap",
        "dynamics",
        format!(
            "the largest tension of this run ({:.0} N over every step) is too low, and so may \
             be the end loads of the line that snapped: {} times a slack element snapped taut \
             within a single step; the largest, element {}{group} at t = {:.3} s, closing at \
             {:.3} m/s, peaks near {:.0} N (+{:.0} %) within {:.1e} s, inside one step of {} s \
             (docs/theory/fem.md#snap-resolution); dt ≤ {:.1e} s resolves such snaps",
            s.computed,
            s.snaps,
            s.element,
            s.t,
            s.speed,
            s.estimate,
            100.0 * s.excess,
            s.resolving_dt / aqua_fem::RESOLVED_PHASE * std::f64::consts::PI,
            s.dt,
            s.resolving_dt,
        ),
    ))
}

/// A warning when the run's largest tension was reached at an unresolved snap of its element:
/// [`aqua_fem::SnapResolution::peak`] (docs/theory/fem.md#snap-resolution). It names the
/// element and its group.
fn peak_snap_warning(record: &RunRecord, model: &Model) -> Option<Diagnostic> {
    let s = record.step_control.as_ref()?.snaps.as_ref()?.peak?;
    Some(Diagnostic::warning(
        "fem/snap",
        "dynamics",
        format!(
            "the largest tension of this run is not resolved at this time step: {:.0} N over \
             every step, in element {}{} at t = {:.3} s, was reached as that element snapped \
             taut {}",
            s.tension,
            s.element,
            group_label(model, s.group),
            s.t,
            unresolved_snap(&s),
        ),
    ))
}

/// A warning when the largest tension of an element with one end held (an anchor's, or a
/// prescribed fairlead's) was reached at an unresolved snap of its own:
/// [`aqua_fem::SnapResolution::support`] (docs/theory/fem.md#snap-resolution), for the supports
/// whose reactions the outputs report, the supported ends of `[[line]]`s, each named.
fn support_snap_warning(record: &RunRecord, built: &crate::build::Built) -> Option<Diagnostic> {
    let snaps = record.step_control.as_ref()?.snaps.as_ref()?;
    // The supports whose reactions are reported: the supported ends of `[[line]]`s.
    let name = |s: &aqua_fem::SnapExtreme| {
        built.line_ends.iter().find_map(|l| {
            if l.anchor_element == s.element && l.supported[0] {
                Some(format!("the anchor reaction of `{}`", l.name))
            } else if l.fairlead_element == s.element && l.supported[1] {
                Some(format!("the fairlead reaction of `{}`", l.name))
            } else {
                None
            }
        })
    };
    let named: Vec<(String, &aqua_fem::SnapExtreme)> = snaps
        .support
        .iter()
        .filter_map(|s| name(s).map(|n| (n, s)))
        .collect();
    let (_, s) = named.first()?;
    let what: Vec<&str> = named.iter().map(|(n, _)| n.as_str()).collect();
    let (verb, others) = match what.len() {
        1 => ("is", String::new()),
        n => ("are", format!(" (the largest of the {n})")),
    };
    Some(Diagnostic::warning(
        "fem/snap",
        "dynamics",
        format!(
            "{} {verb} not resolved at this time step: each largest value over every step was \
             reached as the element at the support snapped taut{others}, {:.0} N at t = {:.3} s \
             {}",
            what.join(", "),
            s.tension,
            s.t,
            unresolved_snap(s),
        ),
    ))
}

/// Largest unresolved snap crest T* of the group that carries the run's largest tension, as a
/// share of that tension, above which a run of the energy-conserving midpoint rule warns that
/// its extremes over every step ring (docs/theory/fem.md#snap-ringing): 10 %, between the
/// right cells of the stability matrix (at most 9 %) and its wrong ones (23–36 %).
pub const SNAP_RINGING_WARNING: f64 = 0.1;

/// A warning when the midpoint rule with θ = ½ runs a structure whose group of the largest
/// tension snaps taut within single steps with crests of at least [`SNAP_RINGING_WARNING`] of
/// that tension: the rule keeps each snap's energy in the unresolved axial modes, which ring on
/// the tensions from step to step (docs/theory/fem.md#snap-ringing).
fn snap_ringing_warning(
    integrator: &Integrator,
    record: &RunRecord,
    model: &Model,
) -> Option<Diagnostic> {
    let Integrator::Hht(s) = integrator else {
        return None;
    };
    if !s.midpoint || s.theta != 0.5 {
        return None;
    }
    let snaps = record.step_control.as_ref()?.snaps.as_ref()?;
    let g = snaps.peak_group?;
    // A run whose tensions were never positive has no extreme to ring on.
    if snaps.computed <= 0.0 {
        return None;
    }
    let share = g.estimate / snaps.computed;
    if share.is_nan() || share <= SNAP_RINGING_WARNING {
        return None;
    }
    Some(Diagnostic::warning(
        "fem/snap",
        "dynamics",
        format!(
            "the largest tension of this run ({} N over every step{}) may lie several per \
             cent above a converged run: that group's elements snapped taut {} times within \
             single steps that do not resolve them, with crests up to {} N ({:.0} % of it), \
             and the midpoint rule with θ = ½ keeps each snap's energy in their unresolved axial \
             modes, which ring on the tensions from step to step (docs/theory/fem.md#snap-ringing); \
             HHT-α or θ > ½ damps them",
            newtons(snaps.computed),
            group_label(model, g.group),
            g.snaps,
            newtons(g.estimate),
            100.0 * share,
        ),
    ))
}

/// A force for a message [N]: whole newtons from 100 N, three decimals below.
fn newtons(f: f64) -> String {
    if f.abs() >= 100.0 {
        format!("{f:.0}")
    } else {
        format!("{f:.3}")
    }
}

/// The words shared by the warnings of an extreme reached at an unresolved snap: the snap's
/// step, closing speed and resolving step.
fn unresolved_snap(s: &aqua_fem::SnapExtreme) -> String {
    format!(
        "within a single step of {} s, closing at {:.3} m/s, which the step samples too coarsely \
         to say how high the snap's crest is: the computed extreme may lie well above or below \
         it (docs/theory/fem.md#snap-resolution); dt ≤ {:.1e} s resolves such snaps",
        s.dt, s.speed, s.resolving_dt
    )
}

/// " of `group`" for element group `g` of `model` (empty if there is no such group).
fn group_label(model: &Model, g: usize) -> String {
    model
        .groups()
        .get(g)
        .map_or_else(String::new, |g| format!(" of `{}`", g.name))
}

/// A warning when `extreme_tolerance` could not be met: steps accepted at `dt_min` with a
/// tension crest sampled more coarsely than the tolerance (docs/theory/fem.md#extremes-to-a-tolerance).
fn extremes_warning(record: &RunRecord, group_names: &[String]) -> Option<Diagnostic> {
    let r = record.step_control.as_ref()?.extremes.as_ref()?;
    if r.unresolved_steps == 0 {
        return None;
    }
    let group = r
        .worst_group
        .and_then(|g| group_names.get(g))
        .map_or("?", String::as_str);
    Some(Diagnostic::warning(
        "fem/extremes-unresolved",
        "dynamics",
        format!(
            "extreme_tolerance {:.2} % was not met in {} steps taken at dt_min: the largest \
             tension of `{group}` is uncertain by about {:.1} %; lower `dt_min` or accept a \
             larger tolerance",
            100.0 * r.tolerance,
            r.unresolved_steps,
            100.0 * r.worst_unresolved
        ),
    ))
}

/// A warning when HHT-α's energy guard rejected many steps: on slack-dominated nets at small
/// steps HHT's accepted answers were measured wrong by several times (a flexible net panel's peak
/// tension 6–9 N against 1.5 N from RK4 and the midpoint rule at Δt = 1–5 ms), while the
/// energy-consistent midpoint rule needed no such rejections (docs/theory/fem.md#stability-matrix).
fn energy_guard_warning(integrator: &Integrator, record: &RunRecord) -> Option<Diagnostic> {
    let Integrator::Hht(settings) = integrator else {
        return None;
    };
    if settings.midpoint {
        return None;
    }
    let control = record.step_control.as_ref()?;
    let rejected: usize = control
        .reasons
        .iter()
        .filter(|(why, _)| *why == aqua_fem::FailureKind::EnergyCreated)
        .map(|(_, n)| n)
        .sum();
    if rejected < 20 || (rejected as f64) < 0.02 * record.steps as f64 {
        return None;
    }
    Some(Diagnostic::warning(
        "fem/energy-guard",
        "dynamics",
        format!(
            "HHT-α's energy guard rejected {rejected} steps in {} accepted: on slack nets and \
             lines this time step gives unreliable extremes (docs/theory/fem.md#stability-matrix); \
             rerun with `scheme = \"midpoint\"` (energy-consistent) or compare with \
             `aqua study --vary dt=...`",
            record.steps
        ),
    ))
}
