//! Cage-to-cage wake: the current reaching a cage is reduced by the nets of the cages upstream
//! of it, and recovers with the distance behind them
//! (docs/theory/hydrodynamics.md#cage-to-cage-wake).
//!
//! For a cage c with horizontal centre o_c, horizontal current direction û, projected
//! half-width R_c across û and net reduction factor r_c, a point p at s = (p − o_c)·û > 0 and
//! lateral offset d = |(p − o_c) − s·û| lies in c's wake when d < R_w = R_c + k·x, with
//! x = max(s − R_c, 0) the distance behind the cage and k the spreading rate; its velocity
//! deficit there, relative to the current reaching c, is
//! δ_c(p) = (1 − r_c²)·(R_c/R_w)² (a top-hat wake that conserves the flux deficit as it widens).
//! Overlapping wakes add their deficits, each scaled by the current reaching its cage:
//! r_cc(p) = max(0, 1 − Σ_c u_c·δ_c(p)), where u_c is r_cc at o_c from the cages upstream of c.
//! With k = 0 this is the product of the r_c² of the cages upstream. The field is a pure
//! function of the present geometry ([`CageShadow::of_nodes`], [`set_inflows`],
//! [`cage_ratio`]): recomputed at every wake update, never compounded on its previous value.

use crate::assembly::WakeGroup;
use crate::wake::{Wake, WakeModel};

/// One cage (a wake group: one cage copy) that shadows the others.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CageWakeSource {
    /// Its wake group (index into `Elements::wake_groups`).
    pub group: usize,
    /// Its net reduction factor r_c ∈ [0, 1] (the flow behind it is multiplied by r_c²).
    pub factor: f64,
}

/// Spreading rate k of a cage's wake, dR_w/dx (docs/theory/hydrodynamics.md#cage-to-cage-wake):
/// Jensen's value for a top-hat wake.
pub const DEFAULT_SPREADING: f64 = 0.1;

/// Which cages shadow each other: every listed group is both a source and a receiver.
/// No sources (the default) = no cage-to-cage wake.
#[derive(Debug, Clone, PartialEq)]
pub struct CageWake {
    /// The participating cages.
    pub sources: Vec<CageWakeSource>,
    /// Spreading rate k ≥ 0 of every wake [-] (0: no recovery, the deficits multiply).
    pub spreading: f64,
}

impl Default for CageWake {
    fn default() -> Self {
        Self {
            sources: Vec::new(),
            spreading: DEFAULT_SPREADING,
        }
    }
}

impl CageWake {
    /// The cage-to-cage wake among `members` (wake group indices), each cage with the net
    /// reduction factor of its own wake model ([`net_reduction_factor`]), spreading at
    /// [`DEFAULT_SPREADING`].
    pub fn among(groups: &[WakeGroup], members: &[usize]) -> Self {
        Self {
            sources: members
                .iter()
                .filter_map(|&g| {
                    groups.get(g).map(|wg| CageWakeSource {
                        group: g,
                        factor: net_reduction_factor(&wg.wake, wg.solidity),
                    })
                })
                .collect(),
            spreading: DEFAULT_SPREADING,
        }
    }

    /// True if no cage takes part.
    pub fn is_empty(&self) -> bool {
        self.sources.is_empty()
    }
}

/// The net reduction factor r of a cage (hydrodynamics.md §6) for the flow through it: its
/// wake model at normal incidence (c = 1); a cage whose own wake is `none` uses Løland's
/// r = 1 − 0.46·C_D0(Sn), since a net always slows the flow that crosses it.
pub fn net_reduction_factor(wake: &Wake, solidity: f64) -> f64 {
    match wake.model {
        WakeModel::None => WakeModel::Loland { cd0: None }.factor(solidity, 1.0),
        m => m.factor(solidity, 1.0),
    }
}

