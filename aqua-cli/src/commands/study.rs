//! `aqua study scene.toml --vary PATH=v1,v2,... [--metric M] --out DIR`: the accuracy–speed
//! study of [`aqua_study::study`], printed as it goes and written to `DIR/study.csv`,
//! `estimates.csv`, `study.json` and `error_vs_cost.png`.

use crate::interrupted;
use aqua_sim::Override;
use aqua_study::study::{Axis, Metric, StudyObserver, StudyRun, StudySpec};
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
    print!("{}", study.to_text());
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
