//! Free 6-DOF rigid bodies (docs/theory/fem.md#rigid-bodies): what a scene gives
//! ([`RigidBodySpec`]), the resolved body ([`RigidBody`]), its pose ([`BodyPose`]), the
//! incremental rotation vector on the body's rotation carrier with its reference frame
//! (Rodrigues' formula, smooth at zero), and the rigid link, a penalty element
//! W = ½·k·|x_p − x_c − R·p|² that holds a node to the body.

use crate::dual::{Dual1, Dual2, Real};
use crate::error::{FemError, Result};

/// The link stiffness k is this factor times the largest axial stiffness EA/L0 of the members
/// at the held point (or of the body's own floor, [`link_floor`]): the link stretches
/// 1/LINK_STIFFNESS_FACTOR of what a line on the point stretches under the same force
/// (docs/theory/fem.md#rigid-bodies).
pub const LINK_STIFFNESS_FACTOR: f64 = 1e4;

/// What a scene gives for a free rigid body.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBodySpec {
    /// Name (unique among the bodies; names the body in errors).
    pub name: String,
    /// Centre of gravity as built [m] (world frame; the body frame's axes are the world's as built).
    pub centre: [f64; 3],
    /// Mass [kg] (> 0).
    pub mass: f64,
    /// Inertia tensor about the centre of gravity in the as-built axes [kg·m²] (symmetric, positive definite).
    pub inertia: [[f64; 3]; 3],
    /// Existing nodes held rigidly to the body (fairleads, hull points); their as-built offsets from `centre` define where they sit on the body.
    pub points: Vec<usize>,
}

/// A free rigid body of a model (resolved).
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    /// Name.
    pub name: String,
    /// Centre-of-gravity node (created by [`crate::ModelBuilder::add_rigid_body`]): its
    /// coordinates are the centre's position [m]; it carries the mass.
    pub node: usize,
    /// Rotation carrier node (created by [`crate::ModelBuilder::add_rigid_body`]): its three
    /// coordinates are the accumulated rotation vector ψ [rad], not a position.
    pub rotation_node: usize,
    /// Mass M [kg].
    pub mass: f64,
    /// Inertia tensor about the centre of gravity in the body frame [kg·m²].
    pub inertia: [[f64; 3]; 3],
    /// Held nodes and their offsets p from the centre in the body frame [m].
    pub points: Vec<(usize, [f64; 3])>,
}

/// The pose and velocity of a body in a state: centre [m], rotation matrix R (body → world),
/// angles [roll, pitch, yaw] [rad] with R = Rz(yaw)·Ry(pitch)·Rx(roll), velocity [m/s],
/// angular velocity (world) [rad/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyPose {
    /// Centre of gravity [m].
    pub centre: [f64; 3],
    /// Rotation matrix R, body → world.
    pub rotation: [[f64; 3]; 3],
    /// [roll, pitch, yaw] [rad], R = Rz(yaw)·Ry(pitch)·Rx(roll); pitch in [−π/2, π/2].
    pub angles: [f64; 3],
    /// Velocity of the centre [m/s].
    pub velocity: [f64; 3],
    /// Angular velocity in the world frame [rad/s].
    pub angular_velocity: [f64; 3],
}

/// A rigid link: node `node` held to body `body` at offset `offset` (body frame) with
/// stiffness `stiffness` [N/m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Link {
    pub body: usize,
    pub node: usize,
    pub centre: usize,
    pub rotation: usize,
    pub offset: [f64; 3],
    pub stiffness: f64,
}

/// The reference of a body's rotation: its orientation R_ref and the carrier's value ψ_ref at
/// the last accepted state; R = exp([ψ − ψ_ref]×)·R_ref.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BodyFrame {
    pub rotation: [[f64; 3]; 3],
    pub psi: [f64; 3],
}

