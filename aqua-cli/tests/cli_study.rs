//! `aqua study` end to end: the Richardson estimate and observed order on ladders whose
//! converged value is known in closed form (docs/theory/fem.md#test-oracles), failed runs as
//! rows, and bad input as exit 2.

mod common;

use common::{aqua, scratch};
use serde_json::Value;
use std::path::{Path, PathBuf};

const G: f64 = 9.80665;

fn study_json(out: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("study.json")).unwrap()).unwrap()
}

fn estimate<'a>(study: &'a Value, metric: &str) -> &'a Value {
    study["estimates"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["metric"] == metric)
        .unwrap_or_else(|| panic!("no estimate of {metric}: {study}"))
}

/// Level elastic catenary (Irvine): horizontal tension H from
/// l = H·L0/EA + (2H/w)·asinh(w·L0/(2H)), by bisection; end tension √(H² + (w·L0/2)²).
fn level_catenary_end_tension(l: f64, l0: f64, w: f64, ea: f64) -> f64 {
    let span = |h: f64| h * l0 / ea + 2.0 * h / w * (w * l0 / (2.0 * h)).asinh() - l;
    let (mut lo, mut hi) = (1e-3, 1e7);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if span(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let h = 0.5 * (lo + hi);
    (h * h + (0.5 * w * l0).powi(2)).sqrt()
}

#[test]
fn segment_ladder_on_the_elastic_catenary_extrapolates_to_the_closed_form() {
    let d = scratch("study", "catenary");
    let (l, l0, w, ea) = (100.0, 105.0, 10.0, 1.0e5);
    let scene = d.join("catenary.toml");
    std::fs::write(
        &scene,
        format!(
            "[sea]\ndepth = 50.0\n[[line]]\nname = \"rope\"\nanchor = [0.0, 0.0, 20.0]\n\
             fairlead = [{l}, 0.0, 20.0]\nlength = {l0}\nsegments = 10\ndiameter = 0.01\n\
             mass_per_length = {}\nea = {ea}\nfixed = [\"anchor\", \"fairlead\"]\n\
             [analysis]\nkind = \"static\"\n",
            w / G
        ),
    )
    .unwrap();
    let out = d.join("out");
    let o = aqua(&[
        "study",
        scene.to_str().unwrap(),
        "--vary",
        "line.0.segments=20,40,80",
        "--metric",
        "rope_fairlead_reaction",
        "--set",
        "analysis.static.tol=1e-12",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = study_json(&out);
    let e = estimate(&s, "rope_fairlead_reaction");
    let exact = level_catenary_end_tension(l, l0, w, ea);
    // The spec's worked value, to be sure the oracle itself is right.
    assert!((exact - 988.8783747).abs() < 1e-6, "{exact}");
    let est = e["value"].as_f64().unwrap();
    assert!(
        ((est - exact) / exact).abs() < 1e-6,
        "estimate {est} vs closed form {exact}"
    );
    let p = e["orders"][0].as_f64().unwrap();
    assert!((p - 2.0).abs() < 0.1, "observed order {p}");
    assert_eq!(e["method"], "richardson");
    // The extrapolation must beat the finest run, which is O(1/N²) off.
    let finest = e["finest"].as_f64().unwrap();
    assert!((est - exact).abs() < 0.01 * (finest - exact).abs());
    // Errors shrink down the ladder by about 4 (order 2, ratio 2).
    let errs: Vec<f64> = s["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["errors"][0].as_f64().unwrap())
        .collect();
    assert!(
        (errs[0] / errs[1] - 4.0).abs() < 0.2 && (errs[1] / errs[2] - 4.0).abs() < 0.2,
        "{errs:?}"
    );
    for f in ["study.csv", "estimates.csv", "error_vs_cost.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }
}

/// A point mass between two pre-stretched vertical cables, released from the as-built
/// (unloaded) position in air: a linear oscillator (docs/theory/fem.md#test-oracles).
fn oscillator(d: &Path) -> (PathBuf, f64) {
    let (l0, ea, mu, m): (f64, f64, f64, f64) = (19.0, 1.0e6, 0.01, 5332.0);
    let scene = d.join("oscillator.toml");
    std::fs::write(
        &scene,
        format!(
            "[sea]\ndepth = 50.0\n[[line]]\nname = \"osc\"\nanchor = [0.0, 0.0, 10.0]\n\
             fairlead = [0.0, 0.0, 30.0]\nlength = {l0}\nsegments = 2\nshape = \"straight\"\n\
             fixed = [\"anchor\", \"fairlead\"]\ndiameter = 0.01\nmass_per_length = {mu}\n\
             ea = {ea}\n[[point]]\nnodes = \"osc/line_nodes[1]\"\nmass = {m}\n\
             [analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\nalpha = 0.0\ndt = 0.01\n\
             t_end = 2.3\noutput_interval = 0.1\n"
        ),
    )
    .unwrap();
    // Exact: the middle node (mass m + μ·L0/2, stiffness 2·EA/(L0/2)) starts m_mid·g/k above
    // its equilibrium at rest; the supports carry the weight of everything plus the inertia
    // of the middle node: Rz = g·(m + μ·L0) − m_mid·g·cos(ω t).
    let m_mid = m + mu * l0 / 2.0;
    let omega = (4.0 * ea / l0 / m_mid).sqrt();
    let t = 2.3;
    (scene, G * (m + mu * l0) - m_mid * G * (omega * t).cos())
}

#[test]
fn time_step_ladder_observes_second_order_for_hht_alpha_0() {
    let d = scratch("study", "oscillator");
    let (scene, exact) = oscillator(&d);
    let out = d.join("out");
    let o = aqua(&[
        "study",
        scene.to_str().unwrap(),
        "--vary",
        "dt=0.02,0.01,0.005",
        "--metric",
        "final:Rz",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = study_json(&out);
    let e = estimate(&s, "final:Rz");
    let p = e["orders"][0].as_f64().unwrap();
    assert!((p - 2.0).abs() < 0.1, "observed order {p}");
    let est = e["value"].as_f64().unwrap();
    let finest = e["finest"].as_f64().unwrap();
    assert!(
        (est - exact).abs() < 0.05 * (finest - exact).abs(),
        "estimate {est}, finest {finest}, exact {exact}"
    );
    assert!(((est - exact) / exact).abs() < 1e-5, "{est} vs {exact}");
}

#[test]
fn failed_runs_are_rows_and_the_recommendation_meets_the_tolerance() {
    let d = scratch("study", "failed");
    let (scene, _) = oscillator(&d);
    let out = d.join("out");
    // dt = 5 s is longer than t_end: that run fails in validation, the others run.
    let o = aqua(&[
        "study",
        scene.to_str().unwrap(),
        "--vary",
        "dt=5,0.02,0.01,0.005",
        "--metric",
        "final:Rz",
        "--tolerance",
        "0.001",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("recommended: run"), "{stdout}");
    let s = study_json(&out);
    let runs = s["runs"].as_array().unwrap();
    assert_eq!(runs[0]["status"], "failed");
    assert!(
        runs[0]["reason"]
            .as_str()
            .unwrap()
            .contains("analysis.dynamic.dt")
    );
    let rec = s["recommended"].as_u64().unwrap() as usize;
    assert!(runs[rec]["errors"][0].as_f64().unwrap() <= 0.001);
    // Cheapest among those within the tolerance.
    for r in runs.iter().filter(|r| r["status"] == "completed") {
        if r["errors"][0].as_f64().unwrap() <= 0.001 {
            assert!(r["wall_s"].as_f64() >= runs[rec]["wall_s"].as_f64());
        }
    }
    let csv = std::fs::read_to_string(out.join("study.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5, "{csv}");
}

#[test]
fn bad_ladders_and_paths_exit_2_naming_them() {
    let d = scratch("study", "bad");
    let (scene, _) = oscillator(&d);
    let scene = scene.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--vary", "analysis.dynamic.dtt=0.1,0.05"], "dtt"),
        (&["--vary", "line.0.segments=a,b"], "line.0.segments=a"),
        (&["--vary", "dt="], "empty"),
        (&["--vary", "dt=0.1"], "one value"),
        (&["--vary", "line.4.segments=2,4"], "no entry 4"),
        (&["--vary", "dt=0.1,0.05", "--metric", "top:Rz"], "absmax"),
        (
            &["--vary", "dt=0.1,0.05", "--tolerance", "0"],
            "--tolerance",
        ),
    ];
    for (args, needle) in cases {
        let mut all = vec!["study", scene, "--out", d.to_str().unwrap()];
        all.extend_from_slice(args);
        let o = aqua(&all);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn run_set_overrides_are_applied_and_recorded() {
    let d = scratch("study", "set");
    let (scene, _) = oscillator(&d);
    let out = d.join("run");
    let o = aqua(&[
        "run",
        scene.to_str().unwrap(),
        "--quiet",
        "--set",
        "analysis.dynamic.t_end=0.5",
        "--set",
        "point.0.mass=100",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let run: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(
        run["overrides"],
        serde_json::json!(["analysis.dynamic.t_end=0.5", "point.0.mass=100"])
    );
    assert_eq!(run["resolved"]["t_end"], 0.5);
    assert_eq!(run["scene"]["point"][0]["mass"], 100.0);
    // An unknown key is the file's own error, prefixed with the override, and the file's line.
    let o = aqua(&["check", scene.to_str().unwrap(), "--set", "point.0.mas=1"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--set point.0.mas=1")
            && err.contains("unknown field `mas`")
            && err.contains("line 14"),
        "{err}"
    );
}
