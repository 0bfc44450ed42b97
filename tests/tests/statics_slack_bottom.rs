//! A model-scale cage with a flat bottom and light sinkers in a weak current: the net streams
//! downstream, its flat bottom of slack twines nearly along the flow, and the water loads
//! (orientation-dependent screen drag and lift, the wake of the upstream half) are not
//! conservative. Backtracking on an energy merit with the loads frozen at the iterate then
//! cycled without end on this cage; the static solve must still find the equilibrium
//! (docs/theory/fem.md#static-solver).

use aqua_env::Phase;
use aqua_fem::solve_static;
mod common;
use common::*;

/// The cage: 1.75 m across, 1.5 m deep, flat bottom, Sn 0.347 (twine 1.41 mm, half mesh
/// 8.3 mm, E = 40 MPa), 6.5 N per metre of sinkers, top ring fixed, fresh water; the current
/// `speed` [m/s] along x, the screen model and the wake model as given.
fn scene(element_length: f64, screen: &str, speed: f64, wake: &str) -> String {
    format!(
        r#"name = "slack-bottom"
[sea]
depth = 2.2
[sea.water]
density = 1000.0
kinematic_viscosity = 1.0e-6
[sea.current]
kind = "uniform"
velocity = [{speed}, 0.0, 0.0]

[[cage]]
type = "CSM"
diameter = 1.75
depth = 1.5
cone_depth = 0.0
element_length = {element_length}
frame_offset = 0.01
rope_depth = 0.02
sinker_weight_per_metre = 6.5189
tip_weight = 0.0
fixed = ["top_ring"]
net.twine_diameter = 1.41e-3
net.half_mesh = 8.3e-3
net.solidity = 0.347
net.youngs_modulus = 4.0e7
net.density = 1140.0
net.screen_model = "{screen}"
net.wake = {{ model = "{wake}" }}
[cage.groups.ropes]
diameter = 0.002
youngs_modulus = 1.0e9
density = 1140.0
[cage.groups.tie_lines]
diameter = 0.002
youngs_modulus = 1.0e9
density = 1140.0
[cage.groups.top_ring]
diameter = 0.01
wall_thickness = 0.001
[cage.groups.top_links]
diameter = 0.002
wall_thickness = 0.0009
youngs_modulus = 1.0e9
density = 1140.0

[analysis]
kind = "static"
"#
    )
}

/// Solves the cage at 0.22 m elements and checks the equilibrium: internal forces cancel in
/// pairs, so the support reactions and the water loads must sum to zero along x and y
/// (weights, sinkers and buoyancy are vertical), to the solver's tolerance summed over the
/// free DOFs; the drag points downstream.
fn solve_and_check_balance(screen: &str, speed: f64, wake: &str, max_iterations: usize) {
    let case = format!("{screen} at {speed} m/s, wake {wake}");
    let dir = scratch(&format!("slack-bottom-{screen}-{speed}-{wake}"));
    let path = dir.join("cage.toml");
    std::fs::write(&path, scene(0.22, screen, speed, wake)).unwrap();
    let prep = aqua_sim::prepare(aqua_sim::PrepareOptions::file(&path)).unwrap();
    let (mut loads, _) = aqua_sim::run::water_loads(&prep, Phase::Static).unwrap();
    let sol = solve_static(&prep.built.model, &mut loads, &prep.plan.statics)
        .unwrap_or_else(|e| panic!("{case}: static solve failed: {e}"));
    let rep = &sol.report;
    assert!(!rep.interrupted);
    // The cost of the whole solve, wake re-solves included.
    eprintln!("{case}: {} Newton iterations", rep.iterations);
    assert!(
        rep.iterations <= max_iterations,
        "{case}: {} Newton iterations",
        rep.iterations
    );
    let tol = prep.plan.statics.tol;
    assert!(
        rep.relative_residual <= tol,
        "{case}: ‖r‖/F_ref = {}",
        rep.relative_residual
    );
    let out = &sol.outputs;
    let n_free = 3 * prep.built.model.n_nodes();
    let bound = (n_free as f64).sqrt() * tol * rep.f_ref;
    let mut drag = [0.0; 3];
    for k in 0..2 {
        let r: f64 = out.reaction.iter().map(|f| f[k]).sum();
        let h: f64 = out.hydro_force.iter().map(|f| f[k]).sum();
        let b: f64 = out.seabed_force.iter().map(|f| f[k]).sum();
        assert!(
            (r + h + b).abs() <= bound,
            "{case}, axis {k}: reactions {r} N + water loads {h} N + bed {b} N (bound {bound:.2e} N)"
        );
        drag[k] = h;
    }
    // No check of the side force: bi2014 at 0.26 m/s without wake settles on an asymmetric
    // equilibrium (side force 1.2 N of 58 N drag; the solver before this one found its mirror
    // image at 0.172 m elements).
    assert!(drag[0] > 10.0, "{case}: drag {} N", drag[0]);
}

/// S1 at 0.26 m/s with the Løland wake: the solver that froze the loads in its merit and had
/// no retry gave up ("static solve failed at load factor 1e-4" after halving the load 14
/// times, about a minute).
#[test]
fn s1_cage_reaches_equilibrium_at_both_speeds_with_and_without_wake() {
    for speed in [0.26, 0.5] {
        for wake in ["loland", "none"] {
            // At most 700 here.
            solve_and_check_balance("S1", speed, wake, 1_500);
        }
    }
}

/// bi2014 at 0.26 m/s without wake: the same solver gave up likewise.
#[test]
fn bi2014_cage_reaches_equilibrium_at_both_speeds_with_and_without_wake() {
    for speed in [0.26, 0.5] {
        for wake in ["loland", "none"] {
            solve_and_check_balance("bi2014", speed, wake, 1_500);
        }
    }
}

/// S5 at 0.26 m/s without wake: its fitted lift did not vanish with the flow in the net plane,
/// so the streaming bottom rested on a jump of the lift and the solve gave up; with the lift
/// tapered to zero there (docs/theory/hydrodynamics.md#model-s5) it reaches equilibrium (2 387
/// iterations). At 0.5 m/s with the Løland wake S5 still gives up (docs/notes/statics-gives-up.md).
#[test]
fn s5_cage_reaches_equilibrium_with_its_lift_tapered_in_the_net_plane() {
    solve_and_check_balance("S5", 0.26, "none", 4_000);
}
