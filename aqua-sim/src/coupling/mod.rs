//! Coupling: another code (a vessel model, CFD, a controller) drives the `[[prescribed]]`
//! nodes of a scene step by step and gets back the forces the structure exerts on them — the
//! create → init → step → close cycle mooring codes offer.
//!
//! ```text
//! let mut c = Coupling::new(scene)?;          // build, every [[prescribed]] node external
//! let f0 = c.init()?;                         // static equilibrium, forces on the points
//! let f = c.step(t, dt, &targets)?;           // move the points to their positions at t + dt
//! c.close();
//! ```
//!
//! The points are the `[[prescribed]]` entries, named by their `nodes` reference (e.g.
//! `"chain/fairlead"`); positions are absolute [m]. Between two calls the solver sees the
//! cubic Hermite motion through the given positions and velocities (velocities not given are
//! the backward difference of the positions, and then the acceleration, if not given, is the
//! backward difference of the velocities). The force on a point is the force of the
//! structure on whatever holds it, F = −R (R the support reaction of the run outputs) [N].
//!
//! The solver runs on its own thread, which owns the model (the integrators borrow it), so
//! a `Coupling` can be kept by a caller with no lifetime, as a Python object.

use crate::build::Prescribed;
use crate::error::{Result, SimError};
use crate::plan::{Integrator, Prepared, prepare_scene};
use crate::run::water_loads;
use crate::scene::{AnalysisKind, Scene};
use crate::solvers::{Stepper, start_integrator, static_equilibrium};
use aqua_env::Phase;
use aqua_fem::{DynamicSettings, ExternalMotion, Outputs, State};

use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

/// The end time given to the integrators of a coupling: the caller decides when to stop.
const OPEN_END: f64 = 1e9;

/// A coupled point: a `[[prescribed]]` node group.
#[derive(Debug, Clone, PartialEq)]
pub struct CoupledPoint {
    /// The `nodes` reference of the `[[prescribed]]` entry.
    pub name: String,
    /// Its nodes.
    pub nodes: Vec<usize>,
    /// Their as-built positions [m].
    pub rest: Vec<[f64; 3]>,
}

/// Where a point is at the end of a step: one entry per node.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Target {
    /// Positions [m].
    pub position: Vec<[f64; 3]>,
    /// Velocities [m/s] (default: backward difference of the positions).
    pub velocity: Option<Vec<[f64; 3]>>,
    /// Accelerations [m/s²] (default: the backward difference of the velocities when these
    /// are not given either, else the cubic's through positions and velocities).
    pub acceleration: Option<Vec<[f64; 3]>>,
}

/// Forces on every coupled point, per node [N], in the order of [`Coupling::points`].
pub type Forces = Vec<Vec<[f64; 3]>>;

enum Request {
    Init,
    Step { t1: f64, dt: f64 },
    Positions,
}

enum Reply {
    Forces(Result<Forces>),
    Positions(Vec<[f64; 3]>),
}

/// A scene driven from outside; see the module docs.
#[derive(Debug)]
pub struct Coupling {
    points: Vec<CoupledPoint>,
    motions: Vec<Vec<ExternalMotion>>,
    last: Vec<Vec<([f64; 3], [f64; 3])>>,
    tx: Option<Sender<Request>>,
    rx: Receiver<Reply>,
    worker: Option<JoinHandle<()>>,
    /// Coupling steps taken.
    steps: u64,
    /// The coupling step, fixed by the first call [s].
    dt: Option<f64>,
    initialised: bool,
}

impl Coupling {
    /// Builds the scene with every `[[prescribed]]` node driven from outside.
    pub fn new(scene: Scene) -> Result<Self> {
        let prep = prepare_scene(scene, Prescribed::External)?;
        let nodes = prep.built.model.nodes();
        let points: Vec<CoupledPoint> = prep
            .built
            .external
            .iter()
            .map(|(name, list)| CoupledPoint {
                name: name.clone(),
                nodes: list.iter().map(|(n, _)| *n).collect(),
                rest: list.iter().map(|(n, _)| nodes[*n]).collect(),
            })
            .collect();
        if points.is_empty() {
            return Err(SimError::Coupling(format!(
                "{}: the scene has no [[prescribed]] nodes to couple",
                prep.scene.path.display()
            )));
        }
        let motions = prep
            .built
            .external
            .iter()
            .map(|(_, list)| list.iter().map(|(_, m)| m.clone()).collect())
            .collect();
        let last = points
            .iter()
            .map(|p| p.rest.iter().map(|x| (*x, [0.0; 3])).collect())
            .collect();
        let (tx, rx_req) = channel();
        let (tx_rep, rx) = channel();
        let worker = std::thread::Builder::new()
            .name("aqua-coupling".into())
            .spawn(move || worker(prep, rx_req, tx_rep))
            .map_err(|e| SimError::Coupling(format!("cannot start the solver thread: {e}")))?;
        Ok(Self {
            points,
            motions,
            last,
            tx: Some(tx),
            rx,
            worker: Some(worker),
            steps: 0,
            dt: None,
            initialised: false,
        })
    }

