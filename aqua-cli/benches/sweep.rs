//! `aqua sweep --local`: the wall time of 6 load cases of the mooring chain
//! (examples/chain-cases.toml without its storm case, 80 segments, 30 s simulated each) run
//! one at a time and two at a time. On 2 cores the aim is a speed-up of at least 1.7.
//! The study's own overhead is printed by `aqua study` ("study overhead beyond the runs").

use criterion::{Criterion, criterion_group, criterion_main};
use std::path::Path;
use std::process::Command;
use std::time::Duration;

fn sweep(cases: &Path, jobs: &str, out: &Path) {
    let status = Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args([
            "sweep",
            cases.to_str().unwrap(),
            "--local",
            "--jobs",
            jobs,
            "--out",
        ])
        .arg(out)
        .stderr(std::process::Stdio::null())
        .status()
        .expect("aqua");
    assert!(status.success());
}

fn bench(c: &mut Criterion) {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
    let dir = std::env::temp_dir().join(format!("aqua-bench-sweep-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = dir.join("cases.toml");
    std::fs::write(
        &cases,
        format!(
            "scene = \"{}\"\nset = {{ \"analysis.dynamic.t_end\" = 30.0, \"sea.current.kind\" = \"uniform\" }}\n\
             [vary]\n\"sea.current.velocity\" = [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]]\n\
             \"prescribed.0.period\" = [8.0, 10.0, 12.0]\n",
            examples.join("mooring-chain.toml").display()
        ),
    )
    .unwrap();
    let mut g = c.benchmark_group("sweep_6_chain_cases");
    g.sample_size(10).measurement_time(Duration::from_secs(30));
    for jobs in ["1", "2"] {
        g.bench_function(format!("local_jobs_{jobs}"), |b| {
            b.iter(|| sweep(&cases, jobs, &dir.join(format!("out{jobs}"))))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
