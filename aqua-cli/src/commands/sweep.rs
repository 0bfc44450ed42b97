//! `aqua sweep cases.toml`: the load cases of a case file ([`aqua_study::sweep`]), run on this
//! machine (`--local`, N child processes at a time: [`aqua_study::local_runner`]), or handed to GNU parallel
//! (`--emit parallel`) or a Slurm job array (`--emit slurm`); `--case K` runs one case and is
//! what every engine calls. Without a mode it lists the cases.

use crate::commands::run::run_scene;
use crate::{InputError, interrupted};
use anyhow::Context;
use aqua_sim::Ending;
use aqua_study::local_runner;
use aqua_study::sweep::{CaseRecord, Sweep, run_diagnostics};
use std::path::PathBuf;
use std::time::Instant;

/// Where the emitted commands go.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Emit {
    /// One command line per case, for GNU parallel (`| parallel --jobs N`).
    Parallel,
    /// A Slurm job-array script (`> cases.sbatch; sbatch cases.sbatch`).
    Slurm,
}

/// Flags of `aqua sweep`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Case file (TOML): scene, [vary], [[case]].
    pub cases: PathBuf,
    /// Run every case on this machine, each its own process.
    #[arg(long, conflicts_with_all = ["emit", "case"])]
    pub local: bool,
    /// Cases run at a time with --local.
    #[arg(long, default_value_t = 1, requires = "local")]
    pub jobs: usize,
    /// Print the commands for GNU parallel or a Slurm array script instead of running.
    #[arg(long, value_enum, conflicts_with = "case")]
    pub emit: Option<Emit>,
    /// Run case K only (what --local, GNU parallel and Slurm call).
    #[arg(long, value_name = "K")]
    pub case: Option<usize>,
    /// Folder for the case folders (default: the case file's `out`).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Run `aqua sweep`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let mut sweep = Sweep::read(&a.cases)?;
    if let Some(out) = &a.out {
        sweep.out = std::path::absolute(out)?;
    }
    if let Some(k) = a.case {
        return run_case(&sweep, k);
    }
    match a.emit {
        Some(Emit::Parallel) => {
            for k in 0..sweep.cases.len() {
                println!(
                    "{}",
                    sweep.case_command(&exe()?, &k.to_string(), a.out.is_some())
                );
            }
            eprintln!(
                "# {} cases; run them with: aqua sweep {} --emit parallel | parallel --jobs N",
                sweep.cases.len(),
                a.cases.display()
            );
            Ok(())
        }
        Some(Emit::Slurm) => {
            for k in 0..sweep.cases.len() {
                // Slurm does not create the folder of an `--output` file.
                let dir = sweep.case_dir(k);
                std::fs::create_dir_all(&dir)
                    .with_context(|| format!("creating {}", dir.display()))?;
            }
            print!("{}", sweep.slurm_script(&exe()?, a.out.is_some()));
            Ok(())
        }
        None if a.local => run_local(&sweep, a.jobs),
        None => {
            list(&sweep);
            Ok(())
        }
    }
}

fn list(sweep: &Sweep) {
    println!(
        "{} cases of {} into {}:",
        sweep.cases.len(),
        sweep.scene.display(),
        sweep.out.display()
    );
    for c in &sweep.cases {
        println!("  {:>4}  {}", c.index, c.name);
    }
    println!("run them with --local [--jobs N], or emit them with --emit parallel | --emit slurm");
}

/// This executable, which the emitted commands call.
fn exe() -> anyhow::Result<PathBuf> {
    std::env::current_exe().context("finding the aqua executable")
}

/// The case's `aqua.log`: every line is written there and to stderr (a tee of the case's own
/// messages), so whichever engine starts the case, its folder holds what it said.
struct CaseLog(Option<std::fs::File>);

impl CaseLog {
    fn line(&mut self, text: &str) {
        use std::io::Write;
        eprintln!("{text}");
        if let Some(f) = self.0.as_mut() {
            let _ = writeln!(f, "{text}");
        }
    }
}