    /// The coupled points.
    pub fn points(&self) -> &[CoupledPoint] {
        &self.points
    }

    /// The index of a point by its name.
    pub fn point(&self, name: &str) -> Result<usize> {
        self.points
            .iter()
            .position(|p| p.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = self.points.iter().map(|p| p.name.as_str()).collect();
                SimError::Coupling(format!(
                    "\"{name}\" is no coupled point; the [[prescribed]] node groups are: {}",
                    names.join(", ")
                ))
            })
    }

    /// The model time [s]: the steps taken times the coupling step, the same product the
    /// solver lands on (a running sum of the steps would drift from it in its last bits;
    /// docs/theory/fem.md#coupling).
    pub fn time(&self) -> f64 {
        self.dt.map_or(0.0, |dt| self.steps as f64 * dt)
    }

    fn ask(&self, req: Request) -> Result<Reply> {
        let closed = || SimError::Coupling("the coupling is closed".into());
        self.tx
            .as_ref()
            .ok_or_else(closed)?
            .send(req)
            .map_err(|_| closed())?;
        self.rx.recv().map_err(|_| closed())
    }

    fn forces(&self, req: Request) -> Result<Forces> {
        match self.ask(req)? {
            Reply::Forces(f) => f,
            Reply::Positions(_) => Err(SimError::Coupling("unexpected reply".into())),
        }
    }

    /// Static equilibrium with the points at rest where built (as-built state at rest for a
    /// `kind = "dynamic"` scene); returns the forces on the points.
    pub fn init(&mut self) -> Result<Forces> {
        if self.initialised {
            return Err(SimError::Coupling("init was already called".into()));
        }
        let f = self.forces(Request::Init)?;
        self.initialised = true;
        Ok(f)
    }

    /// Advances from `t` to `t + dt` [s] with the points given in `targets` (index into
    /// [`Coupling::points`], where the point is at `t + dt`); points not given stay where they
    /// are. Returns the forces on all points at `t + dt`.
    pub fn step(&mut self, t: f64, dt: f64, targets: &[(usize, Target)]) -> Result<Forces> {
        if !self.initialised {
            return Err(SimError::Coupling("call init before step".into()));
        }
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SimError::Coupling(format!("dt = {dt}: a step > 0 s")));
        }
        let now = self.time();
        if (t - now).abs() > 1e-9 * dt.max(1e-300) + 1e-12 * t.abs() {
            return Err(SimError::Coupling(format!(
                "step from t = {t} s, but the model is at t = {now} s"
            )));
        }
        let dt = match self.dt {
            None => dt,
            Some(fixed) if (dt - fixed).abs() <= 1e-12 * fixed => fixed,
            Some(fixed) => {
                return Err(SimError::Coupling(format!(
                    "dt = {dt} s: a coupling keeps the step of its first call ({fixed} s)"
                )));
            }
        };
        // The end of the step is the (k + 1)-th multiple of Δt, the time the solver lands on
        // exactly: the motion's end keyframe and the solver's clock are the same number.
        let t1 = (self.steps + 1) as f64 * dt;
        let mut given = vec![false; self.points.len()];
        for (i, target) in targets {
            self.set_target(*i, target, t1, dt)?;
            given[*i] = true;
        }
        for i in (0..self.points.len()).filter(|&i| !given[i]) {
            let hold = Target {
                position: self.last[i].iter().map(|(x, _)| *x).collect(),
                velocity: Some(vec![[0.0; 3]; self.points[i].nodes.len()]),
                acceleration: None,
            };
            self.set_target(i, &hold, t1, dt)?;
        }
        let f = self.forces(Request::Step { t1, dt })?;
        self.dt = Some(dt);
        self.steps += 1;
        Ok(f)
    }

    fn set_target(&mut self, i: usize, target: &Target, t1: f64, dt: f64) -> Result<()> {
        let p = self
            .points
            .get(i)
            .ok_or_else(|| SimError::Coupling(format!("no coupled point #{i}")))?;
        let n = p.nodes.len();
        let len_ok = |v: &Option<Vec<[f64; 3]>>| v.as_ref().is_none_or(|v| v.len() == n);
        if target.position.len() != n || !len_ok(&target.velocity) || !len_ok(&target.acceleration)
        {
            return Err(SimError::Coupling(format!(
                "\"{}\" has {n} nodes: give {n} positions (and velocities, accelerations)",
                p.name
            )));
        }
        let finite = |v: &[[f64; 3]]| v.iter().flatten().all(|x| x.is_finite());
        if !finite(&target.position)
            || !target.velocity.as_deref().is_none_or(finite)
            || !target.acceleration.as_deref().is_none_or(finite)
        {
            return Err(SimError::Coupling(format!(
                "\"{}\": positions, velocities and accelerations must be finite",
                p.name
            )));
        }
        for k in 0..n {
            let x = target.position[k];
            let x0 = p.rest[k];
            let (x_prev, v_prev) = self.last[i][k];
            let v = target.velocity.as_ref().map(|v| v[k]).unwrap_or([
                (x[0] - x_prev[0]) / dt,
                (x[1] - x_prev[1]) / dt,
                (x[2] - x_prev[2]) / dt,
            ]);
            // Positions alone: the acceleration is the backward difference of the velocities.
            // The cubic's end value through backward-difference velocities would be
            // 2·(v_prev − v)/Δt, minus twice the motion's (docs/theory/fem.md#coupling).
            let a = match (&target.acceleration, &target.velocity) {
                (Some(a), _) => Some(a[k]),
                (None, None) => Some([
                    (v[0] - v_prev[0]) / dt,
                    (v[1] - v_prev[1]) / dt,
                    (v[2] - v_prev[2]) / dt,
                ]),
                (None, Some(_)) => None,
            };
            let d = [x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]];
            self.motions[i][k].set_target(t1, d, v, a);
            self.last[i][k] = (x, v);
        }
        Ok(())
    }

    /// Positions of all model nodes [m] (mesh node order).
    pub fn positions(&self) -> Result<Vec<[f64; 3]>> {
        match self.ask(Request::Positions)? {
            Reply::Positions(x) => Ok(x),
            Reply::Forces(_) => Err(SimError::Coupling("unexpected reply".into())),
        }
    }

    /// Stops the solver thread (also done on drop).
    pub fn close(&mut self) {
        self.tx = None;
        if let Some(w) = self.worker.take() {
            let _ = w.join();
        }
    }
}

