//! The snap warning (docs/theory/fem.md#snap-resolution) on the very slack chain of the
//! stability matrix (examples/mooring-chain.toml at 40 segments, 300 m on a 110 m chord): HHT-α
//! at Δt = 0.5 s absorbs the snap of an element that goes taut inside a step (the run's largest
//! tension 43.6 kN against 182–187 kN at 1–2 ms) and must say so, naming the chain; the same
//! chain at its own length (120 m), which does not snap, must not.

mod common;

use common::{run_matrix_chain as run, scratch};

fn snap_warning(json: &serde_json::Value) -> Option<String> {
    json["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d.as_str().unwrap().to_string())
        .find(|d| d.contains("snap-resolution"))
}

#[test]
fn a_snap_inside_a_step_of_hht_warns_and_a_chain_without_snaps_does_not() {
    let dir = scratch("snap-resolution");
    let slack = run(&dir, "slack-0.5", &["dt=0.5", "line.0.length=300"]);
    let w = snap_warning(&slack).expect("HHT-α at 0.5 s absorbs the slack chain's snap");
    assert!(w.contains("`chain/chain`"), "{w}");
    assert!(w.contains("largest tension"), "{w}");
    let s = &slack["step_control"]["snaps"];
    let (estimate, computed) = (
        s["estimate"].as_f64().unwrap(),
        s["computed"].as_f64().unwrap(),
    );
    // An element of L0 = 7.5 m (k = EA/L0 = 7.2e7 N/m) between two chain nodes of 847 kg
    // (113 kg/m) or more (added mass along it): closing at v_c, its snap peaks at
    // v_c·√(k·m_r) with m_r ≥ 847/2 kg.
    let (k, mr): (f64, f64) = (5.4e8 / 7.5, 0.5 * 113.0 * 7.5);
    let v = s["speed"].as_f64().unwrap();
    assert!(
        estimate >= v * (k * mr).sqrt() * (1.0 - 1e-9),
        "{estimate} {v}"
    );
    // The snap is at least four times the largest tension the coarse run computed.
    assert!(estimate > 4.0 * computed, "{s}");
    // √(m_r/k) ≥ 2.4 ms: the 0.5 s step does not resolve it.
    assert!(s["resolving_dt"].as_f64().unwrap() >= 0.28 * (mr / k).sqrt());

    let taut = run(&dir, "chain-0.5", &["dt=0.5"]);
    assert!(snap_warning(&taut).is_none(), "{:?}", taut["diagnostics"]);
}
