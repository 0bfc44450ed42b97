//! The rods in the global system: evaluation of every rod vertex at a state (with the discrete
//! gradient in the energy-consistent midpoint rule), their forces and tangents into the
//! residual and the Jacobian, the update of the edges' reference frames when a state is
//! accepted, and the per-element section forces (docs/theory/fem.md#rod).

use super::{NONE, System};
use crate::error::{FemError, Result};
use crate::model::Model;
use crate::rod::{self, ROD_DOFS, RodEval, Vars};
use rayon::prelude::*;

/// Vertex count from which the rod kernel runs in parallel (docs/theory/fem.md#threads).
const PAR_THRESHOLD: usize = 16;

fn vertex_vars(v: &crate::rod::RodVertex, x: &[[f64; 3]]) -> Vars {
    let [a, b, c] = v.nodes;
    rod::vars(
        [x[a], x[b], x[c]],
        [x[v.carriers[0]][0], x[v.carriers[1]][0]],
    )
}

/// Adds k·(rod tangents) to the Jacobian's values `vals` at the positions `rod_pos`.
pub(super) fn add_tangents(
    rod_pos: &[[usize; ROD_DOFS * ROD_DOFS]],
    rod: &[RodEval],
    vals: &mut [f64],
    k: f64,
) {
    for (p, ev) in rod_pos.iter().zip(rod) {
        for (r, row) in ev.k.iter().enumerate() {
            for (c, &kv) in row.iter().enumerate() {
                let pp = p[ROD_DOFS * r + c];
                if pp != NONE {
                    vals[pp] += k * kv;
                }
            }
        }
    }
}

impl System {
    /// Evaluates every rod vertex at `x` (the midpoint in the energy-consistent midpoint rule,
    /// where the force is the discrete gradient between the step's ends).
    pub(super) fn evaluate_rods(
        &mut self,
        model: &Model,
        x: &[[f64; 3]],
        tangent: bool,
    ) -> Result<()> {
        let vertices = model.rod_vertices();
        if vertices.is_empty() {
            return Ok(());
        }
        let frames = &self.rod_frames;
        let secant = self.secant.as_ref();
        let kernel = |(v, out): (&crate::rod::RodVertex, &mut RodEval)| {
            let (fa, fb) = (&frames[v.edges[0]], &frames[v.edges[1]]);
            match secant {
                Some((x0, x1)) => {
                    let (y0, y1) = (vertex_vars(v, x0), vertex_vars(v, x1));
                    let ym: Vars = std::array::from_fn(|i| 0.5 * (y0[i] + y1[i]));
                    rod::evaluate(v, fa, fb, &ym, Some((&y0, &y1)), tangent, out);
                }
                None => rod::evaluate(v, fa, fb, &vertex_vars(v, x), None, tangent, out),
            }
        };
        if vertices.len() >= PAR_THRESHOLD {
            vertices
                .par_iter()
                .zip(self.rod.par_iter_mut())
                .for_each(kernel);
        } else {
            vertices.iter().zip(self.rod.iter_mut()).for_each(kernel);
        }
        if let Some(i) = self.rod.iter().position(|r| r.bad) {
            let [a, b, c] = vertices[i].nodes;
            return Err(FemError::NonFinite(format!(
                "rod vertex {i} (nodes {a}-{b}-{c}): an edge has zero length, the edges fold \
                 back onto each other, or the rod force is non-finite"
            )));
        }
        Ok(())
    }

    /// Adds the rod forces of the last evaluation to f_int.
    pub(super) fn add_rod_forces(&mut self, model: &Model) {
        for (v, ev) in model.rod_vertices().iter().zip(&self.rod) {
            for l in 0..9 {
                self.fint[v.nodes[l / 3]][l % 3] += ev.force[l];
            }
            self.fint[v.carriers[0]][0] += ev.force[9];
            self.fint[v.carriers[1]][0] += ev.force[10];
        }
    }

    /// Total rod energy Σ W at the last evaluation [J].
    pub fn rod_energy(&self) -> f64 {
        self.rod.iter().map(|r| r.energy).sum()
    }

    /// Carries each rod edge's reference frame to its direction in the accepted state `x`
    /// (the material frame, and so the energy, is unchanged; docs/theory/fem.md#rod).
    pub(crate) fn accept_rod_frames(&mut self, model: &Model, x: &[[f64; 3]]) {
        for (f, e) in self.rod_frames.iter_mut().zip(model.rod_edges()) {
            let [a, b] = e.nodes;
            let d = [x[b][0] - x[a][0], x[b][1] - x[a][1], x[b][2] - x[a][2]];
            if let Some(g) = f.transported(d) {
                *f = g;
            }
        }
    }

    /// Per node, the largest row sum of |∂²W/∂x²| of the rod vertices (Gershgorin bound) at
    /// the last evaluation with a Jacobian, added into `out` [N/m, N·m/rad on carriers].
    pub fn add_rod_row_sums(&self, model: &Model, out: &mut [f64]) {
        for (v, ev) in model.rod_vertices().iter().zip(&self.rod) {
            let nodes = [
                v.nodes[0],
                v.nodes[1],
                v.nodes[2],
                v.carriers[0],
                v.carriers[1],
            ];
            for (i, &nd) in nodes.iter().enumerate() {
                let rows = if i < 3 {
                    3 * i..3 * i + 3
                } else {
                    6 + i..7 + i
                };
                let m = rows
                    .map(|r| ev.k[r].iter().map(|c| c.abs()).sum::<f64>())
                    .fold(0.0, f64::max);
                out[nd] += m;
            }
        }
    }

    /// Section forces of each cable element that is a rod edge at the last evaluation: the
    /// largest bending moment |M| at its two ends and the mean torque of its ends [N·m]
    /// (zero for other elements).
    pub(crate) fn rod_section_forces(&self, model: &Model, moment: &mut [f64], torque: &mut [f64]) {
        moment.iter_mut().for_each(|m| *m = 0.0);
        torque.iter_mut().for_each(|t| *t = 0.0);
        let edges = model.rod_edges();
        let mut count = vec![0u8; moment.len()];
        for (v, ev) in model.rod_vertices().iter().zip(&self.rod) {
            for &ie in &v.edges {
                if let Some(el) = edges[ie].element {
                    moment[el] = moment[el].max(ev.moment);
                    torque[el] += ev.torque;
                    count[el] += 1;
                }
            }
        }
        for (t, c) in torque.iter_mut().zip(count) {
            if c > 1 {
                *t /= f64::from(c);
            }
        }
    }
}
