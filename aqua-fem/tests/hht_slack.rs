//! The energy-consistent HHT-α on tension-only members (docs/theory/fem.md#energy-consistent-hht-alpha):
//! a swinging slack chain keeps its energy bounded for any step and α, the released slack chain
//! runs without its energy guard halving the step, and a net hanging at rest stays at rest.

mod common;
mod dynamics_helpers;

use aqua_fem::*;
use common::*;

/// Total energy of a structure at a state, computed here from the model's data:
/// ½·Σ m_i·|v_i|² + Σ m_i·g·z_i + Σ_cables W(l) + Σ_triangles E_t [J].
fn total_energy(m: &Model, s: &State) -> f64 {
    let g = m.environment().gravity;
    let mut e = 0.0;
    for (i, &mi) in m.lumped_mass().iter().enumerate() {
        let v = s.v[i];
        e += 0.5 * mi * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + mi * g * s.x[i][2];
    }
    for c in m.elements() {
        let d: Vec<f64> = (0..3).map(|k| s.x[c.b][k] - s.x[c.a][k]).collect();
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let eps = (l - c.l0) / c.l0;
        if eps > 0.0 {
            e += 0.5 * c.ea * eps * eps * c.l0;
        }
    }
    e + m
        .net_triangles()
        .iter()
        .map(|t| t.strain_energy(&s.x))
        .sum::<f64>()
}

/// Halvings of the step because a converged step created energy.
fn energy_rejections(c: &StepControl) -> usize {
    c.reasons
        .iter()
        .filter(|(k, _)| *k == FailureKind::EnergyCreated)
        .map(|(_, n)| n)
        .sum()
}

/// Energy bound of the scheme (docs/theory/fem.md#energy-consistent-hht-alpha): with a
/// conservative structure the algorithmic energy E + ½·h²·(β − γ/2)·aᵀMa never grows, so the
/// energy never exceeds its start by more than ½·h²·(β − γ/2)·a₀ᵀMa₀; released from rest
/// every free node starts at a₀ = g.
fn start_allowance(m: &Model, alpha: f64, h: f64) -> f64 {
    let (beta, gamma) = (0.25 * (1.0 + alpha) * (1.0 + alpha), 0.5 + alpha);
    let g = m.environment().gravity;
    let mass: f64 = m.lumped_mass().iter().sum();
    0.5 * h * h * (beta - 0.5 * gamma) * mass * g * g
}

/// Over 10⁴ steps of the swinging slack chain at α = 0, 0.05 and 0.3 (original HHT
/// convention: 0, −0.05, −0.3) and steps of 1, 10 and 50 ms, the energy computed from the
/// state never exceeds its start beyond the scheme's start allowance and the Newton
/// tolerance, and the energy guard halves fewer than 1 % of the steps. The trapezoidal work
/// of the old end-point force at the slack/taut kink created energy here, which the guard
/// then rejected.
#[test]
fn hht_never_creates_energy_in_a_swinging_slack_chain() {
    // A 10 m chain of 10 tension-only elements (EA 2e5 N, 1 kg/m) pinned at one end and
    // released horizontally from rest: it falls, swings, and its elements go slack and taut.
    let (m, _) = dynamics_helpers::swinging_chain();
    let e0 = total_energy(&m, &State::as_built(&m, 0.0));
    for alpha in [0.0, 0.05, 0.3] {
        for dt in [1e-3, 1e-2, 5e-2] {
            let mut s = DynamicSettings::new(dt, 1e4 * dt);
            s.alpha = alpha;
            s.tol = 1e-8;
            let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
            let (mut steps, mut worst, mut scale, mut saw_slack) = (0, f64::MIN, 0.0f64, false);
            while !solver.is_finished() {
                let r = solver.step(&mut NoLoads).unwrap();
                let e = total_energy(&m, solver.state());
                worst = worst.max(e - e0);
                scale = scale.max(r.energies.kinetic);
                saw_slack |= solver.outputs().n_slack() > 0;
                steps += 1;
            }
            let allowance = start_allowance(&m, alpha, dt) + 1e-6 * scale;
            let c = solver.step_control();
            eprintln!(
                "alpha {alpha} dt {dt}: {steps} steps, {} halvings, max E − E0 = {worst:.3e} J \
                 (allowance {allowance:.3e} J, peak kinetic {scale:.3e} J) {:?} {:?}",
                c.halvings,
                c.reasons,
                c.events.first()
            );
            assert!(steps >= 10_000, "alpha {alpha} dt {dt}: {steps} steps");
            assert!(
                saw_slack,
                "alpha {alpha} dt {dt}: the chain never went slack"
            );
            let rejected = energy_rejections(c);
            assert!(
                (rejected as f64) < 0.01 * steps as f64,
                "alpha {alpha} dt {dt}: {rejected} energy rejections in {steps} steps"
            );
            assert!(
                worst <= allowance,
                "alpha {alpha} dt {dt}: energy grew by {worst} J (allowed {allowance} J)"
            );
        }
    }
}

