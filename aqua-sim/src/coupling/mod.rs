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
//! Each call may take its own step; the solver advances with its own step (the scene's
//! `analysis.dynamic.dt`, else the first call's) and lands on the call's end. A call that fails
//! leaves the coupling where it was, to be retried with a smaller step (implicit schemes).
//! [`Coupling::save`] and [`Coupling::restore`] keep and put back the whole state;
//! [`Coupling::tensions`] and [`Coupling::positions`] read the structure mid-run, and
//! [`Coupling::add_body`] groups points on a rigid body driven by its pose (`body.rs`).
//!
//! The points are the `[[prescribed]]` entries, named by their `nodes` reference (e.g.
//! `"chain/fairlead"`); positions are absolute [m]. Between two calls the solver sees the
//! cubic Hermite motion through the given positions and velocities (velocities not given are
//! the backward difference of the positions, and then the acceleration, if not given, is the
//! backward difference of the velocities). The force on a point is the force of the
//! structure on whatever holds it, F = −R (R the support reaction of the run outputs) [N].
//!
//! The solver runs on its own thread (`worker.rs`), which owns the model (the integrators
//! borrow it), so a `Coupling` can be kept by a caller with no lifetime, as a Python object.

mod body;
mod output;
mod worker;

pub use body::{BodyTarget, CoupledBody, rotation};

use crate::build::Prescribed;
use crate::error::{Result, SimError};
use crate::plan::{PrepareOptions, prepare};
use crate::scene::Scene;
use aqua_fem::{ExternalMotion, Keyframes, Snapshot};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;
use worker::{Reply, Request, worker};

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

/// The element tensions and what names them: element e joins `elements[e]` (mesh nodes, the
/// order of [`Coupling::positions`]) and belongs to group `group_names[groups[e]]`
/// ("object/group", as in the scene).
#[derive(Debug, Clone, PartialEq)]
pub struct ElementTable {
    /// Node pairs.
    pub elements: Vec<[usize; 2]>,
    /// Group index per element.
    pub groups: Vec<usize>,
    /// Group names.
    pub group_names: Vec<String>,
}

/// The caller's clock: call k of a run of equal steps ends at `base + k·dt` exactly, the same
/// product the solver lands on (a running sum would drift from it in its last bits;
/// docs/theory/fem.md#coupling).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Clock {
    base: f64,
    k: u64,
    dt: f64,
}

impl Clock {
    /// The end of a call of step `dt` from `now`, and the clock after it.
    fn advance(self, now: f64, dt: f64) -> (f64, Clock) {
        if self.dt > 0.0 && (dt - self.dt).abs() <= 1e-12 * self.dt {
            let k = self.k + 1;
            (self.base + k as f64 * self.dt, Clock { k, ..self })
        } else {
            let c = Clock {
                base: now,
                k: 1,
                dt,
            };
            (now + dt, c)
        }
    }
}

/// The coupling's whole state, from [`Coupling::save`].
#[derive(Debug, Clone)]
pub struct CouplingState {
    solver: Option<Box<Snapshot>>,
    keyframes: Vec<Vec<Keyframes>>,
    last: Vec<Vec<([f64; 3], [f64; 3])>>,
    poses: Vec<[f64; 6]>,
    time: f64,
    clock: Clock,
}

impl CouplingState {
    /// The model time of the saved state [s].
    pub fn time(&self) -> f64 {
        self.time
    }
}

/// A scene driven from outside; see the module docs.
#[derive(Debug)]
pub struct Coupling {
    points: Vec<CoupledPoint>,
    bodies: Vec<CoupledBody>,
    /// Each body's pose at the end of the last call.
    poses: Vec<[f64; 6]>,
    motions: Vec<Vec<ExternalMotion>>,
    last: Vec<Vec<([f64; 3], [f64; 3])>>,
    table: ElementTable,
    tx: Option<Sender<Request>>,
    rx: Receiver<Reply>,
    worker: Option<JoinHandle<()>>,
    /// The model time: the end of the last call that succeeded [s].
    time: f64,
    clock: Clock,
    initialised: bool,
}

