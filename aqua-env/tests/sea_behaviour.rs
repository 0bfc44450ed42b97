//! Behavioural checks of docs/theory/environment.md#tests-and-worked-numbers against independent
//! numbers: conservation (divergence-free, irrotational), statistics of generated records,
//! reproducibility.

use aqua_env::record::{significant_height, variance, welch};
use aqua_env::{BuildOptions, Phase, Sea, SeaSpec, SeaSummary, Spectrum};
use proptest::prelude::*;

fn sea(toml_text: &str) -> (Sea, SeaSummary) {
    let spec: SeaSpec = toml::from_str(toml_text).expect("valid sea");
    spec.build(&BuildOptions::default()).expect("buildable sea")
}

fn irregular(seed: u64, spacing: &str, n: usize, extra: &str) -> String {
    format!(
        "depth = 60\n[waves]\nkind = \"irregular\"\nramp_time = 0\n{extra}\n[waves.spectrum]\n\
         hs = 2.0\ntp = 8.0\ngamma = 3.3\ncomponents = {n}\nspacing = \"{spacing}\"\nseed = {seed}\n"
    )
}

/// Velocity at a point (total).
fn vel(s: &Sea, p: [f64; 3], t: f64) -> [f64; 3] {
    s.at(p, t, Phase::Dynamic).velocity()
}

/// ∇·u and |∇×u| by central differences (h = 1e-4 m).
fn div_curl(s: &Sea, p: [f64; 3], t: f64) -> (f64, f64) {
    let h = 1e-4;
    let mut g = [[0.0; 3]; 3]; // g[i][j] = ∂u_i/∂x_j
    for j in 0..3 {
        let mut a = p;
        let mut b = p;
        a[j] += h;
        b[j] -= h;
        let (ua, ub) = (vel(s, a, t), vel(s, b, t));
        for i in 0..3 {
            g[i][j] = (ua[i] - ub[i]) / (2.0 * h);
        }
    }
    let div = g[0][0] + g[1][1] + g[2][2];
    let curl = [g[2][1] - g[1][2], g[0][2] - g[2][0], g[1][0] - g[0][1]];
    (
        div,
        (curl[0].powi(2) + curl[1].powi(2) + curl[2].powi(2)).sqrt(),
    )
}

#[test]
fn airy_kinematics_are_divergence_free_and_irrotational() {
    let (s, _) = sea(
        "gravity = 9.81\ndepth = 30\n[waves]\nkind = \"airy\"\nheight = 2\nperiod = 7\ndirection = 30\nramp_time = 0\n",
    );
    // velocity gradient scale: ω²a/g·ω ~ 0.1 1/s; FD error ~ h² ≈ 1e-8
    for (i, z) in [-1.5, -5.0, -12.0, -25.0].iter().enumerate() {
        let p = [3.0 * i as f64, -2.0, *z];
        for t in [0.0, 1.3, 4.4] {
            let (d, c) = div_curl(&s, p, t);
            assert!(d.abs() < 1e-7, "div {d} at {p:?}");
            assert!(c < 1e-7, "curl {c} at {p:?}");
        }
    }
}

#[test]
fn irregular_short_crested_sea_is_divergence_free_below_the_trough() {
    // Wheeler stretching makes the field depend on η; below the trough with "none" stretching
    // each component is a potential flow, so the sum is too.
    let (s, _) = sea(&format!(
        "{}spreading_s = 6\n",
        irregular(5, "random_in_bin", 60, "stretching = \"none\"")
    ));
    for z in [-3.0, -10.0, -40.0] {
        let (d, c) = div_curl(&s, [1.0, 2.0, z], 17.0);
        assert!(d.abs() < 1e-6 && c < 1e-6, "z={z}: div {d}, curl {c}");
    }
}

