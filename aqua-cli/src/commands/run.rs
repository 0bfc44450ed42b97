//! `aqua run scene.toml --out DIR`: static and/or dynamic solve with a progress bar, writing
//! `DIR/<scene>.pvd` + `.vtu` per output step, `DIR/summary.csv` and `DIR/run.json`.
//!
//! Ctrl-C or a failed step stops cleanly: every step already written stays readable, the
//! `.pvd` lists exactly those steps, `run.json` records why the run ended, and the exit code is
//! non-zero (1 for a failed solve, 130 for an interruption).

use crate::build::{Built, build};
use crate::output::{RunOutput, SummaryRow};
use crate::provider::WaterLoads;
use crate::scene::{AnalysisKind, MassSpec, Scene, Scheme, read_scene};
use crate::{InputError, interrupted};
use anyhow::Context;
use aqua_env::Phase;
use aqua_fem::{
    DynamicSettings, DynamicSolver, ExplicitScheme, ExplicitSettings, ExplicitSolver, MassMatrix,
    Outputs, State, StaticControl, StaticProgress, StaticSettings, StepReport,
    solve_static_observed,
};
use aqua_hydro::assembly::{ElementOutput, LoadAssembly};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::time::Instant;

/// Flags of `aqua run`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Output directory (created if missing).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ending {
    /// Reached the end.
    Completed,
    /// Stopped by Ctrl-C.
    Interrupted,
    /// A solve failed.
    Failed,
}

/// Everything `run.json` reports.
#[derive(Debug)]
struct Record {
    wall: f64,
    dyn_wall: f64,
    steps: usize,
    iterations: usize,
    static_iterations: usize,
    /// ‖r‖/F_ref of every static Newton iterate.
    static_residuals: Vec<f64>,
    ending: Ending,
    error: Option<String>,
}

/// Static settings from the scene.
pub fn static_settings(scene: &Scene) -> StaticSettings {
    let s = &scene.analysis.statics;
    StaticSettings {
        tol: s.tol,
        max_iter: s.max_iter,
        load_steps: s.load_steps,
        min_load_step: s.min_load_step,
        stabilisation: s.stabilisation,
        line_search: s.line_search,
        ..StaticSettings::default()
    }
}

/// The HHT α the scene asks for (default 0.3), validated.
pub fn alpha(scene: &Scene) -> Result<f64, InputError> {
    let d = &scene.analysis.dynamic;
    let file = scene.path.display();
    match (d.alpha, d.rho_inf) {
        (Some(_), Some(_)) => Err(InputError::new(format!(
            "{file}: [analysis.dynamic]: give either alpha or rho_inf, not both"
        ))),
        (Some(a), None) => {
            if (0.0..=1.0 / 3.0).contains(&a) {
                Ok(a)
            } else {
                Err(InputError::new(format!(
                    "{file}: analysis.dynamic.alpha = {a}: valid is 0 <= alpha <= 1/3 (our convention; \
                     the original HHT/Code_Aster ALPHA is -alpha, in [-1/3, 0])"
                )))
            }
        }
        (None, Some(r)) => {
            if (0.5..=1.0).contains(&r) {
                Ok((1.0 - r) / (1.0 + r))
            } else {
                Err(InputError::new(format!(
                    "{file}: analysis.dynamic.rho_inf = {r}: valid is 0.5 <= rho_inf <= 1"
                )))
            }
        }
        (None, None) => Ok(0.3),
    }
}

/// The nominal step, output interval and end time, validated.
pub fn timing(scene: &Scene) -> Result<(f64, f64, f64), InputError> {
    let d = &scene.analysis.dynamic;
    let file = scene.path.display();
    if !(d.t_end > 0.0 && d.t_end.is_finite()) {
        return Err(InputError::new(format!(
            "{file}: analysis.dynamic.t_end = {}: a duration > 0 in s",
            d.t_end
        )));
    }
    if d.reuse_factor == 0 {
        return Err(InputError::new(format!(
            "{file}: analysis.dynamic.reuse_factor = 0: an integer >= 1 (1 = full Newton)"
        )));
    }
    let dt = d.dt.unwrap_or(0.1);
    if !(dt > 0.0 && dt <= d.t_end) {
        return Err(InputError::new(format!(
            "{file}: analysis.dynamic.dt = {dt}: a time step > 0 s and <= t_end ({} s)",
            d.t_end
        )));
    }
    let out = d.output_interval.unwrap_or(dt.max(d.t_end / 200.0));
    if !(out > 0.0) {
        return Err(InputError::new(format!(
            "{file}: analysis.dynamic.output_interval = {out}: an interval > 0 in s"
        )));
    }
    Ok((dt, out.max(dt), d.t_end))
}

