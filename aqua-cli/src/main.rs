//! The `aqua` binary: parses the command line and dispatches to [`aqua_cli::commands`].

use aqua_cli::commands;
use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// aqua — fast simulation of aquaculture nets, ropes and moorings in current and waves.
#[derive(Parser, Debug)]
#[command(name = "aqua", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
// Parsed once per process: the size of the flag structs does not matter.
#[allow(clippy::large_enum_variant)]
enum Command {
    /// Preview a sea state: summary, CSV time series of elevation and kinematics.
    Waves(commands::waves::Args),
    /// Build a cage, panel or line or import a gmsh mesh; report groups, λ, diameters; write VTK.
    Mesh(commands::mesh::Args),
    /// Validate a scene and print what a run will compute and what it will cost.
    Check(commands::check::Args),
    /// Run a scene: statics and/or dynamics, ParaView series, summary.csv, run.json.
    Run(commands::run::Args),
    /// Run a scene over ladders of settings; estimate converged values, errors and the
    /// cheapest setting within a tolerance.
    Study(commands::study::Args),
    /// Run the load cases of a case file here (--local), or emit them for GNU parallel or a
    /// Slurm array.
    Sweep(commands::sweep::Args),
    /// Merge the run folders under a directory into one table; print the governing cases.
    Collect(commands::collect::Args),
    /// Draw PNG pictures of a run folder (time series, static convergence).
    Plot(commands::plot::Args),
    /// Compare screen (θ, Cd, Cl) and Morison (Re, Cn, Ct) coefficient models.
    Coeffs(commands::coeffs::Args),
}

/// A reader that closed the pipe (`aqua check scene.toml | head`) is not an error of ours:
/// `print!` panics on EPIPE, so such a panic ends the process quietly with status 0.
fn quiet_on_broken_pipe() {
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let msg = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if msg.contains("Broken pipe") {
            std::process::exit(0);
        }
        default_hook(info);
    }));
}

/// A thread that turns SIGINT, SIGTERM and SIGHUP into a stop request.
fn stop_on_signals() -> std::io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::Builder::new()
        .name("aqua-signals".into())
        .spawn(move || {
            for signal in signals.forever() {
                aqua_cli::request_stop(signal);
            }
        })?;
    Ok(())
}

fn main() -> ExitCode {
    quiet_on_broken_pipe();
    let cli = Cli::parse();
    // Ctrl-C (SIGINT), SIGTERM (what `kill` and Slurm's time limit send) and SIGHUP ask the
    // run to stop after the current step; its outputs stay consistent and run.json says
    // `interrupted`.
    if let Err(e) = stop_on_signals() {
        eprintln!(
            "warning: cannot install the signal handler ({e}); an interrupted run may leave a \
             partial step"
        );
    }
    let result = match cli.command {
        Command::Waves(a) => commands::waves::run(a),
        Command::Mesh(a) => commands::mesh::run(a),
        Command::Check(a) => commands::check::run(a),
        Command::Run(a) => commands::run::run(a),
        Command::Coeffs(a) => commands::coeffs::run(a),
        Command::Study(a) => commands::study::run(a),
        Command::Plot(a) => commands::plot::run(a),
        Command::Sweep(a) => commands::sweep::run(a),
        Command::Collect(a) => commands::collect::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            if aqua_cli::is_input_error(&err) {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}
