//! Run files: a ParaView multiblock time series (`<scene>.pvd` → `<scene>_NNNNNN.vtm` per output
//! step → one `.vtu` per object and kind in `<scene>_NNNNNN/`, see [`aqua_mesh::io::vtm`]), the
//! undeformed geometry once (`<scene>_reference.vtm`), a pvpython starting point
//! (`open_in_paraview.py`), `summary.csv` (one row per output step), `extremes.csv` (the
//! extremes of the load columns over every accepted step, [`crate::extremes`]) and `run.json`
//! (resolved scene, name tables, final values, extremes, timing). Every output step is a
//! `summary.csv` row; only every `paraview_interval` is it also a step of the ParaView series
//! ([`RunFiles::write_frame`]).
//!
//! Every file is written so that an interrupted run leaves it readable: a step's block files
//! are written first, then its `.vtm` (temporary name + rename), and only then is the step
//! appended to the `.pvd` (one line, no rewrite); nothing is fsynced (see [`aqua_mesh::io::vtm`]
//! for what holds when the process stops). A step's `summary.csv` row is written and flushed
//! before its `.pvd` line, so whatever stops the process — even SIGKILL — `summary.csv` holds
//! a row for every step the `.pvd` lists (one short write per output step).
//!
//! **The files are written by a background thread** (docs/theory/fem.md#outputs): the run
//! loop checks a step's arrays for non-finite values, copies them and hands them over, and
//! goes on with the next time step while the thread encodes and writes them. At most
//! [`QUEUE_STEPS`] steps wait, so a disk slower than the solver slows the run instead of
//! filling memory. The thread writes the steps in order with the same guarantees as above.
//! [`RunFiles::flush`], [`RunFiles::steps_written`] and dropping wait until every handed-over
//! step is on disk, so what an ended, interrupted or failed run reports was written. The first
//! write error (or a panic of the writer thread, with its message) is returned by the next
//! call, and every later call fails with the same message; no step after it is written.
//!
//! Arrays of a step (docs/theory/fem.md#outputs) — points: `displacement` (x − X from the
//! as-built position X), `velocity`, `hydro_force`, `reaction`, `point_mass`, `supported`
//! (1 where a DOF is fixed or prescribed); lines: `tension`
//! (the axial force where it pulls, 0 where the member is slack), `slack` (1 where the axial
//! force is ≤ 0), `axial_force` (signed, incl. axial damping: negative values are compression of
//! bars or the damping and compression-ratio parts of a slack cable), `strain`, `wake_factor`;
//! panels: `wake_factor`.

use crate::build::Built;
use crate::error::{Result, SimError};
use crate::extremes::Extremes;
use crate::post::SummaryRow;
use aqua_fem::{Outputs, State};
use aqua_mesh::{BlockArray, Mesh, MultiblockSeries, NameTables, StepArrays};
use nalgebra::Point3;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

/// The pvpython script written next to every run (`DIR/open_in_paraview.py`).
pub const PARAVIEW_SCRIPT: &str = include_str!("open_in_paraview.py");

/// Output steps that may wait for the writer thread (each holds a copy of one step's arrays).
pub const QUEUE_STEPS: usize = 2;

/// Writers of one run.
#[derive(Debug)]
pub struct RunFiles {
    dir: PathBuf,
    pvd_path: PathBuf,
    names: NameTables,
    /// Point mass per node [kg] (point bodies incl. weights W/g), the same every step.
    point_mass: Vec<f64>,
    /// 1 where a node has a fixed or prescribed DOF (builders, `[[fix]]`, `[[prescribed]]`).
    supported: Vec<i32>,
    /// To the writer thread (`None` once closed).
    tx: Option<SyncSender<Job>>,
    thread: Option<JoinHandle<()>>,
    /// Steps written and the first write error, kept by the writer thread.
    shared: Arc<Mutex<Written>>,
    /// The first write error once it was returned: every later call fails with it.
    failed: Option<String>,
}

/// What the writer thread reports.
#[derive(Debug, Default)]
struct Written {
    steps: usize,
    paraview_steps: usize,
    error: Option<SimError>,
}

