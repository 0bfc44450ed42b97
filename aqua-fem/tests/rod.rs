//! Rod (pipe) oracles (docs/theory/fem.md#rod): torsion of a straight pipe, a clamped
//! cantilever at order 2, a quarter ring loaded out of its plane (bending and torsion together,
//! Castigliano), the pinched ring of thin-ring theory with an out-of-plane imperfection, and the
//! energy of a swinging, twisting pipe under the energy-consistent midpoint rule.

use aqua_fem::*;
use std::f64::consts::PI;

fn no_gravity() -> Environment {
    Environment {
        gravity: 0.0,
        ..Default::default()
    }
}

fn load(b: &mut ModelBuilder, node: usize, force: [f64; 3]) {
    b.add_point_body(PointBody {
        node,
        mass: 0.0,
        force,
        seabed_stiffness: 0.0,
    })
    .unwrap();
}

fn joined(b: &mut ModelBuilder, nodes: &[usize], ea: f64, closed: bool) {
    let g = b
        .add_group(
            "pipe",
            CableSection::new(ea, 1.0).with_compression_ratio(1.0),
        )
        .unwrap();
    let n = nodes.len();
    let m = if closed { n } else { n - 1 };
    for j in 0..m {
        b.add_cable(
            nodes[j],
            nodes[(j + 1) % n],
            g,
            UnstretchedLength::AsBuilt {
                initial_tension: 0.0,
            },
        )
        .unwrap();
    }
}

fn statics(m: &Model) -> StaticSolution {
    let st = StaticSettings {
        tol: 1e-11,
        ..Default::default()
    };
    solve_static(m, &mut NoLoads, &st).unwrap()
}

/// A straight pipe clamped at one end and twisted by an end torque T turns each edge by
/// T·s/GJ at its midpoint s (the last by T·(L − h/2)/GJ), and a torque alone bends nothing.
#[test]
fn end_torque_twists_a_straight_pipe_by_tl_over_gj() {
    let (l, n, gj, ei, t) = (3.0, 12, 250.0, 400.0, 7.0);
    let mut b = ModelBuilder::new(no_gravity());
    let nodes: Vec<usize> = (0..=n)
        .map(|i| b.add_node([l * i as f64 / n as f64, 0.0, 0.0]).unwrap())
        .collect();
    joined(&mut b, &nodes, 1e6, false);
    let sec = RodSection {
        ei,
        gj,
        spin_inertia: 0.1,
    };
    let carriers = b.add_rod(&nodes, sec, false, [true, false]).unwrap();
    b.fix(nodes[0], Dofs::ALL).unwrap();
    load(&mut b, *carriers.last().unwrap(), [t, 0.0, 0.0]);
    let m = b.build().unwrap();
    let sol = statics(&m);
    let theta = sol.state.x[*carriers.last().unwrap()][0];
    let h = l / n as f64;
    let expect = t * (l - 0.5 * h) / gj;
    assert!(
        (theta / expect - 1.0).abs() < 1e-8,
        "end rotation {theta} vs T(L - h/2)/GJ = {expect}"
    );
    // Twist grows linearly along the pipe; the axis stays straight.
    for (j, &c) in carriers.iter().enumerate() {
        let want = t * (j as f64 + 0.5) * h / gj;
        assert!((sol.state.x[c][0] - want).abs() < 1e-9, "edge {j}");
    }
    for &nd in &nodes {
        assert!(sol.state.x[nd][1].abs() < 1e-12 && sol.state.x[nd][2].abs() < 1e-12);
    }
    // The torque is reported per element.
    let out = &sol.outputs;
    for (e, &tq) in out.torque.iter().enumerate() {
        assert!((tq - t).abs() < 1e-6 * t, "element {e}: torque {tq}");
    }
}

