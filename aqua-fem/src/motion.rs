//! Prescribed motions of nodes: x(t) = X + d(t), with analytic velocity and acceleration.

use crate::error::{FemError, Result, invalid};

/// Smooth start r(τ) = 10τ³ − 15τ⁴ + 6τ⁵, τ = min(t/t_r, 1), and its first two time
/// derivatives. `ramp_time` ≤ 0 gives r ≡ 1.
pub fn smooth_ramp(t: f64, ramp_time: f64) -> (f64, f64, f64) {
    if ramp_time <= 0.0 || t >= ramp_time {
        return (1.0, 0.0, 0.0);
    }
    if t <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let s = t / ramp_time;
    let r = s * s * s * (10.0 + s * (-15.0 + 6.0 * s));
    let dr = 30.0 * s * s * (1.0 - s) * (1.0 - s) / ramp_time;
    let ddr = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (ramp_time * ramp_time);
    (r, dr, ddr)
}

/// Natural cubic spline through (t_i, y_i) for three components.
#[derive(Debug, Clone, PartialEq)]
pub struct TableSpline {
    t: Vec<f64>,
    y: Vec<[f64; 3]>,
    /// Second derivatives at the knots.
    m: Vec<[f64; 3]>,
}

impl TableSpline {
    /// Builds the spline from rows (t [s], dx, dy, dz [m]). Times must be finite and strictly
    /// increasing; at least two rows. Outside the table the end value is held (v = a = 0).
    pub fn new(rows: &[[f64; 4]]) -> Result<Self> {
        if rows.len() < 2 {
            return Err(invalid(
                "prescribed motion table rows",
                rows.len() as f64,
                "at least 2 rows (t, dx, dy, dz)",
            ));
        }
        for (i, r) in rows.iter().enumerate() {
            for (k, v) in r.iter().enumerate() {
                if !v.is_finite() {
                    return Err(invalid(
                        format!("prescribed motion table row {i} column {k}"),
                        *v,
                        "a finite number",
                    ));
                }
            }
            if i > 0 && r[0] <= rows[i - 1][0] {
                return Err(invalid(
                    format!("prescribed motion table row {i} time"),
                    r[0],
                    format!("strictly greater than the previous time {}", rows[i - 1][0]),
                ));
            }
        }
        let n = rows.len();
        let t: Vec<f64> = rows.iter().map(|r| r[0]).collect();
        let y: Vec<[f64; 3]> = rows.iter().map(|r| [r[1], r[2], r[3]]).collect();
        let mut m = vec![[0.0; 3]; n];
        if n > 2 {
            // Thomas algorithm on the interior knots (natural end conditions m_0 = m_{n-1} = 0).
            for k in 0..3 {
                let ni = n - 2;
                let mut diag = vec![0.0; ni];
                let mut rhs = vec![0.0; ni];
                let mut sup = vec![0.0; ni];
                for i in 1..n - 1 {
                    let h0 = t[i] - t[i - 1];
                    let h1 = t[i + 1] - t[i];
                    diag[i - 1] = 2.0 * (h0 + h1);
                    sup[i - 1] = h1;
                    rhs[i - 1] =
                        6.0 * ((y[i + 1][k] - y[i][k]) / h1 - (y[i][k] - y[i - 1][k]) / h0);
                }
                for i in 1..ni {
                    let sub = t[i + 1] - t[i];
                    let w = sub / diag[i - 1];
                    diag[i] -= w * sup[i - 1];
                    rhs[i] -= w * rhs[i - 1];
                }
                let mut sol = vec![0.0; ni];
                for i in (0..ni).rev() {
                    let upper = if i + 1 < ni { sup[i] * sol[i + 1] } else { 0.0 };
                    sol[i] = (rhs[i] - upper) / diag[i];
                }
                for i in 0..ni {
                    m[i + 1][k] = sol[i];
                }
            }
        }
        Ok(Self { t, y, m })
    }

    /// Displacement, velocity and acceleration at time `t`.
    pub fn eval(&self, t: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let n = self.t.len();
        if t <= self.t[0] {
            return (self.y[0], [0.0; 3], [0.0; 3]);
        }
        if t >= self.t[n - 1] {
            return (self.y[n - 1], [0.0; 3], [0.0; 3]);
        }
        let i = match self.t.binary_search_by(|p| p.total_cmp(&t)) {
            Ok(i) => i.min(n - 2),
            Err(i) => i - 1,
        };
        let h = self.t[i + 1] - self.t[i];
        let a = (self.t[i + 1] - t) / h;
        let b = (t - self.t[i]) / h;
        let mut d = [0.0; 3];
        let mut v = [0.0; 3];
        let mut acc = [0.0; 3];
        for k in 0..3 {
            let (y0, y1, m0, m1) = (
                self.y[i][k],
                self.y[i + 1][k],
                self.m[i][k],
                self.m[i + 1][k],
            );
            d[k] = a * y0 + b * y1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
            v[k] = (y1 - y0) / h - (3.0 * a * a - 1.0) * h * m0 / 6.0
                + (3.0 * b * b - 1.0) * h * m1 / 6.0;
            acc[k] = a * m0 + b * m1;
        }
        (d, v, acc)
    }
}

