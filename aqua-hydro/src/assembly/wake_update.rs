//! Wake membership: which elements lie in the shadow of their cage's net, and the
//! cage-to-cage ratio of the elements of cages in the wake of other cages, updated per step.

use super::*;
use crate::cage_wake::{CageShadow, cage_ratio, set_inflows};

/// Smallest change of a wake factor (own or cage-to-cage, absolute) that the wake update
/// applies: below it the loads keep the wake they have, so that a static state is exactly the
/// equilibrium of the wake it reports (docs/theory/hydrodynamics.md#wake-update).
pub const WAKE_TOLERANCE: f64 = 1e-6;

impl LoadAssembly {
    /// Recomputes shadow membership and wake factors from positions `x` at time t (called at
    /// the start of each time step and in statics, through aqua-fem's `accept_state`). Groups
    /// with `update = "frozen"` keep their first result; the cage-to-cage ratio
    /// ([`set_cage_wake`](Self::set_cage_wake)) is recomputed from `x` at every call.
    ///
    /// The new wake replaces the old one only if some element entered or left its cage's
    /// shadow or some factor (own or cage-to-cage) moved by more than [`WAKE_TOLERANCE`];
    /// then it returns true. Otherwise the loads keep the old wake, unchanged to the bit, and
    /// it returns false: a false return always means the loads are the same as before.
    pub fn update_wake(&mut self, t: f64, x: &[[f64; 3]]) -> Result<bool, HydroError> {
        self.check_len("positions", x.len())?;
        self.wake_next.copy_from_slice(&self.wake);
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
                self.wake_next[e] = own_cell(&self.sea, g, self.elems[e], o, x, t);
            }
        }
        self.next_cage_wake(t, x);
        let changed = self.wake.iter().zip(&self.wake_next).any(|(a, b)| {
            a.in_shadow != b.in_shadow || (a.factor - b.factor).abs() > WAKE_TOLERANCE
        }) || self
            .cage_factor
            .iter()
            .zip(&self.cage_next)
            .any(|(a, b)| (a - b).abs() > WAKE_TOLERANCE);
        if changed || !self.wake_ready {
            std::mem::swap(&mut self.wake, &mut self.wake_next);
            std::mem::swap(&mut self.cage_factor, &mut self.cage_next);
            for st in &mut self.group_state {
                st.computed = true;
            }
        }
        self.wake_ready = true;
        Ok(changed)
    }

    /// Sets the cage-to-cage wake (docs/theory/hydrodynamics.md#cage-to-cage-wake): the
    /// listed wake groups (cage copies) shadow each other's elements (panels, twines and
    /// lines of the group). Takes effect at the next wake update (the first evaluation, or
    /// [`update_wake`](Self::update_wake)). Errors name a group index that does not exist,
    /// a factor outside [0, 1], a negative or non-finite spreading rate or a group without
    /// net panels or twines.
    pub fn set_cage_wake(&mut self, cage_wake: CageWake) -> Result<(), HydroError> {
        let ng = self.groups.len();
        if !(cage_wake.spreading.is_finite() && cage_wake.spreading >= 0.0) {
            return Err(HydroError::range(
                "cage_wake.spreading",
                cage_wake.spreading,
                "a spreading rate >= 0 (e.g. 0.1)",
            ));
        }
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
        self.shadows = Vec::with_capacity(cage_wake.sources.len());
        self.shadow_order = Vec::with_capacity(cage_wake.sources.len());
        self.cage_wake = cage_wake;
        self.cage_factor.fill(1.0);
        self.wake_ready = false;
        Ok(())
    }

    /// Computes the cage-to-cage ratio of every receiving element from positions `x` into
    /// `cage_next` (never compounded: each call starts from the geometry alone).
    fn next_cage_wake(&mut self, t: f64, x: &[[f64; 3]]) {
        self.cage_next.copy_from_slice(&self.cage_factor);
        if self.cage_wake.is_empty() {
            return;
        }
        self.shadows.clear();
        for s in &self.cage_wake.sources {
            let st = &self.group_state[s.group];
            self.shadow_pts.clear();
            self.shadow_pts.extend(st.net_nodes.iter().map(|&n| x[n]));
            let pts = &self.shadow_pts;
            let k = 1.0 / pts.len().max(1) as f64;
            let zc = pts.iter().map(|p| p[2]).sum::<f64>() * k;
            let o = pts
                .iter()
                .fold([0.0; 2], |a, p| [a[0] + p[0] * k, a[1] + p[1] * k]);
            let uc = unramped_current(&self.sea, [o[0], o[1], zc], t);
            if let Some(sh) =
                CageShadow::of_nodes(*s, pts, [uc[0], uc[1]], self.cage_wake.spreading)
            {
                self.shadows.push(sh);
            }
        }
        set_inflows(&mut self.shadows, &mut self.shadow_order);
        for &(e, g) in &self.cage_receivers {
            let el = self.elems[e];
            let mut c = [0.0; 2];
            for &nd in &el.nodes[..el.n] {
                c[0] += x[nd][0] / el.n as f64;
                c[1] += x[nd][1] / el.n as f64;
            }
            self.cage_next[e] = cage_ratio(&self.shadows, g, c);
        }
    }
}

/// The own-cage wake state of element `el` of group `g` whose net centre is `o`
/// (docs/theory/hydrodynamics.md#shadow-region).
fn own_cell(sea: &Sea, g: &WakeGroup, el: Elem, o: [f64; 2], x: &[[f64; 3]], t: f64) -> WakeCell {
    let mut c = [0.0; 3];
    for &nd in &el.nodes[..el.n] {
        for k in 0..3 {
            c[k] += x[nd][k];
        }
    }
    for ck in &mut c {
        *ck /= el.n as f64;
    }
    let uc = unramped_current(sea, c, t);
    let uh = (uc[0] * uc[0] + uc[1] * uc[1]).sqrt();
    if uh < 1e-6 {
        return WakeCell::default();
    }
    let d = ((c[0] - o[0]) * uc[0] + (c[1] - o[1]) * uc[1]) / uh;
    if d <= g.wake.margin {
        return WakeCell::default();
    }
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
    WakeCell {
        in_shadow: true,
        factor: g.wake.model.factor(g.solidity, cos),
    }
}
