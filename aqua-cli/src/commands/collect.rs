//! `aqua collect DIR`: merges every run folder under DIR (the cases of `aqua sweep`, or any
//! `aqua run` outputs) into one CSV table ([`aqua_study::sweep::collect`]) and prints the
//! governing case of every summary column. Max and min of the load columns are over every
//! accepted step where a run wrote its extremes (`extremes.csv`), else over its output steps.

use std::path::PathBuf;

/// Flags of `aqua collect`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Folder holding one sub-folder per run (case_NNNN/ or any run output with run.json).
    pub dir: PathBuf,
    /// Table to write (default: DIR/collected.csv).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Run `aqua collect`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let c = aqua_study::sweep::collect(&a.dir)?;
    let out = a.out.unwrap_or_else(|| a.dir.join("collected.csv"));
    std::fs::write(&out, c.csv()).map_err(|e| anyhow::anyhow!("writing {}: {e}", out.display()))?;
    println!("{:<12} {:<11} {:>9}  name", "folder", "status", "wall [s]");
    for r in &c.runs {
        println!(
            "{:<12} {:<11} {:>9.2}  {}{}",
            r.folder,
            r.status,
            r.wall_time_s,
            r.name,
            r.error
                .as_ref()
                .map(|e| format!("\n             error: {e}"))
                .unwrap_or_default()
        );
    }
    println!();
    println!(
        "{:<44} {:>15} {:<12} {:>15} {:<12}",
        "governing cases", "largest max", "in", "smallest min", "in"
    );
    for g in c.governing() {
        println!(
            "{:<44} {:>15.6e} {:<12} {:>15.6e} {:<12}",
            g.column, g.largest.1, g.largest.0, g.smallest.1, g.smallest.0
        );
    }
    let done = c.runs.iter().filter(|r| r.status == "completed").count();
    println!(
        "{} runs ({} completed) merged into {} (min, max, mean, std of each summary column over the dynamic part)",
        c.runs.len(),
        done,
        out.display()
    );
    let sampled: Vec<&str> = c
        .runs
        .iter()
        .filter(|r| !r.every_step && !r.stats.is_empty())
        .map(|r| r.folder.as_str())
        .collect();
    if sampled.is_empty() {
        println!("max and min are over every accepted step (extremes.csv)");
    } else {
        println!(
            "max and min are over every accepted step (extremes.csv), except in {} (written \
             before extremes.csv existed: over output steps only, peaks between them are missed)",
            sampled.join(", ")
        );
    }
    Ok(())
}