impl Coupling {
    /// Builds the scene with every `[[prescribed]]` node driven from outside.
    pub fn new(scene: Scene) -> Result<Self> {
        let prep = prepare(PrepareOptions::scene(scene).with_prescribed(Prescribed::External))?;
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
        let elements = prep.built.model.elements();
        let table = ElementTable {
            elements: elements.iter().map(|e| [e.a, e.b]).collect(),
            groups: elements.iter().map(|e| e.group).collect(),
            group_names: prep.built.group_names.clone(),
        };
        let (tx, rx_req) = channel();
        let (tx_rep, rx) = channel();
        let worker = std::thread::Builder::new()
            .name("aqua-coupling".into())
            .spawn(move || worker(prep, rx_req, tx_rep))
            .map_err(|e| SimError::Coupling(format!("cannot start the solver thread: {e}")))?;
        Ok(Self {
            points,
            bodies: Vec::new(),
            poses: Vec::new(),
            motions,
            last,
            table,
            tx: Some(tx),
            rx,
            worker: Some(worker),
            time: 0.0,
            clock: Clock {
                base: 0.0,
                k: 0,
                dt: 0.0,
            },
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

    /// Puts the points named in `points` on a rigid body called `name` whose reference point
    /// is built at `origin` [m] (see `body.rs` for the pose and its conventions). A point
    /// belongs to one body at most. Returns the body's index.
    pub fn add_body(&mut self, name: &str, points: &[&str], origin: [f64; 3]) -> Result<usize> {
        if self.bodies.iter().any(|b| b.name == name) {
            return Err(SimError::Coupling(format!(
                "a body called \"{name}\" exists already"
            )));
        }
        if points.is_empty() {
            return Err(SimError::Coupling(format!(
                "body \"{name}\": give the coupled points it carries"
            )));
        }
        let mut idx = Vec::with_capacity(points.len());
        for p in points {
            let i = self.point(p)?;
            if idx.contains(&i) || self.bodies.iter().any(|b| b.points.contains(&i)) {
                return Err(SimError::Coupling(format!(
                    "body \"{name}\": point \"{p}\" is already on a body"
                )));
            }
            idx.push(i);
        }
        let body = CoupledBody::new(name, idx, &self.points, origin)?;
        self.bodies.push(body);
        self.poses
            .push([origin[0], origin[1], origin[2], 0.0, 0.0, 0.0]);
        Ok(self.bodies.len() - 1)
    }

    /// The coupled bodies.
    pub fn bodies(&self) -> &[CoupledBody] {
        &self.bodies
    }

    /// The index of a body by its name.
    pub fn body(&self, name: &str) -> Result<usize> {
        self.bodies
            .iter()
            .position(|b| b.name == name)
            .ok_or_else(|| SimError::Coupling(format!("\"{name}\" is no coupled body")))
    }

    /// The model time [s]: the end of the last call that succeeded.
    pub fn time(&self) -> f64 {
        self.time
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
            _ => Err(SimError::Coupling("unexpected reply".into())),
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
    /// [`Coupling::points`], where the point is at `t + dt`) and the bodies in `bodies`
    /// (index into [`Coupling::bodies`]); points and bodies not given stay where they are.
    /// Returns the forces on all points at `t + dt`. When the step fails the coupling stays
    /// at `t` (implicit schemes) and the call may be repeated with a smaller `dt`.
    pub fn step(
        &mut self,
        t: f64,
        dt: f64,
        targets: &[(usize, Target)],
        bodies: &[(usize, BodyTarget)],
    ) -> Result<Forces> {
        if !self.initialised {
            return Err(SimError::Coupling("call init before step".into()));
        }
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SimError::Coupling(format!("dt = {dt}: a step > 0 s")));
        }
        let now = self.time;
        if (t - now).abs() > 1e-9 * dt + 1e-12 * t.abs() {
            return Err(SimError::Coupling(format!(
                "step from t = {t} s, but the model is at t = {now} s"
            )));
        }
        // The end of the call is the clock's product, the time the solver lands on exactly:
        // the motion's end keyframe and the solver's clock are the same number.
        let (t1, clock) = self.clock.advance(now, dt);
        let mut all: Vec<(usize, Target)> = targets.to_vec();
        for (b, target) in bodies {
            let body = self
                .bodies
                .get(*b)
                .ok_or_else(|| SimError::Coupling(format!("no coupled body #{b}")))?;
            all.extend(body.targets(target)?);
        }
        let mut given = vec![false; self.points.len()];
        for (i, _) in &all {
            let g = given
                .get_mut(*i)
                .ok_or_else(|| SimError::Coupling(format!("no coupled point #{i}")))?;
            if *g {
                return Err(SimError::Coupling(format!(
                    "\"{}\" is given twice (as a point and on a body, or twice)",
                    self.points[*i].name
                )));
            }
            *g = true;
        }
        let saved = self.keyframes();
        let last = self.last.clone();
        let set = (|| {
            for (i, target) in &all {
                self.set_target(*i, target, t1, dt)?;
            }
            for i in (0..self.points.len()).filter(|&i| !given[i]) {
                let hold = Target {
                    position: self.last[i].iter().map(|(x, _)| *x).collect(),
                    velocity: Some(vec![[0.0; 3]; self.points[i].nodes.len()]),
                    acceleration: None,
                };
                self.set_target(i, &hold, t1, dt)?;
            }
            self.forces(Request::Step { t1, dt })
        })();
        match set {
            Ok(f) => {
                self.time = t1;
                self.clock = clock;
                for (b, target) in bodies {
                    self.poses[*b] = target.pose;
                }
                Ok(f)
            }
            Err(e) => {
                // Back to where the call started, so that it can be retried.
                self.set_keyframes(&saved);
                self.last = last;
                Err(e)
            }
        }
    }

    /// [F_x, F_y, F_z, M_x, M_y, M_z] [N, N·m] of `forces` (as returned by the last call) on
    /// body `b`, the moment about its reference point where the last call put it.
    pub fn body_wrench(&self, b: usize, forces: &Forces) -> Result<[f64; 6]> {
        let body = self
            .bodies
            .get(b)
            .ok_or_else(|| SimError::Coupling(format!("no coupled body #{b}")))?;
        let positions: Vec<Vec<[f64; 3]>> = self
            .last
            .iter()
            .map(|p| p.iter().map(|(x, _)| *x).collect())
            .collect();
        Ok(body.wrench(forces, &positions, self.poses[b]))
    }

    fn keyframes(&self) -> Vec<Vec<Keyframes>> {
        self.motions
            .iter()
            .map(|m| m.iter().map(|m| m.keyframes()).collect())
            .collect()
    }

    fn set_keyframes(&self, frames: &[Vec<Keyframes>]) {
        for (m, f) in self.motions.iter().zip(frames) {
            for (m, f) in m.iter().zip(f) {
                m.set_keyframes(*f);
            }
        }
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

    /// Positions of the mesh nodes [m], in mesh node order (the order of
    /// [`ElementTable::elements`]).
    pub fn positions(&self) -> Result<Vec<[f64; 3]>> {
        match self.ask(Request::Positions)? {
            Reply::Positions(x) => Ok(x),
            _ => Err(SimError::Coupling("unexpected reply".into())),
        }
    }

    /// Tension of every cable element [N] at the current state, in the order of
    /// [`Coupling::elements`].
    pub fn tensions(&self) -> Result<Vec<f64>> {
        match self.ask(Request::Tensions)? {
            Reply::Tensions(x) => Ok(x),
            _ => Err(SimError::Coupling("unexpected reply".into())),
        }
    }

    /// What names the elements of [`Coupling::tensions`].
    pub fn elements(&self) -> &ElementTable {
        &self.table
    }

    /// The whole state: the solver's, the points' motions, the bodies' poses and the clock.
    /// [`Coupling::restore`] puts it back, and the calls after it repeat those after the save
    /// bit for bit (implicit schemes).
    pub fn save(&mut self) -> Result<CouplingState> {
        if !self.initialised {
            return Err(SimError::Coupling("call init before save".into()));
        }
        let solver = match self.ask(Request::Save)? {
            Reply::Saved(s) => s?,
            _ => return Err(SimError::Coupling("unexpected reply".into())),
        };
        Ok(CouplingState {
            solver,
            keyframes: self.keyframes(),
            last: self.last.clone(),
            poses: self.poses.clone(),
            time: self.time,
            clock: self.clock,
        })
    }

    /// Puts back a state of [`Coupling::save`] of this coupling.
    pub fn restore(&mut self, state: &CouplingState) -> Result<()> {
        if state.keyframes.len() != self.motions.len() || state.poses.len() > self.poses.len() {
            return Err(SimError::Coupling(
                "restore: the state is of another coupling".into(),
            ));
        }
        match self.ask(Request::Restore(state.solver.clone()))? {
            Reply::Restored(r) => r?,
            _ => return Err(SimError::Coupling("unexpected reply".into())),
        }
        self.set_keyframes(&state.keyframes);
        self.last.clone_from(&state.last);
        self.poses[..state.poses.len()].copy_from_slice(&state.poses);
        self.time = state.time;
        self.clock = state.clock;
        Ok(())
    }

    /// Writes the run's files into `dir` (created if missing) from `init` on: `summary.csv`
    /// with a row at the end of every call, the ParaView series, `extremes.csv` over every
    /// step the solver accepted (see `output.rs`). Call before `init`.
    pub fn write_to(&mut self, dir: &std::path::Path) -> Result<()> {
        if self.initialised {
            return Err(SimError::Coupling(
                "write_to must come before init (the files start with its state)".into(),
            ));
        }
        match self.ask(Request::Output(dir.to_path_buf()))? {
            Reply::Done(r) => r,
            _ => Err(SimError::Coupling("unexpected reply".into())),
        }
    }

    /// Writes what is still queued and `extremes.csv`, then stops the solver thread (also
    /// done on drop, where a write error is lost: call `close` to see it). Later calls fail.
    pub fn close(&mut self) -> Result<()> {
        let finished = match self.tx.is_some().then(|| self.ask(Request::Finish)) {
            Some(Ok(Reply::Done(r))) => r,
            Some(Ok(_)) => Err(SimError::Coupling("unexpected reply".into())),
            Some(Err(e)) => Err(e),
            None => Ok(()),
        };
        self.tx = None;
        if let Some(w) = self.worker.take() {
            let _ = w.join();
        }
        finished
    }
}

impl Drop for Coupling {
    fn drop(&mut self) {
        let _ = self.close();
    }
}
