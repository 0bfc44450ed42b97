//! Shared helpers of the end-to-end tests: run a scene through `aqua run` (the library entry
//! point of the binary) and read its outputs back.

#![allow(dead_code)]

use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The repository root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A fresh scratch directory for one test.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("aqua-e2e-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `text` as a scene file in `dir` and runs it; returns the output directory.
pub fn run_text(dir: &Path, name: &str, text: &str) -> PathBuf {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).unwrap();
    run_file(&scene, &dir.join(format!("{name}-out")))
}

/// Runs a scene file into `out`.
pub fn run_file(scene: &Path, out: &Path) -> PathBuf {
    aqua_cli::commands::run::run_scene(scene, &[], out, true)
        .unwrap_or_else(|e| panic!("run of {} failed: {e:#}", scene.display()));
    out.to_path_buf()
}

/// summary.csv as rows of column → value.
/// `run.json` of a run's output folder.
pub fn run_json(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap()
}

pub fn summary(out: &Path) -> Vec<HashMap<String, f64>> {
    let text = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(|v| v.parse::<f64>().unwrap()))
                .collect()
        })
        .collect()
}

/// The example scene text.
pub fn example(name: &str) -> String {
    std::fs::read_to_string(root().join("examples").join(name)).unwrap()
}

/// The example's chain with the default scheme (HHT-α) at dt 0.1 s instead of its midpoint
/// rule at 0.025 s.
pub fn example_chain_hht() -> String {
    let text = example("mooring-chain.toml");
    let own = "scheme = \"midpoint\"\ndt = 0.025\n";
    assert!(
        text.contains(own),
        "the chain example's scheme or step moved"
    );
    text.replace(own, "dt = 0.1\n")
}

/// The stability matrix's chain: examples/mooring-chain.toml at 40 segments, 30 s, samples
/// every second, with the default scheme (HHT-α).
pub fn matrix_chain() -> String {
    example_chain_hht()
        .replace("segments = 80", "segments = 40")
        .replace("t_end = 60.0", "t_end = 30.0")
        .replace("output_interval = 0.5", "output_interval = 1.0")
}

/// Runs [`matrix_chain`] in `dir` with the scene changes `set` (and a ParaView step every
/// 30 s) and returns its run.json.
pub fn run_matrix_chain(dir: &Path, name: &str, set: &[&str]) -> serde_json::Value {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, matrix_chain()).unwrap();
    let out = dir.join(format!("{name}-out"));
    let mut set: Vec<_> = set
        .iter()
        .map(|s| s.parse::<aqua_sim::Override>().unwrap())
        .collect();
    set.push("analysis.dynamic.paraview_interval=30".parse().unwrap());
    aqua_cli::commands::run::run_scene(&scene, &set, &out, true).unwrap();
    run_json(&out)
}

/// Reads and builds the scene file at `path` and solves its statics to the end; returns the
/// prepared scene, its water loads (at the equilibrium) and the static solution.
pub fn static_solve(
    path: &Path,
) -> (
    aqua_sim::Prepared,
    aqua_sim::provider::WaterLoads,
    aqua_fem::StaticSolution,
) {
    let scene = aqua_sim::read_scene(aqua_sim::SceneInput::File(path), &[])
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let prep = aqua_sim::prepare(aqua_sim::PrepareOptions::scene(scene))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (mut loads, _) = aqua_sim::run::water_loads(&prep, aqua_env::Phase::Static).unwrap();
    let sol = aqua_sim::static_equilibrium(
        &prep.built.model,
        &prep.built.mesh,
        &mut loads,
        &prep.plan.statics,
        &mut |_| aqua_fem::StaticControl::Continue,
    )
    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    (prep, loads, sol)
}
