//! The reference SSM cage (docs/theory/cages.md#worked-ssm-case) in a uniform current, at a coarser
//! element length so the suite stays quick: symmetry, monotone trends with current speed, and
//! agreement between the static equilibrium and a long dynamic run from the as-built state.

mod common;
use common::*;

fn scene(speed: f64, kind: &str, t_end: f64) -> String {
    scene_dt(speed, kind, t_end, 0.2)
}

fn scene_dt(speed: f64, kind: &str, t_end: f64, dt: f64) -> String {
    example("reference-cage.toml")
        .replace("element_length = 2.5", "element_length = 5.0")
        .replace(
            "velocity = [0.5, 0.0, 0.0]",
            &format!("velocity = [{speed}, 0.0, 0.0]"),
        )
        .replace("kind = \"static+dynamic\"", &format!("kind = \"{kind}\""))
        .replace("dt = 0.1", &format!("dt = {dt}"))
        .replace("t_end = 10.0", &format!("t_end = {t_end}"))
        .replace("output_interval = 0.5", "output_interval = 10.0")
}

#[test]
fn symmetric_loads_and_monotone_trends() {
    let dir = scratch("refcage");
    let slow = &summary(&run_text(&dir, "slow", &scene(0.25, "static", 1.0)))[0];
    let fast = &summary(&run_text(&dir, "fast", &scene(0.5, "static", 1.0)))[0];
    for row in [slow, fast] {
        // The cage is symmetric about the x–z plane and the current runs along x.
        let fx = row["Fx_net"];
        assert!(fx > 0.0);
        assert!(
            row["Fy_net"].abs() < 1e-6 * fx,
            "lateral force {}",
            row["Fy_net"]
        );
        assert!(
            row["Ry"].abs() < 1e-6 * fx,
            "lateral reaction {}",
            row["Ry"]
        );
        // Yaw moment of the supports about the cage axis vanishes; roll too.
        assert!(
            row["Mz"].abs() < 1e-6 * fx * 15.0,
            "yaw moment {}",
            row["Mz"]
        );
        assert!(
            row["Mx"].abs() < 1e-6 * fx * 15.0,
            "roll moment {}",
            row["Mx"]
        );
        // The supports hold the whole structure against the current.
        assert!(row["Rx"] < -fx);
        assert!(row["volume_ratio"] > 0.0 && row["volume_ratio"] < 1.0);
    }
    assert!(
        fast["Fx_net"] > 2.0 * slow["Fx_net"],
        "drag grows faster than U"
    );
    assert!(
        fast["Fx_net"] < 4.0 * slow["Fx_net"],
        "the net deforms: slower than U²"
    );
    assert!(fast["volume_ratio"] < slow["volume_ratio"]);
}

#[test]
fn dynamic_run_from_rest_settles_on_the_static_equilibrium() {
    let dir = scratch("refcage-dyn");
    let stat = &summary(&run_text(&dir, "static", &scene(0.5, "static", 1.0)))[0];
    // The net creeps into place with a time constant of ~20 s (drag-dominated): 200 s at a
    // long implicit step reaches the steady state.
    let rows = summary(&run_text(
        &dir,
        "dynamic",
        &scene_dt(0.5, "dynamic", 200.0, 0.5),
    ));
    let last = rows.last().unwrap();
    assert!((last["t"] - 200.0).abs() < 1e-9);
    for key in ["Fx_net", "Rx", "Rz", "volume_ratio"] {
        let rel = (last[key] - stat[key]).abs() / stat[key].abs();
        assert!(
            rel < 0.01,
            "{key}: dynamic {} vs static {}",
            last[key],
            stat[key]
        );
    }
}

/// `static_newton_iterations` and `static_residual_history` of a run.
fn static_history(out: &std::path::Path) -> (u64, Vec<f64>) {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    let hist = json["static_residual_history"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    (json["static_newton_iterations"].as_u64().unwrap(), hist)
}

#[test]
fn static_solve_of_the_cage_is_newton_not_relaxation() {
    // docs/theory/fem.md#static-solver: 67 iterations at 10 m elements and 79 at 5 m (at 10 m
    // the pseudo-transient solver it replaced needed 138, the first one 813). Bounds with
    // margin, so a regression to a relaxation fails.
    let dir = scratch("refcage-newton");
    for (el, bound) in [(10.0, 100), (5.0, 120)] {
        let text = scene(0.5, "static", 1.0)
            .replace("element_length = 5.0", &format!("element_length = {el}"));
        let (iters, h) = static_history(&run_text(&dir, &format!("el{el}"), &text));
        assert!(iters <= bound, "{el} m elements: {iters} iterations");
        // Newton's quadratic convergence at the end: some iterate below 1e-2·F_ref whose
        // successor has at least 1.6 times as many correct digits.
        let quadratic = h
            .windows(2)
            .any(|w| w[0] < 1e-2 && w[1] > 1e-13 && w[1].ln() / w[0].ln() >= 1.6);
        assert!(quadratic, "{el} m elements: no quadratic step in {h:?}");
        assert!(*h.last().unwrap() <= 1e-6, "{h:?}");
    }
}