/// The released slack chain of the failure cases: 10 m, 80 tension-only elements, EA 1e7 N,
/// 1 kg/m, pinned at the top and released straight and unstretched 1° off the vertical; HHT
/// α = 0.05, Δt = 5 ms, 3 s. Energy bound on the tension: no damping and no water, so the
/// strain energy U ≤ m·g·Δz_cm, the drop of the centre of mass, which is at most the
/// straightening of the 1° tilt, L/2·(1 − cos 1°), plus the chain's elongation δ, itself
/// bounded by its energy: δ ≤ √(2·U·L/EA). One element carrying T stores T²·L0/(2·EA) ≤ U.
#[test]
fn hht_runs_the_released_slack_chain_without_energy_rejections() {
    let (len, n, ea, mu) = (10.0, 80, 1e7, 1.0);
    let mut b = ModelBuilder::new(Environment::default());
    let g = b.add_group("chain", CableSection::new(ea, mu)).unwrap();
    let tilt = 1f64.to_radians();
    let top = [0.0, 0.0, 30.0];
    let bottom = [len * tilt.sin(), 0.0, 30.0 - len * tilt.cos()];
    let nodes = add_line(&mut b, top, bottom, n, len, g, 0.0);
    b.fix(nodes[0], Dofs::ALL).unwrap();
    let m = b.build().unwrap();
    let mut s = DynamicSettings::new(0.005, 3.0);
    s.alpha = 0.05;
    let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
    let e0 = total_energy(&m, solver.state());
    let (mut steps, mut t_max, mut worst) = (0usize, 0.0f64, f64::MIN);
    while !solver.is_finished() {
        solver.step(&mut NoLoads).unwrap();
        t_max = solver
            .outputs()
            .tension
            .iter()
            .fold(t_max, |a, &t| a.max(t));
        worst = worst.max(total_energy(&m, solver.state()) - e0);
        steps += 1;
    }
    // U ≤ w·(c + k·√U), w = m·g, c = L/2·(1 − cos 1°), k = √(2L/EA): √U ≤ the positive root.
    let w = mu * len * m.environment().gravity;
    let (c, k) = (0.5 * len * (1.0 - tilt.cos()), (2.0 * len / ea).sqrt());
    let root = 0.5 * (w * k + ((w * k).powi(2) + 4.0 * w * c).sqrt());
    let u_max = root * root;
    let t_bound = (2.0 * ea * u_max / (len / n as f64)).sqrt();
    let c = solver.step_control();
    let rejected = energy_rejections(c);
    eprintln!(
        "{steps} steps, {} halvings ({rejected} by the energy guard), smallest step {:.2e} s, \
         largest tension {t_max:.1} N (bound {t_bound:.0} N), max E − E0 {worst:.3e} J",
        c.halvings, c.smallest_dt
    );
    eprintln!("{:?}", c.reasons);
    assert!(
        (rejected as f64) < 0.01 * steps as f64,
        "{rejected} energy rejections in {steps} steps"
    );
    assert!(
        t_max < t_bound,
        "tension {t_max} N above the energy bound {t_bound} N"
    );
    assert!(worst < 1e-3 * u_max, "energy grew by {worst} J");
}

