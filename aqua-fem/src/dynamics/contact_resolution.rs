//! Whether the time step resolves the seabed contact of the nodes that land on or lift off the
//! bed (docs/theory/fem.md#seabed-contact-resolution): for each landing or lift-off with an
//! impact, its contact frequency ω_c = √(k_c/m) and the share of a contact oscillation's
//! amplitude the scheme removes over one period 2π/ω_c at that step, from the scheme's
//! spectral radius on a linear oscillator.

use super::scheme::Scheme;
use crate::model::Model;
use crate::seabed::BedLaw;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A landing or lift-off counts as an impact when its dynamic contact force, as far as the line
/// passes it on, per metre of line at the node, is at least this multiple of the node's weight
/// [1/m] (J ≥ 0.3 m⁻¹; calibrated on the mooring chain at 40 and 80 segments,
/// docs/theory/fem.md#seabed-contact-resolution).
pub const CONTACT_IMPACT: f64 = 0.3;

/// An impact's amplitude loss above which a run warns that the seabed contact is not resolved
/// (1 %).
pub const CONTACT_LOSS_WARNING: f64 = 0.01;

/// What the run's landings and lift-offs tell about the time step's resolution of the seabed
/// contact (reported in run.json under `step_control.seabed_contact`;
/// docs/theory/fem.md#seabed-contact-resolution).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactResolution {
    /// Node crossings of the bed plane (landings and lift-offs) over the accepted steps.
    pub events: usize,
    /// Those whose impact J reached [`CONTACT_IMPACT`].
    pub impacts: usize,
    /// The largest impact J of any landing or lift-off [1/m].
    pub largest_impact: f64,
    /// The impact with the largest amplitude loss (the first of equal ones): its node.
    pub node: usize,
    /// Its contact frequency ω_c = √(k_c/m) [rad/s]: bed stiffness k_c = k_b·d_c·L_i (plus a
    /// point body's k_p) over the node's vertical mass m (structural plus added).
    pub omega: f64,
    /// Its step Δt [s].
    pub dt: f64,
    /// Its impact J [1/m]: the dynamic contact force m·ω_c·|v_z| of a landing (or lift-off) at
    /// the vertical speed |v_z| (the larger of the step's ends) over the node's weight w, times
    /// the share τ = k_a/(k_a + k_c) of it the node's line passes on (k_a = Σ EA/L0 of its
    /// cable elements), per length L_i = Σ L0/2 of line at the node: on a smooth line a node
    /// lands at a speed that grows with its element length, so J is a property of the line's
    /// motion, not of its mesh.
    pub impact: f64,
    /// The share of a contact oscillation's amplitude the scheme removes over one contact
    /// period, 1 − ρ(ω_c·Δt)^max(1, 2π/(ω_c·Δt)), ρ the scheme's spectral radius on a linear
    /// oscillator (0 for the midpoint rule with θ = ½). The estimate of how far low the
    /// extremes of the tensions the contact drives may be (an upper-bound-like figure: the
    /// crest cannot lose more than the contact oscillation it rides on).
    pub loss: f64,
    /// The largest step at which this scheme's loss at ω_c is at most
    /// [`CONTACT_LOSS_WARNING`] [s] (the event's Δt when it already is).
    pub resolving_dt: f64,
}

/// The per-node constants of the contact check.
#[derive(Debug, Clone)]
pub(crate) struct ContactTracker {
    /// Bed height z_s [m].
    zs: f64,
    /// Contact stiffness k_c of each node [N/m] (0: the node cannot touch the bed or its z is
    /// held).
    k: Vec<f64>,
    /// Axial stiffness k_a = Σ EA/L0 of each node's cable elements [N/m].
    axial: Vec<f64>,
    /// Line length L_i = Σ L0/2 of each node's cable elements [m].
    length: Vec<f64>,
}

impl ContactTracker {
    /// The tracker of `model`'s free nodes that can touch its seabed (None without a seabed or
    /// such a node).
    pub(crate) fn new(model: &Model) -> Option<Self> {
        let seabed = model.env.seabed?;
        let bed = BedLaw::new(model, true);
        let n = model.n_nodes();
        let k: Vec<f64> = (0..n)
            .map(|i| {
                if bed.acts_on(model, i) && !model.is_constrained(i, 2) {
                    bed.stiffness(model, i)
                } else {
                    0.0
                }
            })
            .collect();
        if k.iter().all(|&k| k <= 0.0) {
            return None;
        }
        let (mut axial, mut length) = (vec![0.0; n], vec![0.0; n]);
        for e in model.elements.iter().filter(|e| e.l0 > 0.0) {
            for i in [e.a, e.b] {
                axial[i] += e.ea / e.l0;
                length[i] += 0.5 * e.l0;
            }
        }
        Some(Self {
            zs: -seabed.depth,
            k,
            axial,
            length,
        })
    }

