//! The coupling's solver thread: it owns the prepared scene (the integrators borrow its
//! model) and answers the caller's requests in order until the channel closes.

use super::Forces;
use super::output::CoupledOutput;
use crate::error::{Result, SimError};
use crate::plan::{Integrator, Prepared};
use crate::run::water_loads;
use crate::scene::AnalysisKind;
use crate::solvers::{Stepper, start_integrator, static_equilibrium};
use aqua_env::Phase;
use aqua_fem::{DynamicSettings, Outputs, Snapshot, State};
use std::path::PathBuf;
use std::sync::mpsc::{Receiver, Sender};

/// The end time given to an integrator when it starts: each call then sets its own end.
const OPEN_END: f64 = 1e9;

pub(super) enum Request {
    Init,
    /// Advance to t1; `dt` is the caller's step (the solver's own when the scene gives none).
    Step {
        t1: f64,
        dt: f64,
    },
    Positions,
    Tensions,
    Save,
    Restore(Option<Box<Snapshot>>),
    /// Write the run's files into this directory.
    Output(PathBuf),
    /// Write what is queued and the extremes.
    Finish,
}

pub(super) enum Reply {
    Forces(Result<Forces>),
    Positions(Vec<[f64; 3]>),
    Tensions(Vec<f64>),
    Saved(Result<Option<Box<Snapshot>>>),
    Restored(Result<()>),
    Done(Result<()>),
}

/// The forces on the points: −R at their nodes.
fn point_forces(prep: &Prepared, outputs: &Outputs) -> Forces {
    prep.built
        .external
        .iter()
        .map(|(_, list)| {
            list.iter()
                .map(|(n, _)| outputs.reaction[*n].map(|r| -r))
                .collect()
        })
        .collect()
}

/// The integrator of a coupling: the scene's scheme and settings, with the scene's
/// `analysis.dynamic.dt` as its own step (the first call's step when the scene gives none),
/// each call setting the end it lands on (docs/theory/fem.md#coupling).
fn coupled_integrator(prep: &Prepared, first_dt: f64) -> Integrator {
    let dt = prep.scene.analysis.dynamic.dt.unwrap_or(first_dt);
    match &prep.plan.dynamics {
        Some(Integrator::Hht(s)) => Integrator::Hht(DynamicSettings {
            dt,
            t_end: OPEN_END,
            output_interval: None,
            ..s.clone()
        }),
        Some(Integrator::Explicit(s)) => {
            let mut s = s.clone();
            s.t_end = OPEN_END;
            s.output_interval = None;
            Integrator::Explicit(s)
        }
        None => Integrator::Hht(DynamicSettings::new(dt, OPEN_END)),
    }
}

/// The solver thread's state.
struct Worker<'p> {
    prep: &'p Prepared,
    loads: crate::provider::WaterLoads,
    initial: Option<(State, Outputs)>,
    solver: Option<Box<dyn Stepper + 'p>>,
    /// A failed call of an integrator that cannot go back (explicit) ends the coupling.
    broken: Option<String>,
    /// The run's files, when asked for.
    output: Option<CoupledOutput>,
}

impl<'p> Worker<'p> {
    fn init(&mut self) -> Result<Forces> {
        let prep = self.prep;
        if prep.plan.kind == AnalysisKind::Dynamic {
            // Dynamics from the as-built state at rest: no forces known before a step (the
            // files' first row is the first call's end).
            return Ok(prep
                .built
                .external
                .iter()
                .map(|(_, list)| vec![[0.0; 3]; list.len()])
                .collect());
        }
        let mut go_on = |_: &aqua_fem::StaticProgress| aqua_fem::StaticControl::Continue;
        let s = static_equilibrium(
            &prep.built.model,
            &prep.built.mesh,
            &mut self.loads,
            &prep.plan.statics,
            &mut go_on,
        )?;
        let f = point_forces(prep, &s.outputs);
        if let Some(o) = self.output.as_mut() {
            let poses = s.body_poses(&prep.built.model);
            o.start(
                prep,
                &self.loads,
                &s.state,
                &s.outputs,
                &poses,
                s.report.iterations,
            )?;
        }
        self.initial = Some((s.state, s.outputs));
        Ok(f)
    }

