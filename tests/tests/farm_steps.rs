//! A scaled-down farm (1 × 2 cages of the bundled farm) in its sea with HHT-α: the slack
//! bridles, frame lines and lee anchor chains must not set off a cascade of step halvings
//! (docs/theory/fem.md#energy-consistent-hht-alpha, issue: halving cascades on slack parts).

mod common;
use common::*;

/// The bundled farm (HHT-α, α = 0.3, its default scheme) with one row of two cages, for 10 s.
fn small_farm_hht() -> String {
    let text = example("farm.toml");
    for key in ["rows = 2 ", "columns = 3 ", "t_end = 30.0"] {
        assert!(text.contains(key), "farm.toml has no `{key}`");
    }
    assert!(
        !text.contains("scheme ="),
        "farm.toml no longer runs the default HHT-α"
    );
    text.replace("rows = 2 ", "rows = 1 ")
        .replace("columns = 3 ", "columns = 2 ")
        .replace("t_end = 30.0", "t_end = 10.0")
}

#[test]
fn hht_runs_a_small_farm_without_halving_cascades() {
    let dir = scratch("farm-steps");
    let out = run_text(&dir, "farm", &small_farm_hht());
    let j = run_json(&out);
    let steps = j["steps"].as_f64().unwrap();
    let iterations = j["newton_iterations"].as_f64().unwrap();
    let control = &j["step_control"];
    let halvings = control["halvings"].as_f64().unwrap();
    let energy_rejections: f64 = control["reasons"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r[0] == "the step created energy")
        .map(|r| r[1].as_f64().unwrap())
        .sum();
    // 10 s at the nominal 0.1 s are 100 steps (the output landings add none at 1 s).
    assert!(steps >= 100.0, "{steps} steps");
    assert!(
        energy_rejections <= 0.01 * steps,
        "the energy guard rejected {energy_rejections} of {steps} steps: {control}"
    );
    assert!(
        halvings <= 0.1 * steps,
        "{halvings} halvings in {steps} steps: {control}"
    );
    assert!(
        iterations / steps <= 8.0,
        "{:.2} Newton iterations per step",
        iterations / steps
    );
}
