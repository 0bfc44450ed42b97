//! The bundled farm (examples/farm.toml: 2 × 3 cages on floating collars, mooring grid, 14
//! anchor lines, current plus a 40-component short-crested sea). Issue 12 targets: statics
//! under 10 s, dynamics faster than real time on this 2-core machine. Criterion samples the
//! static solve; the whole run (statics, then 30 s of dynamics at the nominal dt = 0.1 s
//! with its halvings) is timed once and printed with its steps, ms per step and real-time
//! factor (too long to sample). Both run on a rayon worker, as `aqua run` does
//! (docs/theory/fem.md#threads).

use aqua_env::Phase;
use aqua_fem::solve_static;
use aqua_sim::plan::Prepared;
use aqua_sim::run::{Observer, Simulation, water_loads};
use criterion::{Criterion, criterion_group, criterion_main};
use std::path::Path;
use std::time::{Duration, Instant};

fn farm() -> Prepared {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/farm.toml");
    aqua_sim::prepare(aqua_sim::PrepareOptions::file(&path)).expect("scene")
}

/// One static solve: (wall, Newton iterations).
fn solve(prep: &Prepared) -> (Duration, usize) {
    let (mut loads, _) = water_loads(prep, Phase::Static).expect("water loads");
    let t = Instant::now();
    let sol = solve_static(&prep.built.model, &mut loads, &prep.plan.statics).expect("statics");
    (t.elapsed(), sol.report.iterations)
}

struct Quiet;
impl Observer for Quiet {}

fn bench(c: &mut Criterion) {
    let prep = farm();
    rayon::scope(|_| {
        let (d, it) = solve(&prep);
        eprintln!(
            "farm statics: {} free DOFs, {it} Newton iterations, {:.2} s",
            aqua_sim::check::free_dofs(&prep.built),
            d.as_secs_f64()
        );
    });
    let mut g = c.benchmark_group("farm");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(20));
    g.bench_function("statics", |b| {
        b.iter_custom(|k| rayon::scope(|_| (0..k).map(|_| solve(&prep).0).sum()))
    });
    g.finish();
    let record = rayon::scope(|_| {
        let mut sim = Simulation::new(&prep).expect("water loads");
        let (record, result) = sim.run(&mut Quiet);
        result.expect("farm run");
        record
    });
    let t_end = prep.plan.t_end;
    eprintln!(
        "farm run: statics {} iterations; dynamics {t_end} s in {:.1} s: {} steps, {} Newton \
         iterations, {:.1} ms per step, real-time factor {:.2} (wall / simulated time)",
        record.static_iterations,
        record.dyn_wall,
        record.steps,
        record.iterations,
        1e3 * record.dyn_wall / record.steps as f64,
        record.dyn_wall / t_end
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
