//! `aqua plot DIR`: PNG pictures of a run folder's time series and static convergence
//! ([`aqua_study::plot::plot_run`]), written to `DIR/plots/`.

use std::path::PathBuf;

/// Flags of `aqua plot`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A run folder (the `--out` of `aqua run`, holding summary.csv and run.json).
    pub dir: PathBuf,
}

/// Run `aqua plot`.
pub fn run(a: Args) -> anyhow::Result<()> {
    print_pictures(&aqua_study::plot::plot_run(&a.dir)?);
    Ok(())
}

/// Lists the pictures written, with the range of every series.
pub fn print_pictures(pictures: &[aqua_study::plot::Picture]) {
    if pictures.is_empty() {
        println!("nothing to plot: one output step and no static convergence history");
    }
    for p in pictures {
        println!("{}: {}", p.path.display(), p.title);
        for s in &p.series {
            println!("  {:<44} {:>14.6e} .. {:>14.6e}", s.name, s.min, s.max);
        }
    }
}
