//! The bulk API: every element at once into caller-owned nodal arrays (in parallel), and
//! the expansion of compact Jacobian blocks into dense element matrices.

use super::*;

/// Caller-owned outputs of [`LoadAssembly::evaluate`]; every slice given is overwritten.
#[derive(Debug)]
pub struct Outputs<'a> {
    /// Force per node [N], length `n_nodes`.
    pub forces: &'a mut [[f64; 3]],
    /// Added-mass block per node [kg], length `n_nodes`.
    pub added_mass: Option<&'a mut [Block]>,
    /// ∂f/∂v blocks [N·s/m], length [`LoadAssembly::n_velocity_blocks`] (module docs).
    pub dfdv: Option<&'a mut [Block]>,
    /// ∂f/∂x blocks [N/m], length [`LoadAssembly::n_position_blocks`] (module docs).
    pub dfdx: Option<&'a mut [Block]>,
}

impl LoadAssembly {
    /// Everything at once: [`prepare`](Self::prepare) then [`assemble`](Self::assemble).
    /// `x`, `v`: node positions [m] and velocities [m/s] (length `n_nodes`) at time t [s].
    /// Fills `out` (see [`Outputs`]; Jacobian layout in the module docs) and allocates
    /// nothing.
    pub fn evaluate(
        &mut self,
        t: f64,
        phase: Phase,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        out: Outputs<'_>,
    ) -> Result<(), HydroError> {
        self.prepare(t, phase, x)?;
        self.assemble(x, v, out)
    }

    /// All elements (in parallel) and the nodal sums, with the flow cached by the last
    /// [`prepare`](Self::prepare) (call that first at the same positions).
    pub fn assemble(
        &mut self,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        out: Outputs<'_>,
    ) -> Result<(), HydroError> {
        self.check_len("positions", x.len())?;
        self.check_len("velocities", v.len())?;
        self.check_len("forces", out.forces.len())?;
        if let Some(m) = &out.added_mass {
            self.check_len("added_mass", m.len())?;
        }
        let nv = self.n_velocity_blocks();
        let nx = self.n_position_blocks();
        for (what, got, need) in [
            ("dfdv", out.dfdv.as_ref().map(|s| s.len()), nv),
            ("dfdx", out.dfdx.as_ref().map(|s| s.len()), nx),
        ] {
            if let Some(got) = got
                && got != need
            {
                return Err(HydroError::range(
                    format!("{what} length"),
                    got,
                    format!("must equal {need} blocks (see n_velocity_blocks/n_position_blocks)"),
                ));
            }
        }
        let want = Want {
            dfdv: out.dfdv.is_some(),
            dfdx: out.dfdx.is_some(),
        };
        let mut empty_v: [Block; 0] = [];
        let mut empty_x: [Block; 0] = [];
        let dv: &mut [Block] = match out.dfdv {
            Some(s) => s,
            None => &mut empty_v,
        };
        let dx: &mut [Block] = match out.dfdx {
            Some(s) => s,
            None => &mut empty_x,
        };
        let mut ef = std::mem::take(&mut self.elem_force);
        let mut em = std::mem::take(&mut self.elem_mass);
        let ne = self.elems.len();
        let local = self.run_range(0, ne, x, v, want, &mut ef, &mut em, dv, dx);
        self.stats.publish(&local);
        // nodal sums
        out.forces.fill([0.0; 3]);
        for (el, f) in self.elems.iter().zip(&ef) {
            for i in 0..el.n {
                let t = &mut out.forces[el.nodes[i]];
                t[0] += f[i][0];
                t[1] += f[i][1];
                t[2] += f[i][2];
            }
        }
        if let Some(am) = out.added_mass {
            am.fill([[0.0; 3]; 3]);
            for (el, m) in self.elems.iter().zip(&em) {
                if matches!(el.kind, Kind::Line | Kind::Point) {
                    for i in 0..el.n {
                        let t = &mut am[el.nodes[i]];
                        for r in 0..3 {
                            for c in 0..3 {
                                t[r][c] += m[r][c];
                            }
                        }
                    }
                }
            }
        }
        self.elem_force = ef;
        self.elem_mass = em;
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn run_range(
        &self,
        lo: usize,
        hi: usize,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        want: Want,
        ef: &mut [[[f64; 3]; MAX_NODES]],
        em: &mut [Block],
        dv: &mut [Block],
        dx: &mut [Block],
    ) -> Local {
        if hi - lo <= GRAIN {
            let mut local = Local::new();
            let mut xs = [[0.0; 3]; MAX_NODES];
            let mut vs = [[0.0; 3]; MAX_NODES];
            for e in lo..hi {
                let el = &self.elems[e];
                for i in 0..el.n {
                    xs[i] = x[el.nodes[i]];
                    vs[i] = v[el.nodes[i]];
                }
                let f = &mut ef[e - lo];
                *f = [[0.0; 3]; MAX_NODES];
                let vr = if want.dfdv {
                    self.voff[e] - self.voff[lo]..self.voff[e + 1] - self.voff[lo]
                } else {
                    0..0
                };
                let xr = if want.dfdx {
                    self.xoff[e] - self.xoff[lo]..self.xoff[e + 1] - self.xoff[lo]
                } else {
                    0..0
                };
                let mut sink = CompactSink {
                    force: f,
                    mass: &mut em[e - lo],
                    dv: &mut dv[vr],
                    dx: &mut dx[xr],
                    piece_len: el.piece_len(),
                };
                self.compute(e, &xs[..el.n], &vs[..el.n], want, &mut sink, &mut local);
            }
            return local;
        }
        let mid = lo + (hi - lo) / 2;
        let (ef1, ef2) = ef.split_at_mut(mid - lo);
        let (em1, em2) = em.split_at_mut(mid - lo);
        let sv = if want.dfdv {
            self.voff[mid] - self.voff[lo]
        } else {
            0
        };
        let sx = if want.dfdx {
            self.xoff[mid] - self.xoff[lo]
        } else {
            0
        };
        let (dv1, dv2) = dv.split_at_mut(sv);
        let (dx1, dx2) = dx.split_at_mut(sx);
        let (a, b) = rayon::join(
            || self.run_range(lo, mid, x, v, want, ef1, em1, dv1, dx1),
            || self.run_range(mid, hi, x, v, want, ef2, em2, dv2, dx2),
        );
        a.merge(b)
    }

    /// Expands element `e`'s compact blocks (slices of the full `dfdv`/`dfdx` arrays of
    /// [`Outputs`]) into a dense 3n×3n matrix (`dense` is overwritten in its leading block).
    pub fn expand(
        &self,
        e: usize,
        blocks: &[Block],
        position: bool,
        dense: &mut [[f64; MAX_DOFS]; MAX_DOFS],
    ) {
        let el = &self.elems[e];
        for row in dense.iter_mut().take(3 * el.n) {
            row[..3 * el.n].fill(0.0);
        }
        let pl = el.piece_len();
        for k in 0..el.n_pieces() {
            let nodes = el.piece(k);
            for (q, &j) in nodes.iter().enumerate() {
                let b = if position {
                    &blocks[self.xoff[e] + k * pl + q]
                } else {
                    &blocks[self.voff[e] + k]
                };
                for &i in nodes {
                    for r in 0..3 {
                        for c in 0..3 {
                            dense[3 * i + r][3 * j + c] += b[r][c];
                        }
                    }
                }
            }
        }
    }
}
