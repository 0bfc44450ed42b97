//! Midpoint-rule oracles (docs/theory/fem.md#test-oracles): energy kept on a swinging slack
//! chain and through seabed impacts, and the energy-decaying variant's closed-form amplification,
//! velocity-jump dissipation and midpoint prescribed velocities.

mod common;
mod dynamics_helpers;

use aqua_fem::*;
use common::*;
use dynamics_helpers::*;
use std::f64::consts::PI;

/// The energy-consistent midpoint rule (docs/theory/fem.md#energy-consistent-midpoint) on a
/// tension-only chain released horizontally: it swings, its elements go slack and taut again,
/// and no energy may appear or vanish over 10⁴ steps, whatever the step. (HHT-α's trapezoidal
/// family gains energy at the slack/taut switches; its guard rejects such steps instead.)
#[test]
fn midpoint_keeps_the_energy_of_a_swinging_slack_chain_for_any_step() {
    let (m, _) = swinging_chain();
    for dt in [1e-3, 1e-2, 5e-2] {
        let mut s = DynamicSettings::new(dt, 1e4 * dt);
        s.midpoint = true;
        // 1e-10 is below the round-off of (x1 − x_n)/Δt at these steps.
        s.tol = 1e-8;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        let (mut steps, mut worst, mut scale) = (0, 0.0f64, 0.0f64);
        let mut saw_slack = false;
        while !solver.is_finished() {
            let r = solver.step(&mut NoLoads).unwrap();
            let e = r.energies;
            scale = scale.max(e.kinetic + e.strain).max(e.external_work.abs());
            worst = worst.max(e.numerical_dissipation.abs());
            saw_slack |= solver.outputs().n_slack() > 0;
            steps += 1;
        }
        assert!(steps >= 10_000, "dt {dt}: {steps} steps");
        assert!(saw_slack, "dt {dt}: the chain never went slack");
        assert!(
            worst <= 1e-6 * scale,
            "dt {dt}: energy error {worst} J of {scale} J"
        );
    }
}

/// The midpoint rule with seabed contact (docs/theory/fem.md#energy-consistent-midpoint): the
/// swinging tension-only chain now strikes an elastic, undamped seabed. The contact force is the
/// discrete gradient of the penalty energy, so the total energy — kinetic + strain + gravity +
/// contact, computed here from the state — stays constant through landings and lift-offs.
#[test]
fn midpoint_keeps_the_energy_through_seabed_impacts() {
    let (depth, k_b, d_c) = (6.0, 3e6, 0.05);
    let env = Environment {
        seabed: Some(Seabed {
            depth,
            stiffness: k_b,
            damping: 0.0,
            damping_depth: 1e-2,
            friction: SeabedFriction::default(),
        }),
        ..Default::default()
    };
    let g_acc = env.gravity;
    let mut b = ModelBuilder::new(env);
    let g = b
        .add_group("chain", CableSection::new(2e5, 1.0).with_contact(d_c))
        .unwrap();
    let nodes = add_line(
        &mut b,
        [0.0, 0.0, -1.0],
        [10.0, 0.0, -1.0],
        10,
        10.0,
        g,
        0.0,
    );
    b.fix(nodes[0], Dofs::ALL).unwrap();
    let m = b.build().unwrap();
    // Tributary length of each node of the 10 × 1 m chain (1 kg/m).
    let trib = |k: usize| if k == 0 || k == 10 { 0.5 } else { 1.0 };
    for dt in [1e-3, 1e-2] {
        let mut s = DynamicSettings::new(dt, 3000.0 * dt);
        s.midpoint = true;
        s.tol = 1e-8;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        let total = |e: &Energies, x: &[[f64; 3]]| {
            let mut pot = 0.0;
            for (k, &nd) in nodes.iter().enumerate() {
                pot += trib(k) * g_acc * x[nd][2];
                let pen = (-depth - x[nd][2]).max(0.0);
                pot += 0.5 * k_b * d_c * trib(k) * pen * pen;
            }
            e.kinetic + e.strain + pot
        };
        let e0 = total(&Energies::default(), &solver.state().x);
        let (mut worst, mut lowest) = (0.0f64, f64::INFINITY);
        while !solver.is_finished() {
            let e = solver.step(&mut NoLoads).unwrap().energies;
            let x = &solver.state().x;
            worst = worst.max((total(&e, x) - e0).abs());
            lowest = x.iter().map(|x| x[2]).fold(lowest, f64::min);
        }
        assert!(
            lowest < -depth,
            "dt {dt}: the chain never reached the seabed ({lowest})"
        );
        // 10 kg falling ~5 m: ~500 J of exchange.
        assert!(worst <= 1e-3, "dt {dt}: total energy drifted by {worst} J");
    }
}