/// Work for the writer thread.
enum Job {
    Step(Box<StepJob>),
    /// A `summary.csv` row alone (an output step that is not a ParaView step).
    Row(String),
    /// Flush `summary.csv` and answer once every earlier job is done.
    Sync(std::sync::mpsc::Sender<()>),
}

/// One output step, owned.
struct StepJob {
    t: f64,
    positions: Vec<Point3<f64>>,
    arrays: StepArrays,
    csv_line: String,
}

/// The writer thread's side: the series and `summary.csv`.
struct Disk {
    series: MultiblockSeries,
    mesh: Arc<Mesh>,
    csv: std::io::BufWriter<std::fs::File>,
    csv_path: PathBuf,
}

impl Disk {
    /// Writes jobs in order until the channel closes; after an error, only answers syncs.
    fn serve(mut self, rx: Receiver<Job>, shared: Arc<Mutex<Written>>) {
        let mut failed = false;
        while let Ok(job) = rx.recv() {
            match job {
                Job::Step(step) if !failed => {
                    let r = self.write(&step);
                    let mut w = shared.lock().unwrap_or_else(|e| e.into_inner());
                    match r {
                        Ok(()) => {
                            w.steps += 1;
                            w.paraview_steps += 1;
                        }
                        Err(e) => {
                            w.error.get_or_insert(e);
                            failed = true;
                        }
                    }
                }
                Job::Row(line) if !failed => {
                    let r = self.write_row(&line);
                    let mut w = shared.lock().unwrap_or_else(|e| e.into_inner());
                    match r {
                        Ok(()) => w.steps += 1,
                        Err(e) => {
                            w.error.get_or_insert(e);
                            failed = true;
                        }
                    }
                }
                Job::Step(_) | Job::Row(_) => {}
                Job::Sync(done) => {
                    let _ = done.send(());
                }
            }
        }
    }

    /// The step's `summary.csv` row (flushed), then its blocks, `.vtm` and `.pvd` line.
    fn write(&mut self, step: &StepJob) -> Result<()> {
        self.write_row(&step.csv_line)?;
        self.series
            .write_step(step.t, &self.mesh, &step.positions, &step.arrays)
            .map_err(|e| SimError::Output(Box::new(e)))?;
        Ok(())
    }

    /// A `summary.csv` row, flushed.
    fn write_row(&mut self, line: &str) -> Result<()> {
        writeln!(self.csv, "{line}")
            .and_then(|_| self.csv.flush())
            .map_err(io("writing", &self.csv_path))
    }
}

fn io(what: &'static str, path: &Path) -> impl FnOnce(std::io::Error) -> SimError {
    let path = path.to_path_buf();
    move |source| SimError::Io { what, path, source }
}

impl RunFiles {
    /// Creates the output directory, removes the steps of an earlier run of the same scene,
    /// writes the undeformed geometry, the ParaView script and `summary.csv`'s header.
    pub fn create(dir: &Path, scene_name: &str, built: &Built) -> Result<Self> {
        std::fs::create_dir_all(dir).map_err(io("creating the output directory", dir))?;
        let out = |e| SimError::Output(Box::new(e));
        let series = MultiblockSeries::new(dir, scene_name, &built.mesh).map_err(out)?;
        series.write_reference(&built.mesh).map_err(out)?;
        let script = dir.join("open_in_paraview.py");
        let abs = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
        let here = serde_json::to_string(&abs.to_string_lossy()).unwrap_or_else(|_| "None".into());
        let text =
            PARAVIEW_SCRIPT.replacen("WRITTEN_IN = None", &format!("WRITTEN_IN = {here}"), 1);
        std::fs::write(&script, text).map_err(io("writing", &script))?;
        let mut point_mass = vec![0.0; built.mesh.nodes.len()];
        for b in built.model.point_bodies() {
            if let Some(m) = point_mass.get_mut(b.node) {
                *m += b.mass;
            }
        }
        let mut supported = vec![0; built.mesh.nodes.len()];
        for &n in &built.supported_nodes {
            if let Some(s) = supported.get_mut(n) {
                *s = 1;
            }
        }
        // An earlier run's extremes would stand for this run's until it writes its own.
        let stale = dir.join("extremes.csv");
        if stale.exists() {
            std::fs::remove_file(&stale).map_err(io("removing", &stale))?;
        }
        let path = dir.join("summary.csv");
        let mut csv =
            std::io::BufWriter::new(std::fs::File::create(&path).map_err(io("creating", &path))?);
        writeln!(csv, "{}", SummaryRow::columns(built).join(","))
            .and_then(|_| csv.flush())
            .map_err(io("writing", &path))?;
        let (pvd_path, names) = (series.pvd_path().to_path_buf(), series.names().clone());
        let disk = Disk {
            series,
            mesh: Arc::new(built.mesh.clone()),
            csv,
            csv_path: path,
        };
        let shared = Arc::new(Mutex::new(Written::default()));
        let (tx, rx) = std::sync::mpsc::sync_channel(QUEUE_STEPS);
        let thread = {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new()
                .name("aqua-output".into())
                .spawn(move || disk.serve(rx, shared))
                .map_err(io("starting the output writer for", dir))?
        };
        Ok(Self {
            dir: dir.to_path_buf(),
            pvd_path,
            names,
            point_mass,
            supported,
            tx: Some(tx),
            thread: Some(thread),
            shared,
            failed: None,
        })
    }

