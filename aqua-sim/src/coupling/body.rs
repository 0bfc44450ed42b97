//! A coupled rigid body: a set of coupled points fixed to a body whose pose (position of a
//! reference point and Tait–Bryan angles) and velocity come from outside; the force and moment
//! the structure exerts on it go back (docs/guide/coupling.md).
//!
//! Pose p = [x, y, z, φ, θ, ψ]: the reference point's position [m] and roll, pitch, yaw [rad]
//! with R = R_z(ψ)·R_y(θ)·R_x(φ). The body frame is the scene's frame moved to the reference
//! point's as-built position `origin`: a node built at x₀ sits at r = x₀ − origin in the body
//! and at x = X + R·r when the body is at pose p. Velocity [u, v, w, ω_x, ω_y, ω_z]: of the
//! reference point [m/s] and the angular velocity in the scene's frame [rad/s], so
//! v = V + ω × R·r; with accelerations [A, α], a = A + α × R·r + ω × (ω × R·r).
//! The wrench is F = Σ f and M = Σ (x − X) × f about the reference point where it is.

use super::{CoupledPoint, Forces, Target};
use crate::error::{Result, SimError};

/// A rigid body carrying coupled points.
#[derive(Debug, Clone, PartialEq)]
pub struct CoupledBody {
    /// Its name.
    pub name: String,
    /// Indices of its points in [`super::Coupling::points`].
    pub points: Vec<usize>,
    /// The reference point's as-built position [m].
    pub origin: [f64; 3],
    /// Per point, per node: its position in the body frame [m].
    pub(super) local: Vec<Vec<[f64; 3]>>,
}

/// Where a body is at the end of a step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyTarget {
    /// [x, y, z, roll, pitch, yaw] [m, rad].
    pub pose: [f64; 6],
    /// [u, v, w, ω_x, ω_y, ω_z] [m/s, rad/s] (default: the backward difference of the nodes'
    /// positions).
    pub velocity: Option<[f64; 6]>,
    /// [a_x, a_y, a_z, α_x, α_y, α_z] [m/s², rad/s²] (only with a velocity).
    pub acceleration: Option<[f64; 6]>,
}

/// R = R_z(ψ)·R_y(θ)·R_x(φ), rows.
pub fn rotation(roll: f64, pitch: f64, yaw: f64) -> [[f64; 3]; 3] {
    let (sf, cf) = roll.sin_cos();
    let (st, ct) = pitch.sin_cos();
    let (sp, cp) = yaw.sin_cos();
    [
        [cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf],
        [sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf],
        [-st, ct * sf, ct * cf],
    ]
}

fn mul(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2])
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

impl CoupledBody {
    /// A body of `points` (indices into `all`) whose reference point is built at `origin`.
    pub(super) fn new(
        name: &str,
        points: Vec<usize>,
        all: &[CoupledPoint],
        origin: [f64; 3],
    ) -> Result<Self> {
        if !origin.iter().all(|x| x.is_finite()) {
            return Err(SimError::Coupling(format!(
                "body \"{name}\": origin = {origin:?} must be finite"
            )));
        }
        let local = points
            .iter()
            .map(|&i| {
                all[i]
                    .rest
                    .iter()
                    .map(|x| [x[0] - origin[0], x[1] - origin[1], x[2] - origin[2]])
                    .collect()
            })
            .collect();
        Ok(Self {
            name: name.to_string(),
            points,
            origin,
            local,
        })
    }

    /// The targets of the body's points for a body at `target`.
    pub fn targets(&self, target: &BodyTarget) -> Result<Vec<(usize, Target)>> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&target.pose)
            || !target.velocity.as_ref().is_none_or(|v| finite(v))
            || !target.acceleration.as_ref().is_none_or(|v| finite(v))
        {
            return Err(SimError::Coupling(format!(
                "body \"{}\": pose, velocity and acceleration must be finite",
                self.name
            )));
        }
        if target.acceleration.is_some() && target.velocity.is_none() {
            return Err(SimError::Coupling(format!(
                "body \"{}\": an acceleration needs a velocity",
                self.name
            )));
        }
        let p = target.pose;
        let rot = rotation(p[3], p[4], p[5]);
        let centre = [p[0], p[1], p[2]];
        Ok(self
            .points
            .iter()
            .zip(&self.local)
            .map(|(&i, local)| {
                let arms: Vec<[f64; 3]> = local.iter().map(|r| mul(&rot, *r)).collect();
                let position = arms.iter().map(|a| add(centre, *a)).collect();
                let velocity = target.velocity.map(|v| {
                    let (lin, w) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
                    arms.iter().map(|a| add(lin, cross(w, *a))).collect()
                });
                let acceleration = match (target.velocity, target.acceleration) {
                    (Some(v), Some(acc)) => {
                        let w = [v[3], v[4], v[5]];
                        let (lin, al) = ([acc[0], acc[1], acc[2]], [acc[3], acc[4], acc[5]]);
                        Some(
                            arms.iter()
                                .map(|a| add(add(lin, cross(al, *a)), cross(w, cross(w, *a))))
                                .collect(),
                        )
                    }
                    _ => None,
                };
                (
                    i,
                    Target {
                        position,
                        velocity,
                        acceleration,
                    },
                )
            })
            .collect())
    }

    /// [F_x, F_y, F_z, M_x, M_y, M_z] [N, N·m] of the forces on the body's points about its
    /// reference point at `pose`; `positions` are the points' node positions (as `forces`).
    pub fn wrench(&self, forces: &Forces, positions: &[Vec<[f64; 3]>], pose: [f64; 6]) -> [f64; 6] {
        let mut w = [0.0; 6];
        for &i in &self.points {
            for (f, x) in forces[i].iter().zip(&positions[i]) {
                let arm = [x[0] - pose[0], x[1] - pose[1], x[2] - pose[2]];
                let m = cross(arm, *f);
                for k in 0..3 {
                    w[k] += f[k];
                    w[3 + k] += m[k];
                }
            }
        }
        w
    }
}
