//! The reference cage (examples/reference-cage.toml: SSM, 1057 nodes, 1920 cable elements,
//! 672 screen panels, 0.5 m/s current), 10 s simulated at dt = 0.1 s with HHT-α (α = 0.3):
//! time per dynamic step, (a) continuing from the static equilibrium (the example's run) and
//! (b) starting from the as-built net at rest with the current ramped up over 10 s (the hard
//! case: the net swings back), and a Newton iteration against one bare factorise + solve of the
//! same matrix with each linear solver. Issue 15's aims: under 4 ms per step, ratio ≤ 1.5.

use aqua_env::Phase;
use aqua_fem::{DynamicSettings, DynamicSolver, LinearSolverKind, State, solve_static};
use aqua_hydro::assembly::LoadAssembly;
use aqua_sim::provider::WaterLoads;
use aqua_sim::{PrepareOptions, prepare};
use criterion::{Criterion, criterion_group, criterion_main};
use std::path::Path;
use std::time::{Duration, Instant};

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/reference-cage.toml");
    let prep = prepare(PrepareOptions::file(&path)).expect("scene");
    let (scene, built) = (&prep.scene, &prep.built);
    let assembly = LoadAssembly::new(
        built.sea.clone(),
        built.model.n_nodes(),
        built.elements.clone(),
    )
    .unwrap();
    let mut loads = WaterLoads::new(assembly, Phase::Static, &built.elements);
    let t = Instant::now();
    let stat = solve_static(&built.model, &mut loads, &scene.analysis.statics).expect("statics");
    eprintln!(
        "static solve: {:.2} s, {} Newton iterations",
        t.elapsed().as_secs_f64(),
        stat.report.iterations
    );
    loads.phase = Phase::Dynamic;
    let run = |initial: Option<&State>, loads: &mut WaterLoads| -> (Duration, usize, usize) {
        let mut s = DynamicSettings::new(0.1, 10.0);
        s.alpha = 0.3;
        s.output_interval = Some(10.0);
        let mut solver = DynamicSolver::new(&built.model, s, initial, loads).expect("solver");
        let t = Instant::now();
        let mut steps = 0;
        let mut iters = 0;
        while !solver.is_finished() {
            let r = solver.step(loads).expect("step");
            steps += 1;
            iters += r.iterations;
        }
        (t.elapsed(), steps, iters)
    };
    let (d, n, it) = run(Some(&stat.state), &mut loads);
    eprintln!(
        "from equilibrium: {n} steps, {:.2} ms/step, {:.2} Newton iterations/step",
        1e3 * d.as_secs_f64() / n as f64,
        it as f64 / n as f64
    );
    // A Newton iteration against one bare factorise + solve of the same matrix, per solver.
    for kind in [LinearSolverKind::Symmetric, LinearSolverKind::Lu] {
        let mut s = DynamicSettings::new(0.1, 1e9);
        s.alpha = 0.3;
        s.linear_solver = kind;
        let mut solver =
            DynamicSolver::new(&built.model, s, Some(&stat.state), &mut loads).expect("solver");
        let k = 40;
        let t0 = Instant::now();
        let mut iters = 0;
        for _ in 0..k {
            iters += solver.step(&mut loads).expect("step").iterations;
        }
        let per_step = t0.elapsed().as_secs_f64() / k as f64;
        let per_iter = t0.elapsed().as_secs_f64() / iters.max(1) as f64;
        let t0 = Instant::now();
        for _ in 0..k {
            solver.factorize_and_solve_last().expect("factorise");
        }
        let bare = t0.elapsed().as_secs_f64() / k as f64;
        let st = solver.linear_solver_stats();
        eprintln!(
            "{kind:?}: {:.2} ms/step, {:.2} ms per Newton iteration, {:.2} ms bare factorise+solve, ratio {:.2}; {:.1} refinement sweeps per solve; {st:?}",
            1e3 * per_step,
            1e3 * per_iter,
            1e3 * bare,
            per_iter / bare,
            st.refinement_sweeps as f64 / (iters + k) as f64
        );
    }
    let mut g = c.benchmark_group("reference_cage_10s_dt0.1");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(20));
    g.bench_function("from_static_equilibrium_per_step", |b| {
        b.iter_custom(|k| {
            let mut total = Duration::ZERO;
            for _ in 0..k {
                let (d, n, _) = run(Some(&stat.state), &mut loads);
                total += d / n as u32;
            }
            total
        })
    });
    // Dynamics from rest: the current ramps over its ramp time.
    let sea_ramped = aqua_env::Sea::clone(&built.sea).with_current_ramp(true);
    let assembly =
        LoadAssembly::new(sea_ramped, built.model.n_nodes(), built.elements.clone()).unwrap();
    let mut ramped = WaterLoads::new(assembly, Phase::Dynamic, &built.elements);
    let (d, n, it) = run(None, &mut ramped);
    eprintln!(
        "from rest: {n} steps, {:.2} ms/step, {:.2} Newton iterations/step",
        1e3 * d.as_secs_f64() / n as f64,
        it as f64 / n as f64
    );
    g.bench_function("from_rest_per_step", |b| {
        b.iter_custom(|k| {
            let mut total = Duration::ZERO;
            for _ in 0..k {
                let (d, n, _) = run(None, &mut ramped);
                total += d / n as u32;
            }
            total
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