    /// Records the landings and lift-offs of an accepted step of length h [s] from (x_n, v_n)
    /// to (x1, v1); `added` is the nodes' added-mass blocks [kg].
    pub(crate) fn step(
        &self,
        model: &Model,
        scheme: &Scheme,
        added: &[[[f64; 3]; 3]],
        (xn, vn): (&[[f64; 3]], &[[f64; 3]]),
        (x1, v1): (&[[f64; 3]], &[[f64; 3]]),
        h: f64,
        out: &mut ContactResolution,
    ) {
        for (i, &k) in self.k.iter().enumerate() {
            if k <= 0.0 || (xn[i][2] < self.zs) == (x1[i][2] < self.zs) {
                continue;
            }
            out.events += 1;
            let m = model.lumped_mass[i] + added.get(i).map_or(0.0, |a| a[2][2]);
            let w = model.weight[i][2].abs();
            let l = self.length[i];
            if m <= 0.0 || w <= 0.0 || l <= 0.0 {
                continue;
            }
            let omega = (k / m).sqrt();
            let speed = vn[i][2].abs().max(v1[i][2].abs());
            let share = self.axial[i] / (self.axial[i] + k);
            let impact = share * m * omega * speed / (w * l);
            out.largest_impact = out.largest_impact.max(impact);
            if impact < CONTACT_IMPACT {
                continue;
            }
            out.impacts += 1;
            let wdt = omega * h;
            let loss = period_loss(scheme.spectral_radius(wdt), wdt);
            if out.impacts == 1 || loss > out.loss {
                *out = ContactResolution {
                    events: out.events,
                    impacts: out.impacts,
                    largest_impact: out.largest_impact,
                    node: i,
                    omega,
                    dt: h,
                    impact,
                    loss,
                    resolving_dt: resolving_step(scheme, omega, h),
                };
            }
        }
    }
}

/// The largest step h ≤ `dt` [s] whose amplitude loss at ω [rad/s] is at most
/// [`CONTACT_LOSS_WARNING`] (bisection; the loss grows with ωh up to its peak).
fn resolving_step(scheme: &Scheme, omega: f64, dt: f64) -> f64 {
    let loss = |h: f64| period_loss(scheme.spectral_radius(omega * h), omega * h);
    if loss(dt) <= CONTACT_LOSS_WARNING {
        return dt;
    }
    let (mut lo, mut hi) = (0.0, dt);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if loss(mid) <= CONTACT_LOSS_WARNING {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The share 1 − ρ^N of an oscillation's amplitude removed over one period, N = 2π/Ω steps
/// (at least one: a step longer than the period still removes 1 − ρ).
pub(crate) fn period_loss(rho: f64, omega_dt: f64) -> f64 {
    let steps = if omega_dt > 0.0 {
        (2.0 * PI / omega_dt).max(1.0)
    } else {
        return 0.0;
    };
    (1.0 - rho.clamp(0.0, 1.0).powf(steps)).max(0.0)
}

/// The largest |λ| of a real 3×3 matrix: a real root of its characteristic polynomial by
/// bisection, the other two from the deflated quadratic.
pub(crate) fn spectral_radius_3(m: &[[f64; 3]; 3]) -> f64 {
    // λ³ − c2·λ² + c1·λ − c0 with c2 the trace, c1 the sum of principal 2×2 minors, c0 the
    // determinant.
    let c2 = m[0][0] + m[1][1] + m[2][2];
    let c1 = m[0][0] * m[1][1] - m[0][1] * m[1][0] + m[0][0] * m[2][2] - m[0][2] * m[2][0]
        + m[1][1] * m[2][2]
        - m[1][2] * m[2][1];
    let c0 = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    let p = |l: f64| ((l - c2) * l + c1) * l - c0;
    // Cauchy's bound on the roots.
    let bound = 1.0 + c2.abs().max(c1.abs()).max(c0.abs());
    let (mut lo, mut hi) = (-bound, bound);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if p(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let r = 0.5 * (lo + hi);
    // λ² + b·λ + c = p(λ)/(λ − r).
    let b = r - c2;
    let c = c1 + r * b;
    let disc = b * b - 4.0 * c;
    let pair = if disc < 0.0 {
        c.abs().sqrt()
    } else {
        0.5 * (b.abs() + disc.sqrt())
    };
    r.abs().max(pair)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_radius_of_a_diagonal_and_a_rotation() {
        let d = [[0.5, 0.0, 0.0], [0.0, -0.9, 0.0], [0.0, 0.0, 0.2]];
        assert!((spectral_radius_3(&d) - 0.9).abs() < 1e-12);
        // A rotation scaled by 0.8 in the first two axes and 0.1 on the third.
        let (c, s) = (0.8 * 0.3f64.cos(), 0.8 * 0.3f64.sin());
        let r = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 0.1]];
        assert!((spectral_radius_3(&r) - 0.8).abs() < 1e-12);
    }

    #[test]
    fn spectral_radii_match_the_schemes_known_limits() {
        use super::super::{hht::Hht, midpoint::Midpoint};
        // docs/theory/fem.md#hht-spectral-properties: α = 0.1 at Ω = 2π·0.1, ρ = 0.998727782
        // (fitted on a cable oscillator), and ρ∞ = (1 − α)/(1 + α).
        let h = Hht::new(0.1);
        assert!((h.spectral_radius(0.2 * PI) - 0.998727782).abs() < 1e-8);
        assert!((h.spectral_radius(1e6) - 0.9 / 1.1).abs() < 1e-6);
        assert!((Hht::new(0.0).spectral_radius(3.0) - 1.0).abs() < 1e-12);
        // The midpoint rule: θ = ½ conserves; θ > ½ damps at moderate Ω and tends back to 1
        // as Ω → ∞.
        let mid = Midpoint::new(0.5, 0);
        for w in [0.1, 1.0, 10.0] {
            assert!((mid.spectral_radius(w) - 1.0).abs() < 1e-12);
        }
        let decaying = Midpoint::new(0.75, 0);
        assert!(decaying.spectral_radius(1.0) < 0.95);
        assert!(decaying.spectral_radius(1e4) > 0.999);
    }

    #[test]
    fn period_loss_counts_at_least_one_step() {
        assert_eq!(period_loss(1.0, 0.5), 0.0);
        assert!((period_loss(0.9, 10.0) - 0.1).abs() < 1e-12);
        let w = 2.0 * PI / 4.0;
        assert!((period_loss(0.9, w) - (1.0 - 0.9f64.powi(4))).abs() < 1e-12);
    }
}
