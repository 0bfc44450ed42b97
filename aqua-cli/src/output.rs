//! Run outputs: a ParaView time series (`<scene>.pvd` + one `.vtu` per output step),
//! `summary.csv` (one row per output step) and `run.json` (resolved scene, final values, timing).
//!
//! Every file is written so that an interrupted run leaves it readable: `.vtu` files and the
//! `.pvd` are written to a temporary name and renamed, the `.pvd` lists exactly the steps on
//! disk, and `summary.csv` is flushed row by row.

use crate::build::{Built, NetCells};
use anyhow::Context;
use aqua_fem::{Outputs, State};
use aqua_mesh::{PanelNodes, Role, VtkArray, VtkArrays, VtuSeries};
use nalgebra::{Point3, Vector3};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// One row of `summary.csv`.
#[derive(Debug, Clone, Serialize)]
pub struct SummaryRow {
    /// Time [s].
    pub t: f64,
    /// Total hydrodynamic force on the nets (panels and twines) [N].
    pub net_force: [f64; 3],
    /// Sum of reactions at fixed and prescribed nodes (force of the supports on the
    /// structure) [N].
    pub reaction: [f64; 3],
    /// Enclosed net volume [m³] (cages; 0 without a closed net).
    pub volume: f64,
    /// Moment of the reactions about the origin [N·m].
    pub reaction_moment: [f64; 3],
    /// Volume over the undeformed volume.
    pub volume_ratio: f64,
    /// Largest tension per structural group [N].
    pub max_tension: Vec<f64>,
    /// Per line: |R| at the anchor, |R| at the fairlead, tension of the anchor element and of
    /// the fairlead element [N].
    pub line_ends: Vec<[f64; 4]>,
    /// Newton iterations of the step (statics: all iterations).
    pub iterations: usize,
    /// Step size [s] (0 for statics).
    pub dt: f64,
}

/// Signed volume between the net surface and the plane z = z0 (divergence theorem with
/// F = (0, 0, z − z0)): for a net open only at a top rim lying in that plane this is the
/// enclosed volume [m³].
pub fn enclosed_volume(net: &NetCells, mesh: &aqua_mesh::Mesh, x: &[[f64; 3]], z0: f64) -> f64 {
    let p = |i: usize| Vector3::from(x[i]);
    let tri = |a: usize, b: usize, c: usize| {
        let area = 0.5 * (p(b) - p(a)).cross(&(p(c) - p(a)));
        let zc = (x[a][2] + x[b][2] + x[c][2]) / 3.0;
        (zc - z0) * area.z
    };
    let mut v = 0.0;
    for &pi in &net.panels {
        v += match mesh.panels[pi].nodes {
            PanelNodes::Tri([a, b, c]) => tri(a, b, c),
            PanelNodes::Quad([a, b, c, d]) => {
                0.5 * (tri(a, b, c) + tri(a, c, d) + tri(b, c, d) + tri(b, d, a))
            }
        };
    }
    v.abs()
}

