//! The schema of `run.json`: the scene with its defaults, the resolved numbers, how the run
//! ended, its final values and extremes, the names of the output blocks and its timing.

use crate::error::Result;
use crate::files::RunFiles;
use crate::plan::Prepared;
use crate::run::RunRecord;

/// `run.json` of a run of `prep` that wrote `files` and printed `diagnostics`.
pub(crate) fn run_json(
    prep: &Prepared,
    record: &RunRecord,
    result: &Result<()>,
    files: &RunFiles,
    diagnostics: &[String],
) -> serde_json::Value {
    let built = &prep.built;
    let plan = &prep.plan;
    let mut json = serde_json::json!({
        "scene": &prep.scene,
        "overrides": &prep.scene.overrides,
        "resolved": {
            "mesh": built.mesh.summary(),
            "sea": &built.sea_summary,
            "scheme": &prep.scene.analysis.dynamic.scheme,
            "alpha": plan.alpha,
            "dt": plan.dt,
            "output_interval": plan.output_interval,
            "paraview_interval": plan.paraview_interval(),
            "t_end": plan.t_end,
            "structural_groups": &built.group_names,
        },
        "status": record.ending.as_str(),
        "error": result.as_ref().err().map(|e| e.chain()),
        "final": record.last,
        "extremes": record.extremes.as_ref().map(|e| e.to_json()),
        "output_steps": files.steps_written(),
        "paraview_steps": files.paraview_steps_written(),
        "pvd": files.pvd_path(),
        "paraview_script": files.dir().join("open_in_paraview.py"),
        "names": files.names(),
        "wall_time_s": record.wall,
        "dynamic_wall_time_s": record.dyn_wall,
        "steps": record.steps,
        "newton_iterations": record.iterations,
        "static_newton_iterations": record.static_iterations,
        "static_sequence_iterations": record.static_sequence_iterations,
        "static_residual_history": &record.static_residuals,
        "static_load_factor": record.static_load_factor,
        "static_converged": record.static_converged,
        "static_relative_residual": record.static_relative_residual,
        "static_block_solve": record.static_block_solve.map(|(parts, interface)| {
            serde_json::json!({"parts": parts, "interface_dofs": interface})
        }),
        "step_control": &record.step_control,
        "energies": &record.energies,
        "linear_solver": &record.linear_solver,
        "peak_tension_resolution": record.step_control.as_ref().map(|c| c.peak_tension_resolution()),
        "time_per_step_s": if record.steps > 0 { record.dyn_wall / record.steps as f64 } else { 0.0 },
    });
    json["diagnostics"] = serde_json::json!(diagnostics);
    json
}
