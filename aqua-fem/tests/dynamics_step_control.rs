//! Newton iterations and step control in dynamics (docs/theory/fem.md#step-control): failure
//! handling, modified Newton, the time-error indicator, peak-tension resolution, output landings,
//! line relaxation and the symmetric factorisation.

mod common;
mod dynamics_helpers;

use aqua_fem::*;
use common::*;
use dynamics_helpers::*;
use std::f64::consts::PI;

#[test]
fn a_step_that_cannot_converge_is_a_clear_error() {
    let (m, _) = swinging_chain();
    let mut s = DynamicSettings::new(0.5, 2.0);
    s.max_iter = 1;
    s.dt_min = Some(0.1);
    let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
    let t0 = solver.time();
    match solver.step(&mut NoLoads) {
        Err(FemError::StepFailed(f)) => {
            assert_eq!(f.t, t0);
            assert!(f.dt < 0.2 && !f.history.is_empty());
            assert!(f.to_string().contains("worst node"));
        }
        other => panic!("{other:?}"),
    }
    // Last converged state untouched and finite.
    assert!(solver.state().x.iter().flatten().all(|v| v.is_finite()));
}

/// Modified Newton (`reuse_factor`, docs/theory/fem.md#hht-alpha) converges to the same discrete
/// solution as full Newton: each step meets the same residual and correction tolerances, so the
/// swinging tip agrees to well within 1e-3 of the chain length; `reuse_factor = 0` is rejected.
#[test]
fn modified_newton_matches_full_newton() {
    let (m, tip) = swinging_chain();
    let run = |reuse: usize| {
        let mut s = DynamicSettings::new(1e-2, 1.0);
        s.reuse_factor = reuse;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        solver.run(&mut NoLoads, |_, _| true).unwrap();
        solver.state().x[tip]
    };
    let (a, b) = (run(1), run(8));
    let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    assert!(d < 1e-2, "full {a:?} vs modified {b:?}");
    assert!(a[2] < 9.0, "the chain has swung down");
    let mut s = DynamicSettings::new(1e-2, 1.0);
    s.reuse_factor = 0;
    let err = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap_err();
    assert!(err.to_string().contains("reuse_factor"), "{err}");
}

/// A failed modified-Newton attempt is retried with full Newton before the step is halved
/// (docs/theory/fem.md#hht-alpha): on the swinging slack chain at steps where a stale
/// factorisation does not contract, `reuse_factor = 8` must halve no more often than full Newton.
#[test]
fn modified_newton_halves_no_more_than_full_newton() {
    let (m, _) = swinging_chain();
    let halvings = |reuse: usize, dt: f64| {
        let mut s = DynamicSettings::new(dt, 2.0);
        s.reuse_factor = reuse;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        solver.run(&mut NoLoads, |_, _| true).unwrap();
        solver.step_control().halvings
    };
    for dt in [0.02, 0.05, 0.1] {
        let (full, modified) = (halvings(1, dt), halvings(8, dt));
        eprintln!("dt {dt}: halvings full {full}, modified {modified}");
        assert!(
            modified <= full,
            "dt {dt}: modified Newton halved {modified}×, full {full}×"
        );
    }
}

/// The time-step error indicator (docs/theory/fem.md#time-step-error-indicator) on a linear
/// oscillator with a known solution: it falls like Δt² as the true error does, and stays
/// within a small factor of the true position error.
#[test]
fn time_error_indicator_tracks_the_true_error_of_a_linear_oscillator() {
    let (m, mid) = sdof(0.0, 4.0 * PI * PI);
    let amp = 0.01;
    let t_end = 2.3;
    let mut rows = Vec::new();
    for dt in [0.02, 0.01, 0.005] {
        let mut init = State::as_built(&m, 0.0);
        init.x[mid][2] += amp;
        let mut s = DynamicSettings::new(dt, t_end);
        s.alpha = 0.0;
        s.tol = 1e-12;
        let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
        solver.run(&mut NoLoads, |_, _| true).unwrap();
        let z = solver.state().x[mid][2];
        let exact = amp * (2.0 * PI * t_end).cos();
        let c = solver.step_control();
        rows.push((
            (z - exact).abs(),
            c.sum_local_error,
            c.relative_time_error(),
        ));
    }
    for w in rows.windows(2) {
        let p_true = (w[0].0 / w[1].0).log2();
        let p_ind = (w[0].1 / w[1].1).log2();
        assert!((p_true - 2.0).abs() < 0.3, "true order {p_true}: {rows:?}");
        assert!(
            (p_ind - 2.0).abs() < 0.3,
            "indicator order {p_ind}: {rows:?}"
        );
    }
    for (err, ind, rel) in &rows {
        let ratio = err / ind;
        assert!((0.2..5.0).contains(&ratio), "true {err} vs indicator {ind}");
        // The largest displacement from the start is the peak-to-peak 2·amp.
        assert!((rel - ind / (2.0 * amp)).abs() < 0.05 * rel, "{rel}");
    }
    eprintln!("(true error, indicator, relative) per dt 0.02, 0.01, 0.005: {rows:?}");
}

