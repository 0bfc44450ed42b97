//! Wake membership: which elements lie in the shadow of their cage's net, updated per step.

use super::*;

impl LoadAssembly {
    /// Recomputes shadow membership and wake factors from positions `x` at time t (call at
    /// the start of each time step and after each accepted static load increment). Groups
    /// with `update = "frozen"` keep their first result. Returns true if any element's
    /// membership changed.
    pub fn update_wake(&mut self, t: f64, x: &[[f64; 3]]) -> Result<bool, HydroError> {
        self.check_len("positions", x.len())?;
        let mut changed = false;
        for gi in 0..self.groups.len() {
            let g = &self.groups[gi];
            let st = &self.group_state[gi];
            if g.wake.model == WakeModel::None
                || (st.computed && g.wake.update == WakeUpdate::Frozen)
            {
                continue;
            }
            let mut o = [0.0, 0.0];
            for &nd in &st.net_nodes {
                o[0] += x[nd][0];
                o[1] += x[nd][1];
            }
            let inv = 1.0 / st.net_nodes.len() as f64;
            o[0] *= inv;
            o[1] *= inv;
            for &e in &st.members {
                let el = self.elems[e];
                let mut c = [0.0; 3];
                for &nd in &el.nodes[..el.n] {
                    for k in 0..3 {
                        c[k] += x[nd][k];
                    }
                }
                for ck in &mut c {
                    *ck /= el.n as f64;
                }
                let uc = unramped_current(&self.sea, c, t);
                let uh = (uc[0] * uc[0] + uc[1] * uc[1]).sqrt();
                let mut cell = WakeCell::default();
                if uh >= 1e-6 {
                    let d = ((c[0] - o[0]) * uc[0] + (c[1] - o[1]) * uc[1]) / uh;
                    if d > g.wake.margin {
                        let cos = match el.kind {
                            Kind::Tri | Kind::Quad => {
                                let p = |i: usize| V3::from(x[el.nodes[i]]);
                                let a = if el.kind == Kind::Tri {
                                    (p(1) - p(0)).cross(&(p(2) - p(0)))
                                } else {
                                    (p(2) - p(0)).cross(&(p(3) - p(1)))
                                };
                                let u = V3::from(uc);
                                let den = a.norm() * u.norm();
                                if den > 0.0 {
                                    a.dot(&u).abs() / den
                                } else {
                                    1.0
                                }
                            }
                            _ => 1.0,
                        };
                        cell = WakeCell {
                            in_shadow: true,
                            factor: g.wake.model.factor(g.solidity, cos),
                        };
                    }
                }
                if cell.in_shadow != self.wake[e].in_shadow {
                    changed = true;
                }
                self.wake[e] = cell;
            }
            self.group_state[gi].computed = true;
        }
        self.wake_ready = true;
        Ok(changed)
    }
}
