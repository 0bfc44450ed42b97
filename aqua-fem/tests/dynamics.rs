//! Dynamic oracles (docs/theory/fem.md#test-oracles): explicit vs implicit, the explicit step
//! estimate, a slack round trip, consistent mass with water loads and a chain landing on a damped
//! seabed.

mod common;
mod dynamics_helpers;

use aqua_fem::*;
use common::*;
use dynamics_helpers::*;

#[test]
fn explicit_and_implicit_agree_on_a_swinging_chain() {
    let (m, tip) = swinging_chain();
    let t_end = 1.5;
    let mut s = DynamicSettings::new(1e-3, t_end);
    s.alpha = 0.05;
    let mut implicit = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
    implicit.run(&mut NoLoads, |_, _| true).unwrap();
    for scheme in [ExplicitScheme::SemiImplicitEuler, ExplicitScheme::Rk4] {
        let mut es = ExplicitSettings::new(t_end);
        es.scheme = scheme;
        let mut explicit = ExplicitSolver::new(&m, es, None, &mut NoLoads).unwrap();
        while !explicit.is_finished() {
            explicit.step(&mut NoLoads).unwrap();
        }
        let (a, b) = (implicit.state().x[tip], explicit.state().x[tip]);
        let d = ((a[0] - b[0]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
        // Tolerance: 1 % of the chain length on the tip position after 1.5 s of swing.
        assert!(d < 0.1, "{scheme:?}: tip {a:?} vs {b:?}");
        assert!(explicit.state().x[tip][2] < 5.0, "the chain has swung down");
    }
}

#[test]
fn explicit_step_estimate_and_user_dt() {
    let (m, _) = swinging_chain();
    let mut es = ExplicitSettings::new(0.01);
    es.dt = Some(1.0);
    let solver = ExplicitSolver::new(&m, es.clone(), None, &mut NoLoads).unwrap();
    // Gershgorin bound for this chain: 2/ω = 2/√(4·EA/(L0·m)) with m = μL0 (interior node).
    let est = 0.5 * 2.0 / (4.0 * 2e5 / 1.0 / 1.0f64).sqrt();
    assert!(
        solver.dt() <= est * 1.0001 && solver.dt() > 0.5 * est,
        "{} vs {est}",
        solver.dt()
    );
    assert_eq!(solver.warnings().len(), 1);
    es.dt_fixed = true;
    assert!(ExplicitSolver::new(&m, es, None, &mut NoLoads).is_err());
}

#[test]
fn line_pulled_through_slack_and_back_does_not_blow_up() {
    // Taut line, fairlead moved 20 % towards the anchor (slack, compressed) and back.
    let env = Environment {
        seabed: Some(Seabed::new(30.0)),
        ..Default::default()
    };
    let mut b = ModelBuilder::new(env);
    let sec = CableSection::new(1e7, 20.0)
        .with_contact(0.05)
        .with_axial_damping(AxialDamping::Ratio(0.05));
    let g = b.add_group("line", sec).unwrap();
    let nodes = add_line(
        &mut b,
        [0.0, 0.0, -30.0],
        [40.0, 0.0, -5.0],
        40,
        47.0,
        g,
        0.0,
    );
    b.fix(nodes[0], Dofs::ALL).unwrap();
    let rows = [
        [0.0, 0.0, 0.0, 0.0],
        [5.0, -10.0, 0.0, -5.0],
        [10.0, 3.0, 0.0, 1.0],
        [15.0, 0.0, 0.0, 0.0],
        [30.0, 0.0, 0.0, 0.0],
    ];
    b.prescribe(nodes[40], Motion::table(&rows).unwrap())
        .unwrap();
    let m = b.build().unwrap();
    let st = solve_static(&m, &mut NoLoads, &StaticSettings::default()).unwrap();
    let t_static = st.outputs.tension[39];
    let mut s = DynamicSettings::new(0.02, 40.0);
    // Mass-proportional damping settles the swing in air after the excursion.
    s.rayleigh = [0.5, 0.0];
    let mut solver = DynamicSolver::new(&m, s, Some(&st.state), &mut NoLoads).unwrap();
    let mut min_t = f64::INFINITY;
    let mut max_t: f64 = 0.0;
    let mut saw_slack = false;
    while !solver.is_finished() {
        solver.step(&mut NoLoads).unwrap();
        let o = solver.outputs();
        assert!(o.tension.iter().all(|t| t.is_finite()));
        saw_slack |= o.n_slack() > 10;
        min_t = min_t.min(o.tension.iter().cloned().fold(f64::INFINITY, f64::min));
        max_t = max_t.max(o.tension.iter().cloned().fold(0.0, f64::max));
    }
    assert!(saw_slack, "the line went slack");
    // Slack elements push at most r_c·EA·|ε|; axial damping may add a small negative part.
    assert!(min_t > -0.01 * max_t, "min tension {min_t} vs max {max_t}");
    let t_end = solver.outputs().tension[39];
    assert!(
        ((t_end - t_static) / t_static).abs() < 0.05,
        "{t_end} vs {t_static}"
    );
    assert!(max_t.is_finite());
}

#[test]
fn consistent_mass_and_water_loads_run() {
    let env = Environment {
        seabed: Some(Seabed::new(20.0)),
        ..Default::default()
    };
    let mut b = ModelBuilder::new(env);
    let g = b
        .add_group("rope", CableSection::new(1e6, 3.0).with_contact(0.04))
        .unwrap();
    let nodes = add_line(
        &mut b,
        [0.0, 0.0, -20.0],
        [25.0, 0.0, -2.0],
        30,
        33.0,
        g,
        3.0,
    );
    b.fix(nodes[0], Dofs::ALL).unwrap();
    b.prescribe(
        nodes[30],
        Motion::harmonic([1.0, 0.0, 0.0], [0.0; 3], 4.0, 0.0, 4.0).unwrap(),
    )
    .unwrap();
    let m = b.build().unwrap();
    let mut w = WaterLines::new(&m, 0.04, 1.2, [0.3, 0.0, 0.0]);
    let st = solve_static(&m, &mut w, &StaticSettings::default()).unwrap();
    let mut w_fd = w.clone();
    w_fd.analytic = false;
    let mut ends = Vec::new();
    let mut w_c = w.clone();
    for (mass, prov) in [
        (MassMatrix::Lumped, &mut w),
        (MassMatrix::Consistent, &mut w_c),
        (MassMatrix::Lumped, &mut w_fd),
    ] {
        let mut s = DynamicSettings::new(0.05, 6.0);
        s.mass_matrix = mass;
        let mut solver = DynamicSolver::new(&m, s, Some(&st.state), prov).unwrap();
        let mut iters = 0;
        while !solver.is_finished() {
            iters += solver.step(prov).unwrap().iterations;
        }
        assert!(iters < 10 * solver.n_steps(), "{iters} iterations");
        ends.push(solver.state().x[nodes[15]]);
    }
    // Finite-difference damping Jacobian gives the same trajectory (only the tangent differs).
    let d = (0..3)
        .map(|k| (ends[0][k] - ends[2][k]).abs())
        .fold(0.0, f64::max);
    assert!(d < 1e-4, "{:?} vs {:?}", ends[0], ends[2]);
    // Lumped and consistent mass agree at this slow excitation.
    let d = (0..3)
        .map(|k| (ends[0][k] - ends[1][k]).abs())
        .fold(0.0, f64::max);
    assert!(d < 0.05, "{:?} vs {:?}", ends[0], ends[1]);
}

/// A horizontal chain dropped 5 cm onto a damped seabed (docs/theory/fem.md#seabed-contact).
/// With the damping switched on at full strength at δ = 0+, the contact force jumped by
/// c_b·C·v (several times the chain's weight here) across the bed plane and Newton cycled
/// between the two sides until the step was halved (5 halvings for "no convergence" with
/// δ_c → 0); with the damping ramped in over δ_c the force is continuous, and backtracking
/// breaks the remaining cycles at its kinks, so Newton converges at every step of both
/// schemes. The chain then comes to rest with the bed carrying its whole weight.
#[test]
fn chain_lands_on_a_damped_seabed_without_newton_failures() {
    let (depth, d_c, mu, drop) = (6.0, 0.05, 5.0, 0.05);
    for midpoint in [false, true] {
        let env = Environment {
            seabed: Some(Seabed::new(depth)),
            ..Default::default()
        };
        let g_acc = env.gravity;
        let mut b = ModelBuilder::new(env);
        let g = b
            .add_group("chain", CableSection::new(1e7, mu).with_contact(d_c))
            .unwrap();
        let z0 = -depth + drop;
        let nodes = add_line(&mut b, [0.0, 0.0, z0], [10.0, 0.0, z0], 10, 10.0, g, 0.0);
        let m = b.build().unwrap();
        let mut s = DynamicSettings::new(0.05, 8.0);
        s.alpha = 0.1;
        s.midpoint = midpoint;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        let mut deepest = 0.0f64;
        while !solver.is_finished() {
            solver.step(&mut NoLoads).unwrap();
            deepest = deepest.max(-depth - solver.state().x[nodes[5]][2]);
        }
        // Newton itself must not fail. (HHT's energy guard may still reject steps: the
        // penalty contact, ω ≈ 170 rad/s, is not resolved by Δt = 0.05 s.)
        let c = solver.step_control();
        let newton: usize = c
            .reasons
            .iter()
            .filter(|(r, _)| *r != aqua_fem::FailureKind::EnergyCreated)
            .map(|(_, n)| n)
            .sum();
        assert_eq!(newton, 0, "midpoint {midpoint}: halvings {:?}", c.reasons);
        let k = 3e6 * d_c;
        let w = mu * g_acc;
        if midpoint {
            // Energy-consistent contact, dissipative damping: the penetration stays within
            // the free-fall energy stored in the bed spring, ½·k_b·d_c·δ² ≤ w·(drop + δ).
            let bound = (w + (w * w + 2.0 * k * w * drop).sqrt()) / k;
            assert!(deepest <= bound, "penetration {deepest} m > {bound} m");
        }
        // At rest: Σ f_bed = μ·L·g, all through the bed, the chain sunk by w/(k_b·d_c).
        let bed: f64 = solver.outputs().seabed_force.iter().map(|f| f[2]).sum();
        let weight = mu * 10.0 * g_acc;
        assert!(
            (bed - weight).abs() < 1e-3 * weight,
            "midpoint {midpoint}: bed carries {bed} N of {weight} N"
        );
        let sink = -depth - solver.state().x[nodes[5]][2];
        assert!(
            (sink - w / k).abs() < 1e-2 * w / k,
            "midpoint {midpoint}: sunk {sink} m vs {}",
            w / k
        );
    }
}
