//! The bundled mooring chain: the static fairlead and anchor reactions against the elastic
//! catenary with touchdown on a frictionless seabed (docs/theory/fem.md#test-oracles), solved here
//! independently.

mod common;
use common::*;

/// (H, V_B) of an elastic catenary with touchdown: anchor on the seabed, fairlead l away and h
/// above it, unstretched length L0, submerged weight w per metre, axial stiffness EA.
fn touchdown(l: f64, h: f64, l0: f64, w: f64, ea: f64) -> (f64, f64) {
    let f = |hh: f64, v: f64| {
        let laid = l0 - v / w;
        (
            laid + hh / w * (v / hh).asinh() + hh * l0 / ea - l,
            hh / w * ((1.0 + (v / hh).powi(2)).sqrt() - 1.0) + v * v / (2.0 * ea * w) - h,
        )
    };
    let (mut hh, mut v) = (0.3 * w * l0, 0.5 * w * l0);
    for _ in 0..100 {
        let (f0, f1) = f(hh, v);
        let e = 1e-6 * hh.max(1.0);
        let (a0, a1) = f(hh + e, v);
        let (b0, b1) = f(hh, v + e);
        let j = [
            [(a0 - f0) / e, (b0 - f0) / e],
            [(a1 - f1) / e, (b1 - f1) / e],
        ];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        hh -= (f0 * j[1][1] - f1 * j[0][1]) / det;
        v -= (j[0][0] * f1 - j[1][0] * f0) / det;
    }
    (hh, v)
}

#[test]
fn chain_end_reactions_match_the_elastic_catenary() {
    let dir = scratch("chain");
    // Statics only (the dynamic part of the example is exercised by the CLI tests).
    let text =
        example("mooring-chain.toml").replace("kind = \"static+dynamic\"", "kind = \"static\"");
    let out = run_text(&dir, "chain", &text);
    let row = &summary(&out)[0];
    let g = 9.80665;
    let d = 0.1354f64;
    let w = (113.0 - 1025.0 * std::f64::consts::FRAC_PI_4 * d * d) * g;
    // Laid nodes sink w/(k_b·d_c) into the penalty seabed: the effective height grows by that.
    let sink = w / (3e6 * d);
    let (hh, v) = touchdown(100.0, 45.0 + sink, 120.0, w, 5.4e8);
    let t_fair = hh.hypot(v);
    let fair = row["chain_fairlead_reaction"];
    let anchor = row["chain_anchor_reaction"];
    assert!(
        (fair / t_fair - 1.0).abs() < 5e-4,
        "fairlead {fair} vs {t_fair}"
    );
    assert!(
        (anchor / hh - 1.0).abs() < 5e-4,
        "anchor {anchor} vs H = {hh}"
    );
    // The end-element tension differs from the end reaction by the lumped half-element weight.
    let te = row["chain_fairlead_element_tension"];
    assert!(
        te < fair && fair - te < 0.6 * w * 1.5 + 1.0,
        "element {te} vs reaction {fair}"
    );
}

/// `mesh/coarse-line` (docs/theory/fem.md#mesh-resolution-warnings): the chain at 20 segments
/// sags and is warned about, with its largest turn near touchdown equal to the discrete
/// catenary's atan(w·s/H) (H from the closed form above); at 40 segments it is not, and neither
/// is a taut line of 4 segments.
#[test]
fn coarse_sagging_lines_are_warned_about_and_straight_ones_are_not() {
    let dir = scratch("coarse-line");
    let base =
        example("mooring-chain.toml").replace("kind = \"static+dynamic\"", "kind = \"static\"");
    let warnings = |name: &str, text: &str| -> Vec<String> {
        let out = run_text(&dir, name, text);
        let json = run_json(&out);
        json["diagnostics"]
            .as_array()
            .unwrap()
            .iter()
            .map(|d| d.as_str().unwrap().to_string())
            .filter(|d| d.contains("sags"))
            .collect()
    };
    let coarse = warnings("n20", &base.replace("segments = 80", "segments = 20"));
    assert_eq!(coarse.len(), 1, "{coarse:?}");
    let turn: f64 = coarse[0]
        .split("turn by up to ")
        .nth(1)
        .and_then(|s| s.split('°').next())
        .and_then(|s| s.parse().ok())
        .expect("the warning gives the turn");
    let g = 9.80665;
    let d = 0.1354f64;
    let w = (113.0 - 1025.0 * std::f64::consts::FRAC_PI_4 * d * d) * g;
    let (hh, _) = touchdown(100.0, 45.0, 120.0, w, 5.4e8);
    let expected = (w * 6.0 / hh).atan().to_degrees();
    assert!(
        (turn / expected - 1.0).abs() < 0.1,
        "largest turn {turn}° against atan(w·s/H) = {expected}°"
    );
    assert!(warnings("n40", &base.replace("segments = 80", "segments = 40")).is_empty());
    // Taut: 4 segments, unstretched length = the chord (109.659 m); it sags only by its stretch.
    let taut = base
        .replace("segments = 80", "segments = 4")
        .replace("length = 120.0", "length = 109.66");
    assert!(warnings("taut", &taut).is_empty());
}

