//! Run files: a ParaView multiblock time series (`<scene>.pvd` → `<scene>_NNNNNN.vtm` per output
//! step → one `.vtu` per object and kind in `<scene>_NNNNNN/`, see [`aqua_mesh::vtm`]), the
//! undeformed geometry once (`<scene>_reference.vtm`), a pvpython starting point
//! (`open_in_paraview.py`), `summary.csv` (one row per output step) and `run.json` (resolved
//! scene, name tables, final values, timing).
//!
//! Every file is written so that an interrupted run leaves it readable: a step's block files
//! are written first, then its `.vtm` (temporary name + rename), and only then is the step
//! appended to the `.pvd` (one line, no rewrite); nothing is fsynced (see [`aqua_mesh::vtm`]
//! for what holds when the process stops). `summary.csv` rows are buffered and flushed at
//! least every [`CSV_FLUSH_INTERVAL`] of wall time and by [`RunFiles::flush`] (which the end
//! of a run, an interruption or a failure calls, and dropping [`RunFiles`] does too).
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
use crate::post::SummaryRow;
use aqua_fem::{Outputs, State};
use aqua_mesh::{BlockArray, MultiblockSeries, NameTables, StepArrays};
use nalgebra::Point3;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The pvpython script written next to every run (`DIR/open_in_paraview.py`).
pub const PARAVIEW_SCRIPT: &str = include_str!("open_in_paraview.py");

/// Longest wall time a `summary.csv` row stays in memory while a run goes on.
pub const CSV_FLUSH_INTERVAL: std::time::Duration = std::time::Duration::from_secs(1);

/// Writers of one run.
#[derive(Debug)]
pub struct RunFiles {
    dir: PathBuf,
    series: MultiblockSeries,
    /// Point mass per node [kg] (point bodies incl. weights W/g), the same every step.
    point_mass: Vec<f64>,
    /// 1 where a node has a fixed or prescribed DOF (builders, `[[fix]]`, `[[prescribed]]`).
    supported: Vec<i32>,
    csv: std::io::BufWriter<std::fs::File>,
    csv_path: PathBuf,
    /// When `summary.csv` was last flushed.
    csv_flushed: std::time::Instant,
    /// Output steps written.
    pub steps_written: usize,
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
        let path = dir.join("summary.csv");
        let mut csv =
            std::io::BufWriter::new(std::fs::File::create(&path).map_err(io("creating", &path))?);
        writeln!(csv, "{}", SummaryRow::columns(built).join(","))
            .and_then(|_| csv.flush())
            .map_err(io("writing", &path))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            series,
            point_mass,
            supported,
            csv,
            csv_path: path,
            csv_flushed: std::time::Instant::now(),
            steps_written: 0,
        })
    }

    /// The `.pvd` path.
    pub fn pvd_path(&self) -> PathBuf {
        self.series.pvd_path().to_path_buf()
    }

    /// The output directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Object, group, role and block names (the field data of every block; `run.json`).
    pub fn names(&self) -> &NameTables {
        self.series.names()
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
        let x = &state.x;
        let model = &built.model;
        let mesh = &built.mesh;
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
            BlockArray::vectors("velocity", &state.v),
            BlockArray::vectors("hydro_force", &out.hydro_force),
            BlockArray::vectors("reaction", &out.reaction),
            BlockArray::scalar("point_mass", self.point_mass.clone()),
            BlockArray::int("supported", self.supported.clone()),
        ];
        for a in &point {
            if let aqua_mesh::vtm::ArrayValues::F64 { values, .. } = &a.values {
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
        let arrays = StepArrays {
            point,
            line: vec![
                BlockArray::scalar("tension", tension),
                BlockArray::int("slack", slack),
                BlockArray::scalar("axial_force", axial.to_vec()),
                BlockArray::scalar("strain", out.strain[..nl.min(out.strain.len())].to_vec()),
                BlockArray::scalar("wake_factor", wake_lines.to_vec()),
            ],
            panel: vec![BlockArray::scalar("wake_factor", wake_panels.to_vec())],
        };
        self.series
            .write_step(state.t, mesh, &positions, &arrays)
            .map_err(|e| SimError::Output(Box::new(e)))?;
        let line: Vec<String> = row.values_text();
        writeln!(self.csv, "{}", line.join(",")).map_err(io("writing", &self.csv_path))?;
        self.steps_written += 1;
        if self.csv_flushed.elapsed() >= CSV_FLUSH_INTERVAL {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes the buffered `summary.csv` rows to the file.
    pub fn flush(&mut self) -> Result<()> {
        self.csv_flushed = std::time::Instant::now();
        self.csv.flush().map_err(io("writing", &self.csv_path))
    }

    /// Writes `run.json` atomically.
    pub fn write_json(&self, value: &serde_json::Value) -> Result<()> {
        let path = self.dir.join("run.json");
        let tmp = self.dir.join(".run.json.tmp");
        let text = serde_json::to_string_pretty(value)
            .unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
        std::fs::write(&tmp, text).map_err(io("writing", &tmp))?;
        std::fs::rename(&tmp, &path).map_err(io("writing", &path))?;
        Ok(())
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
