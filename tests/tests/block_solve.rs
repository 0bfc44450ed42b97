//! The block solve of a partitioned farm (docs/theory/fem.md#block-solve): each cage's
//! interior eliminated apart, the interface through its Schur complement. It must give the
//! serial LU's equilibrium to round-off, and the same bits on one thread and on two.

mod common;
use common::*;

/// The bundled farm with one row of two cages, statics only.
fn small_farm_statics() -> aqua_sim::Prepared {
    let text = example("farm.toml");
    for key in ["rows = 2 ", "columns = 3 ", "kind = \"static+dynamic\""] {
        assert!(text.contains(key), "farm.toml has no `{key}`");
    }
    let text = text
        .replace("rows = 2 ", "rows = 1 ")
        .replace("columns = 3 ", "columns = 2 ")
        .replace("kind = \"static+dynamic\"", "kind = \"static\"");
    let dir = scratch("block-solve");
    let path = dir.join("farm.toml");
    std::fs::write(&path, text).unwrap();
    let scene = aqua_sim::read_scene(aqua_sim::SceneInput::File(&path), &[]).unwrap();
    aqua_sim::prepare(aqua_sim::PrepareOptions::scene(scene)).unwrap()
}

/// The static equilibrium of `model` (the prepared scene's, or another partition of it).
fn solve(prep: &aqua_sim::Prepared, model: &aqua_fem::Model) -> aqua_fem::StaticSolution {
    let (mut loads, _) = aqua_sim::run::water_loads(prep, aqua_env::Phase::Static).unwrap();
    aqua_sim::static_equilibrium(
        model,
        &prep.built.mesh,
        &mut loads,
        &prep.plan.statics,
        &mut |_| aqua_fem::StaticControl::Continue,
    )
    .unwrap()
}

/// Largest distance between the nodes of two states [m].
fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_block_solve_finds_the_serial_lus_equilibrium_on_every_thread_count() {
    let prep = small_farm_statics();
    let model = &prep.built.model;
    assert!(model.partition().is_some(), "two cages: a partition");
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| solve(&prep, model))
    };
    let (one, two) = (on(1), on(2));
    // Two cages and the rest (grid, lines, buoys); the interface is the bridle ends.
    let (parts, interface) = one.report.block_solve.expect("the block solve served");
    assert_eq!(parts, 3);
    assert!(
        interface > 0 && interface < 500,
        "{interface} interface DOFs"
    );
    assert_eq!(one.report.iterations, two.report.iterations);
    assert!(one.state.x == two.state.x, "the threads changed the bits");

    let mut whole = model.clone();
    whole.set_partition(None).unwrap();
    let lu = solve(&prep, &whole);
    assert_eq!(lu.report.block_solve, None);
    let f_ref = lu.report.f_ref;
    assert!(lu.report.relative_residual <= 1e-5 && one.report.relative_residual <= 1e-5);
    // The same Newton path to round-off (measured 2.6e-13 m over a 200 m farm in 126
    // iterations); a wrong interface would leave residuals the solve cannot converge on.
    let d = max_distance(&one.state.x, &lu.state.x);
    assert!(
        d <= 1e-9,
        "the equilibria differ by {d} m (F_ref {f_ref} N)"
    );
}

/// The states and the linear solver's counters of a run.
#[derive(Default)]
struct Frames {
    x: Vec<Vec<[f64; 3]>>,
}

impl aqua_sim::Observer for Frames {
    fn frame(&mut self, f: &aqua_sim::Frame<'_>) -> aqua_sim::Result<()> {
        self.x.push(f.state.x.clone());
        Ok(())
    }
}

/// The bundled farm at one row of two cages, 0.5 s of dynamics from the as-built state
/// (HHT-α, Δt = 0.1 s, a frame every step).
fn small_farm_dynamics() -> aqua_sim::Prepared {
    let mut text = example("farm.toml");
    for (from, to) in [
        ("rows = 2 ", "rows = 1 "),
        ("columns = 3 ", "columns = 2 "),
        ("kind = \"static+dynamic\"", "kind = \"dynamic\""),
        ("t_end = 30.0", "t_end = 0.5"),
        ("output_interval = 1.0", "output_interval = 0.1"),
    ] {
        assert!(text.contains(from), "farm.toml has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    let dir = scratch("block-solve-dynamics");
    let path = dir.join("farm.toml");
    std::fs::write(&path, text).unwrap();
    let scene = aqua_sim::read_scene(aqua_sim::SceneInput::File(&path), &[]).unwrap();
    aqua_sim::prepare(aqua_sim::PrepareOptions::scene(scene)).unwrap()
}

/// Runs `prep` on a pool of `threads`: its frames and run record.
fn dynamics(prep: &aqua_sim::Prepared, threads: usize) -> (Frames, aqua_sim::RunRecord) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut frames = Frames::default();
        let mut sim = aqua_sim::Simulation::new(prep).unwrap();
        let (record, result) = sim.run(&mut frames);
        result.unwrap();
        (frames, record)
    })
}

/// In dynamics the symmetric part of the tangent is factorised part by part (an L·D·Lᵀ per
/// cage, in parallel) with the interface through its Schur complement: the same Newton
/// path as one L·D·Lᵀ of the whole, to round-off, and the same bits on one thread and two.
#[test]
fn the_dynamic_block_ldlt_follows_the_whole_ldlt_on_every_thread_count() {
    let prep = small_farm_dynamics();
    assert!(
        prep.built.model.partition().is_some(),
        "two cages: a partition"
    );
    let (one, rec1) = dynamics(&prep, 1);
    let (two, rec2) = dynamics(&prep, 2);
    let (ls, ls2) = (rec1.linear_solver.unwrap(), rec2.linear_solver.unwrap());
    assert_eq!((ls.block_parts, ls2.block_parts), (3, 3));
    assert!(ls.block_interface > 0 && ls.block_interface < 500, "{ls:?}");
    assert_eq!(ls.fallbacks, 0, "{ls:?}");
    assert!(one.x.len() >= 6, "{} frames", one.x.len());
    assert!(one.x == two.x, "the threads changed the bits");

    let mut whole = aqua_sim::prepare(aqua_sim::PrepareOptions::scene(prep.scene.clone())).unwrap();
    whole.built.model.set_partition(None).unwrap();
    let (serial, rec) = dynamics(&whole, 1);
    let lw = rec.linear_solver.unwrap();
    eprintln!("block: {ls:?}\nwhole: {lw:?}");
    assert_eq!(lw.block_parts, 0);
    // The blocks apply S⁻¹ exactly, so the refinement needs the whole factor's sweeps (an
    // approximate S⁻¹ would still be refined to the answer, with more sweeps).
    assert_eq!(
        ls.factorisations, lw.factorisations,
        "{ls:?} against {lw:?}"
    );
    assert!(
        ls.refinement_sweeps.abs_diff(lw.refinement_sweeps) <= 2,
        "{ls:?} against {lw:?}"
    );
    assert_eq!(rec.steps, rec1.steps, "the same steps");
    assert_eq!(serial.x.len(), one.x.len());
    // The refinement solves J·y = b to 1e-10 with either preconditioner, so the Newton
    // iterates differ by round-off only; a wrong interface would leave them apart.
    let d = serial
        .x
        .iter()
        .zip(&one.x)
        .map(|(a, b)| max_distance(a, b))
        .fold(0.0, f64::max);
    assert!(d <= 1e-8, "the runs differ by {d} m");
}
