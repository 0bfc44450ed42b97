//! A whole run of a scene, the one `aqua run`, the Python module and the tests share: prepare
//! the scene, run it ([`crate::run`]) and, with an output directory, write every output file —
//! the ParaView series and `open_in_paraview.py`, `summary.csv` ([`crate::files`]),
//! `wave_components.csv` (a dynamic run in waves), `extremes.csv` and `run.json`
//! ([`crate::run_json`]).
//!
//! Nothing here prints: diagnostics, progress and frames go to the caller's [`Observer`], and
//! the [`RunOutcome`] says how the run ended and what was written.

use crate::diagnostic::Diagnostic;
use crate::error::Result;
use crate::files::{RunFiles, write_component_table};
use crate::plan::{PrepareOptions, Prepared, prepare};
use crate::run::{Ending, Frame, Observer, RunRecord, Simulation};
use crate::run_json::run_json;
use aqua_fem::{StaticProgress, StepReport};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What [`run_scene`] runs and where it writes.
#[derive(Debug, Clone)]
pub struct RunOptions<'a> {
    /// The scene and its changes.
    pub scene: PrepareOptions<'a>,
    /// The output directory (created if missing); `None` writes no file.
    pub out: Option<&'a Path>,
}

/// What the run files hold at the end of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    /// The output directory.
    pub dir: PathBuf,
    /// The `.pvd` of the ParaView series.
    pub pvd: PathBuf,
    /// Output steps written (`summary.csv` rows).
    pub steps: usize,
}

/// How a run ended.
#[derive(Debug)]
pub struct RunOutcome {
    /// The scene as it ran: its model and plan.
    pub prepared: Prepared,
    /// Counters, timing, the last summary row and the extremes; `ending` says how it ended.
    pub record: RunRecord,
    /// The run's error (a failed solve or a failed write), also in `run.json`.
    pub result: Result<()>,
    /// A write error found after the run had already failed (the run's error stays
    /// `result`), as `run.json` lists it among the diagnostics.
    pub late_error: Option<String>,
    /// The files written (with an output directory).
    pub written: Option<Written>,
}

/// Prepares and runs a scene; with `options.out`, writes every output file. Diagnostics of
/// building, of the water loads and of the run go to `observer` (and into `run.json`), as do
/// the progress and the frames (after they are written).
///
/// An error before the run starts (the scene, the model, the output directory) or in writing
/// `extremes.csv` or `run.json` is returned as `Err`; a failed solve or a failed write of an
/// output step ends the run and is in [`RunOutcome::result`], with every step written before
/// it kept and `run.json` saying why the run ended.
pub fn run_scene(options: RunOptions<'_>, observer: &mut dyn Observer) -> Result<RunOutcome> {
    let t0 = Instant::now();
    let prep = prepare(options.scene)?;
    let mut diagnostics = Vec::new();
    for d in prep.diagnostics() {
        observer.diagnostic(d);
        diagnostics.push(d.to_string());
    }
    let (record, result, files, late_error, diagnostics) = {
        let mut sim = Simulation::new(&prep)?;
        for d in sim.diagnostics() {
            observer.diagnostic(d);
            diagnostics.push(d.to_string());
        }
        let files = match options.out {
            Some(dir) => {
                let files = RunFiles::create(dir, &prep.scene.name, &prep.built)?;
                if prep.built.sea.has_waves() && prep.plan.dynamics.is_some() {
                    // The component table makes the run reproducible exactly
                    // (docs/theory/environment.md#summation).
                    write_component_table(&prep.built.sea, &dir.join("wave_components.csv"))?;
                }
                Some(files)
            }
            None => None,
        };
        let mut writer = Writer {
            prep: &prep,
            files,
            inner: observer,
            diagnostics,
        };
        let (mut record, mut result) = sim.run(&mut writer);
        let Writer {
            files,
            mut diagnostics,
            ..
        } = writer;
        let mut late_error = None;
        let mut files = files;
        // The steps still queued for the writer and the summary rows still buffered: written
        // whether the run completed, was interrupted or failed. A write error found here
        // fails the run (a solver error found first stays the run's error) and run.json says
        // so.
        if let Some(f) = &mut files {
            let failed_before = f.write_failed();
            if let Err(e) = f.flush() {
                if result.is_ok() {
                    result = Err(e);
                } else if !failed_before {
                    // A second failure after the run's own (which stays its error).
                    let d = format!("error: {}", e.chain());
                    diagnostics.push(d.clone());
                    late_error = Some(d);
                }
                record.ending = Ending::Failed;
            }
        }
        (record, result, files, late_error, diagnostics)
    };
    let mut record = record;
    record.wall = t0.elapsed().as_secs_f64();
    let written = match &files {
        Some(files) => {
            let json = run_json(&prep, &record, &result, files, &diagnostics);
            if let Some(e) = &record.extremes {
                files.write_extremes(e)?;
            }
            files.write_json(&json)?;
            Some(Written {
                dir: files.dir().to_path_buf(),
                pvd: files.pvd_path(),
                steps: files.steps_written(),
            })
        }
        None => None,
    };
    Ok(RunOutcome {
        prepared: prep,
        record,
        result,
        late_error,
        written,
    })
}

/// Writes every frame, keeps every diagnostic for `run.json` and passes everything on to the
/// caller's observer.
struct Writer<'a, 'o> {
    prep: &'a Prepared,
    files: Option<RunFiles>,
    inner: &'o mut dyn Observer,
    diagnostics: Vec<String>,
}

impl Observer for Writer<'_, '_> {
    fn diagnostic(&mut self, d: &Diagnostic) {
        self.inner.diagnostic(d);
        self.diagnostics.push(d.to_string());
    }
    fn static_started(&mut self) {
        self.inner.static_started();
    }
    fn static_progress(&mut self, p: &StaticProgress) {
        self.inner.static_progress(p);
    }
    fn dynamics_started(&mut self, t_end: f64) {
        self.inner.dynamics_started(t_end);
    }
    fn step_done(&mut self, report: &StepReport, steps: usize) {
        self.inner.step_done(report, steps);
    }
    fn frame(&mut self, f: &Frame<'_>) -> Result<()> {
        if let Some(files) = &mut self.files {
            files.write_frame(&self.prep.built, f)?;
        }
        self.inner.frame(f)
    }
    fn stop_requested(&self) -> bool {
        self.inner.stop_requested()
    }
}
