//! Cage-to-cage wake: the current reaching a cage is reduced by the nets of the cages upstream
//! of it (docs/theory/hydrodynamics.md#cage-to-cage-wake).
//!
//! For a cage c with horizontal centre o_c, horizontal current direction û, projected
//! half-width R_c across û and net reduction factor r_c, a point p of another cage with
//! s = (p − o_c)·û > 0 and |(p − o_c) − s·û| < R_c lies in c's shadow: the current reaching it
//! has crossed c's upstream and downstream walls and is multiplied by r_c². The factors of
//! several upstream cages multiply. The field is a pure function of the present geometry
//! ([`CageShadow::of_nodes`], [`cage_ratio`]): recomputed at every wake update, never compounded
//! on its previous value. It sits behind these two functions so that a better field (a
//! published wake law, a velocity field from CFD) can replace it.

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

/// Which cages shadow each other: every listed group is both a source and a receiver.
/// Empty (the default) = no cage-to-cage wake.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CageWake {
    /// The participating cages.
    pub sources: Vec<CageWakeSource>,
}

impl CageWake {
    /// The cage-to-cage wake among `members` (wake group indices), each cage with the net
    /// reduction factor of its own wake model ([`net_reduction_factor`]).
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

/// The shadow of one cage at an instant.
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
}

impl CageShadow {
    /// The shadow of the cage whose net nodes are at `nodes`, in a current of horizontal
    /// components `current` [m/s]; `None` for an empty net or a horizontal current below
    /// 1e-6 m/s (no wake direction).
    pub fn of_nodes(source: CageWakeSource, nodes: &[[f64; 3]], current: [f64; 2]) -> Option<Self> {
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
        })
    }

    /// r_c² if the horizontal point `p` lies in this cage's shadow, else 1.
    pub fn ratio_at(&self, p: [f64; 2]) -> f64 {
        let (s, off) = lateral(self.centre, self.direction, p);
        if s > 0.0 && off < self.half_width {
            self.factor * self.factor
        } else {
            1.0
        }
    }
}

/// (s, |lateral offset|) of p relative to o along the unit direction u.
fn lateral(o: [f64; 2], u: [f64; 2], p: [f64; 2]) -> (f64, f64) {
    let d = [p[0] - o[0], p[1] - o[1]];
    let s = d[0] * u[0] + d[1] * u[1];
    (s, (d[0] - s * u[0]).hypot(d[1] - s * u[1]))
}

/// The cage-to-cage ratio r_cc ∈ (0, 1] at the horizontal point `p` of an element of wake
/// group `own`: the product of r_c² over the other cages whose shadow contains p.
pub fn cage_ratio(shadows: &[CageShadow], own: usize, p: [f64; 2]) -> f64 {
    shadows
        .iter()
        .filter(|s| s.group != own)
        .map(|s| s.ratio_at(p))
        .product()
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
    fn shadow_is_the_downstream_strip_of_the_projected_width() {
        let src = CageWakeSource {
            group: 0,
            factor: 0.8,
        };
        let s = CageShadow::of_nodes(src, &ring(0.0, 0.0, 10.0), [0.5, 0.0]).unwrap();
        assert!(s.centre[0].abs() < 1e-12 && s.centre[1].abs() < 1e-12);
        assert!((s.half_width - 10.0).abs() < 1e-12);
        assert!((s.ratio_at([30.0, 9.9]) - 0.64).abs() < 1e-15);
        assert_eq!(s.ratio_at([30.0, 10.1]), 1.0);
        assert_eq!(s.ratio_at([-30.0, 0.0]), 1.0);
        // Several upstream cages multiply; a cage never shadows itself.
        let s2 = CageShadow::of_nodes(
            CageWakeSource { group: 1, ..src },
            &ring(40.0, 0.0, 10.0),
            [0.5, 0.0],
        )
        .unwrap();
        let both = [s, s2];
        assert!((cage_ratio(&both, 2, [80.0, 0.0]) - 0.64 * 0.64).abs() < 1e-15);
        assert!((cage_ratio(&both, 1, [40.0, 0.0]) - 0.64).abs() < 1e-15);
        assert_eq!(cage_ratio(&both, 0, [0.0, 0.0]), 1.0);
        // A current along y turns the shadow.
        let sy = CageShadow::of_nodes(src, &ring(0.0, 0.0, 10.0), [0.0, -0.3]).unwrap();
        assert!((sy.ratio_at([0.0, -40.0]) - 0.64).abs() < 1e-15);
        assert_eq!(sy.ratio_at([40.0, 0.0]), 1.0);
        assert!(CageShadow::of_nodes(src, &ring(0.0, 0.0, 10.0), [0.0, 0.0]).is_none());
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
