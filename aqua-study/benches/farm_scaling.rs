//! Scaling of a dynamic step of a fish farm with its size (issue 40), on a log–log plot.
//!
//! The scene is examples/farm-full-scale.toml (CSM cages of 50 m on a buoyed mooring grid,
//! current and a short-crested JONSWAP sea) run with HHT-α, the default scheme, in two
//! families:
//!
//! * **farms at fixed λ** (1.6 m net elements): 1 × 1, 1 × 2, 2 × 2, 2 × 4, 3 × 4 and 4 × 4
//!   cages (14 000 to about 200 000 free DOFs);
//! * **an element-length ladder of one cage** (1 × 1): 3.2, 1.6, 1.13, 0.8 and 0.55 m net
//!   elements (about 5 000 to 100 000 free DOFs; 0.38 m, 200 000, would take about half an
//!   hour on its own: docs/theory/fem.md#scaling-of-a-farm).
//!
//! Every point runs [`T_END`] seconds of dynamics from the as-built state at rest (no statics:
//! those of the 2 × 4 farm alone take about 5 min; the same window and sea for every point,
//! halvings included), timed from the run record, on a rayon worker as `aqua run` does.
//! Each point runs in a child process of this binary, so that its peak resident memory
//! (VmHWM) is its own. Prints a table and writes `scaling-farm.csv` and `scaling-farm.png`
//! into `$AQUA_SCALING_OUT` (default: a `scaling-farm` folder in the target directory), with
//! the least-squares slope of log(wall per step) against log(free DOFs) over all points.
//! Run it alone (about 15 min): `cargo bench -p aqua-study --bench farm_scaling`. Not part of
//! any test. With `AQUA_SCALING_KEEP` naming an earlier `scaling-farm.csv`, the points found
//! there (same family, rows, columns and element length) are taken from it, each with the load
//! it was measured at, and only the others are run.

use aqua_sim::{Observer, Override, PrepareOptions, Simulation};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Simulated seconds of dynamics per point.
const T_END: f64 = 0.4;

struct Discard;

impl Observer for Discard {}

/// One measured point.
#[derive(Debug, Clone)]
struct Point {
    family: String,
    rows: usize,
    columns: usize,
    element_length: f64,
    dofs: usize,
    steps: usize,
    iterations: usize,
    factorisations: usize,
    halvings: usize,
    dyn_wall: f64,
    peak_rss: f64,
    load: (f64, f64),
}

impl Point {
    fn ms_per_step(&self) -> f64 {
        1e3 * self.dyn_wall / self.steps.max(1) as f64
    }
    fn iterations_per_step(&self) -> f64 {
        self.iterations as f64 / self.steps.max(1) as f64
    }
    fn ms_per_iteration(&self) -> f64 {
        1e3 * self.dyn_wall / self.iterations.max(1) as f64
    }
    fn bytes_per_dof(&self) -> f64 {
        self.peak_rss / self.dofs.max(1) as f64
    }
}

/// The point of `family rows columns element_length` in the CSV written by [`write`], if any.
fn kept(
    csv: &str,
    family: &str,
    rows: usize,
    columns: usize,
    element_length: f64,
) -> Option<Point> {
    csv.lines().skip(1).find_map(|l| {
        let w: Vec<&str> = l.split(',').collect();
        let f = |k: usize| w.get(k)?.parse::<f64>().ok();
        let same = w.first() == Some(&family)
            && f(1)? as usize == rows
            && f(2)? as usize == columns
            && (f(3)? - element_length).abs() < 1e-9;
        same.then(|| {
            Some(Point {
                family: family.to_string(),
                rows,
                columns,
                element_length,
                dofs: f(4)? as usize,
                steps: f(5)? as usize,
                iterations: f(6)? as usize,
                factorisations: f(7)? as usize,
                halvings: f(8)? as usize,
                dyn_wall: f(9)?,
                peak_rss: f(13)? * 1e6,
                load: (f(15)?, f(16)?),
            })
        })?
    })
}

/// The one-minute load average of the machine (/proc/loadavg; NaN where there is none).
fn load() -> f64 {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or(f64::NAN)
}

/// Peak resident memory of this process [bytes] (VmHWM; 0 where there is none).
fn peak() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
            line.split_whitespace().nth(1)?.parse::<f64>().ok()
        })
        .map_or(0.0, |kb| kb * 1024.0)
}