    /// The `.pvd` path.
    pub fn pvd_path(&self) -> PathBuf {
        self.pvd_path.clone()
    }

    /// The output directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Object, group, role and block names (written into `run.json`).
    pub fn names(&self) -> &NameTables {
        &self.names
    }

    /// Writes an output frame of the run loop: its `summary.csv` row, and, when it is a step of
    /// the ParaView series (`frame.paraview`), its blocks, `.vtm` and `.pvd` line.
    pub fn write_frame(&mut self, built: &Built, frame: &crate::run::Frame<'_>) -> Result<()> {
        if frame.paraview {
            self.write_step(built, frame.state, frame.outputs, frame.wake, frame.row)
        } else {
            self.write_row(frame.row)
        }
    }

    /// Writes a `summary.csv` row alone (an output step that is not a ParaView step).
    pub fn write_row(&mut self, row: &SummaryRow) -> Result<()> {
        self.take_error()?;
        self.send(Job::Row(row.values_text().join(",")))
    }

    /// Hands a job to the writer thread.
    fn send(&mut self, job: Job) -> Result<()> {
        if self.tx.as_ref().is_none_or(|tx| tx.send(job).is_err()) {
            // A write error found meanwhile explains the closed queue better.
            self.take_error()?;
            return Err(self.writer_gone());
        }
        Ok(())
    }