/// Net force and wake factors at an output step (net panels and twines only).
fn net_force_and_wake(
    built: &Built,
    loads: &LoadAssembly,
    x: &[[f64; 3]],
    v: &[[f64; 3]],
) -> ([f64; 3], Vec<f64>) {
    let mut f = [0.0; 3];
    let mut out = ElementOutput::default();
    let n_panels = loads.n_panels();
    let twines: Vec<bool> = built.elements.lines.iter().map(|l| l.net_twine).collect();
    let mut xs = [[0.0; 3]; 4];
    let mut vs = [[0.0; 3]; 4];
    for e in 0..(n_panels + loads.n_lines()) {
        if e >= n_panels && !twines[e - n_panels] {
            continue;
        }
        let nodes = loads.element_nodes(e);
        for (i, &n) in nodes.iter().enumerate() {
            xs[i] = x[n];
            vs[i] = v[n];
        }
        let k = nodes.len();
        loads.element_load(e, &xs[..k], &vs[..k], aqua_hydro::Want::default(), &mut out);
        for node_force in &out.force[..k] {
            for c in 0..3 {
                f[c] += node_force[c];
            }
        }
    }
    // Wake factor per VTK cell: lines first, then panels, as the mesh orders them.
    let mesh = &built.mesh;
    let mut wake = vec![1.0; mesh.lines.len() + mesh.panels.len()];
    let cells = loads.wake();
    let mut k = 0;
    for (pi, loaded) in built.panel_loaded.iter().enumerate() {
        if *loaded {
            if let Some(c) = cells.get(k) {
                wake[mesh.lines.len() + pi] = c.factor;
            }
            k += 1;
        }
    }
    for (e, c) in cells
        .iter()
        .skip(n_panels)
        .take(mesh.lines.len())
        .enumerate()
    {
        wake[e] = c.factor;
    }
    (f, wake)
}

fn write_step(
    outw: &mut RunOutput,
    built: &Built,
    loads: &LoadAssembly,
    state: &State,
    outputs: &Outputs,
    iterations: usize,
    dt: f64,
) -> anyhow::Result<SummaryRow> {
    let (f, wake) = net_force_and_wake(built, loads, &state.x, &state.v);
    outw.write_step(built, state, outputs, f, &wake, iterations, dt)
}