/// Cantilever clamped at the root (position, tangent and twist held), small tip load: the tip
/// deflection converges to P·L³/(3EI) at order 2.
#[test]
fn clamped_cantilever_converges_at_order_two() {
    let (l, ei, p) = (2.0f64, 1e4, 1.0);
    let exact = p * l.powi(3) / (3.0 * ei);
    let mut errs = Vec::new();
    for n in [4usize, 8, 16] {
        let mut b = ModelBuilder::new(no_gravity());
        let nodes: Vec<usize> = (0..=n)
            .map(|i| b.add_node([l * i as f64 / n as f64, 0.0, 0.0]).unwrap())
            .collect();
        joined(&mut b, &nodes, 1e4 * ei / (l * l) * 1e3, false);
        let sec = RodSection {
            ei,
            gj: 0.7 * ei,
            spin_inertia: 0.0,
        };
        b.add_rod(&nodes, sec, false, [true, false]).unwrap();
        b.fix(nodes[0], Dofs::ALL).unwrap();
        load(&mut b, nodes[n], [0.0, 0.0, -p]);
        let m = b.build().unwrap();
        let sol = statics(&m);
        errs.push((-sol.state.x[nodes[n]][2] - exact).abs() / exact);
    }
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((order - 2.0).abs() < 0.25, "order {order}: errors {errs:?}");
    }
    assert!(errs[2] < 0.01, "{errs:?}");
}

/// A quarter ring of radius R clamped at one end and loaded at the other by P normal to its
/// plane carries a bending moment P·R·sin φ and a torque P·R·(1 − cos φ); Castigliano gives the
/// tip deflection P·R³·[π/(4EI) + (3π/4 − 2)/GJ]. The rod converges to it at order 2; a rod
/// without torsional stiffness could not carry the load at all.
#[test]
fn quarter_ring_loaded_out_of_plane_bends_and_twists_as_castigliano_says() {
    let (r, ei, gj) = (4.0f64, 2e4, 1.3e4);
    let p = 1e-4 * ei / (r * r);
    let exact = p * r.powi(3) * (PI / (4.0 * ei) + (0.75 * PI - 2.0) / gj);
    let mut errs = Vec::new();
    for n in [8usize, 16, 32] {
        let mut b = ModelBuilder::new(no_gravity());
        let nodes: Vec<usize> = (0..=n)
            .map(|i| {
                let phi = 0.5 * PI * i as f64 / n as f64;
                b.add_node([r * phi.cos(), r * phi.sin(), 0.0]).unwrap()
            })
            .collect();
        joined(&mut b, &nodes, 1e6 * ei / (r * r), false);
        let sec = RodSection {
            ei,
            gj,
            spin_inertia: 0.0,
        };
        b.add_rod(&nodes, sec, false, [true, false]).unwrap();
        b.fix(nodes[0], Dofs::ALL).unwrap();
        load(&mut b, nodes[n], [0.0, 0.0, -p]);
        let m = b.build().unwrap();
        let sol = statics(&m);
        let dz = -sol.state.x[nodes[n]][2];
        errs.push((dz - exact).abs() / exact);
    }
    eprintln!("quarter ring errors n = 8, 16, 32: {errs:?}");
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((order - 2.0).abs() < 0.3, "order {order}: errors {errs:?}");
    }
    assert!(errs[2] < 0.005, "{errs:?}");
}