/// The static solve from the stretched touchdown-catenary start (docs/theory/cages.md#single-line):
/// the reactions match the elastic catenary at 80, 320 and 1280 segments, within one iteration
/// bound that fails if the count grows with the segments again (from the free catenary projected
/// onto the seabed: 155 iterations at 80 segments and no convergence at 320; from the unstretched
/// touchdown catenary 61 and 210; now 12, 14 and 15).
#[test]
fn fine_chains_reach_the_elastic_catenary_within_bounded_iterations() {
    let dir = scratch("chain-fine");
    let g = 9.80665;
    let d = 0.1354f64;
    let w = (113.0 - 1025.0 * std::f64::consts::FRAC_PI_4 * d * d) * g;
    let sink = w / (3e6 * d);
    let (hh, v) = touchdown(100.0, 45.0 + sink, 120.0, w, 5.4e8);
    for (segments, bound) in [(80, 25), (320, 25), (1280, 25)] {
        let text = example("mooring-chain.toml")
            .replace("kind = \"static+dynamic\"", "kind = \"static\"")
            .replace("segments = 80", &format!("segments = {segments}"));
        let out = run_text(&dir, &format!("n{segments}"), &text);
        let row = &summary(&out)[0];
        let json = run_json(&out);
        let iterations = json["static_newton_iterations"].as_u64().unwrap();
        assert!(
            iterations <= bound,
            "{segments} segments: {iterations} iterations"
        );
        let fair = row["chain_fairlead_reaction"];
        assert!(
            (fair / hh.hypot(v) - 1.0).abs() < 5e-4,
            "{segments}: fairlead {fair}"
        );
        let anchor = row["chain_anchor_reaction"];
        assert!(
            (anchor / hh - 1.0).abs() < 5e-4,
            "{segments}: anchor {anchor} vs H {hh}"
        );
    }
}

/// The bundled chain at 160 segments with axial damping ratio 1 (the MoorDyn benchmark's line),
/// surged for `t_end` seconds with HHT-α.
fn surged_chain(t_end: f64) -> String {
    example_chain_hht()
        .replace("segments = 80", "segments = 160")
        .replace("t_end = 60.0", &format!("t_end = {t_end:.1}"))
        .replace(
            "added_mass = 1.0",
            "added_mass = 1.0\naxial_damping_ratio = 1.0",
        )
}

/// The inexact solve's forcing term (docs/theory/fem.md#sparse-linear-algebra): on the surged
/// 160-segment chain, where each step's first updates leave remainders far above the Newton
/// tolerance, the symmetric refinement stops at a tenth of the predicted remainder. It must take
/// fewer sweeps per Newton iteration than a solve to 1 % of tol does (3.9 on this run) and no
/// more Newton iterations than exact LU solves, give or take 2 %. (HHT-α's energy-consistent
/// cable tangent is not symmetric, by O(Δd): 3.6 sweeps per iteration against 3.5 before it,
/// docs/theory/fem.md#energy-consistent-hht-alpha.)
#[test]
fn the_surged_chain_solves_its_updates_no_tighter_than_newton_needs() {
    let dir = scratch("chain-forcing");
    let base = surged_chain(10.0).replace("output_interval = 0.5", "output_interval = 5.0");
    let run = |name: &str, solver: &str| {
        let text = base.replace(
            "[analysis.dynamic]",
            &format!("[analysis.dynamic]\nlinear_solver = \"{solver}\""),
        );
        let out = run_text(&dir, name, &text);
        run_json(&out)
    };
    let (sym, lu) = (run("sym", "symmetric"), run("lu", "lu"));
    let its = |j: &serde_json::Value| j["newton_iterations"].as_f64().unwrap();
    let sweeps = sym["linear_solver"]["refinement_sweeps"].as_f64().unwrap();
    assert!(
        its(&sym) <= 1.02 * its(&lu),
        "{} Newton iterations against the LU's {}",
        its(&sym),
        its(&lu)
    );
    assert!(
        sweeps <= 3.7 * its(&sym),
        "{sweeps} refinement sweeps for {} iterations",
        its(&sym)
    );
    assert_eq!(sym["step_control"]["halvings"].as_u64(), Some(0));
}