/// A prescribed displacement history d(t) of a node (all three DOFs).
#[derive(Debug, Clone, PartialEq)]
pub enum Motion {
    /// Constant offset d [m] from the as-built position.
    Constant([f64; 3]),
    /// Linear ramp from 0 to `target` [m] over `duration` [s], then held.
    Ramp {
        /// Final offset [m].
        target: [f64; 3],
        /// Ramp duration [s] (> 0).
        duration: f64,
    },
    /// d(t) = r(t)·(mean + A·sin(2πt/T + φ)) with the smooth start r of [`smooth_ramp`].
    /// A fairlead surge d = r·A·(1 − cos 2πt/T) x̂ is `mean = A`, `phase = −π/2`.
    Harmonic {
        /// Amplitude vector A [m].
        amplitude: [f64; 3],
        /// Mean offset [m].
        mean: [f64; 3],
        /// Period T [s] (> 0).
        period: f64,
        /// Phase φ [rad].
        phase: f64,
        /// Ramp time t_r [s] (0 = no ramp).
        ramp_time: f64,
    },
    /// Table of (t, dx, dy, dz), natural cubic spline.
    Table(TableSpline),
    /// Given from outside step by step (a coupled vessel, CFD or control code).
    External(ExternalMotion),
}

impl Motion {
    /// Harmonic motion builder (validates T > 0, t_r ≥ 0, finite values).
    pub fn harmonic(
        amplitude: [f64; 3],
        mean: [f64; 3],
        period: f64,
        phase: f64,
        ramp_time: f64,
    ) -> Result<Self> {
        let m = Motion::Harmonic {
            amplitude,
            mean,
            period,
            phase,
            ramp_time,
        };
        m.validate()?;
        Ok(m)
    }

    /// Table motion from rows (t, dx, dy, dz).
    pub fn table(rows: &[[f64; 4]]) -> Result<Self> {
        Ok(Motion::Table(TableSpline::new(rows)?))
    }

    pub(crate) fn validate(&self) -> Result<()> {
        let finite3 = |name: &str, v: &[f64; 3]| -> Result<()> {
            for x in v {
                if !x.is_finite() {
                    return Err(invalid(format!("prescribed motion {name}"), *x, "finite"));
                }
            }
            Ok(())
        };
        match self {
            Motion::Constant(d) => finite3("offset", d),
            Motion::Ramp { target, duration } => {
                finite3("target", target)?;
                if !(duration.is_finite() && *duration > 0.0) {
                    return Err(invalid("prescribed ramp duration [s]", *duration, "> 0"));
                }
                Ok(())
            }
            Motion::Harmonic {
                amplitude,
                mean,
                period,
                phase,
                ramp_time,
            } => {
                finite3("amplitude", amplitude)?;
                finite3("mean", mean)?;
                if !(period.is_finite() && *period > 0.0) {
                    return Err(invalid("prescribed harmonic period [s]", *period, "> 0"));
                }
                if !phase.is_finite() {
                    return Err(invalid("prescribed harmonic phase [rad]", *phase, "finite"));
                }
                if !(ramp_time.is_finite() && *ramp_time >= 0.0) {
                    return Err(invalid(
                        "prescribed harmonic ramp_time [s]",
                        *ramp_time,
                        ">= 0",
                    ));
                }
                Ok(())
            }
            Motion::Table(_) | Motion::External(_) => Ok(()),
        }
    }

