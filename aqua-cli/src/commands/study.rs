//! `aqua study scene.toml --vary PATH=v1,v2,... [--metric M] --out DIR`: the accuracy–speed
//! study of [`aqua_study::study`], printed as it goes and written to `DIR/study.csv`,
//! `estimates.csv`, `study.json` and `error_vs_cost.png`.

use crate::interrupted;
use aqua_sim::Override;
use aqua_study::study::{Axis, Metric, Study, StudyObserver, StudyRun, StudySpec};
use std::path::PathBuf;

/// Flags of `aqua study`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// A ladder, coarse to fine: PATH=v1,v2,... (e.g. element_length=10,5,2.5, dt=0.2,0.1,0.05,
    /// scheme=hht,rk4, line.0.segments=20,40,80). Repeat for a factorial study.
    #[arg(long = "vary", value_name = "PATH=V1,V2,...", required = true)]
    pub vary: Vec<Axis>,
    /// A metric: a summary.csv column, F_net or R, optionally as STAT:COLUMN with STAT one of
    /// static, max, min, absmax, mean, final (default: net drag, reactions, volume ratio,
    /// largest tension per group, line-end loads; extremes over the run for dynamics).
    #[arg(long = "metric", value_name = "[STAT:]COLUMN")]
    pub metric: Vec<Metric>,
    /// Relative error the recommended setting must meet in every metric.
    #[arg(long, default_value_t = 0.01)]
    pub tolerance: f64,
    /// Change a scene key for every run: PATH=VALUE (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<Override>,
    /// Output directory for the tables and the picture.
    #[arg(long, default_value = "study")]
    pub out: PathBuf,
    /// Print only the final tables.
    #[arg(long)]
    pub quiet: bool,
}

struct Terminal {
    quiet: bool,
}

impl StudyObserver for Terminal {
    fn run_started(&mut self, index: usize, total: usize, setting: &str) {
        if !self.quiet {
            eprint!("run {}/{total}: {setting} ... ", index + 1);
        }
    }
    fn run_finished(&mut self, r: &StudyRun) {
        if !self.quiet {
            eprintln!(
                "{} in {:.2} s ({} DOFs, {} steps{})",
                r.status,
                r.wall_s,
                r.dofs,
                r.steps,
                r.reason
                    .as_ref()
                    .map(|m| format!("; {m}"))
                    .unwrap_or_default()
            );
        }
    }
    fn stop_requested(&self) -> bool {
        interrupted()
    }
}

/// Run `aqua study`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let spec = StudySpec {
        scene: a.scene.clone(),
        base: a.set,
        axes: a.vary,
        metrics: a.metric,
        tolerance: a.tolerance,
    };
    let study = aqua_study::study::run_study(&spec, &mut Terminal { quiet: a.quiet })?;
    aqua_study::study::write_tables(&study, &a.out)?;
    let png = a.out.join("error_vs_cost.png");
    aqua_study::plot::plot_study(&study, &png)?;
    print_study(&study);
    println!(
        "tables in {}, {}, {}; picture {}; study overhead beyond the runs {:.3} s of {:.2} s",
        a.out.join("study.csv").display(),
        a.out.join("estimates.csv").display(),
        a.out.join("study.json").display(),
        png.display(),
        study.overhead_s,
        study.wall_s
    );
    if study.interrupted {
        eprintln!(
            "interrupted: {} of the runs were made; the tables hold those",
            study.runs.len()
        );
        std::process::exit(crate::interrupted_exit_code());
    }
    Ok(())
}

fn print_study(s: &Study) {
    let axes: Vec<&str> = s.axes.iter().map(|a| a.path.as_str()).collect();
    println!(
        "{:>4}  {:<28} {:>11} {:>9} {:>7} {:>7}  {:>14}  worst metric",
        "run",
        axes.join(" / "),
        "status",
        "wall [s]",
        "DOFs",
        "steps",
        "largest error"
    );
    for r in &s.runs {
        let worst = r
            .errors
            .iter()
            .enumerate()
            .filter_map(|(k, e)| e.map(|e| (k, e)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let mark = if s.recommended == Some(r.index) {
            "  <- recommended"
        } else {
            ""
        };
        println!(
            "{:>4}  {:<28} {:>11} {:>9.3} {:>7} {:>7}  {:>14}  {}{mark}",
            r.index,
            r.setting.join(" / "),
            r.status,
            r.wall_s,
            r.dofs,
            r.steps,
            worst
                .map(|(_, e)| format!("{:.3e}", e))
                .unwrap_or_else(|| "-".into()),
            worst.map(|(k, _)| s.metrics[k].as_str()).unwrap_or(""),
        );
        if let Some(reason) = &r.reason {
            println!("      reason: {reason}");
        }
    }
    println!();
    println!(
        "{:<40} {:>17} {:>17}  {:<11} observed order per ladder ({})",
        "metric",
        "estimate",
        "finest run",
        "method",
        axes.join(", ")
    );
    for e in &s.estimates {
        let orders: Vec<String> = e
            .orders
            .iter()
            .zip(&e.notes)
            .map(|(p, note)| match (p, note) {
                (Some(p), _) => format!("{p:.3}"),
                (None, Some(n)) => format!("- ({n})"),
                (None, None) => "-".into(),
            })
            .collect();
        let fmt = |v: Option<f64>| v.map(|v| format!("{v:.10e}")).unwrap_or("-".into());
        println!(
            "{:<40} {:>17} {:>17}  {:<11} {}{}",
            e.metric,
            fmt(e.value),
            fmt(e.finest),
            e.method,
            orders.join("; "),
            if e.negligible {
                " (negligible: not used)"
            } else {
                ""
            }
        );
    }
    println!();
    if s.estimates.iter().any(|e| e.value.is_none()) {
        println!(
            "no estimate for some metrics (the reference run, the last value of every ladder, \
             did not complete): nothing can be recommended"
        );
        return;
    }
    if s.estimates.iter().all(|e| e.method != "richardson") {
        println!(
            "note: no ladder could be extrapolated, so errors are measured against the finest \
             run, whose own error is unknown; give three geometric values (e.g. 10,5,2.5) to \
             estimate it"
        );
    }
    match s
        .recommended
        .and_then(|i| s.runs.iter().find(|r| r.index == i))
    {
        Some(r) => println!(
            "recommended: run {} ({}) — {:.3} s, every metric within {} % of its estimate",
            r.index,
            s.axes
                .iter()
                .zip(&r.setting)
                .map(|(a, v)| format!("{}={v}", a.path))
                .collect::<Vec<_>>()
                .join(" "),
            r.wall_s,
            100.0 * s.tolerance
        ),
        None => println!(
            "no run has every metric within {} % of its estimate: refine the ladders",
            100.0 * s.tolerance
        ),
    }
}
