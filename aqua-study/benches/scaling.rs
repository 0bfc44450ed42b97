//! Scaling of the dynamic step with the number of unknowns (issue 15), on a log–log plot.
//!
//! Three families, each run as `aqua run` would (static equilibrium, then 2 s of HHT-α at
//! Δt = 0.1 s, no output files), timed from the run record:
//!
//! * the mooring chain (examples/mooring-chain.toml) at 160 … 10 240 segments;
//! * the reference cage (examples/reference-cage.toml) at element lengths 5, 2.5 and 1.25 m;
//! * 2 … 16 copies of the reference cage in one scene (`origins` 40 m apart).
//!
//! Prints a table (DOFs = 3 × nodes, ms per step, ms per Newton iteration, µs per iteration and
//! DOF) and writes `scaling.csv` and `scaling.png` into `$AQUA_SCALING_OUT` (default: a
//! `scaling` folder in the target directory). The criterion measurement is the per-step time of
//! the 2-copy scene.

use aqua_sim::{Observer, Override, PrepareOptions, Prepared, Simulation};
use criterion::{Criterion, criterion_group, criterion_main};
use std::path::{Path, PathBuf};
use std::time::Duration;

struct Discard;

impl Observer for Discard {}

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name)
}

fn prepare(file: &str, set: &[String]) -> Prepared {
    let mut all: Vec<String> = vec![
        "analysis.kind=static+dynamic".into(),
        "analysis.dynamic.t_end=2.0".into(),
        "analysis.dynamic.output_interval=2.0".into(),
    ];
    all.extend(set.iter().cloned());
    let set: Vec<Override> = all.iter().map(|s| s.parse().unwrap()).collect();
    aqua_sim::prepare(PrepareOptions::file(&example(file)).with_overrides(&set)).expect("scene")
}

/// One measured case.
struct Point {
    family: &'static str,
    label: String,
    dofs: usize,
    ms_per_step: f64,
    ms_per_iteration: f64,
    static_s: f64,
}

fn measure(family: &'static str, label: String, file: &str, set: &[String]) -> Point {
    let prep = prepare(file, set);
    let dofs = 3 * prep.built.model.n_nodes();
    let mut sim = Simulation::new(&prep).expect("simulation");
    let (rec, r) = sim.run(&mut Discard);
    r.unwrap_or_else(|e| panic!("{label}: {e}"));
    let p = Point {
        family,
        label,
        dofs,
        ms_per_step: 1e3 * rec.dyn_wall / rec.steps.max(1) as f64,
        ms_per_iteration: 1e3 * rec.dyn_wall / rec.iterations.max(1) as f64,
        static_s: rec.wall - rec.dyn_wall,
    };
    eprintln!(
        "{:<8} {:<22} {:>7} DOFs  {:>9.2} ms/step  {:>9.2} ms/iteration  {:>6.3} µs/(iteration·DOF)  statics {:.1} s",
        p.family,
        p.label,
        p.dofs,
        p.ms_per_step,
        p.ms_per_iteration,
        1e3 * p.ms_per_iteration / p.dofs as f64,
        p.static_s
    );
    p
}

fn copies(n: usize) -> String {
    let origins: Vec<String> = (0..n)
        .map(|k| format!("[{}.0, {}.0, 0.0]", 40 * (k % 4), 40 * (k / 4)))
        .collect();
    format!("cage.0.origins=[{}]", origins.join(", "))
}

fn sweep() -> Vec<Point> {
    let mut pts = Vec::new();
    for n in [160, 640, 2560, 10240] {
        pts.push(measure(
            "chain",
            format!("{n} segments"),
            "mooring-chain.toml",
            &[
                format!("line.0.segments={n}"),
                "analysis.dynamic.scheme=hht".to_string(),
            ],
        ));
    }
    for el in ["5.0", "2.5", "1.25"] {
        pts.push(measure(
            "cage",
            format!("element_length {el} m"),
            "reference-cage.toml",
            &[format!("cage.0.element_length={el}")],
        ));
    }
    for n in [2, 4, 8, 16] {
        pts.push(measure(
            "cages",
            format!("{n} reference cages"),
            "reference-cage.toml",
            &[copies(n)],
        ));
    }
    pts
}

fn write(pts: &[Point]) {
    let dir = std::env::var_os("AQUA_SCALING_OUT")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_TARGET_TMPDIR")).join("scaling"));
    std::fs::create_dir_all(&dir).unwrap();
    let mut csv = String::from("family,case,dofs,ms_per_step,ms_per_iteration,static_s\n");
    for p in pts {
        csv += &format!(
            "{},{},{},{:.4},{:.4},{:.3}\n",
            p.family, p.label, p.dofs, p.ms_per_step, p.ms_per_iteration, p.static_s
        );
    }
    std::fs::write(dir.join("scaling.csv"), csv).unwrap();
    let series = ["chain", "cage", "cages"]
        .iter()
        .map(|f| {
            let name = match *f {
                "chain" => "mooring chain, 160 … 10 240 segments",
                "cage" => "reference cage, element length 5 / 2.5 / 1.25 m",
                _ => "2 … 16 reference cages in one scene",
            };
            aqua_study::plot::Series::new(
                name,
                pts.iter()
                    .filter(|p| p.family == *f)
                    .map(|p| (p.dofs as f64, p.ms_per_iteration))
                    .collect(),
            )
        })
        .collect();
    let png = dir.join("scaling.png");
    aqua_study::plot::loglog_chart(
        &png,
        "Time per Newton iteration of a dynamic step (HHT-α, Δt = 0.1 s, 2 cores)",
        "unknowns (3 × nodes)",
        "time per Newton iteration [ms]",
        series,
        Some(1.0),
    )
    .unwrap();
    eprintln!("wrote {} and scaling.csv", png.display());
}

fn bench(c: &mut Criterion) {
    let pts = sweep();
    write(&pts);
    let prep = prepare("reference-cage.toml", &[copies(2)]);
    let mut g = c.benchmark_group("scaling");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(30));
    g.bench_function("two_reference_cages_per_step", |b| {
        b.iter_custom(|k| {
            let mut total = Duration::ZERO;
            for _ in 0..k {
                let mut sim = Simulation::new(&prep).unwrap();
                let (rec, r) = sim.run(&mut Discard);
                r.unwrap();
                total += Duration::from_secs_f64(rec.dyn_wall / rec.steps.max(1) as f64);
            }
            total
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
