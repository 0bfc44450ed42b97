//! Evaluation of the structure at a state: element, hinge, load, seabed and friction forces,
//! M·a, the residual q and the Jacobian J = m·M + k·K + c·C assembled into the fixed pattern
//! (docs/theory/fem.md#seabed-contact, #bending, #seabed-friction, #threads).

use super::load_derivatives::load_element;
use super::{Coef, EvalOptions, NONE, System, norm, sub};
use crate::bending::{self, HingeEval};
use crate::cable::{self, CableEval};
use crate::error::{FemError, Result};
use crate::friction::{self, Normal};
use crate::loads::{ElementLoad, LoadProvider, MAX_LOAD_NODES, Want};
use crate::model::Model;
use crate::seabed::BedLaw;
use rayon::prelude::*;

/// Element count from which element kernels run in parallel (docs/theory/fem.md#threads).
const PAR_THRESHOLD: usize = 512;

impl System {
    /// Row sums of |J| (free DOFs) of the last assembled Jacobian.
    pub fn row_abs_sums(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.n_free()];
        for c in 0..self.n_free() {
            for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                out[self.row_idx[p]] += self.values[p].abs();
            }
        }
        out
    }

    /// Evaluates forces (and optionally M·a and the Jacobian) at state (x, v, a).
    pub fn evaluate<P: LoadProvider + ?Sized>(
        &mut self,
        model: &Model,
        provider: &mut P,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        a: &[[f64; 3]],
        o: &EvalOptions,
    ) -> Result<()> {
        let n = self.n_nodes;
        provider.prepare(o.t, x, v).map_err(|e| FemError::Load {
            element: usize::MAX,
            error: e,
        })?;
        // Cable elements.
        let elements = model.elements();
        let damping = o.dynamic;
        let a_k = if o.dynamic { o.rayleigh.1 } else { 0.0 };
        let clamp = o.clamp_geometric;
        let secant = self.secant.as_ref();
        let hht = self.hht.as_ref();
        let kernel = |(i, out): (usize, &mut CableEval)| {
            let e = &elements[i];
            *out = cable::evaluate(
                e,
                x[e.a],
                x[e.b],
                v[e.a],
                v[e.b],
                damping,
                a_k * e.ea,
                clamp,
            );
            if let Some((x0, x1)) = secant {
                let l0 = norm(sub(x0[e.b], x0[e.a]));
                cable::use_secant_tension(e, l0, sub(x1[e.b], x1[e.a]), out);
            }
            if let Some(f) = hht {
                let d0 = sub(f.xn[e.b], f.xn[e.a]);
                crate::dynamics::use_hht_force(e, d0, &f.cable[i], &f.w, out);
            }
        };
        if elements.len() >= PAR_THRESHOLD {
            self.cable.par_iter_mut().enumerate().for_each(kernel);
        } else {
            self.cable.iter_mut().enumerate().for_each(kernel);
        }
        if let Some(i) = self.cable.iter().position(|c| c.bad) {
            let e = &elements[i];
            return Err(FemError::NonFinite(format!(
                "element {i} (nodes {}-{}): length {:.3e} m (L0 = {:.3e} m) degenerate or non-finite",
                e.a, e.b, self.cable[i].length, e.l0
            )));
        }
        self.evaluate_hinges(model, x, o.jacobian.is_some())?;
        self.evaluate_rods(model, x, o.jacobian.is_some())?;
        self.evaluate_links(model, x, o.jacobian.is_some())?;
        self.evaluate_net_triangles(model, x, v, o)?;
        // Load elements.
        let nl = self.load_nn.len();
        if nl > 0 {
            let stride = self.load_stride;
            let want = Want {
                dfdv: o.jacobian.is_some_and(|c| c.c != 0.0) && o.dynamic,
                dfdx: o.jacobian.is_some_and(|c| c.k != 0.0),
            };
            let coef = o.jacobian.unwrap_or(Coef {
                m: 0.0,
                k: 0.0,
                c: 0.0,
            });
            let scale = o.load_scale;
            let fd_dfdx = o.fd_dfdx;
            let t = o.t;
            let (load_nodes, load_nn) = (&self.load_nodes, &self.load_nn);
            let prov: &P = provider;
            let kernel = |bufs: &mut (Box<ElementLoad>, Box<ElementLoad>),
                          (e, chunk): (usize, &mut [f64])|
             -> Result<()> {
                let nn = load_nn[e];
                let mut xl = [[0.0; 3]; MAX_LOAD_NODES];
                let mut vl = [[0.0; 3]; MAX_LOAD_NODES];
                for j in 0..nn {
                    xl[j] = x[load_nodes[e][j]];
                    vl[j] = v[load_nodes[e][j]];
                }
                let (out, tmp) = bufs;
                load_element(
                    prov, e, nn, t, &xl, &vl, want, coef, scale, fd_dfdx, chunk, out, tmp,
                )
            };
            let res: Result<()> = if nl >= PAR_THRESHOLD {
                self.load_buf
                    .par_chunks_mut(stride)
                    .enumerate()
                    .try_for_each_init(
                        || (Box::<ElementLoad>::default(), Box::<ElementLoad>::default()),
                        kernel,
                    )
            } else {
                let mut bufs = std::mem::take(&mut self.load_scratch);
                let r = self
                    .load_buf
                    .chunks_mut(stride)
                    .enumerate()
                    .try_for_each(|item| kernel(&mut bufs, item));
                self.load_scratch = bufs;
                r
            };
            res?;
        }
        // Nodal assembly.
        let g_scale = o.load_scale;
        for i in 0..n {
            self.fint[i] = [0.0; 3];
            self.fhydro[i] = [0.0; 3];
            self.fbed[i] = [0.0; 3];
            self.added[i] = [[0.0; 3]; 3];
        }
        for (e, c) in elements.iter().zip(&self.cable) {
            for k in 0..3 {
                self.fint[e.a][k] -= c.force_b[k];
                self.fint[e.b][k] += c.force_b[k];
            }
        }
        for (h, ev) in model.hinges().iter().zip(&self.hinge) {
            for (&nd, f) in h.nodes.iter().zip(&ev.force) {
                for k in 0..3 {
                    self.fint[nd][k] += f[k];
                }
            }
        }
        self.add_rod_forces(model);
        self.add_net_forces(model);
        self.add_body_terms(model, v, o.dynamic);
        for e in 0..nl {
            let nn = self.load_nn[e];
            let chunk = &self.load_buf[e * self.load_stride..];
            for j in 0..nn {
                let nd = self.load_nodes[e][j];
                for k in 0..3 {
                    self.fhydro[nd][k] += g_scale * chunk[3 * j + k];
                    for l in 0..3 {
                        self.added[nd][k][l] += chunk[3 * nn + 9 * j + 3 * k + l];
                    }
                }
            }
        }
        // Seabed.
        let bed = BedLaw::new(model, o.dynamic);
        let secant = self.secant.as_ref();
        for i in 0..n {
            let ends = secant.map(|(x0, x1)| (x0[i][2], x1[i][2]));
            let (f, kz, cz) = bed.node(model, i, x[i][2], v[i][2], ends);
            self.fbed[i][2] += f;
            self.bed_kz[i] = kz;
            self.bed_cz[i] = cz;
        }
        self.seabed_friction(model, x, v, o.dynamic);
        let a_m = if o.dynamic { o.rayleigh.0 } else { 0.0 };
        for i in 0..n {
            for k in 0..3 {
                self.fext[i][k] = g_scale * (model.weight[i][k] + model.point_force[i][k])
                    + self.fhydro[i][k]
                    + self.fbed[i][k];
            }
        }
        // Structural mass products (M·a and Rayleigh a_M·M·v).
        let need_ma = o.inertia;
        if need_ma || a_m != 0.0 {
            for i in 0..n {
                self.ma[i] = [0.0; 3];
            }
            if a_m != 0.0 {
                mul_mass(model, o.consistent_mass, v, &mut self.mv);
                for i in 0..n {
                    for k in 0..3 {
                        self.fint[i][k] += a_m * self.mv[i][k];
                    }
                }
            }
            if need_ma {
                mul_mass(model, o.consistent_mass, a, &mut self.mv);
                for i in 0..n {
                    for k in 0..3 {
                        let mut s = self.mv[i][k];
                        for l in 0..3 {
                            s += self.added[i][k][l] * a[i][l];
                        }
                        self.ma[i][k] = s;
                    }
                }
            }
        }
        for i in 0..n {
            for k in 0..3 {
                self.q[i][k] = self.fint[i][k] - self.fext[i][k];
            }
        }
        if let Some(cf) = o.jacobian {
            self.assemble_jacobian(model, cf, o, a_m);
        }
        Ok(())
    }

    fn assemble_jacobian(&mut self, model: &Model, cf: Coef, o: &EvalOptions, a_m: f64) {
        let vals = &mut self.values;
        vals.iter_mut().for_each(|x| *x = 0.0);
        let mass_c = cf.m + cf.c * a_m;
        for (ie, (e, c)) in model.elements().iter().zip(&self.cable).enumerate() {
            let p = &self.cable_pos[ie];
            let mut blk = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    blk[i][j] = cf.k * c.k[i][j] + cf.c * c.c[i][j];
                }
            }
            let mm = if o.consistent_mass && mass_c != 0.0 {
                mass_c * e.mu * e.l0 / 6.0
            } else {
                0.0
            };
            for i in 0..2 {
                for j in 0..2 {
                    let sign = if i == j { 1.0 } else { -1.0 };
                    let mdiag = if i == j { 2.0 * mm } else { mm };
                    for ki in 0..3 {
                        for kj in 0..3 {
                            let pp = p[(3 * i + ki) * 6 + 3 * j + kj];
                            if pp != NONE {
                                let mut val = sign * blk[ki][kj];
                                if ki == kj {
                                    val += mdiag;
                                }
                                vals[pp] += val;
                            }
                        }
                    }
                }
            }
        }
        // Bending hinges (docs/theory/fem.md#bending).
        if cf.k != 0.0 {
            for (p, ev) in self.hinge_pos.iter().zip(&self.hinge) {
                for (r, row) in ev.k.iter().enumerate() {
                    for (c, &kv) in row.iter().enumerate() {
                        let pp = p[9 * r + c];
                        if pp != NONE {
                            vals[pp] += cf.k * kv;
                        }
                    }
                }
            }
        }
        if cf.k != 0.0 {
            super::rods::add_tangents(&self.rod_pos, &self.rod, vals, cf.k);
        }
        let net_mass = if o.consistent_mass { mass_c } else { 0.0 };
        super::net_triangles::add_tangents(&self.net_pos, model, &self.net, vals, cf, net_mass);
        // Node blocks: lumped/point mass, added mass, seabed.
        for i in 0..self.n_nodes {
            let p = &self.node_pos[i];
            if p.iter().all(|&q| q == NONE) {
                continue;
            }
            let m_struct = if o.consistent_mass {
                model.point_mass_at(i)
            } else {
                model.lumped_mass[i]
            };
            for ki in 0..3 {
                for kj in 0..3 {
                    let pp = p[3 * ki + kj];
                    if pp == NONE {
                        continue;
                    }
                    let mut val = cf.m * self.added[i][ki][kj];
                    if ki == kj {
                        val += mass_c * m_struct;
                    }
                    vals[pp] += val;
                }
            }
            let pz = p[8];
            if pz != NONE {
                vals[pz] += cf.k * self.bed_kz[i] + cf.c * self.bed_cz[i];
            }
            if self.friction_on {
                let (fk, fc) = (&self.fric_k[i], &self.fric_c[i]);
                for ki in 0..2 {
                    for kj in 0..3 {
                        let pp = p[3 * ki + kj];
                        if pp != NONE {
                            vals[pp] += cf.k * fk[ki][kj] + cf.c * fc[ki][kj];
                        }
                    }
                }
            }
        }
        // Load elements: stored block is already −scale·(k·dfdx + c·dfdv).
        for e in 0..self.load_nn.len() {
            let nn = self.load_nn[e];
            let nd = 3 * nn;
            let chunk = &self.load_buf[e * self.load_stride + 12 * nn..];
            let pos = &self.load_pos[self.load_pos_off[e]..self.load_pos_off[e + 1]];
            for (r, &pp) in pos.iter().enumerate() {
                if pp != NONE {
                    vals[pp] += chunk[r];
                }
            }
            debug_assert_eq!(pos.len(), nd * nd);
        }
        if cf.k != 0.0 {
            self.add_link_tangents(cf.k);
        }
        if cf.c != 0.0 {
            self.add_gyroscopic_damping(model, cf.c);
        }
    }

    /// Regularised Coulomb friction of the nodes in contact (dynamics only), from the normal
    /// force N = f_bed,z just formed, added to `fbed` (docs/theory/fem.md#seabed-friction).
    fn seabed_friction(&mut self, model: &Model, x: &[[f64; 3]], v: &[[f64; 3]], dynamic: bool) {
        let params = match model.env.seabed {
            Some(s) if dynamic && s.friction.is_active() => s.friction,
            _ => {
                if self.friction_on {
                    self.fric_spare.iter_mut().for_each(|c| *c = 0.0);
                }
                self.friction_on = false;
                return;
            }
        };
        self.friction_on = true;
        let elements = model.elements();
        for i in 0..self.n_nodes {
            let n = Normal {
                force: self.fbed[i][2],
                kz: self.bed_kz[i],
                cz: self.bed_cz[i],
            };
            if !(n.force > 0.0) {
                self.fric_k[i] = [[0.0; 3]; 3];
                self.fric_c[i] = [[0.0; 3]; 3];
                self.fric_spare[i] = 0.0;
                continue;
            }
            let axis = self.node_lines[i].and_then(|lines| {
                let mut dirs = [[0.0; 3]; 2];
                let mut m = 0;
                for &ie in lines.iter().filter(|&&ie| ie != NONE) {
                    let e = &elements[ie];
                    let d = sub(x[e.b], x[e.a]);
                    let l = norm(d);
                    if l > 0.0 {
                        dirs[m] = [d[0] / l, d[1] / l, d[2] / l];
                        m += 1;
                    }
                }
                friction::line_axis(&dirs[..m])
            });
            let nf = friction::node_friction(&params, n, v[i], axis);
            self.fbed[i][0] += nf.force[0];
            self.fbed[i][1] += nf.force[1];
            self.fric_k[i] = nf.k;
            self.fric_c[i] = nf.c;
            self.fric_spare[i] = nf.spare_c;
        }
    }

    /// Seabed friction damping μN/v_c that the last evaluation's Jacobian left out at node
    /// `i` because the node slid faster than v_c (it returns when the node slows down) [N·s/m].
    pub fn friction_spare_damping(&self, i: usize) -> f64 {
        self.fric_spare[i]
    }

    /// Evaluates the bending hinges at `x` (docs/theory/fem.md#bending); in the energy-consistent
    /// midpoint rule they are evaluated at the midpoint like everything else (no discrete
    /// gradient for bending).
    fn evaluate_hinges(&mut self, model: &Model, x: &[[f64; 3]], tangent: bool) -> Result<()> {
        let hinges = model.hinges();
        let kernel = |(h, out): (&bending::Hinge, &mut HingeEval)| {
            let [a, b, c] = h.nodes;
            bending::evaluate(h, x[a], x[b], x[c], tangent, out);
        };
        if hinges.len() >= PAR_THRESHOLD {
            hinges
                .par_iter()
                .zip(self.hinge.par_iter_mut())
                .for_each(kernel);
        } else {
            hinges.iter().zip(self.hinge.iter_mut()).for_each(kernel);
        }
        if let Some(i) = self.hinge.iter().position(|h| h.bad) {
            let [a, b, c] = hinges[i].nodes;
            return Err(FemError::NonFinite(format!(
                "bending hinge {i} (nodes {a}-{b}-{c}): an edge has zero length, the edges fold \
                 back onto each other, or the bending force is non-finite"
            )));
        }
        Ok(())
    }

    /// Total bending energy Σ W of the hinges and the rods (bending and torsion) at the last
    /// evaluation [J].
    pub fn bending_energy(&self) -> f64 {
        self.hinge.iter().map(|h| h.energy).sum::<f64>() + self.rod_energy()
    }

    /// Strain energy of everything but the cables at the last evaluation: bending (hinges,
    /// rods), the net triangles' twines and the rigid links [J].
    pub fn element_energy(&self) -> f64 {
        self.bending_energy() + self.net_energy() + self.link_energy()
    }

    /// Per node, the largest row sum of |∂²W/∂x²| of the hinges (Gershgorin bound of the
    /// bending stiffness) at the last evaluation with a Jacobian [N/m], added into `out`.
    pub fn add_hinge_row_sums(&self, model: &Model, out: &mut [f64]) {
        for (h, ev) in model.hinges().iter().zip(&self.hinge) {
            for (i, &nd) in h.nodes.iter().enumerate() {
                let m = (0..3)
                    .map(|k| ev.k[3 * i + k].iter().map(|v| v.abs()).sum::<f64>())
                    .fold(0.0, f64::max);
                out[nd] += m;
            }
        }
    }
}

/// Structural mass matrix (lumped or consistent, plus point masses) times a nodal vector.
pub(crate) fn mul_mass(model: &Model, consistent: bool, a: &[[f64; 3]], out: &mut [[f64; 3]]) {
    let n = model.n_nodes();
    if consistent {
        for i in 0..n {
            let m = model.point_mass_at(i);
            for k in 0..3 {
                out[i][k] = m * a[i][k];
            }
        }
        for e in model.elements() {
            let m = e.mu * e.l0 / 6.0;
            for k in 0..3 {
                out[e.a][k] += m * (2.0 * a[e.a][k] + a[e.b][k]);
                out[e.b][k] += m * (a[e.a][k] + 2.0 * a[e.b][k]);
            }
        }
        super::net_triangles::add_consistent_mass(model, a, out);
    } else {
        for i in 0..n {
            let m = model.lumped_mass[i];
            for k in 0..3 {
                out[i][k] = m * a[i][k];
            }
        }
    }
}
