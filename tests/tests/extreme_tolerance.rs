//! `analysis.dynamic.extreme_tolerance` from a scene to the solver and back into run.json
//! (docs/theory/fem.md#extremes-to-a-tolerance), and its validation.

mod common;
use common::*;

/// The bundled mooring chain with the default scheme for `t_end` seconds with extra
/// `[analysis.dynamic]` keys.
fn chain(t_end: f64, keys: &str) -> String {
    let text = example_chain_hht();
    assert!(text.contains("t_end = 60.0"));
    text.replace("t_end = 60.0", &format!("t_end = {t_end}\n{keys}"))
}

#[test]
fn the_tolerance_reaches_the_solver_and_run_json() {
    let dir = scratch("extreme-tolerance");
    let out = run_text(&dir, "chain", &chain(3.0, "extreme_tolerance = 0.01"));
    let j = run_json(&out);
    let ext = &j["step_control"]["extremes"];
    assert_eq!(ext["tolerance"].as_f64(), Some(0.01), "{j}");
    assert!(ext["rejections"].as_u64().is_some(), "{ext}");
    // Without the key nothing is controlled or reported.
    let out = run_text(&dir, "plain", &chain(3.0, ""));
    assert!(run_json(&out)["step_control"].get("extremes").is_none());
}

#[test]
fn bad_tolerances_name_the_key() {
    let dir = scratch("extreme-tolerance-bad");
    for (keys, why) in [
        ("extreme_tolerance = 0.7", "0 < extreme_tolerance < 0.5"),
        ("extreme_tolerance = 0.0", "0 < extreme_tolerance < 0.5"),
        (
            "extreme_tolerance = 0.01\nscheme = \"rk4\"",
            "only with scheme",
        ),
    ] {
        let scene = dir.join("bad.toml");
        std::fs::write(&scene, chain(1.0, keys)).unwrap();
        let e = aqua_cli::commands::run::run_scene(&scene, &[], &dir.join("bad-out"), true)
            .expect_err(keys);
        let msg = format!("{e:#}");
        assert!(
            msg.contains("analysis.dynamic.extreme_tolerance") && msg.contains(why),
            "{keys}: {msg}"
        );
    }
}
