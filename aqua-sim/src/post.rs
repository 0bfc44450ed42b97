//! Physical post-processing of a state: the enclosed net volume, the support reactions and
//! their moment, the net force and the wake factor per mesh cell, the largest tension per
//! group and the line-end values — one [`SummaryRow`] per output step.
//!
//! - Enclosed volume (divergence theorem with F = (0, 0, z − z0)):
//!   V = |Σ_panels (z̄ − z0)·A_z|, z0 the rim height (mean z of the `net_top` nodes).
//! - Reactions R = Σ_supported r_i, moment M = Σ x_i × r_i about the origin.
//! - Net force: Σ of the water loads of the net panels and twines at the state.

use crate::build::{Built, NetCells};
use crate::provider::WaterLoads;
use aqua_fem::{BodyPose, Outputs, State};
use aqua_hydro::assembly::ElementOutput;
use aqua_mesh::{PanelNodes, Role};
use nalgebra::Vector3;
use serde::Serialize;

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
    /// Largest fibre stress per pipe group (docs/theory/fem.md#rod) [Pa].
    pub max_stress: Vec<f64>,
    /// Per line: |R| at the anchor, |R| at the fairlead (at an end attached to another
    /// structure instead of a support: the tension of the end element, the line's pull on
    /// it), tension of the anchor element and of the fairlead element [N].
    pub line_ends: Vec<[f64; 4]>,
    /// Per rigid body: its centre of gravity [m] and [roll, pitch, yaw] [deg]
    /// (R = R_z(yaw)·R_y(pitch)·R_x(roll), docs/theory/fem.md#rigid-bodies).
    pub bodies: Vec<[f64; 6]>,
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

/// Net force and wake factors at a state (net panels and twines only); the wake factor is
/// per VTK cell (mesh lines first, then mesh panels; 1 outside a wake).
pub fn net_force_and_wake(
    built: &Built,
    loads: &WaterLoads,
    state: &State,
) -> ([f64; 3], Vec<f64>) {
    let f = net_force(built, loads, state);
    let mesh = &built.mesh;
    let mut wake = vec![1.0; mesh.lines.len() + mesh.panels.len()];
    for (e, cell) in built.load_cells.iter().enumerate() {
        wake[cell.cell] = loads.assembly.wake_factor(e);
    }
    (f, wake)
}

/// Total water load on the nets (panels and twines) at a state [N]; allocates nothing (the
/// run loop calls it after every step for the extremes).
pub fn net_force(built: &Built, loads: &WaterLoads, state: &State) -> [f64; 3] {
    let assembly = &loads.assembly;
    let (x, v) = (&state.x, &state.v);
    let mut f = [0.0; 3];
    let mut out = ElementOutput::default();
    let mut xs = [[0.0; 3]; 4];
    let mut vs = [[0.0; 3]; 4];
    for (e, cell) in built.load_cells.iter().enumerate() {
        if !cell.net {
            continue;
        }
        let nodes = assembly.element_nodes(e);
        for (i, &n) in nodes.iter().enumerate() {
            xs[i] = x[n];
            vs[i] = v[n];
        }
        let k = nodes.len();
        assembly.element_load(e, &xs[..k], &vs[..k], aqua_hydro::Want::default(), &mut out);
        for node_force in &out.force[..k] {
            for c in 0..3 {
                f[c] += node_force[c];
            }
        }
    }
    f
}

/// Sum of the reactions at the supported nodes [N] and their moment about the origin [N·m].
pub fn support_reactions(built: &Built, x: &[[f64; 3]], out: &Outputs) -> ([f64; 3], [f64; 3]) {
    let mut reaction = [0.0; 3];
    let mut moment = Vector3::zeros();
    for &n in &built.supported_nodes {
        for k in 0..3 {
            reaction[k] += out.reaction[n][k];
        }
        moment += Vector3::from(x[n]).cross(&Vector3::from(out.reaction[n]));
    }
    (reaction, [moment.x, moment.y, moment.z])
}

/// The largest tension of each structural group [N] into `dst` (one per group of
/// [`Built::group_names`]; 0 for a group without elements): the cable groups, then the net
/// triangle groups, whose value is the tension of one physical twine at positions `x`
/// (docs/theory/fem.md#net-triangle).
pub fn group_max_tensions(built: &Built, out: &Outputs, x: &[[f64; 3]], dst: &mut [f64]) {
    let model = &built.model;
    let (cables, nets) = dst.split_at_mut(model.groups().len().min(dst.len()));
    for (d, g) in cables.iter_mut().zip(model.groups()) {
        let t = g
            .elements
            .iter()
            .map(|&e| out.tension[e])
            .fold(f64::NEG_INFINITY, f64::max);
        *d = if t.is_finite() { t } else { 0.0 };
    }
    for (d, g) in nets.iter_mut().zip(model.net_triangle_groups()) {
        let t = g
            .triangles
            .iter()
            .map(|&i| {
                let tw = model.net_triangle_twines(i, x);
                tw.tension_u.max(tw.tension_v)
            })
            .fold(f64::NEG_INFINITY, f64::max);
        *d = if t.is_finite() { t.max(0.0) } else { 0.0 };
    }
}