    /// Writes one output step: the blocks, the `.vtm` (and `.pvd` line) and a `summary.csv` row.
    pub fn write_step(
        &mut self,
        built: &Built,
        state: &State,
        out: &Outputs,
        wake: &[f64],
        row: &SummaryRow,
    ) -> Result<()> {
        let model = &built.model;
        let mesh = &built.mesh;
        // The mesh's nodes; a rod's twist carriers and ghost nodes follow them in the model.
        let np = mesh.nodes.len();
        let x = &state.x[..np];
        let finite = |name: &str, v: &[f64]| -> Result<()> {
            if let Some(i) = v.iter().position(|a| !a.is_finite()) {
                return Err(SimError::NonFinite(format!(
                    "non-finite {name} at index {i}, t = {} s: not written",
                    state.t
                )));
            }
            Ok(())
        };
        let positions: Vec<Point3<f64>> = x.iter().map(|p| Point3::from(*p)).collect();
        let disp: Vec<[f64; 3]> = x
            .iter()
            .zip(model.nodes())
            .map(|(a, b)| [a[0] - b[0], a[1] - b[1], a[2] - b[2]])
            .collect();
        let point = vec![
            BlockArray::vectors("displacement", &disp),
            BlockArray::vectors("velocity", &state.v[..np]),
            BlockArray::vectors("hydro_force", &out.hydro_force[..np]),
            BlockArray::vectors("reaction", &out.reaction[..np]),
            BlockArray::scalar("point_mass", self.point_mass.clone()),
            BlockArray::int("supported", self.supported.clone()),
        ];
        for a in &point {
            if let aqua_mesh::io::vtm::ArrayValues::F64 { values, .. } = &a.values {
                finite(&a.name, values)?;
            }
        }
        let nl = mesh.lines.len();
        let axial = &out.tension[..nl.min(out.tension.len())];
        finite("axial force", axial)?;
        finite("strain", &out.strain)?;
        finite("wake factor", wake)?;
        let tension: Vec<f64> = axial.iter().map(|&n| n.max(0.0)).collect();
        let slack: Vec<i32> = axial.iter().map(|&n| i32::from(n <= 0.0)).collect();
        let (wake_lines, wake_panels) = wake.split_at(nl.min(wake.len()));
        let mut line = vec![
            BlockArray::scalar("tension", tension),
            BlockArray::int("slack", slack),
            BlockArray::scalar("axial_force", axial.to_vec()),
            BlockArray::scalar("strain", out.strain[..nl.min(out.strain.len())].to_vec()),
            BlockArray::scalar("wake_factor", wake_lines.to_vec()),
        ];
        if !built.pipes.is_empty() {
            // Section forces and stress of the pipes modelled as rods (docs/theory/fem.md#rod).
            let mut stress = vec![0.0; nl];
            crate::pipe_stress::fibre_stresses(built, out, &mut stress);
            for (name, v) in [
                ("bending_moment", out.bending_moment[..nl].to_vec()),
                ("torque", out.torque[..nl].to_vec()),
                ("fibre_stress", stress),
            ] {
                finite(name, &v)?;
                line.push(BlockArray::scalar(name, v));
            }
        }
        let arrays = StepArrays {
            point,
            line,
            panel: std::iter::once(BlockArray::scalar("wake_factor", wake_panels.to_vec()))
                .chain(crate::net_triangles::panel_arrays(built, x))
                .collect(),
        };
        self.take_error()?;
        let job = Job::Step(Box::new(StepJob {
            t: state.t,
            positions,
            arrays,
            csv_line: row.values_text().join(","),
        }));
        self.send(job)
    }

    /// Waits until every handed-over step is written and `summary.csv` is flushed; returns
    /// the first write error (also on every call after it).
    pub fn flush(&mut self) -> Result<()> {
        let answered = self.sync();
        self.take_error()?;
        if !answered {
            return Err(self.writer_gone());
        }
        Ok(())
    }

    /// An earlier call already returned a write error (every later call repeats it).
    pub fn write_failed(&self) -> bool {
        self.failed.is_some()
    }

    /// Output steps (`summary.csv` rows) on disk (after waiting for those handed over).
    pub fn steps_written(&self) -> usize {
        self.sync();
        self.shared.lock().unwrap_or_else(|e| e.into_inner()).steps
    }

    /// Steps of the ParaView series on disk (after waiting for those handed over).
    pub fn paraview_steps_written(&self) -> usize {
        self.sync();
        self.shared
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .paraview_steps
    }

    /// Waits for the writer thread to finish what it was given; false when it is not there.
    fn sync(&self) -> bool {
        let (done_tx, done_rx) = std::sync::mpsc::channel();
        match &self.tx {
            Some(tx) if tx.send(Job::Sync(done_tx)).is_ok() => done_rx.recv().is_ok(),
            _ => false,
        }
    }

    /// The write error, first as found, then as the same message on every later call.
    fn take_error(&mut self) -> Result<()> {
        if let Some(msg) = &self.failed {
            return Err(self.earlier_failure(msg.clone()));
        }
        let e = self
            .shared
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .error
            .take();
        match e {
            Some(e) => {
                self.tx = None;
                self.failed = Some(e.chain());
                Err(e)
            }
            None => Ok(()),
        }
    }

    fn earlier_failure(&self, msg: String) -> SimError {
        SimError::Io {
            what: "writing (an earlier output step failed, later steps are not written)",
            path: self.pvd_path.clone(),
            source: std::io::Error::other(msg),
        }
    }