    /// Offset d(t) [m], velocity [m/s] and acceleration [m/s²] at time t [s].
    pub fn eval(&self, t: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        match self {
            Motion::Constant(d) => (*d, [0.0; 3], [0.0; 3]),
            Motion::Ramp { target, duration } => {
                if t <= 0.0 {
                    ([0.0; 3], [0.0; 3], [0.0; 3])
                } else if t >= *duration {
                    (*target, [0.0; 3], [0.0; 3])
                } else {
                    let f = t / duration;
                    (
                        target.map(|x| x * f),
                        target.map(|x| x / duration),
                        [0.0; 3],
                    )
                }
            }
            Motion::Harmonic {
                amplitude,
                mean,
                period,
                phase,
                ramp_time,
            } => {
                let (r, dr, ddr) = smooth_ramp(t, *ramp_time);
                let w = 2.0 * std::f64::consts::PI / period;
                let (s, c) = (w * t + phase).sin_cos();
                let mut d = [0.0; 3];
                let mut v = [0.0; 3];
                let mut a = [0.0; 3];
                for k in 0..3 {
                    let g = mean[k] + amplitude[k] * s;
                    let dg = amplitude[k] * w * c;
                    let ddg = -amplitude[k] * w * w * s;
                    d[k] = r * g;
                    v[k] = dr * g + r * dg;
                    a[k] = ddr * g + 2.0 * dr * dg + r * ddg;
                }
                (d, v, a)
            }
            Motion::Table(s) => s.eval(t),
            Motion::External(e) => e.eval(t),
        }
    }
}