/// Run `aqua run`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let scene = read_scene(&a.scene)?;
    let t0 = Instant::now();
    let built = build(&scene)?;
    for n in &built.notices {
        eprintln!("warning: {n}");
    }
    let kind = scene.analysis.kind;
    let (dt, output_interval, t_end) = if kind == AnalysisKind::Static {
        (0.0, 0.0, 0.0)
    } else {
        timing(&scene)?
    };
    let alpha = if kind == AnalysisKind::Static {
        0.0
    } else {
        alpha(&scene)?
    };
    let assembly = LoadAssembly::new(
        built.sea.clone(),
        built.model.n_nodes(),
        built.elements.clone(),
    )
    .map_err(|e| InputError::new(format!("{}: {e}", scene.path.display())))?;
    for w in assembly.warnings() {
        eprintln!("warning: {w}");
    }
    let mut outw = RunOutput::create(&a.out, &scene.name, &built)?;
    if built.sea.has_waves() && kind != AnalysisKind::Static {
        // The component table makes the run reproducible exactly (environment.md §1).
        crate::commands::waves::write_component_table(
            &built.sea,
            &a.out.join("wave_components.csv"),
        )?;
    }
    let mut record = Record {
        wall: 0.0,
        dyn_wall: 0.0,
        steps: 0,
        iterations: 0,
        static_iterations: 0,
        static_residuals: Vec::new(),
        ending: Ending::Completed,
        error: None,
    };
    let result = solve(
        &scene,
        &built,
        assembly,
        &mut outw,
        &mut record,
        dt,
        output_interval,
        t_end,
        alpha,
        a.quiet,
    );
    record.wall = t0.elapsed().as_secs_f64();
    if let Err(e) = &result {
        record.error = Some(format!("{e:#}"));
        if record.ending == Ending::Completed {
            record.ending = Ending::Failed;
        }
    }
    let json = serde_json::json!({
        "scene": &scene,
        "resolved": {
            "mesh": built.mesh.summary(),
            "sea": &built.sea_summary,
            "alpha": alpha,
            "dt": dt,
            "output_interval": output_interval,
            "t_end": t_end,
            "structural_groups": &built.group_names,
        },
        "status": match record.ending {
            Ending::Completed => "completed",
            Ending::Interrupted => "interrupted",
            Ending::Failed => "failed",
        },
        "error": record.error,
        "final": outw.last,
        "output_steps": outw.steps_written,
        "pvd": outw.pvd_path(),
        "wall_time_s": record.wall,
        "dynamic_wall_time_s": record.dyn_wall,
        "steps": record.steps,
        "newton_iterations": record.iterations,
        "static_newton_iterations": record.static_iterations,
        "static_residual_history": &record.static_residuals,
        "time_per_step_s": if record.steps > 0 { record.dyn_wall / record.steps as f64 } else { 0.0 },
    });
    outw.write_json(&json)?;
    match record.ending {
        Ending::Completed => {
            if !a.quiet {
                print_final(&outw, &record);
            }
            result
        }
        Ending::Interrupted => {
            eprintln!(
                "interrupted at t = {} s: {} output steps kept in {}",
                outw.last.as_ref().map(|r| r.t).unwrap_or(0.0),
                outw.steps_written,
                outw.pvd_path().display()
            );
            std::process::exit(130);
        }
        Ending::Failed => result.with_context(|| {
            format!(
                "the run stopped; {} output steps written before the failure are kept in {}",
                outw.steps_written,
                outw.pvd_path().display()
            )
        }),
    }
}

fn print_final(outw: &RunOutput, r: &Record) {
    if let Some(last) = &outw.last {
        println!(
            "done: t = {} s, net force = [{:.1}, {:.1}, {:.1}] N, reaction = [{:.1}, {:.1}, {:.1}] N, volume ratio {:.4}",
            last.t,
            last.net_force[0],
            last.net_force[1],
            last.net_force[2],
            last.reaction[0],
            last.reaction[1],
            last.reaction[2],
            last.volume_ratio
        );
    }
    println!(
        "{} output steps in {}; wall time {:.2} s{}",
        outw.steps_written,
        outw.dir().display(),
        r.wall,
        if r.steps > 0 {
            format!(
                ", {} dynamic steps, {:.2} ms per step, {:.2} Newton iterations per step",
                r.steps,
                1e3 * r.dyn_wall / r.steps as f64,
                r.iterations as f64 / r.steps as f64
            )
        } else {
            String::new()
        }
    );
}