impl Default for BodyFrame {
    fn default() -> Self {
        Self {
            rotation: IDENTITY,
            psi: [0.0; 3],
        }
    }
}

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl BodyFrame {
    /// The orientation at carrier value ψ.
    pub fn orientation(&self, psi: [f64; 3]) -> [[f64; 3]; 3] {
        matmul(&exp_so3(sub(psi, self.psi)), &self.rotation)
    }

    /// Moves the reference to the accepted carrier value ψ (orientation unchanged).
    pub fn accept(&mut self, psi: [f64; 3]) {
        if psi == self.psi {
            return;
        }
        self.rotation = orthonormalised(self.orientation(psi));
        self.psi = psi;
    }

    /// The inertia tensor in world axes at the reference, R_ref·I·R_refᵀ [kg·m²].
    pub fn world_inertia(&self, inertia: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let r = &self.rotation;
        let ri = matmul(r, inertia);
        let mut out = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                out[i][j] = (0..3).map(|k| ri[i][k] * r[j][k]).sum();
            }
        }
        out
    }

    /// The pose of a body with this frame at (centre, ψ) moving at (v, ψ̇).
    pub fn pose(&self, x: [f64; 3], psi: [f64; 3], v: [f64; 3], psi_dot: [f64; 3]) -> BodyPose {
        let phi = sub(psi, self.psi);
        let rotation = self.orientation(psi);
        BodyPose {
            centre: x,
            rotation,
            angles: angles(&rotation),
            velocity: v,
            angular_velocity: dexp(phi, psi_dot),
        }
    }
}

/// Validates a body's spec: mass, inertia, centre (points are checked by the builder).
pub(crate) fn validate(spec: &RigidBodySpec) -> Result<()> {
    let bad = |key: &str, value: String, valid: &str| FemError::RigidBody {
        body: spec.name.clone(),
        key: key.to_string(),
        value,
        valid: valid.to_string(),
    };
    if spec.name.trim().is_empty() {
        return Err(bad("name", format!("{:?}", spec.name), "a non-empty name"));
    }
    if spec.centre.iter().any(|c| !c.is_finite()) {
        return Err(bad(
            "centre [m]",
            format!("{:?}", spec.centre),
            "finite coordinates",
        ));
    }
    if !(spec.mass.is_finite() && spec.mass > 0.0) {
        return Err(bad("mass [kg]", format!("{}", spec.mass), "> 0"));
    }
    let i = &spec.inertia;
    let shown = format!("{i:?}");
    if i.iter().flatten().any(|c| !c.is_finite()) {
        return Err(bad("inertia [kg m^2]", shown, "finite entries"));
    }
    let scale = i.iter().flatten().fold(0.0f64, |m, c| m.max(c.abs()));
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        if (i[a][b] - i[b][a]).abs() > 1e-9 * scale {
            return Err(bad(
                "inertia [kg m^2]",
                shown,
                "a symmetric tensor (I[a][b] = I[b][a] to 1e-9 of its largest entry)",
            ));
        }
    }
    // Sylvester's criterion: the leading minors are positive.
    let m1 = i[0][0];
    let m2 = i[0][0] * i[1][1] - i[0][1] * i[1][0];
    let m3 = det(i);
    if !(m1 > 0.0 && m2 > 0.0 && m3 > 0.0) {
        return Err(bad(
            "inertia [kg m^2]",
            shown,
            "a positive definite tensor (leading minors > 0)",
        ));
    }
    Ok(())
}

/// The link stiffness floor of a body whose held point has no member: k such that the body's
/// weight (at g ≥ 1 m/s²) stretches the link 1/LINK_STIFFNESS_FACTOR of the body's size
/// L_b = max(largest |p|, 1 m) [N/m].
pub(crate) fn link_floor(mass: f64, gravity: f64, points: &[(usize, [f64; 3])]) -> f64 {
    let size = points.iter().map(|(_, p)| norm(*p)).fold(1.0, f64::max);
    LINK_STIFFNESS_FACTOR * mass * gravity.max(1.0) / size
}

/// Result of evaluating one rigid link.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LinkEval {
    /// Energy W [J].
    pub energy: f64,
    /// ∂W/∂(x_p, x_c, ψ) [N, N, N·m].
    pub force: [f64; 9],
    /// ∂²W over the same DOFs.
    pub k: [[f64; 9]; 9],
    /// |x_p − x_c − R·p| [m].
    pub stretch: f64,
    /// Non-finite.
    pub bad: bool,
}