/// The example with HHT-α instead of its midpoint rule (whose `theta` HHT-α refuses), written
/// where the bench keeps its files.
fn scene() -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/farm-full-scale.toml");
    let text = std::fs::read_to_string(&src).expect("examples/farm-full-scale.toml");
    let text: String = text
        .lines()
        .filter(|l| !l.trim_start().starts_with("theta") && !l.trim_start().starts_with("# HHT"))
        .map(|l| {
            if l.trim_start().starts_with("scheme") {
                "scheme = \"hht\"\n".to_string()
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("scaling-farm");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("farm-hht.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// Child: runs one point and prints it as one `POINT` line.
fn run_point(family: &str, rows: usize, columns: usize, element_length: f64) {
    let load0 = load();
    let path = scene();
    let set: Vec<String> = vec![
        "analysis.kind=dynamic".into(),
        format!("analysis.dynamic.t_end={T_END}"),
        format!("analysis.dynamic.output_interval={T_END}"),
        "analysis.dynamic.paraview_interval=1000".into(),
        format!("farm.0.rows={rows}"),
        format!("farm.0.columns={columns}"),
        format!("farm.0.cage.element_length={element_length}"),
    ];
    let set: Vec<Override> = set.iter().map(|s| s.parse().unwrap()).collect();
    let prep = aqua_sim::prepare(PrepareOptions::file(&path).with_overrides(&set)).expect("scene");
    let dofs = aqua_sim::check::free_dofs(&prep.built);
    let rec = rayon::scope(|_| {
        let mut sim = Simulation::new(&prep).expect("simulation");
        let (rec, r) = sim.run(&mut Discard);
        r.expect("dynamics");
        rec
    });
    let ls = rec.linear_solver.as_ref();
    println!(
        "POINT {family} {rows} {columns} {element_length} {dofs} {} {} {} {} {} {} {} {}",
        rec.steps,
        rec.iterations,
        ls.map_or(0, |s| s.factorisations),
        rec.step_control.as_ref().map_or(0, |c| c.halvings),
        rec.dyn_wall,
        peak(),
        load0,
        load()
    );
}

/// Parent: runs `family rows columns element_length` in a child process, or takes it from
/// `keep` (an earlier CSV's text).
fn measure(keep: &str, family: &str, rows: usize, columns: usize, element_length: f64) -> Point {
    if let Some(p) = kept(keep, family, rows, columns, element_length) {
        eprintln!("{family} {rows}×{columns} {element_length} m: kept from AQUA_SCALING_KEEP");
        return p;
    }
    let exe = std::env::current_exe().unwrap();
    let out = Command::new(exe)
        .args([
            "--point",
            family,
            &rows.to_string(),
            &columns.to_string(),
            &element_length.to_string(),
        ])
        .output()
        .expect("child");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("POINT "))
        .unwrap_or_else(|| {
            panic!(
                "{family} {rows}×{columns} {element_length} m: {}",
                String::from_utf8_lossy(&out.stderr)
            )
        });
    let w: Vec<&str> = line.split_whitespace().skip(1).collect();
    let f = |k: usize| w[k].parse::<f64>().unwrap();
    let p = Point {
        family: w[0].to_string(),
        rows: f(1) as usize,
        columns: f(2) as usize,
        element_length: f(3),
        dofs: f(4) as usize,
        steps: f(5) as usize,
        iterations: f(6) as usize,
        factorisations: f(7) as usize,
        halvings: f(8) as usize,
        dyn_wall: f(9),
        peak_rss: f(10),
        load: (f(11), f(12)),
    };
    eprintln!(
        "{:<7} {}×{} {:>5.2} m {:>7} DOFs  {:>4} steps {:>3} halvings  {:>9.1} ms/step  \
         {:>5.2} it/step  {:>8.1} ms/it  {:>5} MB peak ({:.0} B/DOF)  load {:.1}–{:.1}",
        p.family,
        p.rows,
        p.columns,
        p.element_length,
        p.dofs,
        p.steps,
        p.halvings,
        p.ms_per_step(),
        p.iterations_per_step(),
        p.ms_per_iteration(),
        (p.peak_rss / 1e6).round(),
        p.bytes_per_dof(),
        p.load.0,
        p.load.1
    );
    p
}

/// Least-squares slope of log y against log x.
fn slope(pts: &[(f64, f64)]) -> f64 {
    let n = pts.len() as f64;
    let (mx, my) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + x.ln() / n, b + y.ln() / n)
    });
    let (sxy, sxx) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        let dx = x.ln() - mx;
        (a + dx * (y.ln() - my), b + dx * dx)
    });
    sxy / sxx
}

