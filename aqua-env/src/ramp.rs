//! The C¹-smooth start-up ramp (docs/theory/environment.md#start-up-ramp).

use std::f64::consts::PI;

/// R(t) = ½(1 − cos(πt/T_r)) for 0 ≤ t < T_r, 1 afterwards; R ≡ 1 when T_r = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramp {
    /// Ramp duration T_r [s], ≥ 0.
    pub duration: f64,
}

impl Ramp {
    /// A ramp of duration `duration` seconds (0 disables it).
    pub fn new(duration: f64) -> Self {
        Self { duration }
    }

    /// No ramp: R ≡ 1.
    pub fn off() -> Self {
        Self { duration: 0.0 }
    }

    /// Ramp factor R(t) ∈ [0, 1] (t < 0 gives 0 for an active ramp).
    pub fn value(&self, t: f64) -> f64 {
        if self.duration <= 0.0 || t >= self.duration {
            1.0
        } else if t <= 0.0 {
            0.0
        } else {
            0.5 * (1.0 - (PI * t / self.duration).cos())
        }
    }

    /// Its time derivative Ṙ(t) [1/s].
    pub fn rate(&self, t: f64) -> f64 {
        if self.duration <= 0.0 || t >= self.duration || t <= 0.0 {
            0.0
        } else {
            PI / (2.0 * self.duration) * (PI * t / self.duration).sin()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_e9_values() {
        let r = Ramp::new(10.0);
        assert!((r.value(2.5) - 0.1464466094).abs() < 5e-11);
        assert!((r.value(5.0) - 0.5).abs() < 5e-11);
        assert_eq!(r.value(12.0), 1.0);
        assert_eq!(Ramp::off().value(0.0), 1.0);
    }

    #[test]
    fn rate_is_derivative() {
        let r = Ramp::new(7.0);
        for &t in &[0.3, 1.0, 3.5, 6.9] {
            let h = 1e-6;
            let fd = (r.value(t + h) - r.value(t - h)) / (2.0 * h);
            assert!((fd - r.rate(t)).abs() < 1e-8, "t={t}");
        }
    }
}
