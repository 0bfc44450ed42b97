//! The files of a coupled run (docs/guide/coupling.md#files): the files of `aqua run` but
//! `run.json` — `summary.csv` with a row at the end of every call, the ParaView series every
//! `paraview_interval`-th row (every row by default), `extremes.csv` over every step the solver
//! accepted, and `wave_components.csv` in waves. A call that fails and is put back leaves no
//! trace in them.

use crate::error::Result;
use crate::extremes::Extremes;
use crate::files::{RunFiles, write_component_table};
use crate::plan::Prepared;
use crate::post::{SummaryRow, net_force_and_wake, total_volume};
use crate::provider::WaterLoads;
use crate::run::Frame;
use aqua_fem::{BodyPose, Outputs, State};
use std::path::Path;

/// The open files of a coupled run and its running extremes.
pub(super) struct CoupledOutput {
    files: RunFiles,
    volume0: f64,
    extremes: Extremes,
    /// The extremes before the current call (put back if it fails).
    before_call: Option<Extremes>,
    rows: usize,
}

impl CoupledOutput {
    /// Creates `dir` and its files.
    pub(super) fn create(prep: &Prepared, dir: &Path) -> Result<Self> {
        let files = RunFiles::create(dir, &prep.scene.name, &prep.built)?;
        if prep.built.sea.has_waves() {
            write_component_table(&prep.built.sea, &dir.join("wave_components.csv"))?;
        }
        Ok(Self {
            files,
            volume0: total_volume(&prep.built, prep.built.model.nodes()),
            extremes: Extremes::new(&prep.built),
            before_call: None,
            rows: 0,
        })
    }

    /// Adds an accepted state to the extremes.
    pub(super) fn observe(
        &mut self,
        prep: &Prepared,
        loads: &WaterLoads,
        state: &State,
        outputs: &Outputs,
        poses: &[BodyPose],
    ) {
        self.extremes
            .observe(&prep.built, loads, state, outputs, poses);
    }

    /// The state before the first step (a static equilibrium stands until the first step,
    /// as in `aqua run`).
    pub(super) fn start(
        &mut self,
        prep: &Prepared,
        loads: &WaterLoads,
        state: &State,
        outputs: &Outputs,
        poses: &[BodyPose],
        iterations: usize,
    ) -> Result<()> {
        self.observe(prep, loads, state, outputs, poses);
        self.extremes.until_next();
        self.row(prep, loads, state, outputs, poses, iterations, 0.0)
    }

    /// A call begins: its steps may still be put back.
    pub(super) fn begin_call(&mut self) {
        self.before_call = Some(self.extremes.clone());
    }

    /// The call failed and was put back.
    pub(super) fn revert_call(&mut self) {
        if let Some(e) = self.before_call.take() {
            self.extremes = e;
        }
    }

    /// The row (and, on its turn, the ParaView step) at the end of a call.
    pub(super) fn row(
        &mut self,
        prep: &Prepared,
        loads: &WaterLoads,
        state: &State,
        outputs: &Outputs,
        poses: &[BodyPose],
        iterations: usize,
        dt: f64,
    ) -> Result<()> {
        let built = &prep.built;
        let (net_force, wake) = net_force_and_wake(built, loads, state);
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
        self.files.write_frame(
            built,
            &Frame {
                state,
                outputs,
                wake: &wake,
                row: &row,
                paraview: prep.plan.paraview_step(self.rows),
            },
        )?;
        self.rows += 1;
        self.before_call = None;
        Ok(())
    }

    /// Writes what is queued and `extremes.csv`.
    pub(super) fn finish(&mut self) -> Result<()> {
        self.files.flush()?;
        self.files.write_extremes(&self.extremes)
    }
}
