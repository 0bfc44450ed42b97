//! Wake membership: which elements lie in the shadow of their cage's net, and the
//! cage-to-cage ratio of the elements of cages in the shadow of other cages, updated per step.

use super::*;
use crate::cage_wake::{CageShadow, cage_ratio};

impl LoadAssembly {
    /// Recomputes shadow membership and wake factors from positions `x` at time t (called at
    /// the start of each time step and at each static equilibrium, through aqua-fem's
    /// `accept_state`). Groups with `update = "frozen"` keep their first result; the
    /// cage-to-cage ratio ([`set_cage_wake`](Self::set_cage_wake)) is recomputed from `x` at
    /// every call. Returns
    /// true if any element's membership in its own cage's shadow changed or a cage-to-cage
    /// ratio moved by more than 1e-6.
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
        changed |= self.update_cage_wake(t, x);
        self.wake_ready = true;
        Ok(changed)
    }

    /// Sets the cage-to-cage wake (docs/theory/hydrodynamics.md#cage-to-cage-wake): the
    /// listed wake groups (cage copies) shadow each other's elements (panels, twines and
    /// lines of the group). Takes effect at the next wake update (the first evaluation, or
    /// [`update_wake`](Self::update_wake)). Errors name a group index that does not exist,
    /// a factor outside [0, 1] or a group without net panels or twines.
    pub fn set_cage_wake(&mut self, cage_wake: CageWake) -> Result<(), HydroError> {
        let ng = self.groups.len();
        for (i, s) in cage_wake.sources.iter().enumerate() {
            let key = format!("cage_wake.sources[{i}]");
            if s.group >= ng {
                return Err(HydroError::range(
                    format!("{key}.group"),
                    s.group,
                    format!("must be < {ng} (number of wake groups)"),
                ));
            }
            if !(0.0..=1.0).contains(&s.factor) {
                return Err(HydroError::range(
                    format!("{key}.factor"),
                    s.factor,
                    "a net reduction factor in [0, 1]",
                ));
            }
            if self.group_state[s.group].net_nodes.is_empty() {
                return Err(HydroError::range(
                    format!("{key}.group"),
                    format!("{} ({})", s.group, self.groups[s.group].name),
                    "a cage-to-cage wake needs a group with net panels or twines",
                ));
            }
        }
        let member =
            |g: Option<usize>| g.filter(|g| cage_wake.sources.iter().any(|s| s.group == *g));
        self.cage_receivers = self
            .elems
            .iter()
            .enumerate()
            .filter_map(|(e, el)| {
                let g = match el.kind {
                    Kind::Tri | Kind::Quad => self.panels[el.idx].wake_group,
                    Kind::Line => self.lines[el.idx].wake_group,
                    Kind::Point => None,
                };
                member(g).map(|g| (e, g))
            })
            .collect();
        self.cage_wake = cage_wake;
        self.cage_factor.fill(1.0);
        self.wake_ready = false;
        Ok(())
    }

    /// Recomputes the cage-to-cage ratio of every receiving element from positions `x`
    /// (never compounded: each call starts from the geometry alone).
    /// Recomputes the cage-to-cage ratios; true if any moved by more than 1e-6.
    fn update_cage_wake(&mut self, t: f64, x: &[[f64; 3]]) -> bool {
        if self.cage_wake.is_empty() {
            return false;
        }
        let mut pts = Vec::new();
        let shadows: Vec<CageShadow> = self
            .cage_wake
            .sources
            .iter()
            .filter_map(|s| {
                let st = &self.group_state[s.group];
                pts.clear();
                pts.extend(st.net_nodes.iter().map(|&n| x[n]));
                let zc = pts.iter().map(|p| p[2]).sum::<f64>() / pts.len().max(1) as f64;
                let o = pts
                    .iter()
                    .fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], 0.0]);
                let k = 1.0 / pts.len().max(1) as f64;
                let uc = unramped_current(&self.sea, [o[0] * k, o[1] * k, zc], t);
                CageShadow::of_nodes(*s, &pts, [uc[0], uc[1]])
            })
            .collect();
        let mut changed = false;
        for &(e, g) in &self.cage_receivers {
            let el = self.elems[e];
            let mut c = [0.0; 2];
            for &nd in &el.nodes[..el.n] {
                c[0] += x[nd][0] / el.n as f64;
                c[1] += x[nd][1] / el.n as f64;
            }
            let r = cage_ratio(&shadows, g, c);
            changed |= (r - self.cage_factor[e]).abs() > 1e-6;
            self.cage_factor[e] = r;
        }
        changed
    }
}