#[allow(clippy::too_many_arguments)]
fn solve(
    scene: &Scene,
    built: &Built,
    assembly: LoadAssembly,
    outw: &mut RunOutput,
    record: &mut Record,
    dt: f64,
    output_interval: f64,
    t_end: f64,
    alpha: f64,
    quiet: bool,
) -> anyhow::Result<()> {
    let model = &built.model;
    let kind = scene.analysis.kind;
    let mut loads = WaterLoads::new(assembly, Phase::Static, &built.elements);
    let mut initial: Option<State> = None;
    if kind != AnalysisKind::Dynamic {
        let sbar = if quiet {
            ProgressBar::hidden()
        } else {
            let b = ProgressBar::new_spinner();
            b.set_style(
                ProgressStyle::with_template("{spinner} [{elapsed_precise}] statics: {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            );
            b
        };
        let mut observer = |p: &StaticProgress| {
            sbar.set_message(format!(
                "load factor {:.3}, pseudo-step {}, iteration {}, residual {:.2e}·F_ref",
                p.load_factor, p.pseudo_steps, p.iteration, p.relative_residual
            ));
            sbar.tick();
            if interrupted() {
                StaticControl::Stop
            } else {
                StaticControl::Continue
            }
        };
        let stat = solve_static_observed(model, &mut loads, &static_settings(scene), &mut observer);
        sbar.finish_and_clear();
        let stat = stat.context("static equilibrium failed")?;
        for w in &stat.report.warnings {
            eprintln!("warning: {w}");
        }
        record.static_iterations = stat.report.iterations;
        record.static_residuals = stat.report.residual_history.clone();
        write_step(
            outw,
            built,
            &loads.assembly,
            &stat.state,
            &stat.outputs,
            stat.report.iterations,
            0.0,
        )?;
        if stat.report.interrupted {
            // The last accepted (not converged) state is step 0 of the output.
            record.ending = Ending::Interrupted;
            return Ok(());
        }
        initial = Some(stat.state);
    }
    if kind == AnalysisKind::Static {
        return Ok(());
    }
    loads.phase = Phase::Dynamic;
    let d = &scene.analysis.dynamic;
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new((t_end * 1000.0).round() as u64);
        b.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} t = {msg} (ETA {eta})",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    };
    let t_dyn = Instant::now();
    let result = match d.scheme {
        Scheme::Hht => {
            let mut s = DynamicSettings::new(dt, t_end);
            s.alpha = alpha;
            s.dt_min = d.dt_min;
            s.tol = d.tol;
            s.max_iter = d.max_iter;
            s.mass_matrix = match d.mass_matrix {
                MassSpec::Lumped => MassMatrix::Lumped,
                MassSpec::Consistent => MassMatrix::Consistent,
            };
            s.rayleigh = d.rayleigh;
            s.output_interval = Some(output_interval);
            s.max_strain = d.max_strain;
            s.reuse_factor = d.reuse_factor;
            let mut solver = DynamicSolver::new(model, s, initial.as_ref(), &mut loads)
                .context("starting the dynamic solver")?;
            drive(
                &mut solver,
                &mut loads,
                outw,
                built,
                record,
                &bar,
                initial.is_none(),
            )
        }
        Scheme::SemiImplicitEuler | Scheme::Rk4 => {
            let mut s = ExplicitSettings::new(t_end);
            s.scheme = if d.scheme == Scheme::Rk4 {
                ExplicitScheme::Rk4
            } else {
                ExplicitScheme::SemiImplicitEuler
            };
            s.cfl = d.cfl;
            s.dt = d.dt;
            s.dt_fixed = d.dt_fixed;
            s.output_interval = Some(output_interval);
            let mut solver = ExplicitSolver::new(model, s, initial.as_ref(), &mut loads)
                .context("starting the explicit solver")?;
            for w in solver.warnings() {
                eprintln!("warning: {w}");
            }
            drive(
                &mut solver,
                &mut loads,
                outw,
                built,
                record,
                &bar,
                initial.is_none(),
            )
        }
    };
    record.dyn_wall = t_dyn.elapsed().as_secs_f64();
    bar.finish_and_clear();
    result.context("dynamic run failed")
}

/// What the run loop needs of a time integrator (HHT-α or explicit).
trait Stepper {
    fn is_finished(&self) -> bool;
    fn step(&mut self, loads: &mut WaterLoads) -> aqua_fem::Result<StepReport>;
    fn state(&self) -> &State;
    fn outputs(&self) -> &Outputs;
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
}

/// Steps to the end (or a stop request), writing every output step. A failed step ends the
/// loop with its error; the steps already written stay.
fn drive<S: Stepper>(
    solver: &mut S,
    loads: &mut WaterLoads,
    outw: &mut RunOutput,
    built: &Built,
    record: &mut Record,
    bar: &ProgressBar,
    write_initial: bool,
) -> anyhow::Result<()> {
    if write_initial {
        write_step(
            outw,
            built,
            &loads.assembly,
            solver.state(),
            solver.outputs(),
            0,
            0.0,
        )?;
    }
    while !solver.is_finished() {
        if interrupted() {
            record.ending = Ending::Interrupted;
            return Ok(());
        }
        let report = solver.step(loads)?;
        record.steps += 1;
        record.iterations += report.iterations;
        bar.set_position((report.t * 1000.0).round() as u64);
        bar.set_message(format!("{:.2} s, {} steps", report.t, record.steps));
        if report.output_time {
            write_step(
                outw,
                built,
                &loads.assembly,
                solver.state(),
                solver.outputs(),
                report.iterations,
                report.dt,
            )?;
        }
    }
    Ok(())
}
