//! `aqua run scene.toml --out DIR`: static and/or dynamic solve with a progress bar, writing
//! `DIR/<scene>.pvd` + a multiblock `.vtm` per output step (blocks in `DIR/<scene>_NNNNNN/`), the
//! undeformed `DIR/<scene>_reference.vtm`, `DIR/open_in_paraview.py`, `DIR/summary.csv`,
//! `DIR/extremes.csv` (the load extremes over every accepted step) and `DIR/run.json`.
//!
//! Ctrl-C, SIGTERM or a failed step stops cleanly: every step already written stays readable, the
//! `.pvd` lists exactly those steps, `run.json` records why the run ended, and the exit code is
//! non-zero (1 for a failed solve, 128 + the signal for an interruption: 130 for Ctrl-C, 143 for SIGTERM).

use crate::interrupted;
use anyhow::Context;
use aqua_fem::{StaticProgress, StepReport};
use aqua_sim::Override;
use aqua_sim::files::{RunFiles, write_component_table};
use aqua_sim::{Diagnostic, Ending, Frame, Observer, Prepared, RunRecord, Simulation};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
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
    /// Change a scene key: PATH=VALUE, e.g. `--set analysis.dynamic.dt=0.05`,
    /// `--set cage.0.element_length=5`, `--set line.*.segments=40` (repeatable; recorded in
    /// run.json).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<Override>,
    /// Also draw PNG pictures into OUT/plots (as `aqua plot OUT`).
    #[arg(long)]
    pub plot: bool,
}

/// What `run_scene` needs of the flags.
struct RunOpts<'a> {
    out: &'a Path,
    quiet: bool,
}

/// The run's observer: writes every frame, prints warnings, draws the progress bar and
/// passes Ctrl-C on as a stop request.
struct Terminal<'a> {
    prep: &'a Prepared,
    files: RunFiles,
    bar: ProgressBar,
    quiet: bool,
    /// Every diagnostic printed, for run.json.
    diagnostics: Vec<String>,
}