    /// The error when the writer thread is no longer there: it panicked (its message is
    /// reported), and no later step is written.
    fn writer_gone(&mut self) -> SimError {
        self.tx = None;
        let why = match self.thread.take().map(JoinHandle::join) {
            Some(Err(payload)) => {
                let text = payload
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| payload.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "no message".into());
                format!("the output writer thread panicked: {text}")
            }
            _ => "the output writer thread ended".to_string(),
        };
        self.failed = Some(why.clone());
        SimError::Io {
            what: "writing (the output writer stopped)",
            path: self.pvd_path.clone(),
            source: std::io::Error::other(why),
        }
    }

    /// Writes `run.json` atomically.
    pub fn write_json(&self, value: &serde_json::Value) -> Result<()> {
        let text = serde_json::to_string_pretty(value)
            .unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
        self.write_atomically("run.json", &text)
    }

    /// Writes `extremes.csv` atomically (one row per load column: column, max, t_max, min,
    /// t_min; only the header before any state was reached).
    pub fn write_extremes(&self, extremes: &Extremes) -> Result<()> {
        self.write_atomically("extremes.csv", &extremes.csv())
    }

    /// Writes `DIR/name` through a temporary file and a rename.
    fn write_atomically(&self, name: &str, text: &str) -> Result<()> {
        let path = self.dir.join(name);
        let tmp = self.dir.join(format!(".{name}.tmp"));
        std::fs::write(&tmp, text).map_err(io("writing", &tmp))?;
        std::fs::rename(&tmp, &path).map_err(io("writing", &path))?;
        Ok(())
    }
}

