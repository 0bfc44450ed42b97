//! `mesh/coarse-net`: a cage net with too few nodes around or down gets a warning, and the
//! warning bears on the number that is off (the net's volume), measured here against a finer
//! mesh (docs/theory/fem.md#mesh-resolution-warnings).

mod common;
use common::{example, scratch, static_solve};

/// The stability matrix's small cage (24 m circumference, 5 m + 1 m cone), static.
fn small_cage(element_length: f64) -> String {
    example("reference-cage.toml")
        .replace("circumference = 120.0", "circumference = 24.0")
        .replacen("depth = 15.0", "depth = 5.0", 1)
        .replace("cone_depth = 3.0", "cone_depth = 1.0")
        .replace(
            "element_length = 2.5",
            &format!("element_length = {element_length}"),
        )
        .replace("rope_depth = 2.5", "rope_depth = 1.0")
        .replace("kind = \"static+dynamic\"", "kind = \"static\"")
}

/// Whether the build warns `mesh/coarse-net`, and the static volume ratio.
fn warns_and_volume(element_length: f64) -> (bool, f64) {
    let dir = scratch(&format!("coarse-net-{element_length}"));
    let path = dir.join("s.toml");
    std::fs::write(&path, small_cage(element_length)).unwrap();
    let (prep, _, sol) = static_solve(&path);
    let warns = prep
        .built
        .diagnostics
        .iter()
        .any(|d| d.code == "mesh/coarse-net");
    let v0 = aqua_sim::total_volume(&prep.built, prep.built.model.nodes());
    (
        warns,
        aqua_sim::total_volume(&prep.built, &sol.state.x) / v0,
    )
}

#[test]
fn a_net_too_coarse_for_its_shape_is_warned_about() {
    let (coarse_warns, coarse) = warns_and_volume(4.0); // 8 nodes around, 1 side segment
    let (fine_warns, fine) = warns_and_volume(1.0); // 24 around, 5 down
    assert!(coarse_warns && !fine_warns, "{coarse_warns} {fine_warns}");
    // What the warning is about: the coarse net's volume is far from the finer one's.
    assert!(coarse < 0.8 * fine, "volume ratio {coarse} vs {fine}");
}