    /// Steps to t1. A failure puts the solver back where the call started (implicit schemes),
    /// so the caller may retry with a smaller step.
    fn step(&mut self, t1: f64, dt: f64) -> Result<Forces> {
        if let Some(why) = &self.broken {
            return Err(SimError::Coupling(why.clone()));
        }
        let prep = self.prep;
        if self.solver.is_none() {
            self.loads.phase = Phase::Dynamic;
            let integ = coupled_integrator(prep, dt);
            let init = self.initial.as_ref().map(|s| &s.0);
            self.solver = Some(start_integrator(
                &prep.built.model,
                &integ,
                init,
                &mut self.loads,
            )?);
        }
        let Some(s) = self.solver.as_mut() else {
            return Err(SimError::Coupling("no solver".into()));
        };
        let start = s.checkpoint();
        let t0 = s.state().t;
        let output = &mut self.output;
        if let Some(o) = output.as_mut() {
            o.begin_call();
        }
        let mut iterations = 0;
        let mut advance = || -> aqua_fem::Result<()> {
            s.extend_to(t1)?;
            while !s.is_finished() {
                iterations = s.step(&mut self.loads)?.iterations;
                if let Some(o) = output.as_mut() {
                    let poses = s.body_poses();
                    o.observe(prep, &self.loads, s.state(), s.outputs(), &poses);
                }
            }
            Ok(())
        };
        if let Err(e) = advance() {
            if let Some(o) = self.output.as_mut() {
                o.revert_call();
            }
            match &start {
                Some(c) => s.restore(c).map_err(|e| SimError::Dynamic(Box::new(e)))?,
                None => {
                    self.broken = Some(format!(
                        "a step failed at t < {t1} s and the explicit scheme cannot go back to \
                         retry it; use HHT-α or the midpoint rule to retry failed steps"
                    ))
                }
            }
            return Err(SimError::Dynamic(Box::new(e)));
        }
        let t = s.state().t;
        if (t - t1).abs() > 1e-9 * dt {
            return Err(SimError::Coupling(format!(
                "the solver reached t = {t} s instead of the step's end t = {t1} s"
            )));
        }
        if let Some(o) = self.output.as_mut() {
            o.row(
                prep,
                &self.loads,
                s.state(),
                s.outputs(),
                &s.body_poses(),
                iterations,
                t1 - t0,
            )?;
        }
        Ok(point_forces(prep, s.outputs()))
    }

    fn open(&mut self, dir: PathBuf) -> Result<()> {
        self.output = Some(CoupledOutput::create(self.prep, &dir)?);
        Ok(())
    }

    fn finish(&mut self) -> Result<()> {
        self.output.as_mut().map_or(Ok(()), |o| o.finish())
    }

    /// The mesh's nodes (a rod's twist carriers follow them in the model).
    fn positions(&self) -> Vec<[f64; 3]> {
        let np = self.prep.built.mesh.nodes.len();
        match (&self.solver, &self.initial) {
            (Some(s), _) => s.state().x[..np].to_vec(),
            (None, Some((st, _))) => st.x[..np].to_vec(),
            (None, None) => self.prep.built.model.nodes()[..np].to_vec(),
        }
    }

    fn tensions(&self) -> Vec<f64> {
        match (&self.solver, &self.initial) {
            (Some(s), _) => s.outputs().tension.clone(),
            (None, Some((_, o))) => o.tension.clone(),
            (None, None) => vec![0.0; self.prep.built.model.elements().len()],
        }
    }

    fn save(&mut self) -> Result<Option<Box<Snapshot>>> {
        match self.solver.as_mut() {
            None => Ok(None),
            Some(s) => s.save().map(|s| Some(Box::new(s))).ok_or_else(|| {
                SimError::Coupling(
                    "save needs an implicit scheme (HHT-α or the midpoint rule)".into(),
                )
            }),
        }
    }

    fn restore(&mut self, snapshot: Option<Box<Snapshot>>) -> Result<()> {
        match snapshot {
            // Saved before the first step: the next step starts the integrator afresh.
            None => {
                self.solver = None;
                self.loads.phase = Phase::Static;
            }
            Some(snap) => {
                let s = self.solver.as_mut().ok_or_else(|| {
                    SimError::Coupling("restore: the solver of this state is gone".into())
                })?;
                s.restore(&snap)
                    .map_err(|e| SimError::Dynamic(Box::new(e)))?;
            }
        }
        self.broken = None;
        Ok(())
    }
}

/// The solver thread: owns the model, answers requests until the channel closes.
pub(super) fn worker(prep: Prepared, rx: Receiver<Request>, tx: Sender<Reply>) {
    let loads = match water_loads(&prep, Phase::Static) {
        Ok((l, _)) => l,
        Err(e) => {
            // Every request gets the error.
            let msg = e.chain();
            while rx.recv().is_ok() {
                let _ = tx.send(Reply::Forces(Err(SimError::Coupling(msg.clone()))));
            }
            return;
        }
    };
    let mut w = Worker {
        prep: &prep,
        loads,
        initial: None,
        solver: None,
        broken: None,
        output: None,
    };
    while let Ok(req) = rx.recv() {
        let reply = match req {
            Request::Init => Reply::Forces(w.init()),
            Request::Step { t1, dt } => Reply::Forces(w.step(t1, dt)),
            Request::Positions => Reply::Positions(w.positions()),
            Request::Tensions => Reply::Tensions(w.tensions()),
            Request::Save => Reply::Saved(w.save()),
            Request::Restore(s) => Reply::Restored(w.restore(s)),
            Request::Output(dir) => Reply::Done(w.open(dir)),
            Request::Finish => Reply::Done(w.finish()),
        };
        if tx.send(reply).is_err() {
            break;
        }
    }
}
