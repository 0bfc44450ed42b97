//! Statistics of generated records: significant height and spectral estimates, used to
//! measure a sea back (`aqua waves`) and in tests.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use std::f64::consts::PI;

/// Sample variance of a record [m²] (mean removed).
pub fn variance(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    if x.len() < 2 {
        return 0.0;
    }
    let mean = x.iter().sum::<f64>() / n;
    x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0)
}

/// Spectral significant wave height Hm0 = 4·σ_η [m].
pub fn significant_height(eta: &[f64]) -> f64 {
    4.0 * variance(eta).sqrt()
}

/// A one-sided spectral estimate.
#[derive(Debug, Clone, PartialEq)]
pub struct SpectrumEstimate {
    /// Angular frequencies [rad/s].
    pub omega: Vec<f64>,
    /// S(ω) [m²·s/rad].
    pub density: Vec<f64>,
}

impl SpectrumEstimate {
    /// Peak period Tp [s]: the spectrum is band-averaged over 5 bins (to tame the scatter
    /// of single periodogram bins), then the largest bin is refined by a parabola through ln S
    /// at it and its two neighbours (exact for a Gaussian peak, close for a Hann-windowed line).
    pub fn peak_period(&self) -> f64 {
        let n = self.density.len();
        if n < 3 {
            return f64::NAN;
        }
        let smooth: Vec<f64> = (0..n)
            .map(|k| {
                let lo = k.saturating_sub(2);
                let hi = (k + 2).min(n - 1);
                self.density[lo..=hi].iter().sum::<f64>() / (hi - lo + 1) as f64
            })
            .collect();
        let Some((k, _)) = smooth
            .iter()
            .enumerate()
            .skip(1)
            .max_by(|a, b| a.1.total_cmp(b.1))
        else {
            return f64::NAN;
        };
        let dw = self.omega[1] - self.omega[0];
        let mut w = self.omega[k];
        if k + 1 < n && smooth[k - 1] > 0.0 && smooth[k + 1] > 0.0 {
            let (a, b, c) = (smooth[k - 1].ln(), smooth[k].ln(), smooth[k + 1].ln());
            let den = a - 2.0 * b + c;
            if den < 0.0 {
                w += 0.5 * (a - c) / den * dw;
            }
        }
        2.0 * PI / w
    }

    /// ∫ S dω over the estimate (rectangle rule) [m²].
    pub fn m0(&self) -> f64 {
        if self.omega.len() < 2 {
            return 0.0;
        }
        let dw = self.omega[1] - self.omega[0];
        self.density.iter().sum::<f64>() * dw
    }
}

/// Welch's estimate: Hann-windowed segments of `segment` samples with 50 % overlap, averaged
/// periodograms, one-sided, in rad/s units. `dt` is the sample interval [s].
///
/// Returns `None` if the record is shorter than one segment or `segment` < 8.
pub fn welch(x: &[f64], dt: f64, segment: usize) -> Option<SpectrumEstimate> {
    if segment < 8 || x.len() < segment || !(dt > 0.0) {
        return None;
    }
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let window: Vec<f64> = (0..segment)
        .map(|i| 0.5 * (1.0 - (2.0 * PI * i as f64 / segment as f64).cos()))
        .collect();
    let w2: f64 = window.iter().map(|w| w * w).sum();
    let fft = FftPlanner::new().plan_fft_forward(segment);
    let mut buf = vec![Complex::new(0.0, 0.0); segment];
    let nbins = segment / 2 + 1;
    let mut acc = vec![0.0; nbins];
    let step = segment / 2;
    let mut count = 0usize;
    let mut start = 0;
    while start + segment <= x.len() {
        for i in 0..segment {
            buf[i] = Complex::new((x[start + i] - mean) * window[i], 0.0);
        }
        fft.process(&mut buf);
        for (k, a) in acc.iter_mut().enumerate() {
            *a += buf[k].norm_sqr();
        }
        count += 1;
        start += step;
    }
    let df = 1.0 / (segment as f64 * dt);
    let mut omega = Vec::with_capacity(nbins);
    let mut density = Vec::with_capacity(nbins);
    for (k, a) in acc.iter().enumerate() {
        // One-sided PSD per Hz, then per rad/s.
        let two = if k == 0 || (segment.is_multiple_of(2) && k == nbins - 1) {
            1.0
        } else {
            2.0
        };
        let p_hz = two * a / count as f64 * dt / w2;
        omega.push(2.0 * PI * k as f64 * df);
        density.push(p_hz / (2.0 * PI));
    }
    Some(SpectrumEstimate { omega, density })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_variance_and_welch_energy() {
        let dt = 0.1;
        let a = 1.5;
        let x: Vec<f64> = (0..20_000)
            .map(|i| a * (2.0 * PI * 0.125 * i as f64 * dt).cos())
            .collect();
        assert!((variance(&x) - a * a / 2.0).abs() < 1e-3);
        let est = welch(&x, dt, 1024).unwrap();
        assert!((est.m0() - a * a / 2.0).abs() / (a * a / 2.0) < 0.01);
        let tp = est.peak_period();
        assert!((tp - 8.0).abs() < 0.1, "{tp}");
    }
}

/// Hs and Tp measured from a generated record at x = y = 0.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MeasuredSea {
    /// Record length [s].
    pub record_seconds: f64,
    /// 4σ_η [m].
    pub hs: f64,
    /// Peak period from a Welch spectrum [s].
    pub tp: f64,
}

/// Generates η at the origin over `record` seconds after the ramp and measures Hs and Tp.
pub fn measure_record(
    sea: &crate::Sea,
    record: f64,
    tp_hint: f64,
    ramp: f64,
) -> Option<MeasuredSea> {
    let dt = (tp_hint / 20.0).min(0.5);
    let n = (record / dt).floor() as usize;
    if n < 512 {
        return None;
    }
    let eta: Vec<f64> = (0..n)
        .map(|i| sea.elevation(0.0, 0.0, ramp + i as f64 * dt, crate::Phase::Dynamic))
        .collect();
    let mut seg = 64usize;
    while seg * 2 <= n / 8 {
        seg *= 2;
    }
    let est = welch(&eta, dt, seg)?;
    Some(MeasuredSea {
        record_seconds: n as f64 * dt,
        hs: significant_height(&eta),
        tp: est.peak_period(),
    })
}