fn write(pts: &[Point]) {
    let dir = std::env::var_os("AQUA_SCALING_OUT")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_TARGET_TMPDIR")).join("scaling-farm"));
    std::fs::create_dir_all(&dir).unwrap();
    let mut csv = String::from(
        "family,rows,columns,element_length_m,free_dofs,steps,newton_iterations,factorisations,\
         halvings,dynamics_s,ms_per_step,iterations_per_step,ms_per_iteration,peak_rss_mb,\
         bytes_per_dof,load_before,load_after\n",
    );
    for p in pts {
        csv += &format!(
            "{},{},{},{},{},{},{},{},{},{:.3},{:.2},{:.3},{:.2},{:.1},{:.0},{:.2},{:.2}\n",
            p.family,
            p.rows,
            p.columns,
            p.element_length,
            p.dofs,
            p.steps,
            p.iterations,
            p.factorisations,
            p.halvings,
            p.dyn_wall,
            p.ms_per_step(),
            p.iterations_per_step(),
            p.ms_per_iteration(),
            p.peak_rss / 1e6,
            p.bytes_per_dof(),
            p.load.0,
            p.load.1
        );
    }
    std::fs::write(dir.join("scaling-farm.csv"), csv).unwrap();
    let all: Vec<(f64, f64)> = pts
        .iter()
        .map(|p| (p.dofs as f64, p.ms_per_step()))
        .collect();
    let s_all = slope(&all);
    let mut series = Vec::new();
    for (family, name) in [
        ("farms", "farms of 1 × 1 … 4 × 4 cages, 1.6 m net elements"),
        ("ladder", "one cage, net elements 3.2 … 0.55 m"),
    ] {
        let fam: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| p.family == family)
            .map(|p| (p.dofs as f64, p.ms_per_step()))
            .collect();
        if fam.len() >= 2 {
            eprintln!(
                "{family}: log–log slope of wall per step {:.2}",
                slope(&fam)
            );
        }
        series.push(aqua_study::plot::Series::new(
            format!("{name} (slope {:.2})", slope(&fam)),
            fam,
        ));
    }
    eprintln!("all points: log–log slope of wall per step {s_all:.2}");
    let png = dir.join("scaling-farm.png");
    aqua_study::plot::loglog_chart(
        &png,
        &format!(
            "Wall per dynamic step of a farm (HHT-α, first {T_END} s from rest, 2 cores); slope {s_all:.2}"
        ),
        "free DOFs",
        "wall per step [ms]",
        series,
        Some(1.0),
    )
    .unwrap();
    eprintln!("wrote {} and scaling-farm.csv", png.display());
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(k) = args.iter().position(|a| a == "--point") {
        let a = &args[k + 1..];
        run_point(
            &a[0],
            a[1].parse().unwrap(),
            a[2].parse().unwrap(),
            a[3].parse().unwrap(),
        );
        return;
    }
    // `cargo test --benches` runs this binary without `--bench`: nothing to do then.
    if !args.iter().any(|a| a == "--bench") {
        return;
    }
    let keep = std::env::var_os("AQUA_SCALING_KEEP")
        .map(|p| {
            std::fs::read_to_string(&p)
                .unwrap_or_else(|e| panic!("AQUA_SCALING_KEEP = {}: {e}", p.to_string_lossy()))
        })
        .unwrap_or_default();
    let mut pts = Vec::new();
    for el in [3.2, 1.6, 1.13, 0.8, 0.55] {
        pts.push(measure(&keep, "ladder", 1, 1, el));
    }
    let one = pts[1].clone();
    pts.push(Point {
        family: "farms".into(),
        ..one
    });
    for (rows, columns) in [(1, 2), (2, 2), (2, 4), (3, 4), (4, 4)] {
        pts.push(measure(&keep, "farms", rows, columns, 1.6));
    }
    write(&pts);
}
