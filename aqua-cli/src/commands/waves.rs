//! `aqua waves`: preview a sea state before simulating it.
//!
//! Prints the sea-state summary (each regular wave's T, ω, k, L, c; for an irregular sea Hs, Tp,
//! γ, components, and Hs and Tp measured back from a generated record), optionally writes CSV
//! time series `t,x,y,z,eta,u,v,w,ax,ay,az` at given points and the component table.

use crate::InputError;
use aqua_env::config::{CurrentKind, WaveKind};
use aqua_env::record::{MeasuredSea, measure_record};
use aqua_env::sea_params::{SeaParams, from_name};
use aqua_env::{BuildOptions, SeaSpec, SeaSummary};
use aqua_sim::scene;
use serde::Serialize;
use std::path::PathBuf;

/// Flags of `aqua waves`. Flags override the scene's `[sea]` values.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Scene (or sea) TOML file whose `[sea]` table describes the sea.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Wave kind: none, airy, stokes2, irregular.
    #[arg(long, value_parser = ["none", "airy", "stokes2", "irregular"])]
    pub kind: Option<String>,
    /// Water depth h [m], or "infinite".
    #[arg(long)]
    pub depth: Option<String>,
    /// Regular wave height H [m] (crest to trough).
    #[arg(long)]
    pub height: Option<f64>,
    /// Regular wave period T [s].
    #[arg(long)]
    pub period: Option<f64>,
    /// Travel direction [deg] from +x towards +y (regular waves; mean direction of irregular).
    #[arg(long)]
    pub direction: Option<f64>,
    /// Significant wave height Hs [m] (irregular).
    #[arg(long)]
    pub hs: Option<f64>,
    /// Peak period Tp [s] (irregular).
    #[arg(long)]
    pub tp: Option<f64>,
    /// Spectrum shape: jonswap or pm.
    #[arg(long, value_parser = ["jonswap", "pm"])]
    pub spectrum: Option<String>,
    /// JONSWAP peak enhancement γ (>= 1) or "auto".
    #[arg(long)]
    pub gamma: Option<String>,
    /// Number of irregular components.
    #[arg(long)]
    pub components: Option<usize>,
    /// Seed of the random phases.
    #[arg(long)]
    pub seed: Option<u64>,
    /// cos-2s spreading exponent (short-crested sea).
    #[arg(long)]
    pub spreading: Option<f64>,
    /// Stretching: none, vertical, wheeler.
    #[arg(long, value_parser = ["none", "vertical", "wheeler"])]
    pub stretching: Option<String>,
    /// Uniform current velocity "ux,uy,uz" [m/s].
    #[arg(long, value_delimiter = ',', num_args = 3, allow_hyphen_values = true)]
    pub current: Option<Vec<f64>>,
    /// Gravity g [m/s²].
    #[arg(long)]
    pub gravity: Option<f64>,
    /// Wave ramp duration [s] (0: none).
    #[arg(long)]
    pub ramp_time: Option<f64>,
    /// A point "x,y,z" [m] for the CSV series (repeat for several points).
    #[arg(long = "at", value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub at: Vec<String>,
    /// Duration of the CSV series [s].
    #[arg(long, default_value_t = 100.0)]
    pub duration: f64,
    /// Time step of the CSV series [s].
    #[arg(long, default_value_t = 0.1)]
    pub dt: f64,
    /// Write the CSV series here (needs at least one --at point).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write the component table (i, omega, T, k, a, beta_deg, phase_deg) here.
    #[arg(long)]
    pub component_table: Option<PathBuf>,
    /// Length of the record generated to measure Hs and Tp back [s] (default 3 h).
    #[arg(long, default_value_t = 10_800.0)]
    pub record: f64,
    /// Print the summary as JSON (SI units) instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Serialize)]
struct Report<'a> {
    #[serde(flatten)]
    summary: &'a SeaSummary,
    measured: Option<MeasuredSea>,
}

fn input(msg: String) -> anyhow::Error {
    InputError::new(msg).into()
}

fn parse_point(s: &str) -> anyhow::Result<[f64; 3]> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| input(format!("--at {s}: expected three numbers x,y,z in m")))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(input(format!(
            "--at {s}: expected three finite numbers x,y,z in m"
        )));
    }
    Ok([v[0], v[1], v[2]])
}

/// Applies the flags on top of a sea description.
fn apply_flags(spec: SeaSpec, a: &Args) -> anyhow::Result<SeaSpec> {
    let params = SeaParams {
        depth: a.depth.clone(),
        gravity: a.gravity,
        current: a.current.as_ref().map(|c| [c[0], c[1], c[2]]),
        kind: a.kind.as_deref().and_then(from_name),
        stretching: a.stretching.as_deref().and_then(from_name),
        ramp_time: a.ramp_time,
        height: a.height,
        period: a.period,
        direction: a.direction,
        hs: a.hs,
        tp: a.tp,
        spectrum: a.spectrum.as_deref().and_then(from_name),
        gamma: a.gamma.clone(),
        components: a.components,
        seed: a.seed,
        spreading: a.spreading,
    };
    params.apply(spec).map_err(|_| {
        input(
            "--hs/--tp/--spectrum/--gamma/--components/--seed/--spreading need --kind irregular \
             (or an irregular sea in the scene)"
                .into(),
        )
    })
}

/// Run `aqua waves`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let base = match &a.scene {
        Some(path) => scene::read_sea(path)?,
        None => SeaSpec::default(),
    };
    let spec = apply_flags(base, &a)?;
    if spec.waves.kind == WaveKind::None
        && spec.current.kind == CurrentKind::None
        && a.scene.is_none()
    {
        return Err(input(
            "no sea given: use --scene FILE (its [sea] table) or flags such as \
             --kind airy --height 2 --period 8 --depth 50"
                .into(),
        ));
    }
    let points: Vec<[f64; 3]> =
        a.at.iter()
            .map(|s| parse_point(s))
            .collect::<Result<_, _>>()?;
    if !(a.dt > 0.0 && a.dt.is_finite()) {
        return Err(input(format!(
            "--dt {}: must be a time step > 0 in s",
            a.dt
        )));
    }
    if !(a.duration >= 0.0 && a.duration.is_finite()) {
        return Err(input(format!("--duration {}: must be >= 0 s", a.duration)));
    }
    if a.csv.is_some() && points.is_empty() {
        return Err(input("--csv needs at least one --at x,y,z point".into()));
    }
    let opts = BuildOptions {
        z_ref: 0.0,
        duration: Some(a.duration),
    };
    let (sea, summary) = spec.build(&opts).map_err(|e| {
        let where_ = a
            .scene
            .as_ref()
            .map(|p| format!("{}: ", p.display()))
            .unwrap_or_default();
        input(format!("{where_}{e}"))
    })?;
    let measured = summary
        .irregular
        .as_ref()
        .and_then(|irr| measure_record(&sea, a.record, irr.tp, summary.wave_ramp_time));
    if a.json {
        let report = Report {
            summary: &summary,
            measured: measured.clone(),
        };
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", summary.to_text(measured.as_ref()));
    }
    if let Some(path) = &a.component_table {
        aqua_sim::write_component_table(&sea, path)?;
    }
    if let Some(path) = &a.csv {
        aqua_sim::write_kinematics(&sea, &points, a.duration, a.dt, path)?;
        if !a.json {
            println!(
                "wrote {} ({} points x {} steps)",
                path.display(),
                points.len(),
                (a.duration / a.dt).floor() as usize + 1
            );
        }
    }
    Ok(())
}
