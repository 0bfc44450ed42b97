//! Seabed friction: a regularised Coulomb law per node in contact with the flat seabed
//! (docs/theory/fem.md#seabed-friction, spec farm.md §5).
//!
//! With N the node's normal contact force [N] and v_h its horizontal velocity, split along the
//! horizontal line direction â (axial) and t̂ = ẑ × â (transverse):
//! f = −N·(μ_a·clamp(v_a/v_c, −1, 1)·â + μ_t·clamp(v_t/v_c, −1, 1)·t̂). Nodes without a line
//! direction (no cable element, a junction of three or more, or a vertical line) use the
//! isotropic law f = −μ_t·N·v_h/max(|v_h|, v_c).

use crate::error::{Result, invalid};
use serde::{Deserialize, Serialize};

pub use crate::seabed::DEFAULT_SLIP_VELOCITY;

/// Friction coefficients of the seabed and the regularisation velocity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SeabedFriction {
    /// Axial friction coefficient μ_a (≥ 0) along the local line direction. Default 0 (off).
    pub axial: f64,
    /// Transverse friction coefficient μ_t (≥ 0), also used by nodes without a line direction.
    /// Default 0 (off).
    pub transverse: f64,
    /// Slip velocity v_c [m/s] (> 0): below it the friction grows linearly with the velocity.
    /// Default 1e-2.
    pub slip_velocity: f64,
}

impl Default for SeabedFriction {
    fn default() -> Self {
        Self {
            axial: 0.0,
            transverse: 0.0,
            slip_velocity: DEFAULT_SLIP_VELOCITY,
        }
    }
}

impl SeabedFriction {
    /// Friction with μ_a, μ_t and the default slip velocity.
    pub fn new(axial: f64, transverse: f64) -> Self {
        Self {
            axial,
            transverse,
            ..Self::default()
        }
    }

    /// Whether any friction acts.
    pub fn is_active(&self) -> bool {
        self.axial > 0.0 || self.transverse > 0.0
    }

    pub(crate) fn validate(&self) -> Result<()> {
        for (what, mu) in [
            ("seabed friction_axial", self.axial),
            ("seabed friction_transverse", self.transverse),
        ] {
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(invalid(what, mu, ">= 0"));
            }
        }
        let vc = self.slip_velocity;
        if !(vc.is_finite() && vc > 0.0) {
            return Err(invalid("seabed slip_velocity [m/s]", vc, "> 0"));
        }
        Ok(())
    }
}

/// The friction on one node and its derivatives in the q sense (q = f_int − f_ext, so
/// `k` = −∂f/∂x and `c` = −∂f/∂v; only rows x, y are non-zero).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct NodeFriction {
    /// Friction force [N] (horizontal).
    pub force: [f64; 3],
    /// −∂f/∂x through N(z) [N/m] (the direction's dependence on the neighbours is neglected).
    pub k: [[f64; 3]; 3],
    /// −∂f/∂v [N·s/m]: μN/v_c in the linear zone, and through N(v_z).
    pub c: [[f64; 3]; 3],
    /// Damping μN/v_c of the directions outside the linear zone, which `c` leaves out (their
    /// slope is zero) but which returns when the node slows down (explicit stable step)
    /// [N·s/m].
    pub spare_c: f64,
}

/// The normal contact force of a node and its derivatives.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Normal {
    /// N [N] (> 0 in contact).
    pub force: f64,
    /// −∂N/∂z [N/m].
    pub kz: f64,
    /// −∂N/∂v_z [N·s/m].
    pub cz: f64,
}