/// The energy-decaying midpoint rule (docs/theory/fem.md#energy-decaying-midpoint) on a linear
/// oscillator is the two-step recurrence of its closed-form amplification matrix:
/// (1 + θΩ²/2)·d_{n+1} = (2 − Ω²/2)·d_n − (1 + (1 − θ)Ω²/2)·d_{n−1}, Ω = ωΔt. θ = ½ is the
/// undamped rule; θ > ½ damps, most at Ω = 2/(θ − ½) (ρ 0.90 at Ω = 1 and 0.60 at Ω = 8 for
/// θ = 0.75).
#[test]
fn energy_decaying_midpoint_has_the_closed_form_amplification() {
    for (theta, dt_over_t) in [(0.5, 0.05), (0.75, 0.05), (0.75, 0.2), (1.0, 0.05)] {
        // 45 steps (the fit uses the last 24): the decaying runs keep ≥ 1e-4 of their start,
        // well above the round-off that ends Newton's convergence at tol = 1e-9.
        let (p, q) = midpoint_fit(theta, dt_over_t, 45);
        let om2 = (2.0 * PI * dt_over_t).powi(2);
        let a = 1.0 + 0.5 * theta * om2;
        let (p_exact, q_exact) = (
            (2.0 - 0.5 * om2) / a,
            -(1.0 + 0.5 * (1.0 - theta) * om2) / a,
        );
        eprintln!("theta {theta} dt/T {dt_over_t}: p {p} ({p_exact}), q {q} ({q_exact})");
        // 2e-5: Newton's tolerance is relative to the 1e4 N pretension reactions, about 1e-5
        // of the spring force once the motion has decayed; θ = 0.75 and ½ differ by 0.02 in q
        // at Δt/T = 0.05 and by 0.25 at 0.2.
        assert!(
            (p - p_exact).abs() < 2e-5,
            "theta {theta}: p {p} vs {p_exact}"
        );
        assert!(
            (q - q_exact).abs() < 2e-5,
            "theta {theta}: q {q} vs {q_exact}"
        );
    }
}

/// θ > ½ removes exactly (θ − ½)·‖v_{n+1} − v_n‖²_M per step (docs/theory/fem.md#energy-decaying-midpoint):
/// on the tension-only chain released horizontally, through its slack/taut switches, the
/// numerical dissipation of every step equals that term, and the energy never rises.
#[test]
fn energy_decaying_midpoint_dissipates_its_velocity_jump_term_on_a_slack_chain() {
    let (m, _) = swinging_chain();
    let mass = m.lumped_mass().to_vec();
    for (theta, dt) in [(0.6, 1e-2), (0.75, 5e-2), (1.0, 1e-2)] {
        let mut s = DynamicSettings::new(dt, 10.0);
        s.midpoint = true;
        s.theta = theta;
        s.tol = 1e-8;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        let (mut worst, mut scale, mut lost) = (0.0f64, 0.0f64, 0.0f64);
        let mut saw_slack = false;
        let mut prev = solver.energies().numerical_dissipation;
        while !solver.is_finished() {
            let v0 = solver.state().v.clone();
            // (A halved step is still one accepted step from the state before it.)
            let r = solver.step(&mut NoLoads).unwrap();
            let v1 = &solver.state().v;
            let jump: f64 = (0..mass.len())
                .map(|i| {
                    (0..3)
                        .map(|k| mass[i] * (v1[i][k] - v0[i][k]).powi(2))
                        .sum::<f64>()
                })
                .sum();
            let e = r.energies;
            let step_loss = e.numerical_dissipation - prev;
            prev = e.numerical_dissipation;
            scale = scale.max(e.kinetic + e.strain).max(e.external_work.abs());
            worst = worst.max((step_loss - (theta - 0.5) * jump).abs());
            lost += step_loss;
            saw_slack |= solver.outputs().n_slack() > 0;
        }
        eprintln!("theta {theta}: lost {lost} J of {scale} J, worst step mismatch {worst} J");
        assert!(saw_slack, "theta {theta}: the chain never went slack");
        assert!(
            lost > 1e-3 * scale,
            "theta {theta}: nothing dissipated ({lost} J)"
        );
        assert!(
            worst <= 1e-6 * scale,
            "theta {theta}: {worst} J of {scale} J"
        );
    }
}

