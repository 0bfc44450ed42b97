//! The static solve of the reference cage (examples/reference-cage.toml, 0.5 m/s current) over
//! the element-length ladder 10 / 5 / 2.5 m (criterion), plus one timed solve at 1.25 m
//! (printed: ~25 s, too long to sample). Issue 9 targets: the 2.5 m cage in ≤ 3 s, the 1.25 m
//! cage in < 30 s, iterations roughly flat over the ladder. Iterations and free DOFs are
//! printed for each rung (docs/theory/fem.md#static-solver).

use aqua_env::Phase;
use aqua_fem::solve_static;
use aqua_hydro::assembly::LoadAssembly;
use aqua_sim::build::{Built, build};
use aqua_sim::provider::WaterLoads;
use aqua_sim::scene::{Scene, parse_scene};
use criterion::{Criterion, criterion_group, criterion_main};
use std::path::Path;
use std::time::{Duration, Instant};

fn cage(element_length: f64) -> (Scene, Built) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/reference-cage.toml");
    let text = std::fs::read_to_string(&path).expect("example").replace(
        "element_length = 2.5",
        &format!("element_length = {element_length}"),
    );
    let scene = parse_scene(&text, &path).expect("scene");
    let built = build(&scene).expect("model");
    (scene, built)
}

/// One static solve: (wall, Newton iterations).
fn solve(scene: &Scene, built: &Built) -> (Duration, usize) {
    let assembly = LoadAssembly::new(
        built.sea.clone(),
        built.model.n_nodes(),
        built.elements.clone(),
    )
    .unwrap();
    let mut loads = WaterLoads::new(assembly, Phase::Static, &built.elements);
    let t = Instant::now();
    let sol = solve_static(&built.model, &mut loads, &scene.analysis.statics).expect("statics");
    (t.elapsed(), sol.report.iterations)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("reference_cage_static");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(30));
    for el in [10.0, 5.0, 2.5] {
        let (scene, built) = cage(el);
        let (d, it) = solve(&scene, &built);
        eprintln!(
            "element_length {el} m: {} nodes, {it} Newton iterations, {:.2} s",
            built.model.n_nodes(),
            d.as_secs_f64()
        );
        g.bench_function(format!("element_length_{el}"), |b| {
            b.iter_custom(|k| (0..k).map(|_| solve(&scene, &built).0).sum())
        });
    }
    g.finish();
    let (scene, built) = cage(1.25);
    let (d, it) = solve(&scene, &built);
    eprintln!(
        "element_length 1.25 m: {} nodes, {it} Newton iterations, {:.2} s",
        built.model.n_nodes(),
        d.as_secs_f64()
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
