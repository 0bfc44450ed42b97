//! Output cost, on disk (a directory under the target directory, not a RAM disk):
//!
//! * `reference_cage/write_step`: one output step of the reference cage
//!   (examples/reference-cage.toml: 1057 nodes, 1920 cable elements, 672 panels) written by
//!   [`RunFiles::write_step`] — the blocks, the `.vtm`, the `.pvd` entry and a `summary.csv`
//!   row — from frames captured in a short run (statics, then 1 s of dynamics). Target: ≤ 10 %
//!   of a dynamic step (5 ms). `write_step` measures steps written back to back (the
//!   writer thread's throughput), `write_step_handover` what the run loop pays per step when
//!   the steps are apart in time, as in a run (the rest is done by the writer thread).
//! * `mooring_chain_60s`: the whole `aqua run` of examples/mooring-chain.toml with
//!   `output_interval = 0.1` (601 output steps), with the files written and without any output.
//!
//! Also prints the bytes of one output step.

use aqua_fem::{Outputs, State};
use aqua_sim::RunFiles;
use aqua_sim::{Frame, Observer, Override, PrepareOptions, Prepared, SummaryRow};
use criterion::{Criterion, criterion_group, criterion_main};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name)
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("bench-outputs-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn prepare(file: &str, set: &[&str]) -> Prepared {
    let set: Vec<Override> = set.iter().map(|s| s.parse().unwrap()).collect();
    aqua_sim::prepare(PrepareOptions::file(&example(file)).with_overrides(&set)).expect("scene")
}

/// Keeps copies of every frame.
#[derive(Default)]
struct Capture(Vec<(State, Outputs, Vec<f64>, SummaryRow)>);

impl Observer for Capture {
    fn frame(&mut self, f: &Frame<'_>) -> aqua_sim::Result<()> {
        self.0.push((
            f.state.clone(),
            f.outputs.clone(),
            f.wake.to_vec(),
            f.row.clone(),
        ));
        Ok(())
    }
}

/// Writes every frame, like `aqua run`.
struct Write<'a> {
    prep: &'a Prepared,
    files: RunFiles,
}

impl Observer for Write<'_> {
    fn frame(&mut self, f: &Frame<'_>) -> aqua_sim::Result<()> {
        self.files
            .write_step(&self.prep.built, f.state, f.outputs, f.wake, f.row)
    }
}

/// Writes nothing.
struct Discard;

impl Observer for Discard {}

fn dir_bytes(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| {
            let m = e.metadata().unwrap();
            if m.is_dir() {
                dir_bytes(&e.path())
            } else {
                m.len()
            }
        })
        .sum()
}

fn bench(c: &mut Criterion) {
    // Reference cage: frames of a short run, then written over and over.
    let prep = prepare(
        "reference-cage.toml",
        &[
            "analysis.dynamic.t_end=1.0",
            "analysis.dynamic.output_interval=0.1",
        ],
    );
    let mut sim = aqua_sim::Simulation::new(&prep).unwrap();
    let mut cap = Capture::default();
    let (_, r) = sim.run(&mut cap);
    r.unwrap();
    let frames = cap.0;
    eprintln!("reference cage: {} frames captured", frames.len());
    let dir = scratch("cage");
    let mut files = RunFiles::create(&dir, &prep.scene.name, &prep.built).unwrap();
    let (s, o, w, row) = &frames[0];
    files.write_step(&prep.built, s, o, w, row).unwrap();
    files.flush().unwrap();
    let step_dir = dir.join(format!("{}_000000", prep.scene.name));
    eprintln!(
        "reference cage: one output step = {} bytes ({} in the block files)",
        dir_bytes(&step_dir)
            + std::fs::metadata(dir.join(format!("{}_000000.vtm", prep.scene.name)))
                .unwrap()
                .len(),
        dir_bytes(&step_dir)
    );
    let mut g = c.benchmark_group("outputs");
    g.sample_size(20);
    g.measurement_time(Duration::from_secs(10));
    let mut t = 1.0;
    // Back to back: the writer thread's throughput (the run loop waits on the full queue).
    g.bench_function("reference_cage/write_step", |b| {
        b.iter_custom(|k| {
            // A fresh series every batch keeps the directory (and .pvd) to k steps.
            let mut files = RunFiles::create(&dir, &prep.scene.name, &prep.built).unwrap();
            let start = Instant::now();
            for i in 0..k as usize {
                let (s, o, w, row) = &frames[i % frames.len()];
                let mut s = s.clone();
                t += 0.1;
                s.t = t;
                files.write_step(&prep.built, &s, o, w, row).unwrap();
            }
            drop(files);
            start.elapsed()
        })
    });
    // What the run loop pays per output step when the solver keeps the writer ahead (the
    // steps are apart in time, as in a run): the checks, the copy and the hand-over only.
    g.bench_function("reference_cage/write_step_handover", |b| {
        b.iter_custom(|k| {
            let mut files = RunFiles::create(&dir, &prep.scene.name, &prep.built).unwrap();
            let mut spent = Duration::ZERO;
            for i in 0..k as usize {
                let (s, o, w, row) = &frames[i % frames.len()];
                let mut s = s.clone();
                t += 0.1;
                s.t = t;
                let start = Instant::now();
                files.write_step(&prep.built, &s, o, w, row).unwrap();
                spent += start.elapsed();
                files.flush().unwrap();
            }
            spent
        })
    });
    g.finish();

    // The 60 s chain run, outputs every 0.1 s.
    let prep = prepare(
        "mooring-chain.toml",
        &["analysis.dynamic.output_interval=0.1"],
    );
    let dir = scratch("chain");
    let mut g = c.benchmark_group("mooring_chain_60s");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(20));
    g.bench_function("outputs_on_disk", |b| {
        b.iter_custom(|k| {
            let mut total = Duration::ZERO;
            for _ in 0..k {
                // Removing the previous run's files is not part of the run.
                let _ = std::fs::remove_dir_all(&dir);
                let start = Instant::now();
                let files = RunFiles::create(&dir, &prep.scene.name, &prep.built).unwrap();
                let mut w = Write { prep: &prep, files };
                let mut sim = aqua_sim::Simulation::new(&prep).unwrap();
                let (rec, r) = sim.run(&mut w);
                r.unwrap();
                drop(w);
                total += start.elapsed();
                assert_eq!(rec.frames, 601);
            }
            total
        })
    });
    g.bench_function("no_outputs", |b| {
        b.iter(|| {
            let mut sim = aqua_sim::Simulation::new(&prep).unwrap();
            let (rec, r) = sim.run(&mut Discard);
            r.unwrap();
            assert_eq!(rec.frames, 601);
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