/// A prescribed DOF's velocity at the midpoint time is ½(v_n + v_{n+1}) whatever θ
/// (docs/theory/fem.md#energy-decaying-midpoint). A point mass m is towed along +x by a damped
/// one-element cable whose other end is prescribed with constant acceleration a. The free
/// node's midpoint velocity is (x1 − x_n)/h, that of a quadratic path at t_n + h/2, so once the
/// start-up has decayed (critical damping) the cable neither stretches nor shortens and
/// carries exactly T = m·a: ε = m·a/EA. Weighting the towed end's velocity by θ instead would
/// show a relative velocity (θ − ½)·h·a and a damping force c_a·(θ − ½)·h·a/L0: here a quarter
/// of T at θ = 0.75.
#[test]
fn energy_decaying_midpoint_evaluates_prescribed_velocities_at_the_midpoint() {
    let (ea, l0, mass, acc): (f64, f64, f64, f64) = (1e5, 1.0, 10.0, 1.0);
    let omega = (ea / (l0 * mass)).sqrt();
    let c_a = 2.0 * mass * omega * l0;
    let h = 0.5 / omega;
    let env = Environment {
        gravity: 0.0,
        ..Default::default()
    };
    let mut b = ModelBuilder::new(env);
    let g = b
        .add_group(
            "tow",
            // A bar (compression ratio 1): linear in ε and ε̇ on both sides of the rest length.
            CableSection::new(ea, 1e-6)
                .with_compression_ratio(1.0)
                .with_axial_damping(AxialDamping::Coefficient(c_a)),
        )
        .unwrap();
    let tow = b.add_node([0.0, 0.0, 0.0]).unwrap();
    let body = b.add_node([-l0, 0.0, 0.0]).unwrap();
    b.add_cable(tow, body, g, UnstretchedLength::Given(l0))
        .unwrap();
    b.add_point_body(PointBody {
        node: body,
        mass: mass - 0.5e-6 * l0,
        force: [0.0; 3],
        seabed_stiffness: 0.0,
    })
    .unwrap();
    b.fix(
        body,
        Dofs {
            x: false,
            y: true,
            z: true,
        },
    )
    .unwrap();
    // d = a·t²/2, tabulated well past the end of the run (the natural spline's end conditions
    // do not reach the interior).
    let rows: Vec<[f64; 4]> = (0..=400)
        .map(|i| {
            let t = 0.01 * i as f64;
            [t, 0.5 * acc * t * t, 0.0, 0.0]
        })
        .collect();
    b.prescribe(tow, Motion::table(&rows).unwrap()).unwrap();
    let m = b.build().unwrap();
    let expected = mass * acc / ea;
    for theta in [0.5, 0.75, 1.0] {
        let mut s = DynamicSettings::new(h, 1.5);
        s.midpoint = true;
        s.theta = theta;
        s.tol = 1e-9;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        solver.run(&mut NoLoads, |_, _| true).unwrap();
        let x = &solver.state().x;
        let strain = (x[tow][0] - x[body][0]) / l0 - 1.0;
        assert!(
            (strain - expected).abs() <= 1e-6 * expected,
            "theta {theta}: strain {strain} vs m·a/EA = {expected}"
        );
    }
}