/// The ring of the pinched-ring test: `n` nodes on radius R at height z = ±`imperfection`
/// alternating, pinched by ±P along x. Returns (change of the x diameter, largest |z|, the
/// smallest in-plane curvature sign, largest bending moment [N·m]) of the solved ring. With `hold_z` every node is held in z
/// (the planar ring of thin-ring theory).
fn pinched_ring(
    n: usize,
    r: f64,
    ei: f64,
    p: f64,
    imperfection: f64,
    hold_z: bool,
) -> (f64, f64, f64, f64) {
    let mut b = ModelBuilder::new(no_gravity());
    let positions: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let phi = 2.0 * PI * i as f64 / n as f64;
            let z = if i % 2 == 0 {
                imperfection
            } else {
                -imperfection
            };
            [r * phi.cos(), r * phi.sin(), z]
        })
        .collect();
    let nodes: Vec<usize> = positions.iter().map(|&p| b.add_node(p).unwrap()).collect();
    joined(&mut b, &nodes, 1e5 * ei / (r * r), true);
    let sec = RodSection {
        ei,
        gj: ei / 1.4,
        spin_inertia: 0.0,
    };
    b.add_rod(&nodes, sec, true, [false, false]).unwrap();
    // Rigid-body modes held: x-axis nodes in y, the y-axis nodes in x; vertical springs of a
    // waterplane (every node), or z held.
    let q = n / 4;
    let hold = |b: &mut ModelBuilder, node: usize, [x, y, z]: [bool; 3]| {
        b.fix(node, Dofs { x, y, z }).unwrap();
    };
    hold(&mut b, nodes[0], [false, true, false]);
    hold(&mut b, nodes[2 * q], [false, true, false]);
    hold(&mut b, nodes[q], [true, false, false]);
    if hold_z {
        for &nd in &nodes {
            hold(&mut b, nd, [false, false, true]);
        }
    }
    load(&mut b, nodes[0], [-p, 0.0, 0.0]);
    load(&mut b, nodes[2 * q], [p, 0.0, 0.0]);
    if !hold_z {
        // A floating pipe's waterplane: a vertical spring ρ·g·D·(2πR/n) under every node (a
        // compression-carrying link to a held node 1 km below; no horizontal stiffness at zero
        // tension).
        let kw = 1025.0 * 9.81 * 0.4 * 2.0 * PI * r / n as f64;
        let g = b
            .add_group(
                "heave",
                CableSection::new(kw * 1000.0, 1e-6).with_compression_ratio(1.0),
            )
            .unwrap();
        for &nd in &nodes {
            let p0 = positions[nd];
            let anchor = b.add_node([p0[0], p0[1], p0[2] - 1000.0]).unwrap();
            b.fix(anchor, Dofs::ALL).unwrap();
            b.add_cable(
                nd,
                anchor,
                g,
                UnstretchedLength::AsBuilt {
                    initial_tension: 0.0,
                },
            )
            .unwrap();
        }
    }
    let m = b.build().unwrap();
    let sol = statics(&m);
    let x = &sol.state.x;
    let d0 = x[nodes[0]][0] - x[nodes[2 * q]][0];
    let zmax = nodes.iter().map(|&nd| x[nd][2].abs()).fold(0.0, f64::max);
    // In-plane curvature sign at every node: (e_a × e_b)·ẑ > 0 for a ring built counter-clockwise.
    let mut kmin = f64::INFINITY;
    for i in 0..n {
        let (a, c, d) = (
            x[nodes[(i + n - 1) % n]],
            x[nodes[i]],
            x[nodes[(i + 1) % n]],
        );
        let ea = [c[0] - a[0], c[1] - a[1]];
        let eb = [d[0] - c[0], d[1] - c[1]];
        kmin = kmin.min(ea[0] * eb[1] - ea[1] * eb[0]);
    }
    let peak = sol
        .outputs
        .bending_moment
        .iter()
        .fold(0.0, |a: f64, &b| a.max(b));
    (2.0 * r - d0, zmax, kmin, peak)
}