/// The rim height of a net: mean z of its `net_top` nodes (0 if it has none).
fn rim_height(net: &NetCells, mesh: &aqua_mesh::Mesh, x: &[[f64; 3]]) -> f64 {
    let Some(&first) = net.panels.first() else {
        return 0.0;
    };
    let object = mesh.panels[first].object;
    let copy = mesh.panels[first].copy;
    let mut sum = 0.0;
    let mut n = 0usize;
    for g in mesh
        .groups
        .iter()
        .filter(|g| g.object == object && g.role == Role::NetTop)
    {
        for &node in &g.nodes {
            if mesh.node_owner[node].1 == copy {
                sum += x[node][2];
                n += 1;
            }
        }
    }
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// Total enclosed volume of all closed nets [m³].
pub fn total_volume(built: &Built, x: &[[f64; 3]]) -> f64 {
    built
        .nets
        .iter()
        .filter(|n| n.closed)
        .map(|n| enclosed_volume(n, &built.mesh, x, rim_height(n, &built.mesh, x)))
        .sum()
}

/// Writers of one run.
#[derive(Debug)]
pub struct RunOutput {
    dir: PathBuf,
    series: VtuSeries,
    csv: std::io::BufWriter<std::fs::File>,
    volume0: f64,
    /// Rows written so far (the last one is the final summary).
    pub last: Option<SummaryRow>,
    /// Output steps written.
    pub steps_written: usize,
}

impl RunOutput {
    /// Creates the output directory, the series and `summary.csv` with its header.
    pub fn create(dir: &Path, scene_name: &str, built: &Built) -> anyhow::Result<Self> {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("creating the output directory {}", dir.display()))?;
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
        let series = VtuSeries::new(dir, scene_name)?;
        let path = dir.join("summary.csv");
        let mut csv = std::io::BufWriter::new(
            std::fs::File::create(&path).with_context(|| format!("creating {}", path.display()))?,
        );
        let mut header =
            String::from("t,Fx_net,Fy_net,Fz_net,Rx,Ry,Rz,Mx,My,Mz,volume,volume_ratio");
        for g in &built.group_names {
            header.push_str(&format!(",Tmax_{}", g.replace(',', "_")));
        }
        for l in &built.line_ends {
            let n = l.name.replace(',', "_");
            header.push_str(&format!(
                ",{n}_anchor_reaction,{n}_fairlead_reaction,{n}_anchor_element_tension,{n}_fairlead_element_tension"
            ));
        }
        header.push_str(",newton_iterations,dt");
        writeln!(csv, "{header}")?;
        csv.flush()?;
        let x0: Vec<[f64; 3]> = built.model.nodes().to_vec();
        let volume0 = total_volume(built, &x0);
        Ok(Self {
            dir: dir.to_path_buf(),
            series,
            csv,
            volume0,
            last: None,
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
        net_force: [f64; 3],
        wake: &[f64],
        iterations: usize,
        dt: f64,
    ) -> anyhow::Result<SummaryRow> {
        let x = &state.x;
        let model = &built.model;
        let mesh = &built.mesh;
        let finite = |name: &str, v: &[f64]| -> anyhow::Result<()> {
            if let Some(i) = v.iter().position(|a| !a.is_finite()) {
                anyhow::bail!(
                    "non-finite {name} at index {i}, t = {} s: not written",
                    state.t
                );
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
        let point = vec![
            VtkArray {
                name: "displacement".into(),
                components: 3,
                values: flat(&disp),
            },
            VtkArray {
                name: "velocity".into(),
                components: 3,
                values: flat(&state.v),
            },
            VtkArray {
                name: "hydro_force".into(),
                components: 3,
                values: flat(&out.hydro_force),
            },
            VtkArray {
                name: "reaction".into(),
                components: 3,
                values: flat(&out.reaction),
            },
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
            .write_step(state.t, mesh, Some(&positions), &VtkArrays { point, cell })?;
        let mut reaction = [0.0; 3];
        let mut moment = Vector3::zeros();
        for &n in &built.supported_nodes {
            for k in 0..3 {
                reaction[k] += out.reaction[n][k];
            }
            moment += Vector3::from(x[n]).cross(&Vector3::from(out.reaction[n]));
        }
        let volume = total_volume(built, x);
        let max_tension: Vec<f64> = model
            .groups()
            .iter()
            .map(|g| {
                g.elements
                    .iter()
                    .map(|&e| out.tension[e])
                    .fold(f64::NEG_INFINITY, f64::max)
            })
            .map(|t| if t.is_finite() { t } else { 0.0 })
            .collect();
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let line_ends = built
            .line_ends
            .iter()
            .map(|l| {
                [
                    norm(out.reaction[l.anchor]),
                    norm(out.reaction[l.fairlead]),
                    out.tension[l.anchor_element],
                    out.tension[l.fairlead_element],
                ]
            })
            .collect();
        let row = SummaryRow {
            t: state.t,
            net_force,
            reaction,
            reaction_moment: [moment.x, moment.y, moment.z],
            volume: volume + 0.0,
            volume_ratio: if self.volume0 > 0.0 {
                volume / self.volume0
            } else {
                0.0
            },
            max_tension,
            line_ends,
            iterations,
            dt,
        };
        let mut line = format!(
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            row.t,
            row.net_force[0],
            row.net_force[1],
            row.net_force[2],
            row.reaction[0],
            row.reaction[1],
            row.reaction[2],
            row.reaction_moment[0],
            row.reaction_moment[1],
            row.reaction_moment[2],
            row.volume,
            row.volume_ratio
        );
        for t in &row.max_tension {
            line.push_str(&format!(",{t}"));
        }
        for l in &row.line_ends {
            for v in l {
                line.push_str(&format!(",{v}"));
            }
        }
        line.push_str(&format!(",{},{}", row.iterations, row.dt));
        writeln!(self.csv, "{line}")?;
        self.csv.flush()?;
        self.steps_written += 1;
        self.last = Some(row.clone());
        Ok(row)
    }

    /// Writes `run.json` atomically.
    pub fn write_json(&self, value: &serde_json::Value) -> anyhow::Result<()> {
        let path = self.dir.join("run.json");
        let tmp = self.dir.join(".run.json.tmp");
        std::fs::write(&tmp, serde_json::to_string_pretty(value)?)
            .with_context(|| format!("writing {}", tmp.display()))?;
        std::fs::rename(&tmp, &path).with_context(|| format!("writing {}", path.display()))?;
        Ok(())
    }
}
