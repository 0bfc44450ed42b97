//! Models and fits shared by the dynamics tests: a one-degree-of-freedom oscillator, a swinging
//! chain, a slack towed line, and the period and damping fits of a free vibration.

#![allow(dead_code)]

use crate::common::*;
use aqua_fem::*;
use std::f64::consts::PI;

/// Point mass between two vertical pre-stretched one-element cables (fixed outer ends):
/// axial motion is exactly linear with k = 2EA/L0. Returns (model, mass node, k/m).
pub fn sdof(gravity: f64, omega2: f64) -> (Model, usize) {
    let env = Environment {
        gravity,
        ..Default::default()
    };
    let mut b = ModelBuilder::new(env);
    let (ea, l, t0, mu) = (1e5, 10.0, 1e4, 0.1);
    let l0 = l / (1.0 + t0 / ea);
    let g = b.add_group("spring", CableSection::new(ea, mu)).unwrap();
    let top = b.add_node([0.0, 0.0, l]).unwrap();
    let mid = b.add_node([0.0, 0.0, 0.0]).unwrap();
    let bot = b.add_node([0.0, 0.0, -l]).unwrap();
    b.add_cable(top, mid, g, UnstretchedLength::Given(l0))
        .unwrap();
    b.add_cable(mid, bot, g, UnstretchedLength::Given(l0))
        .unwrap();
    let k = 2.0 * ea / l0;
    let m_total = k / omega2;
    b.add_point_body(PointBody {
        node: mid,
        mass: m_total - mu * l0,
        force: [0.0; 3],
        seabed_stiffness: 0.0,
    })
    .unwrap();
    b.fix(top, Dofs::ALL).unwrap();
    b.fix(bot, Dofs::ALL).unwrap();
    (b.build().unwrap(), mid)
}

/// Runs the SDOF from equilibrium + offset and fits d_{n+1} = p·d_n + q·d_{n−1}.
pub fn hht_fit(alpha: f64, dt_over_t: f64, steps: usize) -> (f64, f64, f64) {
    let (m, mid) = sdof(9.81, 4.0 * PI * PI);
    let st = solve_static(
        &m,
        &mut NoLoads,
        &StaticSettings {
            tol: 1e-12,
            ..Default::default()
        },
    )
    .unwrap();
    let z_eq = st.state.x[mid][2];
    let mut init = st.state.clone();
    init.x[mid][2] += 1e-3;
    let mut s = DynamicSettings::new(dt_over_t, steps as f64 * dt_over_t);
    s.alpha = alpha;
    s.tol = 1e-12;
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let mut d = vec![1e-3];
    while !solver.is_finished() {
        let r = solver.step(&mut NoLoads).unwrap();
        assert_eq!(r.retries, 0);
        d.push(solver.state().x[mid][2] - z_eq);
    }
    let (p, q) = fit(&d);
    let rho = (-q).sqrt();
    let omega_bar = (p / (2.0 * rho)).acos();
    let xi = -rho.ln() / omega_bar;
    let omega = 2.0 * PI * dt_over_t;
    (rho, xi, omega / omega_bar)
}