impl Drop for RunFiles {
    /// Closes the queue and waits until the writer thread has written what it holds.
    fn drop(&mut self) {
        self.tx = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Writes the wave component table (i, ω, T, k, a, β, φ) that reproduces a sea exactly
/// (docs/theory/environment.md#summation).
pub fn write_component_table(sea: &aqua_env::Sea, path: &Path) -> Result<()> {
    let mut text = String::from("i,omega,T,k,a,beta_deg,phase_deg\n");
    if let aqua_env::Waves::Linear { sum, .. } = sea.waves() {
        for (i, c) in sum.components().iter().enumerate() {
            text.push_str(&format!(
                "{i},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e}\n",
                c.omega,
                c.period(),
                c.k,
                c.amplitude,
                c.direction.to_degrees(),
                c.phase.to_degrees()
            ));
        }
    }
    std::fs::write(path, text).map_err(io("writing", path))
}

/// Writes sea kinematics at `points` every `dt` up to `duration` [s] as CSV
/// (`t,x,y,z,eta,u,v,w,ax,ay,az`; velocity and acceleration are current plus waves).
pub fn write_kinematics(
    sea: &aqua_env::Sea,
    points: &[[f64; 3]],
    duration: f64,
    dt: f64,
    path: &Path,
) -> Result<()> {
    let mut f = String::from("t,x,y,z,eta,u,v,w,ax,ay,az\n");
    let steps = (duration / dt + 1e-9).floor() as usize;
    let mut out = vec![aqua_env::FlowPoint::default(); points.len()];
    for n in 0..=steps {
        let t = n as f64 * dt;
        sea.eval(t, aqua_env::Phase::Dynamic, points, &mut out);
        for (p, k) in points.iter().zip(&out) {
            let u = k.velocity();
            let a = [
                k.current_acc[0] + k.wave_acc[0],
                k.current_acc[1] + k.wave_acc[1],
                k.current_acc[2] + k.wave_acc[2],
            ];
            // + 0.0 turns −0 into 0 so the CSV never shows "-0".
            let vals = [k.eta, u[0], u[1], u[2], a[0], a[1], a[2]].map(|v| v + 0.0);
            if vals.iter().any(|v| !v.is_finite()) {
                return Err(SimError::NonFinite(format!(
                    "non-finite sea kinematics at t = {t} s, point {p:?}"
                )));
            }
            f.push_str(&format!(
                "{t},{},{},{},{},{},{},{},{},{},{}\n",
                p[0], p[1], p[2], vals[0], vals[1], vals[2], vals[3], vals[4], vals[5], vals[6]
            ));
        }
    }
    std::fs::write(path, f).map_err(io("writing", path))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{
        Frame, Observer, PrepareOptions, Simulation, prepare,
        scene::{SceneInput, read_scene},
    };

    /// One output frame, owned: state, outputs, wake factors, summary row.
    type Kept = (State, Outputs, Vec<f64>, SummaryRow);

    /// A short static+dynamic run of a 10-segment chain: its output frames, kept.
    fn frames() -> (crate::Prepared, Vec<Kept>) {
        let text = r#"
            name = "chain"
            [sea]
            depth = 50.0
            [[line]]
            name = "chain"
            anchor = [0.0, 0.0, -50.0]
            fairlead = [100.0, 0.0, -5.0]
            length = 120.0
            segments = 10
            diameter = 0.1354
            mass_per_length = 113.0
            ea = 5.4e8
            [analysis]
            kind = "static+dynamic"
            [analysis.dynamic]
            dt = 0.1
            t_end = 0.3
            output_interval = 0.1
        "#;
        let scene = read_scene(
            SceneInput::Text {
                text,
                path: Path::new("chain.toml"),
            },
            &[],
        )
        .unwrap();
        let prep = prepare(PrepareOptions::scene(scene)).unwrap();
        struct Keep(Vec<Kept>);
        impl Observer for Keep {
            fn frame(&mut self, f: &Frame<'_>) -> Result<()> {
                let row = f.row.clone();
                self.0
                    .push((f.state.clone(), f.outputs.clone(), f.wake.to_vec(), row));
                Ok(())
            }
        }
        let mut keep = Keep(Vec::new());
        let (_, result) = Simulation::new(&prep).unwrap().run(&mut keep);
        result.unwrap();
        assert!(keep.0.len() >= 3, "{} frames", keep.0.len());
        (prep, keep.0)
    }

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("aqua-files-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_write_error_is_returned_and_every_later_call_fails_with_it() {
        let (prep, frames) = frames();
        let dir = scratch("error");
        let mut files = RunFiles::create(&dir, "chain", &prep.built).unwrap();
        let (s, o, w, r) = &frames[0];
        files.write_step(&prep.built, s, o, w, r).unwrap();
        files.flush().unwrap();
        assert_eq!(files.steps_written(), 1);
        // The output directory replaced by a file: the next step cannot be written.
        std::fs::remove_dir_all(&dir).unwrap();
        std::fs::write(&dir, "not a directory").unwrap();
        let (s, o, w, r) = &frames[1];
        // Handed over; the error comes from the writer thread, at the next call.
        let _ = files.write_step(&prep.built, s, o, w, r);
        let first = files
            .flush()
            .expect_err("the failed step is reported")
            .chain();
        let again = files.flush().expect_err("still failed").chain();
        assert!(again.contains("earlier output step failed"), "{again}");
        assert!(again.contains(&first), "{again} / {first}");
        let (s, o, w, r) = &frames[2];
        let later = files
            .write_step(&prep.built, s, o, w, r)
            .expect_err("not written")
            .chain();
        assert!(later.contains(&first), "{later}");
        assert_eq!(files.steps_written(), 1, "only the step before the error");
        drop(files);
        std::fs::remove_file(&dir).unwrap();
    }

    #[test]
    fn summary_rows_reach_the_file_before_their_step_reaches_the_pvd() {
        let (prep, frames) = frames();
        let dir = scratch("csv");
        let mut files = RunFiles::create(&dir, "chain", &prep.built).unwrap();
        let pvd = files.pvd_path();
        let rows = || {
            std::fs::read_to_string(dir.join("summary.csv"))
                .unwrap()
                .lines()
                .count()
        };
        let listed = || {
            std::fs::read_to_string(&pvd)
                .map(|t| t.matches("<DataSet").count())
                .unwrap_or(0)
        };
        // Without a flush, wherever the writer thread is: every step the .pvd lists already
        // has its row on disk (what a SIGKILL would leave).
        let rows_cover_the_pvd = || {
            let (l, n) = (listed(), rows());
            assert!(
                n > l,
                "{l} steps listed in the .pvd but {} summary rows",
                n - 1
            );
            l
        };
        for (s, o, w, r) in &frames {
            files.write_step(&prep.built, s, o, w, r).unwrap();
            rows_cover_the_pvd();
        }
        let start = std::time::Instant::now();
        while rows_cover_the_pvd() < frames.len()
            && start.elapsed() < std::time::Duration::from_secs(10)
        {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        assert_eq!(rows(), frames.len() + 1, "header and one row per step");
        files.flush().unwrap();
        assert_eq!(files.steps_written(), frames.len());
        drop(files);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
