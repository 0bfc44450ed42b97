//! The snap warning (docs/theory/fem.md#snap-resolution) on the very slack chain of the
//! stability matrix (examples/mooring-chain.toml at 40 segments, 300 m on a 110 m chord): HHT-α
//! at Δt = 0.5 s absorbs the snap of an element that goes taut inside a step (the run's largest
//! tension 43.6 kN against 182–187 kN at 1–2 ms) and must say so, naming the chain; the same
//! chain at its own length (120 m), which does not snap, must not.

mod common;

use common::{example, run_json, scratch};
use std::path::Path;

/// examples/mooring-chain.toml at 40 segments, 30 s, samples every second.
fn chain() -> String {
    example("mooring-chain.toml")
        .replace("segments = 80", "segments = 40")
        .replace("t_end = 60.0", "t_end = 30.0")
        .replace("output_interval = 0.5", "output_interval = 1.0")
}

/// Runs the chain with `set` and returns its run.json.
fn run(dir: &Path, name: &str, set: &[&str]) -> serde_json::Value {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, chain()).unwrap();
    let out = dir.join(format!("{name}-out"));
    let mut set: Vec<_> = set
        .iter()
        .map(|s| s.parse::<aqua_sim::Override>().unwrap())
        .collect();
    set.push("analysis.dynamic.paraview_interval=30".parse().unwrap());
    aqua_cli::commands::run::run_scene(&scene, &set, &out, true).unwrap();
    run_json(&out)
}

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