impl Default for LinkEval {
    fn default() -> Self {
        Self {
            energy: 0.0,
            force: [0.0; 9],
            k: [[0.0; 9]; 9],
            stretch: 0.0,
            bad: false,
        }
    }
}

/// The 6 variables of a link: u = x_p − x_c and φ = ψ − ψ_ref.
pub(crate) type LinkVars = [f64; 6];

/// Link variables from the point, the centre, the carrier and the reference ψ_ref.
pub(crate) fn link_vars(xp: [f64; 3], xc: [f64; 3], psi: [f64; 3], psi_ref: [f64; 3]) -> LinkVars {
    let u = sub(xp, xc);
    let phi = sub(psi, psi_ref);
    [u[0], u[1], u[2], phi[0], phi[1], phi[2]]
}

fn link_energy_of<D: Real>(k: f64, q: [f64; 3], y: &[D; 6]) -> D {
    let rq = rotate([y[3], y[4], y[5]], q);
    let d = [y[0] - rq[0], y[1] - rq[1], y[2] - rq[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) * (0.5 * k)
}

/// Energy W [J] of a link of stiffness k and reference offset q = R_ref·p at the variables y.
pub(crate) fn link_energy(k: f64, q: [f64; 3], y: &LinkVars) -> f64 {
    link_energy_of(k, q, y)
}

/// Evaluates a link of stiffness `k` and reference offset `q` = R_ref·p at the variables `y`
/// into `out` (tangent only if `tangent`). With `ends = Some((y0, y1))` the force is the
/// discrete gradient between the step's ends and `y` their mean
/// (docs/theory/fem.md#energy-consistent-midpoint).
pub(crate) fn evaluate_link(
    k: f64,
    q: [f64; 3],
    y: &LinkVars,
    ends: Option<(&LinkVars, &LinkVars)>,
    tangent: bool,
    out: &mut LinkEval,
) {
    let (w, mut g) = if tangent {
        let z: [Dual2<6>; 6] = std::array::from_fn(|i| Dual2::var(y[i], i));
        let e = link_energy_of(k, q, &z);
        // B maps (x_p, x_c, ψ) to (u, φ): u = x_p − x_c, φ = ψ − ψ_ref.
        for r in 0..9 {
            for c in 0..9 {
                let (vr, sr) = var_of(r);
                let (vc, sc) = var_of(c);
                out.k[r][c] = sr * sc * e.h[vr][vc];
            }
        }
        (e.v, e.g)
    } else {
        let z: [Dual1<6>; 6] = std::array::from_fn(|i| Dual1::var(y[i], i));
        let e = link_energy_of(k, q, &z);
        (e.v, e.g)
    };
    out.energy = w;
    if let Some((y0, y1)) = ends {
        // Gonzalez's discrete gradient with the metric diag(1, 1, 1, |q|², |q|², |q|²).
        let wq = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
        let wgt = [1.0, 1.0, 1.0, wq, wq, wq];
        let (w0, w1) = (link_energy(k, q, y0), link_energy(k, q, y1));
        let (mut gd, mut dd) = (0.0, 0.0);
        let mut delta = [0.0; 6];
        for i in 0..6 {
            delta[i] = y1[i] - y0[i];
            gd += g[i] * delta[i];
            dd += wgt[i] * delta[i] * delta[i];
        }
        if dd > 1e-300 {
            let corr = (w1 - w0 - gd) / dd;
            for i in 0..6 {
                g[i] += corr * wgt[i] * delta[i];
            }
        }
    }
    for r in 0..9 {
        let (v, s) = var_of(r);
        out.force[r] = s * g[v];
    }
    out.stretch = (2.0 * w / k).max(0.0).sqrt();
    out.bad = !(w.is_finite() && g.iter().all(|c| c.is_finite()));
    if tangent {
        out.bad |= !out.k.iter().flatten().all(|c| c.is_finite());
    }
}

/// The link variable of DOF r of (x_p, x_c, ψ) and its sign.
fn var_of(r: usize) -> (usize, f64) {
    match r {
        0..=2 => (r, 1.0),
        3..=5 => (r - 3, -1.0),
        _ => (r - 3, 1.0),
    }
}

/// Rodrigues' coefficients a = sin θ/θ and b = (1 − cos θ)/θ² of s = θ², by their series for
/// s < 1e-2 (truncation below 1e-21) so that they are smooth at 0.
fn coefficients<D: Real>(s: D) -> (D, D) {
    if s.val() < 1e-2 {
        let a = ((((s * (-1.0 / 39_916_800.0) + 1.0 / 362_880.0) * s + (-1.0 / 5040.0)) * s
            + 1.0 / 120.0)
            * s
            + (-1.0 / 6.0))
            * s
            + 1.0;
        let b = ((((s * (-1.0 / 479_001_600.0) + 1.0 / 3_628_800.0) * s + (-1.0 / 40_320.0)) * s
            + 1.0 / 720.0)
            * s
            + (-1.0 / 24.0))
            * s
            + 0.5;
        (a, b)
    } else {
        let t = s.sqrt();
        (t.sin() / t, (-t.cos() + 1.0) / s)
    }
}

/// exp([φ]×)·q = q + a·φ×q + b·φ×(φ×q) (Rodrigues).
pub(crate) fn rotate<D: Real>(phi: [D; 3], q: [f64; 3]) -> [D; 3] {
    let s = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2];
    let (a, b) = coefficients(s);
    let qd = q.map(D::cst);
    let c1 = cross(phi, qd);
    let c2 = cross(phi, c1);
    [
        qd[0] + a * c1[0] + b * c2[0],
        qd[1] + a * c1[1] + b * c2[1],
        qd[2] + a * c1[2] + b * c2[2],
    ]
}