/// The wake of one cage at an instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CageShadow {
    /// The cage's wake group.
    pub group: usize,
    /// Horizontal centre o_c [m].
    pub centre: [f64; 2],
    /// Horizontal unit direction û of the current.
    pub direction: [f64; 2],
    /// Projected half-width R_c across û [m]: the largest lateral offset of its net nodes.
    pub half_width: f64,
    /// Net reduction factor r_c.
    pub factor: f64,
    /// Spreading rate k [-].
    pub spreading: f64,
    /// u_c: the ratio of the current reaching the cage (r_cc at o_c from the cages upstream;
    /// 1 until [`set_inflows`]).
    pub inflow: f64,
}

impl CageShadow {
    /// The wake of the cage whose net nodes are at `nodes`, in a current of horizontal
    /// components `current` [m/s], spreading at rate `spreading`; `None` for an empty net or a
    /// horizontal current below 1e-6 m/s (no wake direction).
    pub fn of_nodes(
        source: CageWakeSource,
        nodes: &[[f64; 3]],
        current: [f64; 2],
        spreading: f64,
    ) -> Option<Self> {
        let speed = current[0].hypot(current[1]);
        if nodes.is_empty() || speed < 1e-6 {
            return None;
        }
        let u = [current[0] / speed, current[1] / speed];
        let inv = 1.0 / nodes.len() as f64;
        let o = nodes
            .iter()
            .fold([0.0, 0.0], |a, p| [a[0] + p[0] * inv, a[1] + p[1] * inv]);
        let half_width = nodes
            .iter()
            .map(|p| lateral(o, u, [p[0], p[1]]).1)
            .fold(0.0, f64::max);
        Some(Self {
            group: source.group,
            centre: o,
            direction: u,
            half_width,
            factor: source.factor,
            spreading,
            inflow: 1.0,
        })
    }

    /// The velocity deficit δ_c(p) = (1 − r_c²)·(R_c/R_w)² of this cage's wake at the
    /// horizontal point `p`, relative to the current reaching the cage; 0 outside the wake
    /// (upstream of the centre, or farther sideways than R_w = R_c + k·max(s − R_c, 0)).
    pub fn deficit_at(&self, p: [f64; 2]) -> f64 {
        let (s, off) = lateral(self.centre, self.direction, p);
        let r = self.half_width;
        let width = r + self.spreading * (s - r).max(0.0);
        if s <= 0.0 || off >= width {
            return 0.0;
        }
        let shrink = r / width;
        (1.0 - self.factor * self.factor) * shrink * shrink
    }
}

/// (s, |lateral offset|) of p relative to o along the unit direction u.
fn lateral(o: [f64; 2], u: [f64; 2], p: [f64; 2]) -> (f64, f64) {
    let d = [p[0] - o[0], p[1] - o[1]];
    let s = d[0] * u[0] + d[1] * u[1];
    (s, (d[0] - s * u[0]).hypot(d[1] - s * u[1]))
}

/// Sets the inflow u_c of every cage, from upstream to downstream: u_c = r_cc(o_c) from the
/// wakes of the cages ahead of c. Cages are taken in the order of their centres along the
/// mean current direction, and only a cage earlier in that order can slow a later one (so
/// the recursion always ends, even where the current turns with depth).
pub fn set_inflows(shadows: &mut [CageShadow], order: &mut Vec<usize>) {
    let mean = shadows.iter().fold([0.0, 0.0], |a, s| {
        [a[0] + s.direction[0], a[1] + s.direction[1]]
    });
    let along = |s: &CageShadow| s.centre[0] * mean[0] + s.centre[1] * mean[1];
    order.clear();
    order.extend(0..shadows.len());
    order.sort_by(|&a, &b| along(&shadows[a]).total_cmp(&along(&shadows[b])));
    for k in 0..order.len() {
        let c = shadows[order[k]].centre;
        let deficit: f64 = order[..k]
            .iter()
            .map(|&j| shadows[j].inflow * shadows[j].deficit_at(c))
            .sum();
        shadows[order[k]].inflow = (1.0 - deficit).max(0.0);
    }
}

