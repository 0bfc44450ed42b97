//! The seabed-contact warning (docs/theory/fem.md#seabed-contact-resolution) on the 40-segment
//! mooring chain of the stability matrix: HHT-α at Δt = 0.1 s damps the touchdown's contact
//! (its every-step extremes 1.7 % and 3 % low) and must say so, with the contact frequency and
//! the scheme's loss computed here independently; at Δt = 5 ms, with the midpoint rule θ = ½ and
//! in a 3 m/s current whose touchdown lands and lifts only gently, it must stay silent.

mod common;

use common::{run_matrix_chain as run, scratch};

fn contact_warning(json: &serde_json::Value) -> Option<String> {
    json["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d.as_str().unwrap().to_string())
        .find(|d| d.contains("seabed-contact-resolution"))
}

/// The spectral radius of HHT-α (α = 0.3) on x'' + ω²x = 0 at Ω = ωΔt, from the growth of the
/// state's norm over many steps of the scheme written out here (Newmark β = (1 + α)²/4,
/// γ = ½ + α, a_{n+1} + (1 − α)ω²x_{n+1} + αω²x_n = 0).
fn hht_radius(omega_dt: f64) -> f64 {
    let alpha: f64 = 0.3;
    let (beta, gamma) = ((1.0 + alpha).powi(2) / 4.0, 0.5 + alpha);
    let w2 = omega_dt * omega_dt;
    let (mut x, mut v, mut a) = (1.0f64, 0.0f64, -w2);
    let norm = |x: f64, v: f64, a: f64| (x * x + v * v + a * a).sqrt();
    let (skip, count) = (50, 400);
    let mut n0 = 0.0;
    for k in 0..skip + count {
        if k == skip {
            n0 = norm(x, v, a);
        }
        let pred = x + v + (0.5 - beta) * a;
        let a1 = (-(1.0 - alpha) * w2 * pred - alpha * w2 * x) / (1.0 + (1.0 - alpha) * w2 * beta);
        let x1 = pred + beta * a1;
        v += (1.0 - gamma) * a + gamma * a1;
        (x, a) = (x1, a1);
        if norm(x, v, a) < 1e-200 {
            break;
        }
    }
    (norm(x, v, a) / n0).powf(1.0 / count as f64)
}

#[test]
fn unresolved_landing_contact_under_hht_warns_and_resolved_or_gentle_does_not() {
    let dir = scratch("seabed-contact");
    // Contact frequency of a touchdown node: bed stiffness k_b·d_c·L over its structural plus
    // added mass (76 mm chain: 113 kg/m, volume diameter 0.1354 m, C_a = 1, 3 m segments).
    let (kb, dc, l, mu, rho) = (3e6, 0.1354, 3.0, 113.0, 1025.0);
    let m = mu * l + rho * std::f64::consts::PI / 4.0 * dc * dc * l;
    let omega = (kb * dc * l / m).sqrt();

    let coarse = run(&dir, "hht-0.1", &["dt=0.1"]);
    let w = contact_warning(&coarse).expect("HHT-α at 0.1 s does not resolve the contact");
    assert!(
        w.contains("anchor and touchdown tension extremes may be"),
        "{w}"
    );
    let c = &coarse["step_control"]["seabed_contact"];
    assert!(c["impacts"].as_u64().unwrap() >= 1, "{c}");
    let got = c["omega"].as_f64().unwrap();
    assert!(
        (got / omega - 1.0).abs() < 0.01,
        "ω_c {got} rad/s, expected {omega}"
    );
    // One step per contact period at most: the loss over a period is 1 − ρ^max(1, 2π/Ω).
    let big = omega * 0.1;
    let steps = (2.0 * std::f64::consts::PI / big).max(1.0);
    let loss = 1.0 - hht_radius(big).powf(steps);
    let got = c["loss"].as_f64().unwrap();
    assert!(
        (got - loss).abs() < 0.01 * loss,
        "loss {got}, expected {loss} at Ω = {big}"
    );

    // 5 ms: Ω ≈ 0.28, HHT-α removes 0.25 % per contact period: silent.
    let fine = run(&dir, "hht-0.005", &["dt=0.005"]);
    assert_eq!(contact_warning(&fine), None);
    // The energy-conserving midpoint rule removes nothing at any step.
    let mid = run(&dir, "mid-0.1", &["scheme=midpoint", "dt=0.1"]);
    assert_eq!(contact_warning(&mid), None);
    assert!(
        mid["step_control"]["seabed_contact"]["impacts"]
            .as_u64()
            .unwrap()
            >= 1
    );
    // In a 3 m/s current the touchdown lands and lifts at a few cm/s, below g/ω_c: the
    // contact force follows quasi-statically, and HHT-α at 0.1 s is right on every step.
    let current = run(
        &dir,
        "current-0.1",
        &[
            "dt=0.1",
            "sea.current.kind=uniform",
            "sea.current.velocity=[3.0,0.0,0.0]",
        ],
    );
    assert_eq!(contact_warning(&current), None);
    let c = &current["step_control"]["seabed_contact"];
    assert!(c["events"].as_u64().unwrap() >= 1, "{c}");
    assert_eq!(c["impacts"].as_u64().unwrap(), 0, "{c}");
}
