//! The net triangles in the global system: evaluation of every triangle at a state (with the
//! discrete gradient in the energy-consistent midpoint rule), their forces and 9×9 tangents
//! into the residual and the Jacobian, their consistent mass, energy and damping power
//! (docs/theory/fem.md#net-triangle).

use super::{Coef, EvalOptions, NONE, System};
use crate::cable::CableEval;
use crate::error::{FemError, Result};
use crate::model::Model;
use crate::net_triangle::{self, NetTriangle, NetTriangleEval};
use rayon::prelude::*;

/// Triangle count from which the kernel runs in parallel (docs/theory/fem.md#threads).
const PAR_THRESHOLD: usize = 512;

/// Adds the triangles' part of J = m·M + k·K + c·C to the Jacobian's values `vals` at the
/// positions `pos` (9×9 per triangle, row-major over (corner, component)); `mass_c` is the
/// coefficient of the consistent mass (0 with the lumped mass, which the node blocks carry).
pub(super) fn add_tangents(
    pos: &[[usize; 81]],
    model: &Model,
    evals: &[NetTriangleEval],
    vals: &mut [f64],
    cf: Coef,
    mass_c: f64,
) {
    for ((p, t), ev) in pos.iter().zip(model.net_triangles()).zip(evals) {
        let mm = mass_c * t.mass() / 12.0;
        for i in 0..3 {
            for j in 0..3 {
                let blk = ev.block(t, i, j, cf.k, cf.c);
                let m = if i == j { 2.0 * mm } else { mm };
                for ki in 0..3 {
                    for kj in 0..3 {
                        let pp = p[(3 * i + ki) * 9 + 3 * j + kj];
                        if pp == NONE {
                            continue;
                        }
                        let mut val = blk[ki][kj];
                        if ki == kj {
                            val += m;
                        }
                        vals[pp] += val;
                    }
                }
            }
        }
    }
}

/// Adds the consistent mass of the triangles times `a` into `out`: each triangle's mass m
/// as m/12·[2 1 1; 1 2 1; 1 1 2] per component (docs/theory/fem.md#mass).
pub(crate) fn add_consistent_mass(model: &Model, a: &[[f64; 3]], out: &mut [[f64; 3]]) {
    for t in model.net_triangles() {
        let m = t.mass() / 12.0;
        let [p, q, r] = t.nodes;
        for k in 0..3 {
            let s = a[p][k] + a[q][k] + a[r][k];
            for nd in t.nodes {
                out[nd][k] += m * (a[nd][k] + s);
            }
        }
    }
}

impl System {
    /// Evaluates every net triangle at (x, v) (the midpoint in the energy-consistent midpoint
    /// rule, where the elastic force is the discrete gradient between the step's ends).
    pub(super) fn evaluate_net_triangles(
        &mut self,
        model: &Model,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        o: &EvalOptions,
    ) -> Result<()> {
        let tris = model.net_triangles();
        if tris.is_empty() {
            return Ok(());
        }
        let damping = o.dynamic;
        let a_k = if o.dynamic { o.rayleigh.1 } else { 0.0 };
        let clamp = o.clamp_geometric;
        let secant = self
            .secant
            .as_ref()
            .map(|(x0, x1)| (x0.as_slice(), x1.as_slice()));
        let hht = self.hht.as_ref();
        let kernel = |(i, (t, out)): (usize, (&NetTriangle, &mut NetTriangleEval))| {
            net_triangle::evaluate(t, x, v, damping, a_k * t.twine.ea, clamp, secant, out);
            if let Some(f) = hht {
                let (u0, v0) = t.twine_vectors(&f.xn);
                let m = &f.net[i];
                crate::dynamics::use_hht_force(&t.twine, u0, &m[0], &f.w, &mut out.u);
                crate::dynamics::use_hht_force(&t.twine, v0, &m[1], &f.w, &mut out.v);
            }
        };
        if tris.len() >= PAR_THRESHOLD {
            tris.par_iter()
                .zip(self.net.par_iter_mut())
                .enumerate()
                .for_each(kernel);
        } else {
            tris.iter()
                .zip(self.net.iter_mut())
                .enumerate()
                .for_each(kernel);
        }
        if let Some(i) = self.net.iter().position(|ev| ev.bad()) {
            let [a, b, c] = tris[i].nodes;
            let ev = &self.net[i];
            return Err(FemError::NonFinite(format!(
                "net triangle {i} (nodes {a}-{b}-{c}): twine lengths |u| = {:.3e} m, |v| = \
                 {:.3e} m (l_p = {:.3e} m) degenerate or non-finite",
                ev.u.length,
                ev.v.length,
                tris[i].bar_length()
            )));
        }
        Ok(())
    }

