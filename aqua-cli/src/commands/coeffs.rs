//! `aqua coeffs`: tables of screen-model drag/lift coefficients against the inflow angle and of
//! Morison normal/tangential coefficients against the Reynolds number, to compare and choose
//! models (docs/theory/hydrodynamics.md#screen-models, #morison-coefficients).

use crate::InputError;
use aqua_hydro::ScreenModelId;
use aqua_hydro::coefficient_grid::{parse_angles, parse_reynolds};
use aqua_hydro::coefficient_report::{
    CoefficientQuery, CoefficientReport, morison_report, screen_report, select_models,
};

/// Flags of `aqua coeffs`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Model id: a screen model (S1 S2 S3 S4 S5 S6 bi2014 const), a Morison model (M1 M2 M3 M4
    /// M5), or "all" for every model side by side.
    #[arg(long, default_value = "all")]
    pub model: String,
    /// Net solidity Sn, 0 < Sn < 1 (screen models and M5).
    #[arg(long, default_value_t = 0.2)]
    pub solidity: f64,
    /// Inflow angles θ in degrees (0 = flow normal to the net): start:stop:step, or a
    /// comma-separated list.
    #[arg(long, default_value = "0:90:15")]
    pub angles: String,
    /// Physical twine diameter dw0 [m] for the Reynolds number of S3, S4, S6.
    #[arg(long, default_value_t = 0.0024)]
    pub twine_diameter: f64,
    /// Relative flow speed U [m/s] for the Reynolds number of S3, S4, S6.
    #[arg(long, default_value_t = 0.5)]
    pub speed: f64,
    /// Kinematic viscosity ν [m²/s].
    #[arg(long, default_value_t = aqua_env::constants::SEA_WATER_VISCOSITY)]
    pub viscosity: f64,
    /// Fixed cylinder drag coefficient for S3/S6 instead of C_cyl(Re).
    #[arg(long)]
    pub cyl_cd: Option<f64>,
    /// Drag coefficient of the screen model "const" (>= 0).
    #[arg(long)]
    pub cd: Option<f64>,
    /// Lift coefficient of the screen model "const".
    #[arg(long)]
    pub cl: Option<f64>,
    /// Reynolds numbers for the Morison tables: comma-separated list, or lo:hi:n for n
    /// log-spaced values.
    #[arg(long, default_value = "0.5,1,10,100,1000,1e4,1e5,2.33e5,5e5,1e6,1e7")]
    pub reynolds: String,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
}

/// Everything `aqua coeffs` prints.
pub type Report = CoefficientReport;

fn input(msg: String) -> anyhow::Error {
    InputError::new(msg).into()
}

/// Computes the report for the given flags.
pub fn compute(args: &Args) -> anyhow::Result<Report> {
    if !(args.solidity > 0.0 && args.solidity < 1.0) {
        return Err(input(format!(
            "--solidity = {}: solidity must satisfy 0 < Sn < 1 (typical nets 0.1-0.35)",
            args.solidity
        )));
    }
    for (flag, v) in [
        ("--twine-diameter", args.twine_diameter),
        ("--speed", args.speed),
        ("--viscosity", args.viscosity),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(input(format!("{flag} = {v}: must be a finite number > 0")));
        }
    }
    let (screens, morisons) = select_models(&args.model, args.cd.is_some()).ok_or_else(|| {
        input(format!(
            "--model = \"{}\": unknown model; valid: all, screen models {}, Morison models M1, M2, M3, M4, M5",
            args.model,
            ScreenModelId::VALID
        ))
    })?;
    let table_error = |e| input(format!("--model {e}"));
    let mut q = CoefficientQuery {
        screens,
        morisons,
        solidity: args.solidity,
        twine_diameter: args.twine_diameter,
        speed: args.speed,
        viscosity: args.viscosity,
        cyl_cd: args.cyl_cd,
        cd_cl: (args.cd, args.cl),
        angles_deg: Vec::new(),
        reynolds: Vec::new(),
    };
    if !q.screens.is_empty() {
        q.angles_deg = parse_angles("--angles", &args.angles).map_err(|e| input(e.0))?;
    }
    let screen = screen_report(&q).map_err(table_error)?;
    if !q.morisons.is_empty() {
        q.reynolds = parse_reynolds("--reynolds", &args.reynolds).map_err(|e| input(e.0))?;
    }
    let morison = morison_report(&q).map_err(table_error)?;
    Ok(Report { screen, morison })
}

/// Run `aqua coeffs`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let report = compute(&args)?;
    let text = if args.json {
        serde_json::to_string_pretty(&report)? + "\n"
    } else {
        report.to_text()
    };
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        // `aqua coeffs | head` closes the pipe early: not an error
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}