impl Observer for Terminal<'_> {
    fn diagnostic(&mut self, d: &Diagnostic) {
        self.bar.suspend(|| eprintln!("{d}"));
        self.diagnostics.push(d.to_string());
    }
    fn static_started(&mut self) {
        if !self.quiet {
            self.bar = ProgressBar::new_spinner();
            self.bar.set_style(
                ProgressStyle::with_template("{spinner} [{elapsed_precise}] statics: {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            );
        }
    }
    fn static_progress(&mut self, p: &StaticProgress) {
        self.bar.set_message(format!(
            "load factor {:.3}, iteration {}, residual {:.2e}·F_ref, damping {:.1e}",
            p.load_factor, p.iteration, p.relative_residual, p.damping
        ));
        self.bar.tick();
    }
    fn dynamics_started(&mut self, t_end: f64) {
        self.bar.finish_and_clear();
        if !self.quiet {
            self.bar = ProgressBar::new((t_end * 1000.0).round() as u64);
            self.bar.set_style(
                ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] {wide_bar} t = {msg} (ETA {eta})",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
        }
    }
    fn step_done(&mut self, report: &StepReport, steps: usize) {
        self.bar.set_position((report.t * 1000.0).round() as u64);
        self.bar
            .set_message(format!("{:.2} s, {steps} steps", report.t));
    }
    fn frame(&mut self, f: &Frame<'_>) -> aqua_sim::Result<()> {
        self.files.write_frame(&self.prep.built, f)
    }
    fn stop_requested(&self) -> bool {
        interrupted()
    }
}

/// Run `aqua run`.
pub fn run(a: Args) -> anyhow::Result<()> {
    // The run goes to a worker of rayon's pool, so that the solver's parallel loops (sea
    // kinematics, element loads, cable kernels) are split between this worker and the others
    // instead of being handed over by a thread that only waits (docs/theory/fem.md#threads).
    let ending = rayon::scope(|_| run_scene(&a.scene, &a.set, &a.out, a.quiet))?;
    if a.plot {
        let pictures = aqua_sim::plot::plot_run(&a.out)?;
        if !a.quiet {
            crate::commands::plot::print_pictures(&pictures);
        }
    }
    match ending {
        Ending::Interrupted => std::process::exit(crate::interrupted_exit_code()),
        _ => Ok(()),
    }
}

/// Runs a scene changed by `set` into `out`: the whole of `aqua run` but the exit on Ctrl-C
/// (the caller's). A failed solve is an error; an interruption returns
/// [`Ending::Interrupted`] after saying what was kept.
pub fn run_scene(
    scene: &Path,
    set: &[Override],
    out: &Path,
    quiet: bool,
) -> anyhow::Result<Ending> {
    let a = RunOpts { out, quiet };
    let t0 = Instant::now();
    let prep = aqua_sim::prepare_with(scene, set)?;
    let mut diagnostics = Vec::new();
    for d in prep.diagnostics() {
        eprintln!("{d}");
        diagnostics.push(d.to_string());
    }
    let mut sim = Simulation::new(&prep)?;
    for d in sim.diagnostics() {
        eprintln!("{d}");
        diagnostics.push(d.to_string());
    }
    let files = RunFiles::create(a.out, &prep.scene.name, &prep.built)?;
    if prep.built.sea.has_waves() && prep.plan.dynamics.is_some() {
        // The component table makes the run reproducible exactly
        // (docs/theory/environment.md#summation).
        write_component_table(&prep.built.sea, &a.out.join("wave_components.csv"))?;
    }
    let mut term = Terminal {
        prep: &prep,
        files,
        bar: ProgressBar::hidden(),
        quiet: a.quiet,
        diagnostics,
    };
    let (mut record, mut result) = sim.run(&mut term);
    term.bar.finish_and_clear();
    let mut files = term.files;
    // The steps still queued for the writer and the summary rows still buffered: written
    // whether the run completed, was interrupted or failed. A write error found here fails
    // the run (a solver error found first stays the run's error) and run.json says so.
    let failed_before = files.write_failed();
    if let Err(e) = files.flush() {
        if result.is_ok() {
            result = Err(e);
        } else if !failed_before {
            // A second failure after the run's own (which stays its error).
            let d = format!("error: {}", e.chain());
            eprintln!("{d}");
            term.diagnostics.push(d);
        }
        record.ending = Ending::Failed;
    }
    record.wall = t0.elapsed().as_secs_f64();
    print_step_control(&record);
    let mut json = run_json(&prep, &record, &result, &files);
    json["diagnostics"] = serde_json::json!(term.diagnostics);
    if let Some(e) = &record.extremes {
        files.write_extremes(e)?;
    }
    files.write_json(&json)?;
    match record.ending {
        Ending::Completed => {
            if !a.quiet {
                print_final(&files, &record);
            }
            result?;
            Ok(Ending::Completed)
        }
        Ending::Interrupted => {
            let partial = match (record.static_converged, record.static_load_factor) {
                (Some(false), Some(s)) => {
                    let load = if s < 1.0 {
                        format!(" at load factor {s:.4}, not the full load")
                    } else {
                        String::new()
                    };
                    format!(
                        " (step 0 is the last static iterate{load}: NOT converged, \
                         ||r|| = {:.2e}·F_ref; not an equilibrium)",
                        record.static_relative_residual.unwrap_or(f64::NAN)
                    )
                }
                _ => String::new(),
            };
            eprintln!(
                "interrupted at t = {} s{partial}: {} output steps kept in {}",
                record.last.as_ref().map(|r| r.t).unwrap_or(0.0),
                files.steps_written(),
                files.pvd_path().display()
            );
            Ok(Ending::Interrupted)
        }
        Ending::Failed => Err(anyhow::Error::from(result.err().unwrap_or_else(|| {
            aqua_sim::SimError::Coupling("failed without an error".into())
        })))
        .with_context(|| {
            format!(
                "the run stopped; {} output steps written before the failure are kept in {}",
                files.steps_written(),
                files.pvd_path().display()
            )
        }),
    }
}

/// `run.json`: the scene with defaults, resolved numbers, how the run ended and its timing.
fn run_json(
    prep: &Prepared,
    record: &RunRecord,
    result: &aqua_sim::Result<()>,
    files: &RunFiles,
) -> serde_json::Value {
    let built = &prep.built;
    let plan = &prep.plan;
    serde_json::json!({
        "scene": &prep.scene,
        "overrides": &prep.scene.overrides,
        "resolved": {
            "mesh": built.mesh.summary(),
            "sea": &built.sea_summary,
            "scheme": &prep.scene.analysis.dynamic.scheme,
            "alpha": plan.alpha,
            "dt": plan.dt,
            "output_interval": plan.output_interval,
            "paraview_interval": plan.paraview_interval(),
            "t_end": plan.t_end,
            "structural_groups": &built.group_names,
        },
        "status": record.ending.as_str(),
        "error": result.as_ref().err().map(|e| e.chain()),
        "final": record.last,
        "extremes": record.extremes.as_ref().map(|e| e.to_json()),
        "output_steps": files.steps_written(),
        "paraview_steps": files.paraview_steps_written(),
        "pvd": files.pvd_path(),
        "paraview_script": files.dir().join("open_in_paraview.py"),
        "names": files.names(),
        "wall_time_s": record.wall,
        "dynamic_wall_time_s": record.dyn_wall,
        "steps": record.steps,
        "newton_iterations": record.iterations,
        "static_newton_iterations": record.static_iterations,
        "static_residual_history": &record.static_residuals,
        "static_load_factor": record.static_load_factor,
        "static_converged": record.static_converged,
        "static_relative_residual": record.static_relative_residual,
        "step_control": &record.step_control,
        "energies": &record.energies,
        "linear_solver": &record.linear_solver,
        "peak_tension_resolution": record.step_control.as_ref().map(|c| c.peak_tension_resolution()),
        "time_per_step_s": if record.steps > 0 { record.dyn_wall / record.steps as f64 } else { 0.0 },
    })
}

/// Says how often the step control halved the step, and why (docs/theory/fem.md#step-control).
fn print_step_control(r: &RunRecord) {
    let Some(c) = &r.step_control else { return };
    if c.halvings == 0 {
        return;
    }
    let reasons: Vec<String> = c
        .reasons
        .iter()
        .map(|(why, n)| format!("{n}× {why}"))
        .collect();
    eprintln!(
        "note: the time step was halved {} times (smallest {:.3e} s; {}) and grown back {} times; \
         run.json lists them under step_control",
        c.halvings,
        c.smallest_dt,
        reasons.join(", "),
        c.regrowths
    );
}

fn print_final(files: &RunFiles, r: &RunRecord) {
    if let Some(last) = &r.last {
        println!(
            "done: t = {} s, net force = [{:.1}, {:.1}, {:.1}] N, reaction = [{:.1}, {:.1}, {:.1}] N, volume ratio {}",
            last.t,
            last.net_force[0],
            last.net_force[1],
            last.net_force[2],
            last.reaction[0],
            last.reaction[1],
            last.reaction[2],
            // The ratio is 0 only where there is no enclosed volume to compare with.
            if last.volume_ratio > 0.0 {
                format!("{:.4}", last.volume_ratio)
            } else {
                "n/a (no closed net)".to_string()
            }
        );
    }
    println!(
        "{} output steps in {}; wall time {:.2} s{}",
        files.steps_written(),
        files.dir().display(),
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
