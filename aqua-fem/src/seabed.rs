//! The seabed's penalty contact law (docs/theory/fem.md#seabed-contact): the normal force of
//! a node on the flat bed z_s = −depth, its tangent and its energy, with the discrete gradient
//! the energy-consistent midpoint rule uses (docs/theory/fem.md#energy-consistent-midpoint).
//! One definition for the statics' merit, the implicit and explicit schemes' evaluation
//! (`System::evaluate`), the explicit stable step and the line relaxation's local solves.
//! Friction on the bed is `friction.rs`. The scene's `[sea.seabed]` keys and every seabed
//! default are [`SeabedSettings`], here.

use crate::friction::SeabedFriction;
use crate::model::{Model, Seabed};
use serde::{Deserialize, Serialize};

/// Default normal stiffness k_b per unit contact area [Pa/m] (MoorDyn's `kBot` order).
pub const DEFAULT_BED_STIFFNESS: f64 = 3e6;
/// Default normal damping c_b per unit contact area [Pa·s/m].
pub const DEFAULT_BED_DAMPING: f64 = 3e5;
/// Default penetration over which the seabed damping ramps in [m].
pub const DEFAULT_BED_DAMPING_DEPTH: f64 = 1e-2;
/// Default regularisation slip velocity v_c of the seabed friction [m/s].
pub const DEFAULT_SLIP_VELOCITY: f64 = 1e-2;

/// `[sea.seabed]` (docs/guide/scene.md#sea, docs/theory/fem.md#seabed-contact,
/// #seabed-friction): the contact and friction constants of the flat seabed at z = −depth, with
/// the scene's key names. The one owner of the seabed's schema and defaults: a scene's sea
/// deserialises its `[sea.seabed]` table into this type, and [`Seabed::new`] starts from
/// [`SeabedSettings::default`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SeabedSettings {
    /// k_b [Pa/m] (default [`DEFAULT_BED_STIFFNESS`]).
    pub kbot: f64,
    /// c_b [Pa·s/m] (default [`DEFAULT_BED_DAMPING`]).
    pub cbot: f64,
    /// Penetration δ_c over which c_b ramps in from zero [m] (default
    /// [`DEFAULT_BED_DAMPING_DEPTH`]), so that the contact force is continuous at touchdown.
    pub damping_depth: f64,
    /// Axial seabed friction coefficient μ_a, along the line (default 0: no friction).
    pub friction_axial: f64,
    /// Transverse seabed friction coefficient μ_t (default: `friction_axial`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_transverse: Option<f64>,
    /// Slip velocity v_c of the regularised friction [m/s] (default [`DEFAULT_SLIP_VELOCITY`]).
    pub slip_velocity: f64,
}

impl Default for SeabedSettings {
    fn default() -> Self {
        Self {
            kbot: DEFAULT_BED_STIFFNESS,
            cbot: DEFAULT_BED_DAMPING,
            damping_depth: DEFAULT_BED_DAMPING_DEPTH,
            friction_axial: 0.0,
            friction_transverse: None,
            slip_velocity: DEFAULT_SLIP_VELOCITY,
        }
    }
}

/// A `[sea.seabed]` key whose value is out of range: the key (without its table), the value
/// and what would be valid.
#[derive(Debug, Clone, PartialEq)]
pub struct InvalidSeabedKey {
    /// Key name inside `[sea.seabed]`, e.g. `kbot`.
    pub key: &'static str,
    /// The value given.
    pub value: f64,
    /// What would be valid.
    pub valid: String,
}

impl SeabedSettings {
    /// μ_t: `friction_transverse`, or `friction_axial` when it is not given.
    pub fn transverse_friction(&self) -> f64 {
        self.friction_transverse.unwrap_or(self.friction_axial)
    }

    /// Checks every key: k_b, c_b ≥ 0, δ_c > 0, μ ≥ 0 and v_c > 0, all finite.
    pub fn validate(&self) -> Result<(), InvalidSeabedKey> {
        let bad = |key, value, valid: &str| {
            Err(InvalidSeabedKey {
                key,
                value,
                valid: valid.to_string(),
            })
        };
        for (key, v) in [("kbot", self.kbot), ("cbot", self.cbot)] {
            if !(v >= 0.0 && v.is_finite()) {
                return bad(key, v, "a finite number >= 0");
            }
        }
        let dc = self.damping_depth;
        if !(dc > 0.0 && dc.is_finite()) {
            return bad(
                "damping_depth",
                dc,
                &format!(
                    "a penetration in m, finite and > 0 (default {DEFAULT_BED_DAMPING_DEPTH})"
                ),
            );
        }
        let mut mus = vec![("friction_axial", self.friction_axial)];
        if let Some(mu) = self.friction_transverse {
            mus.push(("friction_transverse", mu));
        }
        for (key, mu) in mus {
            if !(mu >= 0.0 && mu.is_finite()) {
                return bad(
                    key,
                    mu,
                    "a friction coefficient, finite and >= 0 (0 = no friction; chain on sand \
                     about 0.7 axial, 1.0 transverse)",
                );
            }
        }
        let vc = self.slip_velocity;
        if !(vc > 0.0 && vc.is_finite()) {
            return bad(
                "slip_velocity",
                vc,
                &format!("a velocity in m/s, finite and > 0 (default {DEFAULT_SLIP_VELOCITY})"),
            );
        }
        Ok(())
    }

    /// The structure's seabed at z = −depth [m] with these constants.
    pub fn seabed(&self, depth: f64) -> Seabed {
        Seabed {
            depth,
            stiffness: self.kbot,
            damping: self.cbot,
            damping_depth: self.damping_depth,
            friction: SeabedFriction {
                axial: self.friction_axial,
                transverse: self.transverse_friction(),
                slip_velocity: self.slip_velocity,
            },
        }
    }
}

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
