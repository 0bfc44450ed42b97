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
    print!("{}", report.to_text(&a.scene));
    Ok(())
}