impl Drop for Coupling {
    fn drop(&mut self) {
        self.close();
    }
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

/// The integrator of a coupling: the scene's, landing on every caller step, without an end.
fn coupled_integrator(prep: &Prepared, dt: f64) -> Integrator {
    match &prep.plan.dynamics {
        Some(Integrator::Hht(s)) => Integrator::Hht(DynamicSettings {
            dt,
            t_end: OPEN_END,
            output_interval: Some(dt),
            ..s.clone()
        }),
        Some(Integrator::Explicit(s)) => {
            let mut s = s.clone();
            s.t_end = OPEN_END;
            s.output_interval = Some(dt);
            Integrator::Explicit(s)
        }
        None => {
            let mut s = DynamicSettings::new(dt, OPEN_END);
            s.output_interval = Some(dt);
            Integrator::Hht(s)
        }
    }
}

/// The solver thread: owns the model, answers requests until the channel closes.
fn worker(prep: Prepared, rx: Receiver<Request>, tx: Sender<Reply>) {
    let model = &prep.built.model;
    let mut loads = match water_loads(&prep, Phase::Static) {
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
    let mut initial: Option<(State, Outputs)> = None;
    let mut solver: Option<Box<dyn Stepper + '_>> = None;
    while let Ok(req) = rx.recv() {
        let reply = match req {
            Request::Init => {
                if prep.plan.kind == AnalysisKind::Dynamic {
                    // Dynamics from the as-built state at rest: no forces known before a step.
                    let zero = prep
                        .built
                        .external
                        .iter()
                        .map(|(_, list)| vec![[0.0; 3]; list.len()])
                        .collect();
                    Reply::Forces(Ok(zero))
                } else {
                    let mut go_on =
                        |_: &aqua_fem::StaticProgress| aqua_fem::StaticControl::Continue;
                    match static_equilibrium(
                        model,
                        &prep.built.mesh,
                        &mut loads,
                        &prep.plan.statics,
                        &mut go_on,
                    ) {
                        Ok(s) => {
                            let f = point_forces(&prep, &s.outputs);
                            initial = Some((s.state, s.outputs));
                            Reply::Forces(Ok(f))
                        }
                        Err(e) => Reply::Forces(Err(e)),
                    }
                }
            }
            Request::Step { t1, dt } => Reply::Forces((|| {
                if solver.is_none() {
                    loads.phase = Phase::Dynamic;
                    let integ = coupled_integrator(&prep, dt);
                    let init = initial.as_ref().map(|s| &s.0);
                    solver = Some(start_integrator(model, &integ, init, &mut loads)?);
                }
                let s = solver
                    .as_mut()
                    .ok_or_else(|| SimError::Coupling("no solver".into()))?;
                // Sub-steps (halvings, an explicit scheme's smaller step) until the solver
                // lands on the next output time, which is t1: one coupling step, never two.
                while !s
                    .step(&mut loads)
                    .map_err(|e| SimError::Dynamic(Box::new(e)))?
                    .output_time
                {}
                let t = s.state().t;
                if (t - t1).abs() > 1e-9 * dt {
                    return Err(SimError::Coupling(format!(
                        "the solver reached t = {t} s instead of the step's end t = {t1} s"
                    )));
                }
                Ok(point_forces(&prep, s.outputs()))
            })()),
            // The mesh's nodes (a rod's twist carriers follow them in the model).
            Request::Positions => Reply::Positions({
                let np = prep.built.mesh.nodes.len();
                match (&solver, &initial) {
                    (Some(s), _) => s.state().x[..np].to_vec(),
                    (None, Some((st, _))) => st.x[..np].to_vec(),
                    (None, None) => model.nodes()[..np].to_vec(),
                }
            }),
        };
        if tx.send(reply).is_err() {
            break;
        }
    }
}
