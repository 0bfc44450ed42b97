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
fn max_distance(a: &aqua_fem::State, b: &aqua_fem::State) -> f64 {
    a.x.iter()
        .zip(&b.x)
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
    let d = max_distance(&one.state, &lu.state);
    assert!(
        d <= 1e-9,
        "the equilibria differ by {d} m (F_ref {f_ref} N)"
    );
}
