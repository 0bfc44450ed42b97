//! Irregular sea, 200 components, 10 000 points, one time instant (issue target: < 20 ns per
//! component·point).

use aqua_env::{BuildOptions, FlowPoint, Phase, SeaSpec};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let spec: SeaSpec = toml::from_str(
        "depth = 60\n[current]\nkind = \"uniform\"\nvelocity = [0.5, 0, 0]\n[waves]\nkind = \"irregular\"\n\
         [waves.spectrum]\nhs = 3\ntp = 9\ncomponents = 200\nspreading_s = 8\n",
    )
    .unwrap();
    let (sea, _) = spec.build(&BuildOptions::default()).unwrap();
    let n = 10_000;
    let points: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let a = i as f64 * 0.37;
            [25.0 * a.cos(), 25.0 * a.sin(), -((i % 150) as f64) * 0.1]
        })
        .collect();
    let mut out = vec![FlowPoint::default(); n];
    let mut g = c.benchmark_group("sea");
    g.throughput(Throughput::Elements((n * 200) as u64));
    g.sample_size(30);
    g.bench_function("irregular_200x10000", |b| {
        b.iter(|| {
            sea.eval(black_box(123.4), Phase::Dynamic, &points, &mut out);
            black_box(&out);
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