#[test]
fn three_hour_record_gives_back_hs_and_spectrum() {
    let (s, summary) = sea(&irregular(11, "random_in_bin", 400, ""));
    let irr = summary.irregular.unwrap();
    let dt = 0.25;
    let n = (3.0 * 3600.0 / dt) as usize;
    let eta: Vec<f64> = (0..n)
        .map(|i| s.elevation(0.0, 0.0, i as f64 * dt, Phase::Dynamic))
        .collect();
    let hs = significant_height(&eta);
    assert!((hs / 2.0 - 1.0).abs() < 0.02, "Hs measured {hs}");
    // Welch spectrum vs the input spectrum, integrated over bands of 0.1 rad/s around the peak
    // (single bins scatter by ~1/sqrt(segments)).
    let est = welch(&eta, dt, 1024).unwrap();
    let spec = Spectrum::Jonswap {
        hs: 2.0,
        tp: 8.0,
        gamma: 3.3,
    };
    let dw = est.omega[1] - est.omega[0];
    for (lo, hi) in [(0.6, 0.7), (0.7, 0.8), (0.8, 0.9), (0.9, 1.1), (1.1, 1.4)] {
        let mut e_est = 0.0;
        let mut e_in = 0.0;
        for (w, sw) in est.omega.iter().zip(&est.density) {
            if *w >= lo && *w < hi {
                e_est += sw * dw;
                e_in += spec.density(*w) * dw;
            }
        }
        assert!(
            (e_est / e_in - 1.0).abs() < 0.12,
            "band [{lo}, {hi}]: measured {e_est}, input {e_in}"
        );
    }
    assert!((est.peak_period() - 8.0).abs() < 0.4);
    assert!(irr.dropped_fraction < 1.1e-3);
}

#[test]
fn record_of_100_peak_periods_has_the_retained_variance() {
    let (s, summary) = sea(&irregular(3, "random_in_bin", 200, ""));
    let m0 = summary.irregular.unwrap().m0_retained;
    let dt = 0.2;
    let n = (100.0 * 8.0 / dt) as usize;
    let eta: Vec<f64> = (0..n)
        .map(|i| s.elevation(0.0, 0.0, i as f64 * dt, Phase::Dynamic))
        .collect();
    let v = variance(&eta);
    assert!((v / m0 - 1.0).abs() < 0.05, "variance {v}, m0 {m0}");
}

#[test]
fn equal_spacing_repeats_exactly() {
    let (s, summary) = sea(&irregular(2, "equal", 150, ""));
    let t_rep = summary.irregular.unwrap().repeat_period.unwrap();
    for t in [0.0, 13.7, 123.4] {
        let a = s.elevation(1.0, 2.0, t, Phase::Dynamic);
        let b = s.elevation(1.0, 2.0, t + t_rep, Phase::Dynamic);
        assert!((a - b).abs() < 1e-9 * 2.0, "t={t}: {a} vs {b}");
    }
}

#[test]
fn same_seed_bit_identical_samples_different_seed_differs() {
    let pts: Vec<[f64; 3]> = (0..300)
        .map(|i| [i as f64 * 0.7, (i % 7) as f64, -((i % 20) as f64)])
        .collect();
    let sample = |seed: u64| {
        let (s, _) = sea(&irregular(seed, "random_in_bin", 200, ""));
        let mut out = vec![aqua_env::FlowPoint::default(); pts.len()];
        s.eval(42.0, Phase::Dynamic, &pts, &mut out);
        out
    };
    let (a, b, c) = (sample(9), sample(9), sample(10));
    for i in 0..pts.len() {
        assert_eq!(a[i].eta.to_bits(), b[i].eta.to_bits());
        for k in 0..3 {
            assert_eq!(a[i].wave_vel[k].to_bits(), b[i].wave_vel[k].to_bits());
            assert_eq!(a[i].wave_acc[k].to_bits(), b[i].wave_acc[k].to_bits());
        }
    }
    assert!(a.iter().zip(&c).filter(|(x, y)| x.eta != y.eta).count() > 290);
}

