//! Snap resolution (docs/theory/fem.md#snap-resolution): a mass that falls on a slack rope
//! and snaps it taut within one step is reported with the snap's estimated peak, against the
//! closed form of the snap; a step that resolves the snap reports none.

mod falling_mass;

use aqua_fem::*;
use falling_mass::*;

/// The largest rope tension over every accepted step until the first snap is over, and the
/// solver's snap report.
fn run(midpoint: bool, dt: f64) -> (f64, Option<SnapResolution>) {
    let model = snap_model();
    let mut s = DynamicSettings::new(dt, 0.42);
    s.midpoint = midpoint;
    s.alpha = if midpoint { 0.0 } else { 0.05 };
    let mut solver = DynamicSolver::new(&model, s, None, &mut NoLoads).unwrap();
    let mut peak = 0.0f64;
    while !solver.is_finished() {
        solver.step(&mut NoLoads).unwrap();
        peak = peak.max(solver.outputs().tension[0]);
    }
    (peak, solver.step_control().snaps.clone())
}

#[test]
fn a_snap_inside_one_step_is_reported_with_its_closed_form_peak() {
    let exact = closed_form_peak();
    // The rope holds the mass for half a period π·√(m/k) = 31 ms (ω = 100 rad/s): a step of
    // 30 ms (ω·Δt = 3) puts the snap inside about one step.
    for midpoint in [false, true] {
        let (peak, report) = run(midpoint, 0.03);
        let r = report.expect("the snap is reported");
        eprintln!("midpoint {midpoint}: peak {peak:.1} N, exact {exact:.1} N, {r:?}");
        assert!(r.snaps >= 1, "{r:?}");
        // The estimate v_c·√(k·m) leaves out the weight's static share m·g (98 N, 3 %).
        let err = (r.estimate - exact) / exact;
        assert!(
            err.abs() < 0.05,
            "midpoint {midpoint}: estimate {:.1} N vs the closed form {exact:.1} N",
            r.estimate
        );
        // The closing speed is the free fall's √(2·g·DROP) = 3.13 m/s.
        let v = (2.0 * G * DROP).sqrt();
        assert!((r.speed - v).abs() < 0.05 * v, "{r:?}");
        assert!((r.computed - peak).abs() <= 1e-9 * peak, "{r:?} {peak}");
        // The largest tension the fixed step computed misses the crest: the report says so.
        assert!(
            peak < 0.95 * exact && r.excess > SNAP_EXCESS_WARNING,
            "midpoint {midpoint}: peak {peak:.1} N, {r:?}"
        );
        // √(m/k) = 10 ms: the step that samples the crest within 1 %.
        assert!(
            (r.resolving_dt - RESOLVED_PHASE * 0.01).abs() < 1e-5,
            "{r:?}"
        );
    }
}

#[test]
fn a_step_that_resolves_the_snap_reports_none() {
    let exact = closed_form_peak();
    // ω·Δt = 0.1: the crest is sampled within 0.2 %.
    for midpoint in [false, true] {
        let (peak, report) = run(midpoint, 0.001);
        assert!(report.is_none(), "{report:?}");
        assert!(
            (peak - exact).abs() / exact < 0.01,
            "midpoint {midpoint}: {peak} vs {exact}"
        );
    }
}