/// Per `[[line]]` into `dst`: |R| at the anchor, |R| at the fairlead (at an end attached to
/// another structure instead of a support, the end element's pull on it), the tension of the
/// anchor element and of the fairlead element [N].
pub fn line_end_loads(built: &Built, out: &Outputs, dst: &mut [[f64; 4]]) {
    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    for (d, l) in dst.iter_mut().zip(&built.line_ends) {
        // A supported end reports the support's force; an end attached to another structure
        // (a collar node, a buoy) the pull of the line's end element on it.
        let end = |k: usize, node: usize, element: usize| {
            if l.supported[k] {
                norm(out.reaction[node])
            } else {
                out.tension[element]
            }
        };
        *d = [
            end(0, l.anchor, l.anchor_element),
            end(1, l.fairlead, l.fairlead_element),
            out.tension[l.anchor_element],
            out.tension[l.fairlead_element],
        ];
    }
}

impl SummaryRow {
    /// The summary of a state: `net_force` from [`net_force_and_wake`], `volume0` the
    /// undeformed enclosed volume ([`total_volume`] of the model's nodes), `poses` the rigid
    /// bodies' (in the model's order).
    #[allow(clippy::too_many_arguments)]
    pub fn of_state(
        built: &Built,
        state: &State,
        out: &Outputs,
        poses: &[BodyPose],
        net_force: [f64; 3],
        volume0: f64,
        iterations: usize,
        dt: f64,
    ) -> Self {
        let x = &state.x;
        let (reaction, reaction_moment) = support_reactions(built, x, out);
        let volume = total_volume(built, x);
        let mut max_tension = vec![0.0; built.group_names.len()];
        group_max_tensions(built, out, x, &mut max_tension);
        let mut max_stress = vec![0.0; built.pipes.len()];
        crate::pipe_stress::group_max_stresses(built, out, &mut max_stress);
        let mut line_ends = vec![[0.0; 4]; built.line_ends.len()];
        line_end_loads(built, out, &mut line_ends);
        SummaryRow {
            t: state.t,
            net_force,
            reaction,
            reaction_moment,
            volume: volume + 0.0,
            volume_ratio: if volume0 > 0.0 { volume / volume0 } else { 0.0 },
            max_tension,
            max_stress,
            line_ends,
            bodies: poses
                .iter()
                .map(|p| {
                    let [r, q, y] = p.angles.map(f64::to_degrees);
                    [p.centre[0], p.centre[1], p.centre[2], r, q, y]
                })
                .collect(),
            iterations,
            dt,
        }
    }

    /// Column names of `summary.csv`, in the order of [`SummaryRow::values`].
    pub fn columns(built: &Built) -> Vec<String> {
        let mut c: Vec<String> = [
            "t",
            "Fx_net",
            "Fy_net",
            "Fz_net",
            "Rx",
            "Ry",
            "Rz",
            "Mx",
            "My",
            "Mz",
            "volume",
            "volume_ratio",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        c.extend(Self::load_columns(built));
        c.push("newton_iterations".into());
        c.push("dt".into());
        c
    }

    /// The columns of the per-group and per-line loads, in the order of [`SummaryRow::values`]:
    /// `Tmax_<group>` per structural group, `stress_max_<group>` per pipe group [Pa], then
    /// per `[[line]]` its anchor and fairlead reactions and end-element tensions, then per rigid
    /// body `<name>_x`, `_y`, `_z` [m] and `_roll`, `_pitch`, `_yaw` [deg].
    pub fn load_columns(built: &Built) -> Vec<String> {
        let mut c = Vec::new();
        for g in &built.group_names {
            c.push(format!("Tmax_{}", g.replace(',', "_")));
        }
        for p in &built.pipes {
            c.push(format!("stress_max_{}", p.name.replace(',', "_")));
        }
        for l in &built.line_ends {
            let n = l.name.replace(',', "_");
            for end in [
                "anchor_reaction",
                "fairlead_reaction",
                "anchor_element_tension",
                "fairlead_element_tension",
            ] {
                c.push(format!("{n}_{end}"));
            }
        }
        for b in built.model.rigid_bodies() {
            let n = b.name.replace(',', "_");
            for k in ["x", "y", "z", "roll", "pitch", "yaw"] {
                c.push(format!("{n}_{k}"));
            }
        }
        c
    }

    /// The row's values as `summary.csv` writes them (integers without a decimal point).
    pub fn values_text(&self) -> Vec<String> {
        let mut v: Vec<String> = self.values().iter().map(|x| x.to_string()).collect();
        let n = v.len();
        v[n - 2] = self.iterations.to_string();
        v
    }

    /// The row's values in the order of [`SummaryRow::columns`].
    pub fn values(&self) -> Vec<f64> {
        let mut v = vec![self.t];
        v.extend(self.net_force);
        v.extend(self.reaction);
        v.extend(self.reaction_moment);
        v.push(self.volume);
        v.push(self.volume_ratio);
        v.extend(&self.max_tension);
        v.extend(&self.max_stress);
        v.extend(self.line_ends.iter().flatten());
        v.extend(self.bodies.iter().flatten());
        v.push(self.iterations as f64);
        v.push(self.dt);
        v
    }
}