/// Thin-ring theory: two opposite forces P on a ring shorten its diameter along them by
/// δ = (π/4 − 2/π)·P·R³/EI. A ring with an alternating 1 mm imperfection out of its plane and
/// free in z must follow it as the ring held in its plane does (the rotation-free hinge let it
/// buckle out of plane at a fraction of the load), stay level and keep its curvature's side.
#[test]
fn pinched_ring_with_an_imperfection_follows_thin_ring_theory() {
    // HDPE ring R = 8 m, D = 0.4 m, SDR 17.
    let (r, d, e) = (8.0f64, 0.4f64, 0.9e9);
    let di = d - 2.0 * d / 17.0;
    let ei = e * PI / 64.0 * (d.powi(4) - di.powi(4));
    for p in [300.0, 1000.0, 2000.0] {
        let theory = (PI / 4.0 - 2.0 / PI) * p * r.powi(3) / ei;
        let (held, _, _, _) = pinched_ring(48, r, ei, p, 0.0, true);
        let (free, zmax, kmin, _) = pinched_ring(48, r, ei, p, 1e-3, false);
        eprintln!(
            "P {p}: theory {theory:.5}, z held {held:.5}, imperfect {free:.5}, |z| {zmax:.2e}"
        );
        // The planar ring follows the linear theory at small loads (its large-deflection
        // stiffening is 4 % at 2 kN); the imperfect ring follows the planar one.
        if p < 500.0 {
            assert!(
                (held / theory - 1.0).abs() < 0.01,
                "P {p}: held {held} vs {theory}"
            );
        }
        assert!(
            (free / held - 1.0).abs() < 0.02,
            "P {p}: imperfect {free} vs held {held}"
        );
        assert!(
            zmax < 1e-3 + 1e-3 * 1e-1,
            "P {p}: the ring left its plane: |z| {zmax} m"
        );
        assert!(kmin > 0.0, "P {p}: the curvature reversed");
    }
}

/// A free curved pipe (0.6π of a 2 m ring, 12 edges, no gravity, no supports) with initial
/// velocities that swing, bend and twist it.
fn swinging_pipe() -> (Model, State) {
    let (r, n) = (2.0f64, 12);
    let mut b = ModelBuilder::new(no_gravity());
    let nodes: Vec<usize> = (0..=n)
        .map(|i| {
            let phi = 0.6 * PI * i as f64 / n as f64;
            b.add_node([r * phi.cos(), r * phi.sin(), 0.0]).unwrap()
        })
        .collect();
    joined(&mut b, &nodes, 2e4, false);
    let sec = RodSection {
        ei: 50.0,
        gj: 35.0,
        spin_inertia: 0.02,
    };
    let carriers = b.add_rod(&nodes, sec, false, [false, false]).unwrap();
    let m = b.build().unwrap();
    let mut init = State::as_built(&m, 0.0);
    for (i, &nd) in nodes.iter().enumerate() {
        let s = i as f64 / n as f64;
        init.v[nd] = [0.3 * s, -0.2 * s * s, 0.8 * (s - 0.5)];
    }
    for (j, &c) in carriers.iter().enumerate() {
        init.v[c][0] = 2.0 * (j as f64 / n as f64 - 0.3);
    }
    (m, init)
}

/// The same pipe under HHT-α (α = 0.1) and the explicit semi-implicit Euler scheme: the rod's
/// forces and stable step work in both; HHT-α's numerical damping only removes energy, the
/// explicit scheme keeps it within 3 %.
#[test]
fn hht_and_the_explicit_scheme_carry_the_swinging_pipe() {
    let (m, init) = swinging_pipe();
    let mut s = DynamicSettings::new(0.01, 5.0);
    s.alpha = 0.1;
    let mut hht = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let e0 = {
        let r = hht.step(&mut NoLoads).unwrap().energies;
        r.kinetic + r.strain + r.numerical_dissipation
    };
    let mut last = 0.0;
    while !hht.is_finished() {
        let e = hht.step(&mut NoLoads).unwrap().energies;
        assert!(
            e.numerical_dissipation >= -1e-9 * e0,
            "HHT created energy: {e:?}"
        );
        last = e.kinetic + e.strain;
    }
    assert!(
        last <= e0 * (1.0 + 1e-9) && last > 0.5 * e0,
        "HHT: {last} J from {e0} J"
    );
    let st = ExplicitSettings::new(0.5);
    let mut ex = ExplicitSolver::new(&m, st, Some(&init), &mut NoLoads).unwrap();
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    let mut steps = 0;
    while !ex.is_finished() {
        let e = ex.step(&mut NoLoads).unwrap().energies;
        let tot = e.kinetic + e.strain;
        lo = lo.min(tot);
        hi = hi.max(tot);
        steps += 1;
    }
    assert!(steps > 10, "{steps} explicit steps");
    // Semi-implicit Euler is symplectic: its energy oscillates by O(Δt) about the exact one
    // (1.2 % here) and does not drift.
    assert!(
        hi - lo <= 0.03 * hi,
        "explicit energy between {lo} and {hi} J"
    );
}