/// Runs case `k` into its folder and writes its `case.json` and `aqua.log`.
fn run_case(sweep: &Sweep, k: usize) -> anyhow::Result<()> {
    let Some(case) = sweep.cases.get(k) else {
        return Err(InputError::new(format!(
            "--case {k}: {} has {} cases (0..{})",
            sweep.file.display(),
            sweep.cases.len(),
            sweep.cases.len() - 1
        ))
        .into());
    };
    let dir = sweep.case_dir(k);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    // A case.json of an earlier sweep must not pass for this run's.
    let _ = std::fs::remove_file(dir.join("case.json"));
    let log_path = dir.join("aqua.log");
    let mut log = CaseLog(Some(
        std::fs::File::create(&log_path)
            .with_context(|| format!("writing {}", log_path.display()))?,
    ));
    let set: Vec<String> = case.overrides.iter().map(|o| o.to_string()).collect();
    log.line(&format!(
        "aqua sweep {} --case {k} ({}) into {}",
        sweep.file.display(),
        case.name,
        dir.display()
    ));
    log.line(&if set.is_empty() {
        "set: nothing (the scene as written)".to_string()
    } else {
        format!("set: {}", set.join(", "))
    });
    let t0 = Instant::now();
    let result = run_scene(&sweep.scene, &case.overrides, &dir, true);
    let (status, error) = match &result {
        Ok(e) => (e.as_str(), None),
        Err(e) => (Ending::Failed.as_str(), Some(format!("{e:#}"))),
    };
    // The run's warnings (printed live above, kept in run.json's diagnostics).
    if let Some(f) = log.0.as_mut() {
        use std::io::Write;
        for text in run_diagnostics(&dir) {
            let _ = writeln!(f, "{text}");
        }
    }
    log.line(&format!(
        "case {k} ({}): {status} in {:.2} s{}",
        case.name,
        t0.elapsed().as_secs_f64(),
        error.as_ref().map(|e| format!(": {e}")).unwrap_or_default()
    ));
    let record = CaseRecord {
        index: k,
        name: case.name.clone(),
        set,
        status: status.to_string(),
        error,
        wall_time_s: t0.elapsed().as_secs_f64(),
    };
    let path = dir.join("case.json");
    record
        .write(&dir)
        .with_context(|| format!("writing {}", path.display()))?;
    // The error itself is printed once more by main; the log already has it.
    log.0 = None;
    match result? {
        Ending::Interrupted => std::process::exit(crate::interrupted_exit_code()),
        _ => Ok(()),
    }
}

/// Runs every case as its own `aqua sweep --case K` process, `jobs` at a time
/// ([`aqua_study::local_runner`]); prints each case's status and the tally.
fn run_local(sweep: &Sweep, jobs: usize) -> anyhow::Result<()> {
    if jobs == 0 {
        return Err(InputError::new("--jobs 0: run at least one case at a time").into());
    }
    let exe = std::env::current_exe().context("finding the aqua executable")?;
    let n = sweep.cases.len();
    let t0 = Instant::now();
    eprintln!("{n} cases, {jobs} at a time, into {}", sweep.out.display());
    let outcomes = local_runner::run_local(sweep, &exe, jobs, &interrupted, &|c, status| {
        eprintln!("case {} of {n} ({}): {status}", c.index, c.name)
    })
    .context("starting the worker threads")?;
    let failed = local_runner::failed_count(&outcomes);
    eprintln!(
        "{} of {n} cases completed in {:.1} s; aqua collect {} merges them",
        n - failed,
        t0.elapsed().as_secs_f64(),
        sweep.out.display()
    );
    if interrupted() {
        std::process::exit(crate::interrupted_exit_code());
    }
    if failed > 0 {
        anyhow::bail!(
            "{failed} of {n} cases did not complete: see case_NNNN/aqua.log and case.json in {}",
            sweep.out.display()
        );
    }
    Ok(())
}