#[test]
fn zero_above_the_surface_for_every_kind() {
    let kinds = [
        "gravity = 9.81\ndepth = 20\n[waves]\nkind = \"stokes2\"\nheight = 2\nperiod = 8\nramp_time = 0\n"
            .to_string(),
        "depth = 20\n[waves]\nkind = \"components\"\nramp_time = 0\ncomponents = [[0.5, 6, 0, 0], [0.3, 9, 40, 90]]\n"
            .to_string(),
        irregular(4, "equal_energy", 100, ""),
        irregular(4, "random_in_bin", 100, "stretching = \"vertical\""),
    ];
    for k in &kinds {
        let (s, _) = sea(k);
        for i in 0..40 {
            let t = 0.61 * i as f64;
            let eta = s.elevation(2.0, 1.0, t, Phase::Dynamic);
            let f = s.at([2.0, 1.0, eta + 1e-7], t, Phase::Dynamic);
            assert_eq!(f.wave_vel, [0.0; 3], "{k}");
            assert_eq!(f.p_dyn, 0.0);
            let g = s.at([2.0, 1.0, eta - 1e-3], t, Phase::Dynamic);
            assert!(g.submergence > 0.0);
        }
    }
}

#[test]
fn wheeler_and_linear_agree_below_the_trough_to_order_a() {
    let make = |st: &str| {
        sea(&format!(
            "gravity = 9.81\ndepth = 40\n[waves]\nkind = \"airy\"\nheight = 0.02\nperiod = 6\nramp_time = 0\nstretching = \"{st}\"\n"
        ))
        .0
    };
    let (w, n) = (make("wheeler"), make("none"));
    let a = 0.01;
    for z in [-0.5, -5.0, -20.0] {
        for t in [0.0, 1.0, 2.5] {
            let (uw, un) = (vel(&w, [0.0, 0.0, z], t), vel(&n, [0.0, 0.0, z], t));
            let amp = 2.0 * std::f64::consts::PI / 6.0 * a;
            // difference is O(a·k·a·ω): well below 5 % of the velocity amplitude
            assert!((uw[0] - un[0]).abs() < 0.05 * amp, "z={z} t={t}");
        }
    }
}

#[test]
fn stokes2_in_10m_depth() {
    let ok =
        sea("gravity = 9.81\ndepth = 10\n[waves]\nkind = \"stokes2\"\nheight = 2\nperiod = 8\n").1;
    assert!(!ok.warnings.iter().any(|w| w.contains("secondary crest")));
    let warn =
        sea("gravity = 9.81\ndepth = 10\n[waves]\nkind = \"stokes2\"\nheight = 6\nperiod = 8\n").1;
    assert!(warn.warnings.iter().any(|w| w.contains("secondary crest")));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn airy_potential_flow_anywhere(
        h in 2.0f64..200.0, period in 2.0f64..20.0, dir in 0.0f64..360.0,
        zf in 0.05f64..0.95, x in -50.0f64..50.0, t in 0.0f64..30.0,
    ) {
        let (s, _) = sea(&format!(
            "gravity = 9.81\ndepth = {h}\n[waves]\nkind = \"airy\"\nheight = 0.5\nperiod = {period}\n\
             direction = {dir}\nramp_time = 0\n"
        ));
        let (d, c) = div_curl(&s, [x, 0.5 * x, -zf * h], t);
        prop_assert!(d.abs() < 1e-6 && c < 1e-6, "div {} curl {}", d, c);
    }

    #[test]
    fn dispersion_residual_vanishes(period in 0.5f64..40.0, h in 0.05f64..1e5) {
        let w = 2.0 * std::f64::consts::PI / period;
        let k = aqua_env::wave_number(w, aqua_env::Depth::Finite(h), 9.81).unwrap();
        prop_assert!(((9.81 * k * (k * h).tanh() - w * w) / (w * w)).abs() < 1e-11);
    }
}