/// A free curved pipe set swinging and twisting (no gravity, no supports): the energy-consistent
/// midpoint rule keeps kinetic + strain + bending/torsion energy to the Newton tolerance over
/// 10⁴ steps.
#[test]
fn midpoint_keeps_the_energy_of_a_swinging_twisting_pipe() {
    let (m, init) = swinging_pipe();
    let dt = 0.01;
    let mut s = DynamicSettings::new(dt, 1e4 * dt);
    s.midpoint = true;
    s.tol = 1e-9;
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let (mut steps, mut worst, mut scale, mut max_bend) = (0, 0.0f64, 0.0f64, 0.0f64);
    while !solver.is_finished() {
        let rep = solver.step(&mut NoLoads).unwrap();
        let e = rep.energies;
        scale = scale.max(e.kinetic + e.strain);
        worst = worst.max(e.numerical_dissipation.abs());
        max_bend = max_bend.max(
            solver
                .outputs()
                .bending_moment
                .iter()
                .fold(0.0, |a: f64, &b| a.max(b)),
        );
        steps += 1;
    }
    assert!(steps >= 10_000, "{steps} steps");
    assert!(max_bend > 1.0, "the pipe hardly bent: {max_bend} N m");
    assert!(worst <= 1e-6 * scale, "energy error {worst} J of {scale} J");
}

/// The bending moment the rod reports at the load points of a pinched ring converges to
/// thin-ring theory's P·R/π as the ring is refined (observed order 2).
#[test]
fn pinched_ring_moment_at_the_load_converges_to_pr_over_pi() {
    let (r, ei, p) = (8.0f64, 4.4e5, 10.0);
    let errs: Vec<f64> = [24usize, 48, 96, 192]
        .iter()
        .map(|&n| (pinched_ring(n, r, ei, p, 0.0, true).3 / (p * r / PI) - 1.0).abs())
        .collect();
    eprintln!("moment errors n = 24, 48, 96, 192: {errs:?}");
    for w in errs.windows(2) {
        assert!(w[1] < 0.6 * w[0], "no convergence: {errs:?}");
    }
    assert!(errs[3] < 0.02, "{errs:?}");
}

/// A saved state carries the rods' reference frames: the swinging, twisting pipe restored to a
/// save repeats the steps after it bit for bit, under HHT-α and the midpoint rule
/// (docs/theory/fem.md#coupling).
#[test]
fn restore_repeats_a_swinging_pipe_bit_for_bit() {
    let (m, init) = swinging_pipe();
    for midpoint in [false, true] {
        let mut s = DynamicSettings::new(0.01, 1.0);
        s.midpoint = midpoint;
        let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
        for _ in 0..30 {
            solver.step(&mut NoLoads).unwrap();
        }
        let saved = solver.save();
        let after = |solver: &mut DynamicSolver| {
            for _ in 0..40 {
                solver.step(&mut NoLoads).unwrap();
            }
            (
                solver.state().clone(),
                solver.outputs().bending_moment.clone(),
            )
        };
        let first = after(&mut solver);
        solver.restore(&saved).unwrap();
        assert_eq!(solver.time(), saved.time());
        let again = after(&mut solver);
        assert!(
            first == again,
            "midpoint {midpoint}: the steps after restore differ"
        );
        // The pipe turned enough for stale frames to matter.
        let turned = first
            .0
            .x
            .iter()
            .zip(&init.x)
            .map(|(a, b)| (a[0] - b[0]).abs() + (a[1] - b[1]).abs() + (a[2] - b[2]).abs())
            .fold(0.0f64, f64::max);
        assert!(turned > 0.1, "{turned}");
    }
}