/// A 1 m × 1 m net panel (square mesh, 10 × 10 cells of two triangles, twine EA 200 N,
/// l_p = 2 cm) hanging from its fixed top edge with a bottom row of point weights, started
/// from its static equilibrium in vacuum: nothing moves it, so its twine tensions must stay
/// at their static values, and the step must not be halved for energy. Its horizontal twines
/// sit at the slack/taut kink, where the old end-point force pumped energy in.
#[test]
fn hht_keeps_a_net_at_rest_at_rest() {
    let (nx, lp, width) = (10usize, 0.02, 1.0);
    let h = width / nx as f64;
    let mut b = ModelBuilder::new(Environment::default());
    let mut id = vec![vec![0usize; nx + 1]; nx + 1];
    for (i, row) in id.iter_mut().enumerate() {
        for (j, node) in row.iter_mut().enumerate() {
            *node = b
                .add_node([j as f64 * h, 0.0, -1.0 - i as f64 * h])
                .unwrap();
        }
    }
    let sec = NetTriangleSection::new(200.0, lp, 2e-3);
    let g = b.add_net_triangle_group("net", sec).unwrap();
    let uv = |i: usize, j: usize| [j as f64 * h / lp, -(i as f64) * h / lp];
    for i in 0..nx {
        for j in 0..nx {
            let (a, bb, c, d) = ((i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j));
            for t in [[a, bb, c], [a, c, d]] {
                b.add_net_triangle(g, t.map(|(p, q)| id[p][q]), t.map(|(p, q)| uv(p, q)))
                    .unwrap();
            }
        }
    }
    for j in 0..=nx {
        b.fix(id[0][j], Dofs::ALL).unwrap();
        b.add_point_body(PointBody {
            node: id[nx][j],
            mass: 0.5 / (nx + 1) as f64,
            force: [0.0; 3],
            seabed_stiffness: 0.0,
        })
        .unwrap();
    }
    let m = b.build().unwrap();
    let st = StaticSettings {
        tol: 1e-10,
        ..Default::default()
    };
    let sol = solve_static(&m, &mut NoLoads, &st).unwrap();
    let tension = |x: &[[f64; 3]]| -> Vec<f64> {
        (0..m.net_triangles().len())
            .flat_map(|i| {
                let t = m.net_triangle_twines(i, x);
                [t.tension_u, t.tension_v]
            })
            .collect()
    };
    let t0 = tension(&sol.state.x);
    let t_ref = t0.iter().fold(0.0f64, |a, &t| a.max(t));
    let mut s = DynamicSettings::new(0.05, 20.0);
    s.alpha = 0.3;
    let mut solver = DynamicSolver::new(&m, s, Some(&sol.state), &mut NoLoads).unwrap();
    let (mut steps, mut drift) = (0usize, 0.0f64);
    while !solver.is_finished() {
        solver.step(&mut NoLoads).unwrap();
        let t1 = tension(&solver.state().x);
        for (a, b) in t0.iter().zip(&t1) {
            drift = drift.max((a - b).abs());
        }
        steps += 1;
    }
    let c = solver.step_control();
    let rejected = energy_rejections(c);
    eprintln!(
        "{steps} steps, {} halvings ({rejected} by the energy guard), twine tension drift \
         {drift:.3e} N of {t_ref:.3e} N",
        c.halvings
    );
    eprintln!("{:?}", c.reasons);
    assert!(
        (rejected as f64) < 0.01 * steps as f64,
        "{rejected} energy rejections in {steps} steps"
    );
    assert!(
        drift < 0.01 * t_ref,
        "twine tension drifted by {drift} N of {t_ref} N"
    );
}
