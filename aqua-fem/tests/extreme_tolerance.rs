//! Extremes to a tolerance (docs/theory/fem.md#extremes-to-a-tolerance): a mass that falls
//! on a slack rope and snaps it taut, against the closed-form peak of the snap.

mod falling_mass;

use aqua_fem::*;
use falling_mass::*;

/// The largest rope tension over every accepted step of the first snap, and the solver's
/// extreme control report.
fn run(midpoint: bool, dt: f64, tolerance: Option<f64>) -> (f64, Option<ExtremeResolution>) {
    let model = snap_model();
    let mut s = DynamicSettings::new(dt, 0.42);
    s.midpoint = midpoint;
    s.alpha = if midpoint { 0.0 } else { 0.05 };
    s.extreme_tolerance = tolerance;
    let mut solver = DynamicSolver::new(&model, s, None, &mut NoLoads).unwrap();
    let mut peak = 0.0f64;
    while !solver.is_finished() {
        solver.step(&mut NoLoads).unwrap();
        peak = peak.max(solver.outputs().tension[0]);
    }
    (peak, solver.step_control().extremes.clone())
}

#[test]
fn a_snap_is_resolved_to_the_tolerance_with_the_midpoint_rule() {
    let exact = closed_form_peak();
    // The free fall takes √(2·DROP/g) = 0.32 s; the rope holds the mass for half a period
    // π·√(m/k) = 31 ms: at dt = 30 ms the snap lasts about a step.
    let dt = 0.03;
    let (coarse, none) = run(true, dt, None);
    assert!(none.is_none());
    assert!(
        (coarse - exact).abs() / exact > 0.05,
        "the fixed step should miss the crest ({coarse} vs {exact})"
    );
    for tol in [0.02, 0.005] {
        let (peak, report) = run(true, dt, Some(tol));
        let report = report.expect("the control ran");
        let err = (peak - exact).abs() / exact;
        // The control bounds the sampling error of the crest; the scheme's own error at the
        // halved steps adds a little to it.
        assert!(
            err <= tol + 0.002,
            "tolerance {tol}: peak {peak:.1} N vs {exact:.1} N ({:.2} %)",
            100.0 * err
        );
        assert!(report.rejections > 0, "{report:?}");
        assert_eq!(report.unresolved_steps, 0, "{report:?}");
    }
}

#[test]
fn hht_alpha_resolves_the_crest_of_its_own_damped_snap() {
    // HHT-α at ωΔt ≈ 9.5 damps the contact mode itself: the control resolves where the
    // scheme's tension peaks, not the physics the scheme removed (docs/theory/fem.md#
    // extremes-to-a-tolerance). Its peak must still rise towards the energy bound when the
    // steps near the crest shrink, and never pass it.
    let exact = closed_form_peak();
    let (coarse, _) = run(false, 0.03, None);
    let (controlled, report) = run(false, 0.03, Some(0.005));
    assert!(report.unwrap().rejections > 0);
    assert!(
        controlled > coarse && controlled <= exact * 1.001,
        "{coarse} {controlled} {exact}"
    );
}

#[test]
fn a_floor_at_dt_min_is_accepted_and_reported_not_failed() {
    let model = snap_model();
    let mut s = DynamicSettings::new(0.02, 0.42);
    s.midpoint = true;
    s.alpha = 0.0;
    s.dt_min = Some(0.01);
    s.extreme_tolerance = Some(0.001);
    let mut solver = DynamicSolver::new(&model, s, None, &mut NoLoads).unwrap();
    while !solver.is_finished() {
        solver.step(&mut NoLoads).unwrap();
    }
    let r = solver.step_control().extremes.clone().unwrap();
    assert!(r.unresolved_steps > 0, "{r:?}");
    assert!(r.worst_unresolved > 0.001, "{r:?}");
    assert_eq!(r.worst_group, Some(0));
}

#[test]
fn the_tolerance_is_validated() {
    let model = snap_model();
    for bad in [0.0, -0.1, 0.5, f64::NAN] {
        let mut s = DynamicSettings::new(0.02, 0.42);
        s.extreme_tolerance = Some(bad);
        let e = DynamicSolver::new(&model, s, None, &mut NoLoads).unwrap_err();
        assert!(e.to_string().contains("extreme_tolerance"), "{e}");
    }
}
