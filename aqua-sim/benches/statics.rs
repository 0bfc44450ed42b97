//! The static solve of the reference cage (examples/reference-cage.toml, 0.5 m/s current) over
//! the element-length ladder 10 / 5 / 2.5 m (criterion), plus one timed solve at 1.25 m
//! (printed: ~25 s, too long to sample). Issue 9 targets: the 2.5 m cage in ≤ 3 s, the 1.25 m
//! cage in < 30 s, iterations roughly flat over the ladder. Iterations and free DOFs are
//! printed for each rung (docs/theory/fem.md#static-solver).

use aqua_env::Phase;
use aqua_fem::solve_static;
use aqua_sim::plan::Prepared;
use aqua_sim::run::water_loads;
use criterion::{Criterion, criterion_group, criterion_main};
use std::path::Path;
use std::time::{Duration, Instant};

/// The example at another element length, through the library's own `--set` path.
fn cage(element_length: f64) -> Prepared {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/reference-cage.toml");
    let set = [format!("element_length={element_length}")
        .parse()
        .expect("override")];
    aqua_sim::prepare(aqua_sim::PrepareOptions::file(&path).with_overrides(&set)).expect("scene")
}

/// One static solve: (wall, Newton iterations).
fn solve(prep: &Prepared) -> (Duration, usize) {
    let (mut loads, _) = water_loads(prep, Phase::Static).expect("water loads");
    let t = Instant::now();
    let sol = solve_static(&prep.built.model, &mut loads, &prep.plan.statics).expect("statics");
    (t.elapsed(), sol.report.iterations)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("reference_cage_static");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(30));
    for el in [10.0, 5.0, 2.5] {
        let prep = cage(el);
        let (d, it) = solve(&prep);
        eprintln!(
            "element_length {el} m: {} nodes, {it} Newton iterations, {:.2} s",
            prep.built.model.n_nodes(),
            d.as_secs_f64()
        );
        g.bench_function(format!("element_length_{el}"), |b| {
            b.iter_custom(|k| (0..k).map(|_| solve(&prep).0).sum())
        });
    }
    g.finish();
    let prep = cage(1.25);
    let (d, it) = solve(&prep);
    eprintln!(
        "element_length 1.25 m: {} nodes, {it} Newton iterations, {:.2} s",
        prep.built.model.n_nodes(),
        d.as_secs_f64()
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
