//! Builder and VTK writer speed.
use aqua_mesh::{CageParams, CageType, VtkArrays, write_vtu};
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
    let path = dir.join("csm.vtu");
    c.bench_function("write_vtu CSM el=0.5", |b| {
        b.iter(|| write_vtu(&path, &mesh, None, &VtkArrays::default()).unwrap())
    });
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
