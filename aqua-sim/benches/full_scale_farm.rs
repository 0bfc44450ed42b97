//! The full-scale farm (examples/farm-full-scale.toml: 2 × 4 CSM cages of 50 m diameter,
//! 20 m + 10 m cone, 1.6 m net elements, 100 m mooring grid in 80 m of water; about 100 000
//! free DOFs; issue 40). Its whole statics take more than an hour today, so this times parts:
//!
//! * `full_scale_farm/static_newton_iteration`: one Levenberg–Marquardt iteration of the static
//!   solve from the as-built net (evaluation, Jacobian, factorisation, solve, trial
//!   evaluations): the time between the solver's first and second progress reports;
//! * `full_scale_farm/dynamic_steps`: [`STEPS`] steps of the scene's integrator (midpoint rule,
//!   dt 0.1 s, halvings included) from the as-built state at rest, in the sea.
//!
//! Before sampling, it prints the counts, the time to build the model, Newton iterations and
//! halvings of the dynamic steps, and the memory: resident bytes per free DOF of the built
//! model (mesh, structure, water-load elements) and, over it, of the solvers (water-load
//! assembly, sparse systems, factors, work arrays: the peak while they run), from
//! /proc/self/statm and VmHWM. Run it alone (about 10 min):
//! `cargo bench -p aqua-sim --bench full_scale_farm`. Both parts run on a rayon worker, as
//! `aqua run` does (docs/theory/fem.md#threads). Not part of any test.

use aqua_env::Phase;
use aqua_fem::{StaticControl, StaticProgress};
use aqua_sim::check::free_dofs;
use aqua_sim::plan::Prepared;
use aqua_sim::run::water_loads;
use aqua_sim::{start_integrator, static_equilibrium};
use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use std::path::Path;
use std::time::{Duration, Instant};

/// Dynamic steps timed per sample.
const STEPS: usize = 3;

fn farm() -> Prepared {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/farm-full-scale.toml");
    aqua_sim::prepare(aqua_sim::PrepareOptions::file(&path)).expect("scene")
}

/// Resident memory of this process [bytes] (/proc/self/statm; 0 where there is none).
fn resident() -> usize {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<usize>().ok())
        .map_or(0, |pages| pages * 4096)
}

/// Peak resident memory of this process [bytes] (VmHWM; 0 where there is none).
fn peak() -> usize {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
            line.split_whitespace().nth(1)?.parse::<usize>().ok()
        })
        .map_or(0, |kb| kb * 1024)
}

/// One static Newton iteration: the time between the first progress report (the as-built
/// iterate evaluated) and the second (one iteration accepted or rejected).
fn static_iteration(prep: &Prepared) -> Duration {
    let (mut loads, _) = water_loads(prep, Phase::Static).expect("water loads");
    let mut first: Option<Instant> = None;
    let mut took = Duration::ZERO;
    let mut progress = |_: &StaticProgress| match first {
        None => {
            first = Some(Instant::now());
            StaticControl::Continue
        }
        Some(t) => {
            took = t.elapsed();
            StaticControl::Stop
        }
    };
    let built = &prep.built;
    let sol = static_equilibrium(
        &built.model,
        &built.mesh,
        &mut loads,
        &prep.plan.statics,
        &mut progress,
    )
    .expect("statics");
    assert!(sol.report.interrupted, "stopped after one iteration");
    took
}

/// [`STEPS`] dynamic steps from the as-built state at rest: (wall, Newton iterations, steps
/// halved).
fn dynamic_steps(prep: &Prepared) -> (Duration, usize, usize) {
    let integrator = prep.plan.dynamics.as_ref().expect("a dynamic phase");
    let (mut loads, _) = water_loads(prep, Phase::Dynamic).expect("water loads");
    let mut solver =
        start_integrator(&prep.built.model, integrator, None, &mut loads).expect("integrator");
    let t = Instant::now();
    let mut iterations = 0;
    for _ in 0..STEPS {
        iterations += solver.step(&mut loads).expect("dynamic step").iterations;
    }
    let halved = solver.step_control().map_or(0, |c| c.halvings);
    (t.elapsed(), iterations, halved)
}

fn bench(c: &mut Criterion) {
    let rss0 = resident();
    let t = Instant::now();
    let prep = farm();
    let build = t.elapsed();
    let rss_model = resident().saturating_sub(rss0);
    let dofs = free_dofs(&prep.built);
    eprintln!(
        "full-scale farm: {} nodes, {dofs} free DOFs, {} cable elements, {} water-load \
         elements; built in {:.2} s",
        prep.built.model.n_nodes(),
        prep.built.model.elements().len(),
        prep.built.elements.panels.len()
            + prep.built.elements.lines.len()
            + prep.built.elements.points.len(),
        build.as_secs_f64()
    );
    let before = resident();
    let it = rayon::scope(|_| static_iteration(&prep));
    let after_static = peak();
    let (d, iterations, halved) = rayon::scope(|_| dynamic_steps(&prep));
    let rss_system = peak().saturating_sub(before);
    eprintln!(
        "full-scale farm: one static Newton iteration {:.2} s; {STEPS} dynamic steps from the \
         as-built state {:.2} s ({iterations} Newton iterations, {halved} halvings, {:.2} s per \
         step)",
        it.as_secs_f64(),
        d.as_secs_f64(),
        d.as_secs_f64() / STEPS as f64
    );
    eprintln!(
        "full-scale farm memory: model {:.0} bytes per free DOF ({:.0} MB), solvers \
         {:.0} bytes per free DOF over the model (peak {:.0} MB after the static iteration, \
         {:.0} MB after the dynamic steps)",
        rss_model as f64 / dofs as f64,
        rss_model as f64 / 1e6,
        rss_system as f64 / dofs as f64,
        after_static as f64 / 1e6,
        peak() as f64 / 1e6
    );
    let mut g = c.benchmark_group("full_scale_farm");
    g.sample_size(10);
    g.sampling_mode(SamplingMode::Flat);
    g.measurement_time(Duration::from_secs(30));
    g.bench_function("static_newton_iteration", |b| {
        b.iter_custom(|k| rayon::scope(|_| (0..k).map(|_| static_iteration(&prep)).sum()))
    });
    // About 50 s a sample on this machine: ten samples take about 8 min.
    g.measurement_time(Duration::from_secs(500));
    g.bench_function("dynamic_steps", |b| {
        b.iter_custom(|k| rayon::scope(|_| (0..k).map(|_| dynamic_steps(&prep).0).sum()))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
