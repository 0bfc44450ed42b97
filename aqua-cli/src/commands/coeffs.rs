//! `aqua coeffs`: tables of screen-model drag/lift coefficients against the inflow angle and of
//! Morison normal/tangential coefficients against the Reynolds number, to compare and choose
//! models (docs/theory/hydrodynamics.md#screen-models, #morison-coefficients).

use crate::InputError;
use aqua_hydro::ScreenModelId;
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

fn parse_number(flag: &str, s: &str) -> anyhow::Result<f64> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| input(format!("{flag}: \"{s}\" is not a finite number")))
}

/// Angles in degrees from "a:b:step" or "a,b,c", each in [0, 90].
pub fn parse_angles(s: &str) -> anyhow::Result<Vec<f64>> {
    let out = if s.contains(':') {
        let parts: Vec<&str> = s.split(':').collect();
        if parts.len() != 3 {
            return Err(input(format!(
                "--angles = \"{s}\": use start:stop:step in degrees (e.g. 0:90:15) or a list 0,30,60"
            )));
        }
        let (a, b, st) = (
            parse_number("--angles", parts[0])?,
            parse_number("--angles", parts[1])?,
            parse_number("--angles", parts[2])?,
        );
        if !(st > 0.0) || b < a {
            return Err(input(format!(
                "--angles = \"{s}\": need start <= stop and step > 0 (e.g. 0:90:15)"
            )));
        }
        let n = ((b - a) / st + 1e-9).floor() as usize;
        if n > 100_000 {
            return Err(input(format!(
                "--angles = \"{s}\": too many angles (step too small)"
            )));
        }
        (0..=n).map(|i| a + i as f64 * st).collect::<Vec<_>>()
    } else {
        s.split(',')
            .map(|p| parse_number("--angles", p))
            .collect::<anyhow::Result<Vec<_>>>()?
    };
    if let Some(bad) = out.iter().find(|a| !(0.0..=90.0).contains(*a)) {
        return Err(input(format!(
            "--angles: {bad} deg is outside 0-90 (θ = 0 is flow normal to the net, 90 flow in its plane)"
        )));
    }
    Ok(out)
}

/// Reynolds numbers from a list or "lo:hi:n" (log-spaced), each > 0.
pub fn parse_reynolds(s: &str) -> anyhow::Result<Vec<f64>> {
    let out = if s.contains(':') {
        let parts: Vec<&str> = s.split(':').collect();
        if parts.len() != 3 {
            return Err(input(format!(
                "--reynolds = \"{s}\": use lo:hi:n (n log-spaced values) or a list 1,10,100"
            )));
        }
        let (lo, hi) = (
            parse_number("--reynolds", parts[0])?,
            parse_number("--reynolds", parts[1])?,
        );
        let n: usize = parts[2].trim().parse().map_err(|_| {
            input(format!(
                "--reynolds = \"{s}\": n must be a whole number >= 2"
            ))
        })?;
        if !(lo > 0.0 && hi > lo) || !(2..=100_000).contains(&n) {
            return Err(input(format!(
                "--reynolds = \"{s}\": need 0 < lo < hi and 2 <= n <= 100000"
            )));
        }
        let (a, b) = (lo.log10(), hi.log10());
        (0..n)
            .map(|i| 10f64.powf(a + (b - a) * i as f64 / (n - 1) as f64))
            .collect()
    } else {
        s.split(',')
            .map(|p| parse_number("--reynolds", p))
            .collect::<anyhow::Result<Vec<_>>>()?
    };
    if let Some(bad) = out.iter().find(|r| !(**r > 0.0)) {
        return Err(input(format!("--reynolds: {bad} must be > 0")));
    }
    Ok(out)
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
        q.angles_deg = parse_angles(&args.angles)?;
    }
    let screen = screen_report(&q).map_err(table_error)?;
    if !q.morisons.is_empty() {
        q.reynolds = parse_reynolds(&args.reynolds)?;
    }
    let morison = morison_report(&q).map_err(table_error)?;
    Ok(Report { screen, morison })
}

/// The text tables.
pub fn render(report: &Report) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    if let Some(sc) = &report.screen {
        let _ = writeln!(
            s,
            "Screen models: Sn = {}, dw0 = {} m, U = {} m/s, nu = {:e} m2/s, Re = U*dw0/nu = {:.1}{}",
            sc.solidity,
            sc.twine_diameter,
            sc.speed,
            sc.viscosity,
            sc.reynolds,
            match sc.cyl_cd {
                Some(c) => format!(", C_cyl = {c} (S3/S6)"),
                None => String::new(),
            }
        );
        let _ = writeln!(
            s,
            "theta = 0 deg: flow normal to the net; 90 deg: flow in the net plane"
        );
        for m in &sc.models {
            let _ = writeln!(s, "  {:<7} {}", m.model, m.reference);
        }
        let _ = write!(s, "{:>9}", "theta_deg");
        for m in &sc.models {
            let _ = write!(
                s,
                " {:>10} {:>10}",
                format!("{} Cd", m.model),
                format!("{} Cl", m.model)
            );
        }
        let _ = writeln!(s);
        let n = sc.models.first().map_or(0, |m| m.rows.len());
        for i in 0..n {
            let _ = write!(s, "{:>9.2}", sc.models[0].rows[i].theta_deg);
            for m in &sc.models {
                let r = m.rows[i];
                let _ = write!(s, " {:>10.6} {:>10.6}", r.cd, r.cl);
            }
            let _ = writeln!(s);
        }
    }
    if let Some(mo) = &report.morison {
        if report.screen.is_some() {
            let _ = writeln!(s);
        }
        let _ = writeln!(
            s,
            "Morison models: Cn, Ct vs Re (Re clamped at 1e7; M5 with Sn = {})",
            mo.solidity
        );
        for m in &mo.models {
            let _ = writeln!(s, "  {:<7} {}", m.model, m.reference);
        }
        let _ = write!(s, "{:>10}", "Re");
        for m in &mo.models {
            let _ = write!(
                s,
                " {:>10} {:>10}",
                format!("{} Cn", m.model),
                format!("{} Ct", m.model)
            );
        }
        let _ = writeln!(s);
        let n = mo.models.first().map_or(0, |m| m.rows.len());
        for i in 0..n {
            let _ = write!(s, "{:>10.4e}", mo.models[0].rows[i].re);
            for m in &mo.models {
                let r = m.rows[i];
                let _ = write!(s, " {:>10.6} {:>10.6}", r.cn, r.ct);
            }
            let _ = writeln!(s);
        }
    }
    s
}

/// Run `aqua coeffs`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let report = compute(&args)?;
    let text = if args.json {
        serde_json::to_string_pretty(&report)? + "\n"
    } else {
        render(&report)
    };
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        // `aqua coeffs | head` closes the pipe early: not an error
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}
