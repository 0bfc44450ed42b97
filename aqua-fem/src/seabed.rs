//! The seabed's penalty contact law (docs/theory/fem.md#seabed-contact): the normal force of
//! a node on the flat bed z_s = −depth, its tangent and its energy, with the discrete gradient
//! the energy-consistent midpoint rule uses (docs/theory/fem.md#energy-consistent-midpoint).
//! One definition for the statics' merit, the implicit and explicit schemes' evaluation
//! (`System::evaluate`), the explicit stable step and the line relaxation's local solves.
//! Friction on the bed is `friction.rs`.

use crate::model::Model;

/// The seabed's normal law (docs/theory/fem.md#seabed-contact).
#[derive(Debug, Clone, Copy)]
pub(crate) struct BedLaw {
    /// Bed height z_s [m] (−∞ without a seabed).
    zs: f64,
    /// k_b [Pa/m] and c_b [Pa·s/m] (0 in statics).
    k: f64,
    c: f64,
    /// Damping ramp depth δ_c [m].
    ramp: f64,
}

impl BedLaw {
    pub(crate) fn new(model: &Model, dynamic: bool) -> Self {
        match model.env.seabed {
            Some(s) => Self {
                zs: -s.depth,
                k: s.stiffness,
                c: if dynamic { s.damping } else { 0.0 },
                ramp: s.damping_depth,
            },
            None => Self {
                zs: f64::NEG_INFINITY,
                k: 0.0,
                c: 0.0,
                ramp: 1.0,
            },
        }
    }

    /// Contact stiffness of node i [N/m] (0 without a seabed): its lines' share k_b·d_c·L_i
    /// and its point bodies' k_p, whose sum is the constant of the penalty energy
    /// ½·k·max(z_s − z, 0)².
    pub(crate) fn stiffness_parts(&self, model: &Model, i: usize) -> (f64, f64) {
        (self.k * model.bed_coef[i], model.bed_point[i])
    }

    /// Contact stiffness k = k_b·d_c·L_i + k_p of node i [N/m].
    pub(crate) fn stiffness(&self, model: &Model, i: usize) -> f64 {
        let (line, point) = self.stiffness_parts(model, i);
        line + point
    }

    /// Change of node i's contact energy ½·k·max(z_s − z, 0)² from height z0 to z1 [J].
    pub(crate) fn energy_change(&self, model: &Model, i: usize, z0: f64, z1: f64) -> f64 {
        let k = self.stiffness(model, i);
        if k > 0.0 {
            let d1 = (self.zs - z1).max(0.0);
            let d0 = (self.zs - z0).max(0.0);
            0.5 * k * (d1 - d0) * (d1 + d0)
        } else {
            0.0
        }
    }

    /// Whether node i can touch the bed at all.
    pub(crate) fn acts_on(&self, model: &Model, i: usize) -> bool {
        self.zs.is_finite() && (model.bed_coef[i] > 0.0 || model.bed_point[i] > 0.0)
    }

    /// Upward force f_z [N] on node i at height z [m] and vertical velocity v_z [m/s], with
    /// −∂f_z/∂z [N/m] and −∂f_z/∂v_z [N·s/m]. `secant`: the step's end heights (z_n, z_{n+1})
    /// for the midpoint rule's discrete gradient, whose stiffness is stored as −∂f/∂z_m.
    pub(crate) fn node(
        &self,
        model: &Model,
        i: usize,
        z: f64,
        vz: f64,
        secant: Option<(f64, f64)>,
    ) -> (f64, f64, f64) {
        let d = self.zs - z;
        let coef = model.bed_coef[i];
        let kb = self.k * coef;
        let kp = model.bed_point[i];
        let (mut f, mut kz, mut cz) = (0.0, 0.0, 0.0);
        if let Some((z0, z1)) = secant {
            // Energy-consistent contact for the midpoint rule: the discrete gradient of
            // ½·k·max(z_s − z, 0)² between the step's ends, its tangent 2·∂f/∂z1
            // (docs/theory/fem.md#energy-consistent-midpoint).
            let (fe, ke) = bed_discrete_gradient(kb, self.zs, z0, z1);
            let (s, ds) = damping_ramp(d, self.ramp);
            let fd = -self.c * coef * s * vz;
            if fe + fd > 0.0 {
                f += fe + fd;
                kz += ke - self.c * coef * ds * vz;
                cz += self.c * coef * s;
            }
            let (fp, kpp) = bed_discrete_gradient(kp, self.zs, z0, z1);
            f += fp;
            kz += kpp;
        } else if d > 0.0 {
            // The damping ramps in over δ_c so that f is continuous at touchdown.
            let (s, ds) = damping_ramp(d, self.ramp);
            let fk = kb * d - self.c * coef * s * vz;
            if fk > 0.0 {
                f += fk;
                kz += kb - self.c * coef * ds * vz;
                cz += self.c * coef * s;
            }
            f += kp * d;
            kz += kp;
        }
        (f, kz, cz)
    }
}

/// The seabed damping's ramp s(δ) = min(1, δ/δ_c) for δ > 0 (0 otherwise) and ds/dδ
/// (docs/theory/fem.md#seabed-contact).
fn damping_ramp(d: f64, depth: f64) -> (f64, f64) {
    if d <= 0.0 {
        (0.0, 0.0)
    } else if d < depth {
        (d / depth, 1.0 / depth)
    } else {
        (1.0, 0.0)
    }
}

#[inline]
/// Discrete gradient of the contact energy E(z) = ½·k·max(z_s − z, 0)² between z0 and z1:
/// the force f_z = −(E(z1) − E(z0))/(z1 − z0) [N] and 2·(−∂f_z/∂z1) [N/m], the midpoint rule's
/// tangent; the limit k·max(z_s − z̄, 0) when the step barely moves
/// (docs/theory/fem.md#energy-consistent-midpoint).
fn bed_discrete_gradient(k: f64, zs: f64, z0: f64, z1: f64) -> (f64, f64) {
    if k == 0.0 {
        return (0.0, 0.0);
    }
    let (d0, d1) = ((zs - z0).max(0.0), (zs - z1).max(0.0));
    let dz = z1 - z0;
    if dz.abs() <= 1e-9 * (1.0 + zs.abs()) {
        let d = (zs - 0.5 * (z0 + z1)).max(0.0);
        return (k * d, if d > 0.0 { k } else { 0.0 });
    }
    let de = 0.5 * k * (d1 * d1 - d0 * d0);
    (-de / dz, 2.0 * (-k * d1 * dz - de) / (dz * dz))
}