/// Friction on a node with normal force `n`, velocity `v` [m/s] and horizontal unit line
/// direction `axis` (`None`: isotropic with μ_t).
pub(crate) fn node_friction(
    p: &SeabedFriction,
    n: Normal,
    v: [f64; 3],
    axis: Option<[f64; 2]>,
) -> NodeFriction {
    let mut out = NodeFriction::default();
    if !(n.force > 0.0) {
        return out;
    }
    let vc = p.slip_velocity;
    // g = −f/N: the friction per newton of normal force, and N·∂g/∂v_h into `ch`.
    let mut g = [0.0; 2];
    let mut ch = [[0.0; 2]; 2];
    match axis {
        Some(a) => {
            let t = [-a[1], a[0]];
            for (mu, e) in [(p.axial, a), (p.transverse, t)] {
                if mu == 0.0 {
                    continue;
                }
                let s = (e[0] * v[0] + e[1] * v[1]) / vc;
                if s.abs() < 1.0 {
                    for r in 0..2 {
                        g[r] += mu * s * e[r];
                        for c in 0..2 {
                            ch[r][c] += mu * n.force / vc * e[r] * e[c];
                        }
                    }
                } else {
                    for r in 0..2 {
                        g[r] += mu * s.signum() * e[r];
                    }
                    out.spare_c += mu * n.force / vc;
                }
            }
        }
        None => {
            let mu = p.transverse;
            let speed = v[0].hypot(v[1]);
            let den = speed.max(vc);
            for r in 0..2 {
                g[r] = mu * v[r] / den;
                for c in 0..2 {
                    let id = if r == c { 1.0 } else { 0.0 };
                    ch[r][c] = if speed < vc {
                        mu * n.force / vc * id
                    } else {
                        mu * n.force / speed * (id - v[r] * v[c] / (speed * speed))
                    };
                }
            }
            out.spare_c = mu * n.force * (1.0 / vc - 1.0 / den);
        }
    }
    for r in 0..2 {
        out.force[r] = -n.force * g[r];
        // f_r = −N·g_r: −∂f_r/∂z = g_r·∂N/∂z = −g_r·kz, −∂f_r/∂v_z = −g_r·cz.
        out.k[r][2] = -g[r] * n.kz;
        out.c[r][2] = -g[r] * n.cz;
        out.c[r][0] = ch[r][0];
        out.c[r][1] = ch[r][1];
    }
    out
}