/// The rotation matrix exp([φ]×).
pub(crate) fn exp_so3(phi: [f64; 3]) -> [[f64; 3]; 3] {
    let mut r = [[0.0; 3]; 3];
    for j in 0..3 {
        let mut e = [0.0; 3];
        e[j] = 1.0;
        let c = rotate(phi, e);
        for i in 0..3 {
            r[i][j] = c[i];
        }
    }
    r
}

/// The angular velocity ω = T(φ)·φ̇ of R = exp([φ]×)·R_ref, with
/// T = I + b·[φ]× + c·[φ]×², c = (1 − a)/θ² (series 1/6 − θ²/120 + θ⁴/5040 near 0).
pub(crate) fn dexp(phi: [f64; 3], phi_dot: [f64; 3]) -> [f64; 3] {
    let s = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2];
    let (a, b) = coefficients(s);
    let c = if s < 1e-2 {
        ((s / 362_880.0 - 1.0 / 5040.0) * s + 1.0 / 120.0) * -s + 1.0 / 6.0
    } else {
        (1.0 - a) / s
    };
    let c1 = cross(phi, phi_dot);
    let c2 = cross(phi, c1);
    std::array::from_fn(|i| phi_dot[i] + b * c1[i] + c * c2[i])
}

/// [roll, pitch, yaw] of R = Rz(yaw)·Ry(pitch)·Rx(roll) [rad].
pub(crate) fn angles(r: &[[f64; 3]; 3]) -> [f64; 3] {
    let roll = r[2][1].atan2(r[2][2]);
    let pitch = (-r[2][0]).atan2((r[0][0] * r[0][0] + r[1][0] * r[1][0]).sqrt());
    let yaw = r[1][0].atan2(r[0][0]);
    [roll, pitch, yaw]
}

fn orthonormalised(r: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let col = |j: usize| [r[0][j], r[1][j], r[2][j]];
    let (c0, c1) = (col(0), col(1));
    let n0 = norm(c0);
    let e0 = c0.map(|c| c / n0);
    let d = dot(e0, c1);
    let c1 = [c1[0] - d * e0[0], c1[1] - d * e0[1], c1[2] - d * e0[2]];
    let n1 = norm(c1);
    let e1 = c1.map(|c| c / n1);
    let e2 = cross(e0, e1);
    let mut out = [[0.0; 3]; 3];
    for i in 0..3 {
        out[i] = [e0[i], e1[i], e2[i]];
    }
    out
}