    /// Adds the net triangles' forces of the last evaluation to f_int.
    pub(super) fn add_net_forces(&mut self, model: &Model) {
        for (t, ev) in model.net_triangles().iter().zip(&self.net) {
            for (k, &nd) in t.nodes.iter().enumerate() {
                let f = ev.force(t, k);
                for c in 0..3 {
                    self.fint[nd][c] += f[c];
                }
            }
        }
    }

    /// Replaces the step forces of the energy-consistent HHT-α in the last evaluation by the
    /// evaluated state's own element forces T·u (cables and twines; f_int and q follow), so
    /// that what is read after a converged step is of the state x_{n+1}
    /// (docs/theory/fem.md#energy-consistent-hht-alpha).
    pub(crate) fn use_state_element_forces(&mut self, model: &Model) {
        let state =
            |c: &CableEval| -> [f64; 3] { std::array::from_fn(|k| c.tension * c.force_b_dir[k]) };
        for (e, c) in model.elements().iter().zip(self.cable.iter_mut()) {
            let f = state(c);
            for k in 0..3 {
                let d = f[k] - c.force_b[k];
                self.fint[e.a][k] -= d;
                self.fint[e.b][k] += d;
                self.q[e.a][k] -= d;
                self.q[e.b][k] += d;
            }
            c.force_b = f;
        }
        for (t, ev) in model.net_triangles().iter().zip(self.net.iter_mut()) {
            let before: [[f64; 3]; 3] = std::array::from_fn(|k| ev.force(t, k));
            ev.u.force_b = state(&ev.u);
            ev.v.force_b = state(&ev.v);
            for (k, &nd) in t.nodes.iter().enumerate() {
                let f = ev.force(t, k);
                for c in 0..3 {
                    let d = f[c] - before[k][c];
                    self.fint[nd][c] += d;
                    self.q[nd][c] += d;
                }
            }
        }
    }

    /// Total strain energy of the net triangles at the last evaluation [J].
    pub fn net_energy(&self) -> f64 {
        self.net.iter().map(|ev| ev.energy).sum()
    }

    /// Power dissipated by the net triangles' axial damping at the last evaluation [W].
    pub fn net_damping_power(&self, model: &Model) -> f64 {
        model
            .net_triangles()
            .iter()
            .zip(&self.net)
            .map(|(t, ev)| ev.damping_power(t))
            .sum()
    }

    /// The twines of every net triangle at the last evaluation (U then V of each).
    pub(crate) fn net_twines(&self) -> impl Iterator<Item = &CableEval> {
        self.net.iter().flat_map(|ev| [&ev.u, &ev.v])
    }

    /// Per node, a bound of the net triangles' stiffness rows at the last evaluation:
    /// Σ_j A_uv·|a_i·a_j|·(EA/l_p + |T_u|/|u|) + the same for V (block Gershgorin, the full
    /// EA of slack twines since they may tighten; docs/theory/fem.md#stable-step) [N/m],
    /// added into `out`.
    pub fn add_net_row_sums(&self, model: &Model, out: &mut [f64]) {
        for (t, ev) in model.net_triangles().iter().zip(&self.net) {
            let ku = t.twine.ea / t.twine.l0 + ev.u.tension.abs() / ev.u.length;
            let kv = t.twine.ea / t.twine.l0 + ev.v.tension.abs() / ev.v.length;
            let su: f64 = t.grad_u.iter().map(|g| g.abs()).sum();
            let sv: f64 = t.grad_v.iter().map(|g| g.abs()).sum();
            for (k, &nd) in t.nodes.iter().enumerate() {
                out[nd] += t.area_uv * (t.grad_u[k].abs() * su * ku + t.grad_v[k].abs() * sv * kv);
            }
        }
    }
}