/// The peak-tension resolution estimate (docs/theory/fem.md#time-step-error-indicator) on a
/// sampled sine T = m + A·sin(φ·n + φ0): at every phase step φ the estimate is of the order of
/// the worst sampling error of the crest, A·(1 − cos(φ/2)), and it falls like φ².
#[test]
fn peak_tension_resolution_of_a_sampled_sine() {
    let (m, a) = (1000.0, 400.0);
    let mut last = f64::NAN;
    for phi in [0.8, 0.4, 0.2, 0.1, 0.05] {
        let control = StepControl {
            peak_tensions: (0..4000)
                .map(|n| m + a * (phi * n as f64 + 0.3).sin())
                .collect(),
            ..Default::default()
        };
        let r = control.peak_tension_resolution();
        let worst = a * (1.0 - (phi / 2.0).cos()) / (m + a);
        assert!(
            r.error > 0.8 * worst && r.error < 1.5 * worst,
            "φ = {phi}: estimate {:.3e} against the worst crest error {worst:.3e}",
            r.error
        );
        if last.is_finite() {
            let ratio = last / r.error;
            assert!((3.6..=4.4).contains(&ratio), "φ = {phi}: falls by {ratio}");
        }
        last = r.error;
    }
}

/// A snap at the start from a slack state up to a third of the later peak does not count:
/// maxima form in the top quarter of the range.
#[test]
fn a_start_up_snap_below_the_peaks_is_not_a_resolution_error() {
    let mut control = StepControl {
        peak_tensions: std::iter::once(0.0)
            .chain((0..200).map(|n| 0.5 + 0.7 * n as f64 / 200.0))
            .chain((0..2000).map(|n| 1.2 + 0.3 * (0.01 * n as f64).sin()))
            .collect(),
        ..Default::default()
    };
    let r = control.peak_tension_resolution();
    assert!(r.error < 1e-4, "{r:?}");
    // The same snap into the top quarter is counted.
    control.peak_tensions[0] = 0.0;
    control.peak_tensions[1] = 1.5;
    assert!(control.peak_tension_resolution().error > 0.1);
}

/// The estimate names the element that carried the peak at the higher end of its largest step
/// change: a loaded line sways smoothly (element 3) while a slack one (element 7) snaps above it
/// in a single step, whether the snap rises or falls within that step.
#[test]
fn the_resolution_names_the_element_of_the_jump() {
    let smooth: Vec<f64> = (0..400).map(|n| 10.0 + (0.05 * n as f64).sin()).collect();
    let mut tensions = smooth.clone();
    let mut elements = vec![3; smooth.len()];
    tensions[200] = 14.0;
    elements[200] = 7;
    let control = StepControl {
        peak_tensions: tensions,
        peak_elements: elements,
        ..Default::default()
    };
    let r = control.peak_tension_resolution();
    assert_eq!(r.element, Some(7), "{r:?}");
    assert!(r.error > 0.01, "{r:?}");
    // Without the snap the loaded line's own element is named, and the error is small.
    let control = StepControl {
        peak_tensions: smooth,
        peak_elements: vec![3; 400],
        ..Default::default()
    };
    let r = control.peak_tension_resolution();
    assert_eq!(r.element, Some(3));
    assert!(r.error < 1e-3, "{r:?}");
    // Unknown elements (a record without them) name none.
    let control = StepControl {
        peak_tensions: vec![0.0, 1.0, 0.5],
        ..Default::default()
    };
    assert_eq!(control.peak_tension_resolution().element, None);
}