pub(crate) fn matmul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            out[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    out
}

pub(crate) fn matvec(a: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}

fn det(m: &[[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

fn cross<D: Real>(a: [D; 3], b: [D; 3]) -> [D; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rodrigues_is_smooth_and_matches_the_closed_form() {
        // A rotation of θ about z.
        for theta in [0.0, 1e-9, 0.05, 0.0999, 0.1001, 1.0, 3.0] {
            let r = exp_so3([0.0, 0.0, theta]);
            let (s, c) = f64::sin_cos(theta);
            let want = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
            for i in 0..3 {
                for j in 0..3 {
                    assert!((r[i][j] - want[i][j]).abs() < 1e-15, "{theta}: {r:?}");
                }
            }
        }
        let r = exp_so3([0.3, -0.2, 0.7]);
        let a = angles(&r);
        let (rx, ry, rz) = (
            exp_so3([a[0], 0.0, 0.0]),
            exp_so3([0.0, a[1], 0.0]),
            exp_so3([0.0, 0.0, a[2]]),
        );
        let back = matmul(&rz, &matmul(&ry, &rx));
        for i in 0..3 {
            for j in 0..3 {
                assert!((back[i][j] - r[i][j]).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn link_force_and_tangent_are_the_derivatives_of_its_energy() {
        let (k, q) = (7.0, [0.4, -1.1, 0.3]);
        // Across the series' edge and at φ = 0.
        for phi in [[0.0; 3], [0.03, 0.05, -0.07], [0.3, 0.5, -0.7]] {
            let y = [0.5, -0.9, 0.4, phi[0], phi[1], phi[2]];
            let mut ev = LinkEval::default();
            evaluate_link(k, q, &y, None, true, &mut ev);
            let h = 1e-6;
            for d in 0..6 {
                let (mut yp, mut ym) = (y, y);
                yp[d] += h;
                ym[d] -= h;
                let fd = (link_energy(k, q, &yp) - link_energy(k, q, &ym)) / (2.0 * h);
                let dof = if d < 3 { d } else { d + 3 };
                assert!((fd - ev.force[dof]).abs() < 1e-7, "{phi:?} {d}");
                if d < 3 {
                    assert_eq!(ev.force[d + 3], -ev.force[d]);
                }
                let (mut ep, mut em) = (LinkEval::default(), LinkEval::default());
                evaluate_link(k, q, &yp, None, false, &mut ep);
                evaluate_link(k, q, &ym, None, false, &mut em);
                for r in 0..9 {
                    let kfd = (ep.force[r] - em.force[r]) / (2.0 * h);
                    assert!((kfd - ev.k[r][dof]).abs() < 1e-6, "{phi:?} k[{r}][{dof}]");
                }
            }
        }
    }

    #[test]
    fn discrete_gradient_gives_the_exact_energy_change() {
        let (k, q) = (3.0, [1.0, 0.5, -0.2]);
        let y0 = [1.1, 0.4, -0.3, 0.0, 0.0, 0.0];
        let y1 = [0.7, 0.9, 0.1, 0.2, -0.4, 0.6];
        let ym: LinkVars = std::array::from_fn(|i| 0.5 * (y0[i] + y1[i]));
        let mut ev = LinkEval::default();
        evaluate_link(k, q, &ym, Some((&y0, &y1)), false, &mut ev);
        let g = [
            ev.force[0],
            ev.force[1],
            ev.force[2],
            ev.force[6],
            ev.force[7],
            ev.force[8],
        ];
        let work: f64 = (0..6).map(|i| g[i] * (y1[i] - y0[i])).sum();
        let dw = link_energy(k, q, &y1) - link_energy(k, q, &y0);
        assert!((work - dw).abs() < 1e-12 * dw.abs().max(1.0), "{work} {dw}");
    }
}