/// The cage-to-cage ratio r_cc ∈ [0, 1] at the horizontal point `p` of an element of wake
/// group `own`: 1 − Σ u_c·δ_c(p) over the other cages, at least 0 (call [`set_inflows`]
/// first).
pub fn cage_ratio(shadows: &[CageShadow], own: usize, p: [f64; 2]) -> f64 {
    let deficit: f64 = shadows
        .iter()
        .filter(|s| s.group != own)
        .map(|s| s.inflow * s.deficit_at(p))
        .sum();
    (1.0 - deficit).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(cx: f64, cy: f64, r: f64) -> Vec<[f64; 3]> {
        (0..16)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 16.0;
                [cx + r * a.cos(), cy + r * a.sin(), -3.0]
            })
            .collect()
    }

    #[test]
    fn without_spreading_the_wake_is_the_downstream_strip_and_factors_multiply() {
        let src = CageWakeSource {
            group: 0,
            factor: 0.8,
        };
        let mut s = CageShadow::of_nodes(src, &ring(0.0, 0.0, 10.0), [0.5, 0.0], 0.0).unwrap();
        assert!(s.centre[0].abs() < 1e-12 && s.centre[1].abs() < 1e-12);
        assert!((s.half_width - 10.0).abs() < 1e-12);
        assert!((s.deficit_at([30.0, 9.9]) - 0.36).abs() < 1e-15);
        assert_eq!(s.deficit_at([30.0, 10.1]), 0.0);
        assert_eq!(s.deficit_at([-30.0, 0.0]), 0.0);
        // Several upstream cages: with k = 0 the ratios multiply; a cage never shadows itself.
        let s2 = CageShadow::of_nodes(
            CageWakeSource { group: 1, ..src },
            &ring(40.0, 0.0, 10.0),
            [0.5, 0.0],
            0.0,
        )
        .unwrap();
        s.inflow = 0.3; // overwritten by set_inflows
        let mut both = [s2, s];
        set_inflows(&mut both, &mut Vec::new());
        assert_eq!(both[1].inflow, 1.0);
        assert!((both[0].inflow - 0.64).abs() < 1e-15);
        assert!((cage_ratio(&both, 2, [80.0, 0.0]) - 0.64 * 0.64).abs() < 1e-15);
        assert!((cage_ratio(&both, 1, [40.0, 0.0]) - 0.64).abs() < 1e-15);
        assert_eq!(cage_ratio(&both, 0, [0.0, 0.0]), 1.0);
        // A current along y turns the wake.
        let sy = CageShadow::of_nodes(src, &ring(0.0, 0.0, 10.0), [0.0, -0.3], 0.0).unwrap();
        assert!((sy.deficit_at([0.0, -40.0]) - 0.36).abs() < 1e-15);
        assert_eq!(sy.deficit_at([40.0, 0.0]), 0.0);
        assert!(CageShadow::of_nodes(src, &ring(0.0, 0.0, 10.0), [0.0, 0.0], 0.0).is_none());
    }

    #[test]
    fn the_wake_widens_and_its_deficit_falls_with_the_square_of_the_width() {
        let src = CageWakeSource {
            group: 0,
            factor: 0.8,
        };
        let s = CageShadow::of_nodes(src, &ring(0.0, 0.0, 10.0), [0.5, 0.0], 0.1).unwrap();
        // Inside the cage's own footprint (s ≤ R) the deficit is the near-wake one.
        assert!((s.deficit_at([5.0, 0.0]) - 0.36).abs() < 1e-15);
        // 30 m behind the rear wall the wake is 13 m wide: deficit 0.36·(10/13)².
        let d = 0.36 * (10.0f64 / 13.0).powi(2);
        assert!((s.deficit_at([40.0, 12.9]) - d).abs() < 1e-15);
        assert_eq!(s.deficit_at([40.0, 13.1]), 0.0);
    }

    #[test]
    fn factor_is_the_nets_own_model_at_normal_incidence() {
        let sn = 0.2056;
        let mut w = Wake::none();
        // Løland for a net without a wake model of its own (worked value of the spec).
        assert!((net_reduction_factor(&w, sn) - 0.8747649546).abs() < 5e-11);
        w.model = WakeModel::Factor(0.7);
        assert_eq!(net_reduction_factor(&w, sn), 0.7);
    }
}