pub(crate) fn check_finite3(what: &str, v: [f64; 3]) -> Result<()> {
    for x in v {
        if !x.is_finite() {
            return Err(FemError::InvalidParameter {
                what: what.to_string(),
                value: x,
                valid: "a finite number".into(),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_derivatives_match_finite_differences() {
        let h = 1e-6;
        for &t in &[0.3, 1.7, 4.2] {
            let (r0, d0, dd0) = smooth_ramp(t, 5.0);
            let (rp, dp, _) = smooth_ramp(t + h, 5.0);
            let (rm, dm, _) = smooth_ramp(t - h, 5.0);
            assert!((d0 - (rp - rm) / (2.0 * h)).abs() < 1e-8);
            assert!((dd0 - (dp - dm) / (2.0 * h)).abs() < 1e-7);
            assert!((0.0..=1.0).contains(&r0));
        }
        assert_eq!(smooth_ramp(6.0, 5.0), (1.0, 0.0, 0.0));
    }

    #[test]
    fn harmonic_derivatives_match_finite_differences() {
        let m = Motion::harmonic([1.5, 0.2, 0.0], [1.5, 0.0, 0.0], 10.0, -1.0, 7.0).unwrap();
        let h = 1e-5;
        for &t in &[0.5, 3.0, 6.9, 12.0] {
            let (_, v, a) = m.eval(t);
            let (dp, vp, _) = m.eval(t + h);
            let (dm, vm, _) = m.eval(t - h);
            for k in 0..3 {
                assert!((v[k] - (dp[k] - dm[k]) / (2.0 * h)).abs() < 1e-7);
                assert!((a[k] - (vp[k] - vm[k]) / (2.0 * h)).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn spline_reproduces_knots_and_cubic_exactness_for_lines() {
        let rows = [
            [0.0, 0.0, 1.0, 2.0],
            [1.0, 2.0, 1.0, 0.0],
            [3.0, 6.0, 1.0, -4.0],
            [4.0, 8.0, 1.0, -6.0],
        ];
        let s = TableSpline::new(&rows).unwrap();
        for r in &rows {
            let (d, _, _) = s.eval(r[0]);
            for k in 0..3 {
                assert!((d[k] - r[k + 1]).abs() < 1e-12);
            }
        }
        // Linear data → exact line, v = slope, a = 0.
        let (d, v, a) = s.eval(2.2);
        assert!((d[0] - 4.4).abs() < 1e-12 && (v[0] - 2.0).abs() < 1e-12 && a[0].abs() < 1e-12);
        assert!(TableSpline::new(&[[0.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]]).is_err());
    }
}

/// One state of an external motion: offset, velocity and (if known) acceleration at time t.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Keyframe {
    t: f64,
    d: [f64; 3],
    v: [f64; 3],
    a: Option<[f64; 3]>,
}

/// The last two keyframes of an external motion: what [`ExternalMotion::keyframes`] saves and
/// [`ExternalMotion::set_keyframes`] puts back (a coupling's retry and restore).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Keyframes {
    start: Keyframe,
    end: Keyframe,
}

/// A prescribed motion given from outside, one step at a time (the coupling interface): the
/// caller sets where the node is at the end of the coming step ([`ExternalMotion::set_target`])
/// and the solver reads d(t), v(t), a(t) for any t in the step.
///
/// Between the start and the end of the step the offset is the cubic Hermite interpolant of
/// (d, v) at both ends (so step halving sees a smooth motion); at the end of the step the
/// given values are returned exactly, the acceleration being the given one or else the
/// interpolant's. Clones share the same keyframes.
#[derive(Debug, Clone, Default)]
pub struct ExternalMotion(std::sync::Arc<std::sync::Mutex<Keyframes>>);

impl PartialEq for ExternalMotion {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0)
    }
}

impl ExternalMotion {
    /// A motion at rest at zero offset from t = 0 on.
    pub fn at_rest() -> Self {
        Self::default()
    }

    fn frames(&self) -> Keyframes {
        *self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The state reached at the end of the current step becomes the start of the next one,
    /// which ends at time `t` [s] with offset `d` [m], velocity `v` [m/s] and, if known,
    /// acceleration `a` [m/s²].
    pub fn set_target(&self, t: f64, d: [f64; 3], v: [f64; 3], a: Option<[f64; 3]>) {
        let mut k = self.0.lock().unwrap_or_else(|p| p.into_inner());
        let (d0, v0, a0) = eval_frames(&k, k.end.t);
        k.start = Keyframe {
            t: k.end.t,
            d: d0,
            v: v0,
            a: Some(a0),
        };
        k.end = Keyframe { t, d, v, a };
    }

    /// The current keyframes.
    pub fn keyframes(&self) -> Keyframes {
        self.frames()
    }

    /// Puts back keyframes saved by [`ExternalMotion::keyframes`].
    pub fn set_keyframes(&self, frames: Keyframes) {
        *self.0.lock().unwrap_or_else(|p| p.into_inner()) = frames;
    }

    /// Offset, velocity and acceleration at time t.
    pub fn eval(&self, t: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        eval_frames(&self.frames(), t)
    }
}

fn eval_frames(k: &Keyframes, t: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let h = k.end.t - k.start.t;
    let eps = 1e-9 * h.abs().max(f64::MIN_POSITIVE);
    if !(h > 0.0) || t >= k.end.t - eps {
        let a = k.end.a.unwrap_or_else(|| hermite(k, h, 1.0).2);
        return (k.end.d, k.end.v, a);
    }
    if t <= k.start.t + eps {
        let a = k.start.a.unwrap_or([0.0; 3]);
        return (k.start.d, k.start.v, a);
    }
    hermite(k, h, (t - k.start.t) / h)
}

/// Cubic Hermite interpolation of (d, v) over a step of length h at s ∈ [0, 1].
fn hermite(k: &Keyframes, h: f64, s: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
    if !(h > 0.0) {
        return (k.end.d, k.end.v, [0.0; 3]);
    }
    let (s2, s3) = (s * s, s * s * s);
    let (h00, h10, h01, h11) = (
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + s,
        -2.0 * s3 + 3.0 * s2,
        s3 - s2,
    );
    let (d00, d10, d01, d11) = (
        6.0 * s2 - 6.0 * s,
        3.0 * s2 - 4.0 * s + 1.0,
        -6.0 * s2 + 6.0 * s,
        3.0 * s2 - 2.0 * s,
    );
    let (e00, e10, e01, e11) = (
        12.0 * s - 6.0,
        6.0 * s - 4.0,
        -12.0 * s + 6.0,
        6.0 * s - 2.0,
    );
    let (a, b) = (k.start, k.end);
    let mut d = [0.0; 3];
    let mut v = [0.0; 3];
    let mut acc = [0.0; 3];
    for c in 0..3 {
        d[c] = h00 * a.d[c] + h10 * h * a.v[c] + h01 * b.d[c] + h11 * h * b.v[c];
        v[c] = (d00 * a.d[c] + d01 * b.d[c]) / h + d10 * a.v[c] + d11 * b.v[c];
        acc[c] = (e00 * a.d[c] + e01 * b.d[c]) / (h * h) + (e10 * a.v[c] + e11 * b.v[c]) / h;
    }
    (d, v, acc)
}

#[cfg(test)]
mod external_tests {
    use super::*;

    #[test]
    fn external_motion_returns_given_values_at_the_end_and_a_cubic_between() {
        let m = ExternalMotion::at_rest();
        assert_eq!(m.eval(0.0), ([0.0; 3], [0.0; 3], [0.0; 3]));
        // d = t³ on [0, 1]: d(1) = 1, v(1) = 3; the Hermite cubic reproduces it exactly.
        m.set_target(1.0, [1.0, 0.0, 0.0], [3.0, 0.0, 0.0], None);
        let (d, v, a) = m.eval(0.5);
        assert!((d[0] - 0.125).abs() < 1e-15 && (v[0] - 0.75).abs() < 1e-15);
        assert!((a[0] - 3.0).abs() < 1e-12);
        let (d, v, a) = m.eval(1.0);
        assert_eq!((d[0], v[0]), (1.0, 3.0));
        assert!((a[0] - 6.0).abs() < 1e-12);
        m.set_target(2.0, [2.0, 0.0, 0.0], [0.0; 3], Some([5.0, 0.0, 0.0]));
        assert_eq!(m.eval(1.0).0[0], 1.0);
        assert_eq!(m.eval(2.0).2[0], 5.0);
    }
}