/// Newton's cost per step on the surged 160-segment chain, whose touchdown nodes cross the bed
/// plane and its damping ramp at many steps (docs/theory/fem.md#line-relaxation and
/// #convergence-check). With the seabed's kink settled in the line relaxation, a step needs
/// one update from the predictor and one convergence check; with the check made with the last
/// factor, that check forms no new J. Before both: 2.9 iterations and 2.9 factorised or
/// preconditioned systems per step (kinks at touchdown converged linearly); with the seabed
/// relaxed but a new J for every check, 2.0 and 2.0; now 2.1 and 1.1.
/// The peak and trough of the fairlead reaction must be those of a run 1000× tighter.
#[test]
fn the_surged_chain_takes_one_update_and_one_check_per_step() {
    let dir = scratch("chain-two-iterations");
    let base = surged_chain(20.0);
    let run = |name: &str, tol: f64| {
        let text = base.replace(
            "[analysis.dynamic]",
            &format!("[analysis.dynamic]\ntol = {tol:e}"),
        );
        let out = run_text(&dir, name, &text);
        let json = run_json(&out);
        let rows = summary(&out);
        let fair: Vec<f64> = rows[1..]
            .iter()
            .map(|r| r["chain_fairlead_reaction"])
            .collect();
        let peak = fair.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let trough = fair.iter().cloned().fold(f64::INFINITY, f64::min);
        (json, peak, trough)
    };
    let (json, peak, trough) = run("default", 1e-5);
    let (_, peak_t, trough_t) = run("tight", 1e-8);
    let count = |k: &str| json["linear_solver"][k].as_f64().unwrap();
    let steps = json["steps"].as_f64().unwrap();
    let iterations = json["newton_iterations"].as_f64().unwrap();
    assert_eq!(json["step_control"]["halvings"].as_u64(), Some(0));
    assert!(
        iterations <= 2.2 * steps,
        "{iterations} Newton iterations for {steps} steps"
    );
    assert!(
        count("stale_checks") >= 0.5 * steps,
        "{} checks with the last factor for {steps} steps",
        count("stale_checks")
    );
    let systems = count("factorisations") + count("factor_reuses");
    assert!(
        systems <= 1.2 * steps,
        "{systems} systems with a new J for {steps} steps"
    );
    for (a, b) in [(peak, peak_t), (trough, trough_t)] {
        assert!(
            (a / b - 1.0).abs() < 1e-5,
            "{a} N against {b} N at tol 1e-8"
        );
    }
}

/// The bundled chain shortened to 100 m, so that it hangs taut on its 109.7 m span, with
/// EA = 1e14 N (a pretension of about 1e13 N): its supports carry its submerged weight,
/// 100 m × (113 kg/m − ρ_w·π/4·d_v²)·g (ρ_w = 1025 kg/m³, g = 9.80665 m/s²). The strain energies are then so large that their
/// round-off (ε_mach·T·|x| per element) exceeds a converging step's predicted decrease; the
/// merit cannot judge the last steps and the residual must (docs/theory/fem.md#static-solver),
/// else the solve ends in "no step lowers the energy" although the line has an equilibrium.
#[test]
fn a_taut_very_stiff_chain_carries_its_weight() {
    let dir = scratch("chain-taut-stiff");
    let text = example("mooring-chain.toml")
        .replace("kind = \"static+dynamic\"", "kind = \"static\"")
        .replace("length = 120.0", "length = 100.0")
        .replace("ea = 5.4e8", "ea = 1e14");
    let row = &summary(&run_text(&dir, "taut", &text))[0];
    let d_v: f64 = 0.1354;
    let weight = 100.0 * (113.0 - 1025.0 * std::f64::consts::FRAC_PI_4 * d_v * d_v) * 9.80665;
    assert!(
        (row["Rz"] - weight).abs() <= 2e-3 * weight,
        "supports carry {} N of {weight} N",
        row["Rz"]
    );
}
