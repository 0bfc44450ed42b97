//! Run files: a ParaView time series (`<scene>.pvd` + one `.vtu` per output step),
//! `summary.csv` (one row per output step) and `run.json` (resolved scene, final values, timing).
//!
//! Every file is written so that an interrupted run leaves it readable: `.vtu` files and the
//! `.pvd` are written to a temporary name and renamed, the `.pvd` lists exactly the steps on
//! disk, and `summary.csv` is flushed row by row.

use crate::build::Built;
use crate::error::{Result, SimError};
use crate::post::SummaryRow;
use aqua_fem::{Outputs, State};
use aqua_mesh::{VtkArray, VtkArrays, VtuSeries};
use nalgebra::Point3;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Writers of one run.
#[derive(Debug)]
pub struct RunFiles {
    dir: PathBuf,
    series: VtuSeries,
    csv: std::io::BufWriter<std::fs::File>,
    csv_path: PathBuf,
    /// Output steps written.
    pub steps_written: usize,
}

fn io(what: &'static str, path: &Path) -> impl FnOnce(std::io::Error) -> SimError {
    let path = path.to_path_buf();
    move |source| SimError::Io { what, path, source }
}

impl RunFiles {
    /// Creates the output directory, the series and `summary.csv` with its header.
    pub fn create(dir: &Path, scene_name: &str, built: &Built) -> Result<Self> {
        std::fs::create_dir_all(dir).map_err(io("creating the output directory", dir))?;
        // Stale steps of an earlier run would be listed by nobody but confuse a reader.
        if let Ok(entries) = std::fs::read_dir(dir) {
            let prefix = format!("{scene_name}_");
            for e in entries.flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                if name.starts_with(&prefix) && name.ends_with(".vtu") {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
        let series = VtuSeries::new(dir, scene_name).map_err(|e| SimError::Output(Box::new(e)))?;
        let path = dir.join("summary.csv");
        let mut csv =
            std::io::BufWriter::new(std::fs::File::create(&path).map_err(io("creating", &path))?);
        writeln!(csv, "{}", SummaryRow::columns(built).join(","))
            .and_then(|_| csv.flush())
            .map_err(io("writing", &path))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            series,
            csv,
            csv_path: path,
            steps_written: 0,
        })
    }

    /// The `.pvd` path.
    pub fn pvd_path(&self) -> PathBuf {
        self.series.pvd().path().to_path_buf()
    }

    /// The output directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Writes one output step: the `.vtu` (and `.pvd`) and a `summary.csv` row.
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
        let flat = |v: &[[f64; 3]]| -> Vec<f64> { v.iter().flatten().copied().collect() };
        let positions: Vec<Point3<f64>> = x.iter().map(|p| Point3::from(*p)).collect();
        let disp: Vec<[f64; 3]> = x
            .iter()
            .zip(model.nodes())
            .map(|(a, b)| [a[0] - b[0], a[1] - b[1], a[2] - b[2]])
            .collect();
        let vector = |name: &str, values: Vec<f64>| VtkArray {
            name: name.into(),
            components: 3,
            values,
        };
        let point = vec![
            vector("displacement", flat(&disp)),
            vector("velocity", flat(&state.v)),
            vector("hydro_force", flat(&out.hydro_force)),
            vector("reaction", flat(&out.reaction)),
        ];
        for a in &point {
            finite(&a.name, &a.values)?;
        }
        let n_cells = mesh.lines.len() + mesh.panels.len();
        let mut tension = vec![0.0; n_cells];
        let mut strain = vec![0.0; n_cells];
        tension[..mesh.lines.len()].copy_from_slice(&out.tension);
        strain[..mesh.lines.len()].copy_from_slice(&out.strain);
        finite("tension", &tension)?;
        finite("strain", &strain)?;
        let cell = vec![
            VtkArray::scalar("tension", tension),
            VtkArray::scalar("strain", strain),
            VtkArray::scalar("wake_factor", wake.to_vec()),
        ];
        self.series
            .write_step(state.t, mesh, Some(&positions), &VtkArrays { point, cell })
            .map_err(|e| SimError::Output(Box::new(e)))?;
        let line: Vec<String> = row.values_text();
        writeln!(self.csv, "{}", line.join(","))
            .and_then(|_| self.csv.flush())
            .map_err(io("writing", &self.csv_path))?;
        self.steps_written += 1;
        Ok(())
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