/// Least-squares fit of d_{n+1} = p·d_n + q·d_{n−1} on rows n ≥ 20.
pub fn fit(d: &[f64]) -> (f64, f64) {
    let (mut a11, mut a12, mut a22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for n in 21..d.len() - 1 {
        let (x1, x2, y) = (d[n], d[n - 1], d[n + 1]);
        a11 += x1 * x1;
        a12 += x1 * x2;
        a22 += x2 * x2;
        b1 += x1 * y;
        b2 += x2 * y;
    }
    let det = a11 * a22 - a12 * a12;
    let p = (b1 * a22 - b2 * a12) / det;
    let q = (a11 * b2 - a12 * b1) / det;
    (p, q)
}

pub fn swinging_chain() -> (Model, usize) {
    let mut b = ModelBuilder::new(Environment::default());
    let g = b.add_group("chain", CableSection::new(2e5, 1.0)).unwrap();
    let nodes = add_line(
        &mut b,
        [0.0, 0.0, 10.0],
        [10.0, 0.0, 10.0],
        10,
        10.0,
        g,
        0.0,
    );
    b.fix(nodes[0], Dofs::ALL).unwrap();
    (b.build().unwrap(), nodes[10])
}

/// A straight tension-only line in zero gravity, every element 1 % slack, fixed at one end
/// and towed at the other: the tightening runs from the towed end to the fixed one. Returns
/// the model and its nodes.
pub fn slack_towed_line(segments: usize) -> (Model, Vec<usize>) {
    let env = Environment {
        gravity: 0.0,
        ..Default::default()
    };
    let mut b = ModelBuilder::new(env);
    let g = b.add_group("line", CableSection::new(1e7, 10.0)).unwrap();
    let chord = 0.99 * segments as f64;
    let nodes = add_line(
        &mut b,
        [0.0, 0.0, 0.0],
        [chord, 0.0, 0.0],
        segments,
        segments as f64,
        g,
        0.0,
    );
    b.fix(nodes[0], Dofs::ALL).unwrap();
    // Towed along +x at 1 m/s after a smooth start over 0.1 s.
    let rows: Vec<[f64; 4]> = (0..=200)
        .map(|k| {
            let t = k as f64 * 0.01;
            let s = t / 0.1;
            let d = if s < 1.0 {
                0.1 * (s.powi(3) - 0.5 * s.powi(4))
            } else {
                t - 0.05
            };
            [t, d, 0.0, 0.0]
        })
        .collect();
    b.prescribe(nodes[segments], Motion::table(&rows).unwrap())
        .unwrap();
    (b.build().unwrap(), nodes)
}

pub fn tightening_line_with_and_without_relaxation(midpoint: bool) {
    let segments = 30;
    let (m, _) = slack_towed_line(segments);
    let run = |relax: bool| {
        let mut s = DynamicSettings::new(0.05, 0.6);
        s.midpoint = midpoint;
        s.max_iter = 200;
        s.tol = 1e-9;
        s.line_relaxation = relax;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        let (mut states, mut most) = (Vec::new(), 0usize);
        while !solver.is_finished() {
            let r = solver.step(&mut NoLoads).unwrap();
            most = most.max(r.iterations);
            states.push(solver.state().x.clone());
        }
        let taut = solver.outputs().n_slack() == 0;
        (states, most, solver.step_control().halvings, taut)
    };
    let (relaxed, most_relaxed, halvings_relaxed, taut) = run(true);
    let (plain, most_plain, halvings_plain, _) = run(false);
    let scheme = if midpoint { "midpoint" } else { "HHT" };
    assert!(taut, "{scheme}: the line should be taut at the end");
    assert_eq!((halvings_relaxed, halvings_plain), (0, 0));
    assert_eq!(relaxed.len(), plain.len());
    let worst = relaxed
        .iter()
        .zip(&plain)
        .flat_map(|(a, b)| a.iter().zip(b))
        .map(|(p, q)| (0..3).map(|k| (p[k] - q[k]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    assert!(worst < 1e-7, "{scheme}: states differ by {worst} m");
    // The front runs about one element per iteration without relaxation (13 of the 30 in the
    // hardest step with the midpoint rule, 9 with HHT-α's damping, measured).
    assert!(
        most_plain >= 8,
        "{scheme}: the plain Newton took at most {most_plain} iterations (relaxed {most_relaxed}): the case does not test the front"
    );
    assert!(
        most_relaxed <= 4,
        "{scheme}: with relaxation a step took {most_relaxed} iterations (plain: {most_plain})"
    );
}

/// Runs the SDOF under the midpoint rule with velocity weight θ from equilibrium + offset and
/// fits d_{n+1} = p·d_n + q·d_{n−1}.
pub fn midpoint_fit(theta: f64, dt_over_t: f64, steps: usize) -> (f64, f64) {
    let (m, mid) = sdof(0.0, 4.0 * PI * PI);
    let mut init = State::as_built(&m, 0.0);
    init.x[mid][2] += 1e-3;
    let mut s = DynamicSettings::new(dt_over_t, steps as f64 * dt_over_t);
    s.midpoint = true;
    s.theta = theta;
    s.tol = 1e-9;
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let mut d = vec![1e-3];
    while !solver.is_finished() {
        let r = solver.step(&mut NoLoads).unwrap();
        assert_eq!(r.retries, 0, "theta {theta}: {:?}", solver.step_control());
        d.push(solver.state().x[mid][2]);
    }
    fit(&d)
}
