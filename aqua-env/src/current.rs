//! Current: uniform, piecewise-linear depth profile, power law, start-up ramp and velocity
//! schedule (docs/theory/environment.md#current).

use crate::error::EnvError;
use crate::ramp::Ramp;

/// The largest current speed a scene may give [m/s]: twice the fastest tidal streams (about
/// 5 m/s); beyond it an input is a typing error, not a sea (docs/theory/environment.md#current).
pub const MAX_CURRENT_SPEED: f64 = 10.0;

/// The depth dependence of the current, U_c(z) [m/s], before any ramp.
#[derive(Debug, Clone, PartialEq)]
pub enum CurrentProfile {
    /// U_c(z) = U.
    Uniform([f64; 3]),
    /// Piecewise-linear in z through points (z_k, U_k), z_k strictly decreasing, z_k ≤ 0;
    /// constant above z_0 and below z_{K−1}.
    Profile(Vec<(f64, [f64; 3])>),
    /// U_c(z) = U_s·((z + h)/h)^p for −h ≤ z ≤ 0, U_s above.
    PowerLaw {
        /// Surface velocity U_s [m/s].
        surface: [f64; 3],
        /// Exponent p (> 0).
        exponent: f64,
        /// Water depth h [m].
        depth: f64,
    },
}

impl CurrentProfile {
    /// Checks the profile's invariants (strictly decreasing depths ≤ 0, positive exponent).
    pub fn validate(&self) -> Result<(), EnvError> {
        match self {
            CurrentProfile::Uniform(_) => Ok(()),
            CurrentProfile::Profile(points) => {
                if points.is_empty() {
                    return Err(EnvError::range(
                        "sea.current.points",
                        "[]",
                        "give at least one [z, ux, uy, uz] point",
                    ));
                }
                for (k, (z, _)) in points.iter().enumerate() {
                    if !(*z <= 0.0) {
                        return Err(EnvError::range(
                            format!("sea.current.points[{k}] z"),
                            z,
                            "profile depths must be <= 0 (z up, 0 at still water)",
                        ));
                    }
                    if k > 0 && !(points[k - 1].0 > *z) {
                        return Err(EnvError::range(
                            format!("sea.current.points[{k}] z"),
                            z,
                            format!(
                                "profile depths must be strictly decreasing (previous z = {})",
                                points[k - 1].0
                            ),
                        ));
                    }
                }
                Ok(())
            }
            CurrentProfile::PowerLaw {
                exponent, depth, ..
            } => {
                if !(*exponent > 0.0 && exponent.is_finite()) {
                    return Err(EnvError::range(
                        "sea.current.exponent",
                        exponent,
                        "a finite number > 0 (1/7 = 0.142857 is the DNV tidal profile)",
                    ));
                }
                if !(*depth > 0.0 && depth.is_finite()) {
                    return Err(EnvError::missing(
                        "sea.depth",
                        "a power-law current needs a finite water depth",
                    ));
                }
                Ok(())
            }
        }
    }

    /// U_c(z) [m/s] at height z (profiles are evaluated at min(z, 0), not stretched).
    pub fn velocity(&self, z: f64) -> [f64; 3] {
        let z = z.min(0.0);
        match self {
            CurrentProfile::Uniform(u) => *u,
            CurrentProfile::Profile(points) => {
                let first = &points[0];
                if z >= first.0 {
                    return first.1;
                }
                for w in points.windows(2) {
                    let (z0, u0) = w[0];
                    let (z1, u1) = w[1];
                    if z == z1 {
                        return u1;
                    }
                    if z > z1 {
                        let s = (z0 - z) / (z0 - z1);
                        return [
                            u0[0] + s * (u1[0] - u0[0]),
                            u0[1] + s * (u1[1] - u0[1]),
                            u0[2] + s * (u1[2] - u0[2]),
                        ];
                    }
                }
                points[points.len() - 1].1
            }
            CurrentProfile::PowerLaw {
                surface,
                exponent,
                depth,
            } => {
                let f = ((z + depth) / depth).max(0.0).powf(*exponent);
                [surface[0] * f, surface[1] * f, surface[2] * f]
            }
        }
    }

    fn scaled(&self, z: f64, s: f64) -> [f64; 3] {
        let u = self.velocity(z);
        [u[0] * s, u[1] * s, u[2] * s]
    }
}

/// A uniform-velocity sweep: at t_j the velocity blends from U_{j−1} to U_j with the cosine
/// ramp shape over `ramp_time` (flume velocity steps).
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    /// (t_j [s], U_j [m/s]), t_j strictly increasing.
    pub steps: Vec<(f64, [f64; 3])>,
    /// Blend duration of each change [s].
    pub blend: Ramp,
}

impl Schedule {
    fn velocity_and_rate(&self, t: f64) -> ([f64; 3], [f64; 3]) {
        let mut u = self.steps[0].1;
        let mut du = [0.0; 3];
        for w in self.steps.windows(2) {
            let (tj, uj) = w[1];
            if t < tj {
                break;
            }
            let prev = u;
            let r = self.blend.value(t - tj);
            let rd = self.blend.rate(t - tj);
            for c in 0..3 {
                u[c] = prev[c] + r * (uj[c] - prev[c]);
                du[c] = rd * (uj[c] - prev[c]);
            }
        }
        (u, du)
    }
}

