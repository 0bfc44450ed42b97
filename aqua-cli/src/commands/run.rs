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
use aqua_sim::{Diagnostic, Ending, Observer, Override, PrepareOptions, RunOptions, RunOutcome};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};

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

/// The run's observer: prints warnings, draws the progress bar and passes Ctrl-C on as a
/// stop request.
struct Terminal {
    bar: ProgressBar,
    quiet: bool,
}

impl Observer for Terminal {
    fn diagnostic(&mut self, d: &Diagnostic) {
        self.bar.suspend(|| eprintln!("{d}"));
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
        let pictures = aqua_study::plot::plot_run(&a.out)?;
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
    let options = RunOptions {
        scene: PrepareOptions::file(scene).with_overrides(set),
        out: Some(out),
    };
    let mut term = Terminal {
        bar: ProgressBar::hidden(),
        quiet,
    };
    let outcome = aqua_sim::run_scene(options, &mut term);
    term.bar.finish_and_clear();
    let RunOutcome {
        record,
        result,
        late_error,
        written,
        ..
    } = outcome?;
    let files = written.context("the run wrote no output files")?;
    if let Some(e) = late_error {
        eprintln!("{e}");
    }
    if let Some(note) = record.step_control_note() {
        eprintln!("{note}");
    }
    match record.ending {
        Ending::Completed => {
            if !quiet {
                print!("{}", record.final_text(&files));
            }
            result?;
            Ok(Ending::Completed)
        }
        Ending::Interrupted => {
            eprintln!("{}", record.interrupted_text(&files));
            Ok(Ending::Interrupted)
        }
        Ending::Failed => Err(anyhow::Error::from(result.err().unwrap_or_else(|| {
            aqua_sim::SimError::Coupling("failed without an error".into())
        })))
        .with_context(|| {
            format!(
                "the run stopped; {} output steps written before the failure are kept in {}",
                files.steps,
                files.pvd.display()
            )
        }),
    }
}
