//! `aqua run` stopped early, through the binary: a failed or interrupted run (Ctrl-C, SIGTERM, in
//! statics or dynamics) leaves a consistent `.pvd` and says why in `run.json`.

mod run_helpers;

use run_helpers::*;

#[test]
fn interrupted_run_leaves_a_consistent_pvd() {
    interrupt_dynamics("INT", 130);
}

#[test]
fn sigterm_in_dynamics_is_an_interruption_with_every_file_written() {
    interrupt_dynamics("TERM", 143);
}

#[test]
fn failed_run_keeps_the_steps_written_and_says_why() {
    let dir = scratch("fail");
    // The fairlead is dragged 300 m away in 2 s: the chain would have to stretch far beyond
    // max_strain, so every step is rejected down to dt_min and the run stops.
    let scene = chain_scene(&dir, 20.0, "");
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace(
            "motion = \"sine\"\namplitude = [1.5, 0.0, 0.0]\nperiod = 10.0\nramp_time = 10.0",
            "motion = \"ramp\"\noffset = [300.0, 0.0, 0.0]\nramp_time = 2.0",
        )
        .replace(
            "[analysis.dynamic]",
            "[analysis.dynamic]\nmax_strain = 0.05\ndt_min = 0.01",
        );
    assert!(text.contains("offset = [300.0"));
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let (code, _, err) = aqua(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    if code == 2 {
        panic!("scene rejected instead of failing in the solver: {err}");
    }
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("kept in"), "{err}");
    let entries = assert_consistent(&out.join("mooring-chain.pvd"));
    assert!(!entries.is_empty(), "the static state at least is written");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "failed");
    assert!(json["error"].as_str().unwrap().len() > 10);
}

#[test]
fn interrupt_during_statics_keeps_the_best_state_as_step_0() {
    interrupt_statics("INT", 130);
}

#[test]
fn sigterm_during_statics_keeps_the_best_state_as_step_0() {
    interrupt_statics("TERM", 143);
}