/// A step that lands on an output time, t_out − t, differs from Δt by round-off only; it is
/// taken as Δt, so outputs neither change the trajectory nor force fresh factorisations (each
/// output used to force two: the landing step and the next full one, 81 factorisations in 200
/// steps of the reference cage; docs/theory/fem.md#sparse-linear-algebra).
#[test]
fn output_landings_are_steps_like_any_other() {
    let (m, tip) = swinging_chain();
    let run = |out: Option<f64>| {
        let mut w = WaterLines::new(&m, 0.05, 1.2, [0.0, 0.8, 0.0]);
        let mut s = DynamicSettings::new(0.01, 1.0);
        s.fd_position_jacobian = true;
        s.output_interval = out;
        let mut solver = DynamicSolver::new(&m, s, None, &mut w).unwrap();
        let (mut outputs, mut off_grid) = (0, 0);
        while !solver.is_finished() {
            let r = solver.step(&mut w).unwrap();
            outputs += r.output_time as usize;
            off_grid += (r.dt != 0.01) as usize;
            if r.output_time && out.is_some() {
                // The clock is on the output time exactly.
                let k = (r.t / 0.03).round();
                assert!(
                    r.t == k * 0.03 || r.t == 1.0,
                    "output at {} dt {}",
                    r.t,
                    r.dt
                );
            }
        }
        (
            solver.linear_solver_stats(),
            outputs,
            off_grid,
            solver.state().x[tip],
        )
    };
    let (free, _, _, x_free) = run(None);
    let (landed, outputs, off_grid, x_landed) = run(Some(0.03));
    assert!(outputs >= 33, "{outputs} output steps");
    // 1.0 is no multiple of 0.03: the last step alone is short.
    assert!(off_grid <= 1, "{off_grid} steps other than Δt");
    assert!(
        landed.factorisations <= free.factorisations + 1,
        "{landed:?} with {outputs} output steps against {free:?} without"
    );
    let d = (0..3)
        .map(|k| (x_free[k] - x_landed[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(d < 1e-9, "tip {x_free:?} vs {x_landed:?}");
}

/// Line relaxation (docs/theory/fem.md#line-relaxation) changes the Newton path, not the
/// answer: with and without it the midpoint rule and HHT-α each land on the same states step
/// by step, and the step in which the slack line pulls taut takes a few iterations instead of
/// about one per element. (The uniformly slack line tightens everywhere at once, so HHT-α's
/// front rule does not fire; the stability matrix's chain at Δt = 1 s is the case where it
/// must, docs/theory/fem.md#line-relaxation-hht.)
#[test]
fn line_relaxation_settles_a_tightening_line_within_the_iteration() {
    for midpoint in [true, false] {
        tightening_line_with_and_without_relaxation(midpoint);
    }
}

/// The symmetric factorisation with refinement (docs/theory/fem.md#sparse-linear-algebra) gives
/// the LU's trajectory within Newton's tolerance: a chain swinging through a cross-current, whose drag's position
/// derivative (finite differences) makes the tangent non-symmetric, so the refinement runs.
#[test]
fn symmetric_factorisation_follows_the_lu_in_a_current() {
    let (m, tip) = swinging_chain();
    let run = |kind: LinearSolverKind, tol: f64| {
        let mut w = WaterLines::new(&m, 0.05, 1.2, [0.0, 0.8, 0.0]);
        let mut s = DynamicSettings::new(0.01, 1.0);
        s.linear_solver = kind;
        s.tol = tol;
        // The drag's position derivative (orientation of the normal) is not symmetric.
        s.fd_position_jacobian = true;
        let mut solver = DynamicSolver::new(&m, s, None, &mut w).unwrap();
        solver.run(&mut w, |_, _| true).unwrap();
        let stats = solver.linear_solver_stats();
        (
            solver.state().x[tip],
            solver.n_steps(),
            solver.total_iterations(),
            stats,
        )
    };
    let tol = DynamicSettings::new(0.01, 1.0).tol;
    let (xl, nl, il, _) = run(LinearSolverKind::Lu, tol);
    let (xs, ns, is, st) = run(LinearSolverKind::Symmetric, tol);
    // The same with a Newton tolerance 1000× tighter: how far the answer may move within
    // Newton's own tolerance.
    let (xt, _, _, _) = run(LinearSolverKind::Lu, 1e-3 * tol);
    assert_eq!(st.fallbacks, 0, "the symmetric path solved every system");
    assert!(
        st.refinement_sweeps > 0,
        "the tangent was not symmetric: the refinement ran"
    );
    // An earlier L·D·Lᵀ preconditions later systems: fewer factorisations than iterations,
    // and every system either factorised, reused, or was a convergence check with the last
    // factor.
    assert!(st.factor_reuses > 0, "{st:?}");
    assert!(st.factorisations < is / 2, "{st:?} for {is} iterations");
    assert!(
        st.factorisations + st.factor_reuses + st.stale_checks >= is,
        "{st:?} for {is} iterations"
    );
    assert!(
        xl[1].abs() > 1e-3,
        "the current pushes the chain sideways: {xl:?}"
    );
    let dist = |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    let (d, d_tol) = (dist(xl, xs), dist(xl, xt));
    eprintln!("tip: symmetric − LU {d:.3e} m, LU at tol/1000 − LU {d_tol:.3e} m");
    // The refinement stops at 1 % of the Newton tolerance (inexact Newton): the answer moves
    // by less than Newton's own tolerance moves it, and the Newton iterations are the LU's.
    assert!(
        d < 0.1 * d_tol.max(1e-12),
        "tip {xl:?} (LU) vs {xs:?} (symmetric)"
    );
    assert_eq!(nl, ns, "same steps");
    assert_eq!(il, is, "same Newton iterations");
    // ... and it stops early: 2.0 sweeps per Newton system here against 3.8 when refined
    // to 1e-10 of the right-hand side.
    assert!(
        st.refinement_sweeps * 2 <= 5 * is,
        "{st:?} for {is} iterations"
    );
}
