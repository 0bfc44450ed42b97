//! Builder and VTK writer speed.
use aqua_mesh::{CageParams, CageType, write_geometry};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    c.bench_function("build SSM default (1057 nodes)", |b| {
        let p = CageParams::new(CageType::Ssm);
        b.iter(|| black_box(p.build().unwrap()))
    });
    c.bench_function("build CCS el=0.5 (fine)", |b| {
        let mut p = CageParams::new(CageType::Ccs);
        p.element_length = Some(0.5);
        b.iter(|| black_box(p.build().unwrap()))
    });
    let mut p = CageParams::new(CageType::Csm);
    p.element_length = Some(0.5);
    let mesh = p.build().unwrap();
    let dir = std::env::temp_dir().join(format!("aqua-mesh-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("csm.vtm");
    c.bench_function("write_geometry CSM el=0.5", |b| {
        b.iter(|| write_geometry(&path, &mesh).unwrap())
    });
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