/// The current of a sea: a profile, whether it is active in the static solve, the start-up
/// ramp, and an optional schedule.
#[derive(Debug, Clone, PartialEq)]
pub struct Current {
    /// Depth dependence; `None` means no current.
    pub profile: Option<CurrentProfile>,
    /// Optional uniform velocity sweep (replaces a uniform profile's velocity).
    pub schedule: Option<Schedule>,
    /// Include the current in static solves.
    pub in_static: bool,
    /// Start-up ramp used when a dynamic run starts without current.
    pub ramp: Ramp,
}

impl Current {
    /// No current.
    pub fn none() -> Self {
        Self {
            profile: None,
            schedule: None,
            in_static: true,
            ramp: Ramp::off(),
        }
    }

    /// A uniform current U [m/s], no ramp.
    pub fn uniform(u: [f64; 3]) -> Self {
        Self {
            profile: Some(CurrentProfile::Uniform(u)),
            ..Self::none()
        }
    }

    /// Any profile, no ramp.
    pub fn with_profile(profile: CurrentProfile) -> Self {
        Self {
            profile: Some(profile),
            ..Self::none()
        }
    }

    /// True if the current is not identically zero.
    pub fn is_active(&self) -> bool {
        self.profile.is_some() || self.schedule.is_some()
    }

    /// The velocity at height z and time t without the start-up ramp, as the wake models
    /// see it to find a net's downstream side: a schedule's latest step (held, not blended
    /// with the next), else the profile [m/s].
    pub fn unramped_velocity(&self, z: f64, t: f64) -> [f64; 3] {
        if let Some(s) = &self.schedule {
            let mut u = s.steps.first().map(|s| s.1).unwrap_or([0.0; 3]);
            for (tj, uj) in &s.steps {
                if t >= *tj {
                    u = *uj;
                }
            }
            return u;
        }
        match &self.profile {
            Some(p) => p.velocity(z),
            None => [0.0; 3],
        }
    }

    /// Current velocity and its time derivative at height z, time t, with ramp factor
    /// (R, Ṙ) already chosen by the caller.
    #[inline]
    pub(crate) fn eval(&self, z: f64, t: f64, r: f64, rdot: f64) -> ([f64; 3], [f64; 3]) {
        if let Some(s) = &self.schedule {
            let (u, du) = s.velocity_and_rate(t);
            let vel = [u[0] * r, u[1] * r, u[2] * r];
            let acc = [
                du[0] * r + u[0] * rdot,
                du[1] * r + u[1] * rdot,
                du[2] * r + u[2] * rdot,
            ];
            return (vel, acc);
        }
        match &self.profile {
            None => ([0.0; 3], [0.0; 3]),
            Some(p) => {
                let u = p.velocity(z);
                let vel = [u[0] * r, u[1] * r, u[2] * r];
                let acc = if rdot != 0.0 {
                    p.scaled(z, rdot)
                } else {
                    [0.0; 3]
                };
                (vel, acc)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn profile() -> CurrentProfile {
        CurrentProfile::Profile(vec![
            (0.0, [0.5, 0.0, 0.0]),
            (-10.0, [0.6, 0.1, 0.0]),
            (-30.0, [0.3, 0.0, 0.0]),
        ])
    }

    #[test]
    fn profile_returns_listed_vectors_at_listed_depths() {
        let p = profile();
        p.validate().unwrap();
        assert_eq!(p.velocity(0.0), [0.5, 0.0, 0.0]);
        assert_eq!(p.velocity(-10.0), [0.6, 0.1, 0.0]);
        assert_eq!(p.velocity(-30.0), [0.3, 0.0, 0.0]);
        assert_eq!(p.velocity(-31.0), [0.3, 0.0, 0.0]);
        assert_eq!(p.velocity(1.0), [0.5, 0.0, 0.0]);
        let mid = p.velocity(-20.0);
        assert!((mid[0] - 0.45).abs() < 1e-15 && (mid[1] - 0.05).abs() < 1e-15);
    }

    #[test]
    fn profile_must_decrease() {
        let p = CurrentProfile::Profile(vec![(0.0, [0.5, 0.0, 0.0]), (0.0, [0.6, 0.0, 0.0])]);
        assert!(p.validate().is_err());
        let p = CurrentProfile::Profile(vec![(1.0, [0.5, 0.0, 0.0])]);
        assert!(p.validate().is_err());
    }

    #[test]
    fn power_law_values() {
        let p = CurrentProfile::PowerLaw {
            surface: [0.8, 0.0, 0.0],
            exponent: 1.0 / 7.0,
            depth: 40.0,
        };
        p.validate().unwrap();
        assert_eq!(p.velocity(0.0)[0], 0.8);
        assert_eq!(p.velocity(-40.0)[0], 0.0);
        let expect = 0.8 * 0.5f64.powf(1.0 / 7.0);
        assert!((p.velocity(-20.0)[0] - expect).abs() < 1e-15);
    }

    #[test]
    fn schedule_blends_between_steps() {
        let c = Current {
            schedule: Some(Schedule {
                steps: vec![(0.0, [0.12, 0.0, 0.0]), (10.0, [0.26, 0.0, 0.0])],
                blend: Ramp::new(4.0),
            }),
            ..Current::none()
        };
        let (u, _) = c.eval(-1.0, 5.0, 1.0, 0.0);
        assert_eq!(u[0], 0.12);
        let (u, du) = c.eval(-1.0, 12.0, 1.0, 0.0);
        assert!((u[0] - 0.19).abs() < 1e-12);
        assert!(du[0] > 0.0);
        let (u, du) = c.eval(-1.0, 15.0, 1.0, 0.0);
        assert!((u[0] - 0.26).abs() < 1e-15 && du[0] == 0.0);
    }
}
