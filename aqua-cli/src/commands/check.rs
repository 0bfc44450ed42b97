//! `aqua check scene.toml`: validates a scene (the validation of `aqua run`) and prints what a
//! run will compute — counts per group, λ and diameters, which physics are active and which
//! are skipped, and a cost estimate ([`aqua_sim::check`]).

use std::path::PathBuf;

/// Flags of `aqua check`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Change a scene key: PATH=VALUE (as `aqua run --set`; repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<aqua_sim::Override>,
}

/// Run `aqua check`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let prep = aqua_sim::prepare(aqua_sim::PrepareOptions::file(&a.scene).with_overrides(&a.set))?;
    let report = aqua_sim::check::report(&prep)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    println!("scene {} ({}): valid", report.scene, a.scene.display());
    // The mesh notices are printed once, with the other diagnostics at the end.
    crate::commands::mesh::report_with(&prep.built.mesh, None, false, false)?;
    // `[[point]]` bodies are not builder weights: their totals on their own line.
    for (i, p) in prep.scene.point.iter().enumerate() {
        let v = &p.value;
        let n = aqua_sim::resolve_ref(&prep.built.mesh, &v.nodes).map_or(0, |n| n.len());
        let k = n as f64;
        let g = prep.built.sea.constants().gravity;
        println!(
            "[[point]] #{} on {} ({n} node{}): mass {:.1} kg (weight {:.1} N), force [{:.1}, {:.1}, \
             {:.1}] N, volume {:.4} m³",
            i + 1,
            v.nodes,
            if n == 1 { "" } else { "s" },
            k * v.mass,
            k * v.mass * g,
            k * v.force[0],
            k * v.force[1],
            k * v.force[2],
            k * v.volume
        );
    }
    for f in &report.farms {
        let c = &f.counts;
        println!(
            "[[farm]] {}: {}, {} with {}, {}, {}, {}; cage-to-cage wake {}",
            f.name,
            counted(c.cages, "cage"),
            counted(c.plates, "plate"),
            counted(c.buoys, "buoy"),
            counted(c.frame_elements, "frame-line element"),
            counted(c.bridles, "bridle"),
            counted(c.anchor_lines, "anchor line"),
            if f.cage_wake { "on" } else { "off" }
        );
    }
    println!("physics:");
    for p in &report.physics {
        println!(
            "  [{}] {:<38} {}",
            if p.active { "x" } else { " " },
            p.name,
            p.why
        );
    }
    let c = &report.cost;
    println!(
        "cost: {} free DOFs, {} cable elements, {} load elements, {} wave components; {} dynamic steps, {} output steps ({} in the ParaView series); estimated {:.1} s (statics {:.1} s, dynamics {:.1} s)",
        c.dofs,
        c.cable_elements,
        c.load_elements,
        c.wave_components,
        c.steps,
        c.output_steps,
        c.paraview_steps,
        c.estimated_seconds,
        c.estimated_static_seconds,
        c.estimated_dynamic_seconds
    );
    for w in &report.warnings {
        println!("{w}");
    }
    Ok(())
}

/// "1 cage", "2 cages".
fn counted(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}