/// Horizontal unit line direction at a node from the unit vectors `dirs` of its adjacent
/// cable elements (one or two; the second is flipped to agree with the first), or `None` when
/// the line is vertical there or the tangent vanishes.
pub(crate) fn line_axis(dirs: &[[f64; 3]]) -> Option<[f64; 2]> {
    let mut t = [0.0; 3];
    for d in dirs {
        let s = if t[0] * d[0] + t[1] * d[1] + t[2] * d[2] < 0.0 {
            -1.0
        } else {
            1.0
        };
        for k in 0..3 {
            t[k] += s * d[k];
        }
    }
    let len = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
    let h = t[0].hypot(t[1]);
    (len > 0.0 && h > 1e-6 * len).then(|| [t[0] / h, t[1] / h])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normal() -> Normal {
        Normal {
            force: 700.0,
            kz: 3e5,
            cz: 2e4,
        }
    }

    /// N(z, v_z) linear, as the penalty contact: N = N0 − kz·z − cz·v_z.
    fn normal_at(x: [f64; 3], v: [f64; 3]) -> Normal {
        let n0 = normal();
        Normal {
            force: n0.force - n0.kz * x[2] - n0.cz * v[2],
            ..n0
        }
    }

    fn force_at(p: &SeabedFriction, x: [f64; 3], v: [f64; 3], axis: Option<[f64; 2]>) -> [f64; 3] {
        node_friction(p, normal_at(x, v), v, axis).force
    }

    /// The analytic q-sense derivatives agree with central differences of the force, in and
    /// out of the linear zone, for the anisotropic and the isotropic law.
    #[test]
    fn derivatives_match_finite_differences() {
        let p = SeabedFriction {
            axial: 0.7,
            transverse: 1.0,
            slip_velocity: 0.01,
        };
        let a = {
            let (s, c) = 0.4f64.sin_cos();
            [c, s]
        };
        let cases = [
            ([0.003, -0.004, 0.001], Some(a)),
            ([0.3, 0.002, -0.001], Some(a)),
            ([-0.2, 0.5, 0.0], Some(a)),
            ([0.004, 0.002, 0.0], None),
            ([0.3, -0.2, 0.001], None),
        ];
        for (v, axis) in cases {
            let nf = node_friction(&p, normal_at([0.0; 3], v), v, axis);
            let h = 1e-7;
            for c in 0..3 {
                let (mut vp, mut vm) = (v, v);
                vp[c] += h;
                vm[c] -= h;
                let (fp, fm) = (
                    force_at(&p, [0.0; 3], vp, axis),
                    force_at(&p, [0.0; 3], vm, axis),
                );
                let (gp, gm) = (
                    force_at(&p, [0.0, 0.0, h], v, axis),
                    force_at(&p, [0.0, 0.0, -h], v, axis),
                );
                for r in 0..3 {
                    let dv = -(fp[r] - fm[r]) / (2.0 * h);
                    let scale = 1.0 + nf.c[r][c].abs();
                    assert!(
                        (dv - nf.c[r][c]).abs() < 1e-5 * scale,
                        "v {v:?} c[{r}][{c}] {} vs fd {dv}",
                        nf.c[r][c]
                    );
                    if c == 2 {
                        let dx = -(gp[r] - gm[r]) / (2.0 * h);
                        assert!(
                            (dx - nf.k[r][2]).abs() < 1e-5 * (1.0 + dx.abs()),
                            "v {v:?} k[{r}][2] {} vs fd {dx}",
                            nf.k[r][2]
                        );
                    }
                }
            }
        }
    }

    /// Friction never does positive work, and saturates at μN per direction.
    #[test]
    fn friction_only_dissipates_and_saturates() {
        let p = SeabedFriction {
            axial: 0.5,
            transverse: 0.9,
            slip_velocity: 0.02,
        };
        let n = normal();
        for i in 0..200 {
            let th = i as f64 * 0.137;
            let s = 1e-4 * 1.07f64.powi(i);
            let v = [s * th.cos(), s * th.sin(), 0.0];
            for axis in [Some([th.sin(), -th.cos()]), Some([1.0, 0.0]), None] {
                let f = node_friction(&p, n, v, axis).force;
                assert!(f[0] * v[0] + f[1] * v[1] <= 0.0, "{v:?} {f:?}");
                let fa = axis.map(|a| f[0] * a[0] + f[1] * a[1]);
                if let Some(fa) = fa {
                    assert!(fa.abs() <= p.axial * n.force * (1.0 + 1e-12));
                } else {
                    assert!(f[0].hypot(f[1]) <= p.transverse * n.force * (1.0 + 1e-12));
                }
            }
        }
        // Well above v_c along the axis: exactly μ_a·N against the motion.
        let f = node_friction(&p, n, [-1.0, 0.0, 0.0], Some([1.0, 0.0])).force;
        assert!((f[0] - p.axial * n.force).abs() < 1e-9 && f[1] == 0.0);
    }

    #[test]
    fn line_axis_is_the_horizontal_mean_tangent() {
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let ax = line_axis(&[[1.0, 0.0, 0.0], [-r, -r, 0.0]]).unwrap();
        // Second flipped: mean of (1, 0) and (r, r), normalised.
        let m = [1.0 + r, r];
        let l = m[0].hypot(m[1]);
        assert!((ax[0] - m[0] / l).abs() < 1e-12 && (ax[1] - m[1] / l).abs() < 1e-12);
        assert!(line_axis(&[[0.0, 0.0, 1.0]]).is_none());
        assert!(line_axis(&[]).is_none());
    }

    #[test]
    fn invalid_parameters_name_the_key() {
        let bad = [
            SeabedFriction::new(-0.1, 0.0),
            SeabedFriction::new(0.1, f64::NAN),
            SeabedFriction {
                slip_velocity: 0.0,
                ..SeabedFriction::default()
            },
        ];
        for (b, key) in bad
            .iter()
            .zip(["friction_axial", "friction_transverse", "slip_velocity"])
        {
            let e = b.validate().unwrap_err().to_string();
            assert!(e.contains(key), "{e}");
        }
        assert!(SeabedFriction::default().validate().is_ok());
        assert!(!SeabedFriction::default().is_active());
    }
}
