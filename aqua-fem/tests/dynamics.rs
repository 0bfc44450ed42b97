//! Dynamic oracles (docs/theory/fem.md#test-oracles): HHT-α spectral properties, energy
//! conservation, taut-string frequency, explicit vs implicit, slack round trip, failure handling.

mod common;
use aqua_fem::*;
use common::*;
use std::f64::consts::PI;

/// Point mass between two vertical pre-stretched one-element cables (fixed outer ends):
/// axial motion is exactly linear with k = 2EA/L0. Returns (model, mass node, k/m).
fn sdof(gravity: f64, omega2: f64) -> (Model, usize) {
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
fn hht_fit(alpha: f64, dt_over_t: f64, steps: usize) -> (f64, f64, f64) {
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
fn fit(d: &[f64]) -> (f64, f64) {
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

#[test]
fn hht_damping_and_period_error_match_spec() {
    let (rho, xi, period_ratio) = hht_fit(0.1, 0.1, 600);
    assert!((xi - 0.002106128972).abs() < 1e-6, "xi {xi}");
    assert!((rho - 0.998727782).abs() < 1e-6, "rho {rho}");
    assert!(
        (period_ratio - 1.0 - 0.03950575512).abs() < 1e-6,
        "T ratio {period_ratio}"
    );
}

#[test]
fn hht_alpha_zero_has_no_damping_and_omega2_over_12_period_error() {
    let (rho, xi, period_ratio) = hht_fit(0.0, 0.01, 2000);
    assert!(
        xi.abs() < 1e-7 && (rho - 1.0).abs() < 1e-7,
        "xi {xi} rho {rho}"
    );
    let om = 2.0 * PI * 0.01;
    // Exact trapezoidal period: Ω̄ = 2·atan(Ω/2).
    let exact = om / (2.0 * (om / 2.0).atan());
    assert!(
        (period_ratio - exact).abs() < 1e-8,
        "{period_ratio} vs {exact}"
    );
    assert!((period_ratio - 1.0 - om * om / 12.0).abs() < 1e-5);
}

#[test]
fn hht_spectral_radius_at_large_steps() {
    // (For α > 0.25 the third, spurious root is no longer negligible and a two-term fit
    // cannot isolate ρ∞; α ≤ 0.25 is checked.)
    for (alpha, rho_inf) in [(0.1, 0.8181818181818181), (0.2, 2.0 / 3.0), (0.25, 0.6)] {
        let (m, mid) = sdof(0.0, 4.0 * PI * PI);
        let mut init = State::as_built(&m, 0.0);
        init.x[mid][2] += 1e-3;
        let mut s = DynamicSettings::new(1000.0, 40_000.0);
        s.alpha = alpha;
        s.tol = 1e-12;
        let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
        let mut d = vec![1e-3];
        while !solver.is_finished() {
            solver.step(&mut NoLoads).unwrap();
            d.push(solver.state().x[mid][2]);
        }
        // Double real root at Ω → ∞: d_n = (A + Bn)·λⁿ; the fit gives ρ = √(−q).
        let (_, q) = fit(&d);
        let ratio = (-q).sqrt();
        assert!(
            (ratio - rho_inf).abs() < 1e-3,
            "alpha {alpha}: {ratio} vs {rho_inf}"
        );
    }
}

#[test]
fn alpha_conventions_and_validation() {
    assert!((DynamicSettings::alpha_from_rho_inf(0.5).unwrap() - 1.0 / 3.0).abs() < 1e-15);
    assert!((DynamicSettings::alpha_from_negative(-0.1).unwrap() - 0.1).abs() < 1e-15);
    let e = DynamicSettings::alpha_from_negative(-10.3).unwrap_err();
    assert!(
        e.to_string().contains("-10.3") && e.to_string().contains("rho_inf"),
        "{e}"
    );
    assert!(DynamicSettings::alpha_from_rho_inf(0.3).is_err());
    let (m, _) = sdof(9.81, 40.0);
    let mut s = DynamicSettings::new(0.1, 1.0);
    s.alpha = 0.5;
    assert!(DynamicSolver::new(&m, s, None, &mut NoLoads).is_err());
}

#[test]
fn alpha_zero_conserves_energy_over_ten_thousand_steps() {
    let (m, mid) = sdof(9.81, 4.0 * PI * PI);
    let mut init = State::as_built(&m, 0.0);
    init.x[mid][2] += 2e-3;
    let mut s = DynamicSettings::new(0.01, 100.0);
    s.alpha = 0.0;
    s.tol = 1e-12;
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let e0 = solver.energies();
    let scale = e0.kinetic + e0.strain;
    let mut steps = 0;
    let mut worst: f64 = 0.0;
    while !solver.is_finished() {
        let r = solver.step(&mut NoLoads).unwrap();
        worst = worst.max(r.energies.numerical_dissipation.abs());
        steps += 1;
    }
    assert!(steps >= 10_000);
    assert!(worst < 1e-9 * scale, "energy drift {worst} of {scale}");
}

#[test]
fn taut_string_first_frequency() {
    let (l, t, mu, ea, n) = (10.0, 1000.0, 0.5, 1e8, 20usize);
    let env = Environment {
        gravity: 0.0,
        ..Default::default()
    };
    let mut b = ModelBuilder::new(env);
    let g = b.add_group("string", CableSection::new(ea, mu)).unwrap();
    let mut nodes = Vec::new();
    for i in 0..=n {
        nodes.push(b.add_node([l * i as f64 / n as f64, 0.0, 0.0]).unwrap());
    }
    for i in 0..n {
        b.add_cable(
            nodes[i],
            nodes[i + 1],
            g,
            UnstretchedLength::AsBuilt { initial_tension: t },
        )
        .unwrap();
    }
    b.fix(nodes[0], Dofs::ALL).unwrap();
    b.fix(nodes[n], Dofs::ALL).unwrap();
    let m = b.build().unwrap();
    let f1 = 2.236067977;
    assert!((1.0 / (2.0 * l) * (t / mu).sqrt() - f1).abs() < 1e-9);
    // Mode shape offset 1e-4·L.
    let mut init = State::as_built(&m, 0.0);
    for i in 0..=n {
        // 1e-5·L rather than 1e-4·L (docs/theory/fem.md#taut-string): with EA = 1e8 the
        // second-order stretch at 1e-4·L raises the tension by ~0.25 % and the frequency by ~0.1 %.
        init.x[nodes[i]][1] = 1e-5 * l * (PI * i as f64 / n as f64).sin();
    }
    let dt = 1.0 / (200.0 * f1);
    let mut s = DynamicSettings::new(dt, 3.2 / f1);
    s.alpha = 0.0;
    s.tol = 1e-8;
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let mid = nodes[n / 2];
    let mut prev = (0.0, init.x[mid][1]);
    let mut crossings = Vec::new();
    while !solver.is_finished() {
        solver.step(&mut NoLoads).unwrap();
        let cur = (solver.time(), solver.state().x[mid][1]);
        if prev.1 > 0.0 && cur.1 <= 0.0 || prev.1 < 0.0 && cur.1 >= 0.0 {
            crossings.push(prev.0 + (cur.0 - prev.0) * prev.1 / (prev.1 - cur.1));
        }
        prev = cur;
    }
    assert!(crossings.len() >= 5);
    let period =
        (crossings[crossings.len() - 1] - crossings[0]) / ((crossings.len() - 1) as f64 / 2.0);
    let f = 1.0 / period;
    // Discrete (lumped) string: f = (N/(πL))·√(T/μ)·sin(π/2N); trapezoid period error Ω²/12.
    let f_discrete = n as f64 / (PI * l) * (t / mu).sqrt() * (PI / (2.0 * n as f64)).sin();
    let om = 2.0 * PI * f_discrete * dt;
    let f_expected = f_discrete / (1.0 + om * om / 12.0);
    assert!(
        ((f - f_expected) / f_expected).abs() < 2e-4,
        "f {f} vs {f_expected}"
    );
    assert!(((f - f1) / f1).abs() < 2e-3, "f {f} vs continuum {f1}");
}

fn swinging_chain() -> (Model, usize) {
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
fn a_step_that_cannot_converge_is_a_clear_error() {
    let (m, _) = swinging_chain();
    let mut s = DynamicSettings::new(0.5, 2.0);
    s.max_iter = 1;
    s.dt_min = Some(0.1);
    let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
    let t0 = solver.time();
    match solver.step(&mut NoLoads) {
        Err(FemError::StepFailed(f)) => {
            assert_eq!(f.t, t0);
            assert!(f.dt < 0.2 && !f.history.is_empty());
            assert!(f.to_string().contains("worst node"));
        }
        other => panic!("{other:?}"),
    }
    // Last converged state untouched and finite.
    assert!(solver.state().x.iter().flatten().all(|v| v.is_finite()));
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

/// Modified Newton (`reuse_factor`, docs/theory/fem.md#hht-alpha) converges to the same discrete
/// solution as full Newton: each step meets the same residual and correction tolerances, so the
/// swinging tip agrees to well within 1e-3 of the chain length; `reuse_factor = 0` is rejected.
#[test]
fn modified_newton_matches_full_newton() {
    let (m, tip) = swinging_chain();
    let run = |reuse: usize| {
        let mut s = DynamicSettings::new(1e-2, 1.0);
        s.reuse_factor = reuse;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        solver.run(&mut NoLoads, |_, _| true).unwrap();
        solver.state().x[tip]
    };
    let (a, b) = (run(1), run(8));
    let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    assert!(d < 1e-2, "full {a:?} vs modified {b:?}");
    assert!(a[2] < 9.0, "the chain has swung down");
    let mut s = DynamicSettings::new(1e-2, 1.0);
    s.reuse_factor = 0;
    let err = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap_err();
    assert!(err.to_string().contains("reuse_factor"), "{err}");
}

/// A failed modified-Newton attempt is retried with full Newton before the step is halved
/// (docs/theory/fem.md#hht-alpha): on the swinging slack chain at steps where a stale
/// factorisation does not contract, `reuse_factor = 8` must halve no more often than full Newton.
#[test]
fn modified_newton_halves_no_more_than_full_newton() {
    let (m, _) = swinging_chain();
    let halvings = |reuse: usize, dt: f64| {
        let mut s = DynamicSettings::new(dt, 2.0);
        s.reuse_factor = reuse;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        solver.run(&mut NoLoads, |_, _| true).unwrap();
        solver.step_control().halvings
    };
    for dt in [0.02, 0.05, 0.1] {
        let (full, modified) = (halvings(1, dt), halvings(8, dt));
        eprintln!("dt {dt}: halvings full {full}, modified {modified}");
        assert!(
            modified <= full,
            "dt {dt}: modified Newton halved {modified}×, full {full}×"
        );
    }
}

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

/// The time-step error indicator (docs/theory/fem.md#time-step-error-indicator) on a linear
/// oscillator with a known solution: it falls like Δt² as the true error does, and stays
/// within a small factor of the true position error.
#[test]
fn time_error_indicator_tracks_the_true_error_of_a_linear_oscillator() {
    let (m, mid) = sdof(0.0, 4.0 * PI * PI);
    let amp = 0.01;
    let t_end = 2.3;
    let mut rows = Vec::new();
    for dt in [0.02, 0.01, 0.005] {
        let mut init = State::as_built(&m, 0.0);
        init.x[mid][2] += amp;
        let mut s = DynamicSettings::new(dt, t_end);
        s.alpha = 0.0;
        s.tol = 1e-12;
        let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
        solver.run(&mut NoLoads, |_, _| true).unwrap();
        let z = solver.state().x[mid][2];
        let exact = amp * (2.0 * PI * t_end).cos();
        let c = solver.step_control();
        rows.push((
            (z - exact).abs(),
            c.sum_local_error,
            c.relative_time_error(),
        ));
    }
    for w in rows.windows(2) {
        let p_true = (w[0].0 / w[1].0).log2();
        let p_ind = (w[0].1 / w[1].1).log2();
        assert!((p_true - 2.0).abs() < 0.3, "true order {p_true}: {rows:?}");
        assert!(
            (p_ind - 2.0).abs() < 0.3,
            "indicator order {p_ind}: {rows:?}"
        );
    }
    for (err, ind, rel) in &rows {
        let ratio = err / ind;
        assert!((0.2..5.0).contains(&ratio), "true {err} vs indicator {ind}");
        // The largest displacement from the start is the peak-to-peak 2·amp.
        assert!((rel - ind / (2.0 * amp)).abs() < 0.05 * rel, "{rel}");
    }
    eprintln!("(true error, indicator, relative) per dt 0.02, 0.01, 0.005: {rows:?}");
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

/// The peak-tension resolution estimate (docs/theory/fem.md#time-step-error-indicator) on a
/// sampled sine T = m + A·sin(φ·n + φ0): at every phase step φ the estimate is of the order of
/// the worst sampling error of the crest, A·(1 − cos(φ/2)), and it falls like φ².
#[test]
fn peak_tension_resolution_of_a_sampled_sine() {
    let (m, a) = (1000.0, 400.0);
    let mut last = f64::NAN;
    for phi in [0.8, 0.4, 0.2, 0.1, 0.05] {
        let control = StepControl {
            peak_tensions: (0..4000)
                .map(|n| m + a * (phi * n as f64 + 0.3).sin())
                .collect(),
            ..Default::default()
        };
        let r = control.peak_tension_resolution();
        let worst = a * (1.0 - (phi / 2.0).cos()) / (m + a);
        assert!(
            r.error > 0.8 * worst && r.error < 1.5 * worst,
            "φ = {phi}: estimate {:.3e} against the worst crest error {worst:.3e}",
            r.error
        );
        if last.is_finite() {
            let ratio = last / r.error;
            assert!((3.6..=4.4).contains(&ratio), "φ = {phi}: falls by {ratio}");
        }
        last = r.error;
    }
}

/// A snap at the start from a slack state up to a third of the later peak does not count:
/// maxima form in the top quarter of the range.
#[test]
fn a_start_up_snap_below_the_peaks_is_not_a_resolution_error() {
    let mut control = StepControl {
        peak_tensions: std::iter::once(0.0)
            .chain((0..200).map(|n| 0.5 + 0.7 * n as f64 / 200.0))
            .chain((0..2000).map(|n| 1.2 + 0.3 * (0.01 * n as f64).sin()))
            .collect(),
        ..Default::default()
    };
    let r = control.peak_tension_resolution();
    assert!(r.error < 1e-4, "{r:?}");
    // The same snap into the top quarter is counted.
    control.peak_tensions[0] = 0.0;
    control.peak_tensions[1] = 1.5;
    assert!(control.peak_tension_resolution().error > 0.1);
}

/// The symmetric factorisation with refinement (docs/theory/fem.md#sparse-linear-algebra) gives
/// the LU's trajectory within Newton's tolerance: a chain swinging through a cross-current, whose drag's position
/// derivative (finite differences) makes the tangent non-symmetric, so the refinement runs.
#[test]
fn symmetric_factorisation_follows_the_lu_in_a_current() {
    let (m, tip) = swinging_chain();
    let run = |kind: LinearSolverKind, tol: f64| {
        let mut w = WaterLines::new(&m, 0.05, 1.2, [0.0, 0.8, 0.0]);
        let mut s = DynamicSettings::new(0.01, 1.0);
        s.linear_solver = kind;
        s.tol = tol;
        // The drag's position derivative (orientation of the normal) is not symmetric.
        s.fd_position_jacobian = true;
        let mut solver = DynamicSolver::new(&m, s, None, &mut w).unwrap();
        solver.run(&mut w, |_, _| true).unwrap();
        let stats = solver.linear_solver_stats();
        (
            solver.state().x[tip],
            solver.n_steps(),
            solver.total_iterations(),
            stats,
        )
    };
    let tol = DynamicSettings::new(0.01, 1.0).tol;
    let (xl, nl, il, _) = run(LinearSolverKind::Lu, tol);
    let (xs, ns, is, st) = run(LinearSolverKind::Symmetric, tol);
    // The same with a Newton tolerance 1000× tighter: how far the answer may move within
    // Newton's own tolerance.
    let (xt, _, _, _) = run(LinearSolverKind::Lu, 1e-3 * tol);
    assert_eq!(st.fallbacks, 0, "the symmetric path solved every system");
    assert!(
        st.refinement_sweeps > 0,
        "the tangent was not symmetric: the refinement ran"
    );
    // An earlier L·D·Lᵀ preconditions later systems: fewer factorisations than iterations,
    // and every system either factorised, reused, or was a convergence check with the last
    // factor.
    assert!(st.factor_reuses > 0, "{st:?}");
    assert!(st.factorisations < is / 2, "{st:?} for {is} iterations");
    assert!(
        st.factorisations + st.factor_reuses + st.stale_checks >= is,
        "{st:?} for {is} iterations"
    );
    assert!(
        xl[1].abs() > 1e-3,
        "the current pushes the chain sideways: {xl:?}"
    );
    let dist = |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    let (d, d_tol) = (dist(xl, xs), dist(xl, xt));
    eprintln!("tip: symmetric − LU {d:.3e} m, LU at tol/1000 − LU {d_tol:.3e} m");
    // The refinement stops at 1 % of the Newton tolerance (inexact Newton): the answer moves
    // by less than Newton's own tolerance moves it, and the Newton iterations are the LU's.
    assert!(
        d < 0.1 * d_tol.max(1e-12),
        "tip {xl:?} (LU) vs {xs:?} (symmetric)"
    );
    assert_eq!(nl, ns, "same steps");
    assert_eq!(il, is, "same Newton iterations");
    // ... and it stops early: 2.0 sweeps per Newton system here against 3.8 when refined
    // to 1e-10 of the right-hand side.
    assert!(
        st.refinement_sweeps * 2 <= 5 * is,
        "{st:?} for {is} iterations"
    );
}

/// A step that lands on an output time, t_out − t, differs from Δt by round-off only; it is
/// taken as Δt, so outputs neither change the trajectory nor force fresh factorisations (each
/// output used to force two: the landing step and the next full one, 81 factorisations in 200
/// steps of the reference cage; docs/theory/fem.md#sparse-linear-algebra).
#[test]
fn output_landings_are_steps_like_any_other() {
    let (m, tip) = swinging_chain();
    let run = |out: Option<f64>| {
        let mut w = WaterLines::new(&m, 0.05, 1.2, [0.0, 0.8, 0.0]);
        let mut s = DynamicSettings::new(0.01, 1.0);
        s.fd_position_jacobian = true;
        s.output_interval = out;
        let mut solver = DynamicSolver::new(&m, s, None, &mut w).unwrap();
        let (mut outputs, mut off_grid) = (0, 0);
        while !solver.is_finished() {
            let r = solver.step(&mut w).unwrap();
            outputs += r.output_time as usize;
            off_grid += (r.dt != 0.01) as usize;
            if r.output_time && out.is_some() {
                // The clock is on the output time exactly.
                let k = (r.t / 0.03).round();
                assert!(
                    r.t == k * 0.03 || r.t == 1.0,
                    "output at {} dt {}",
                    r.t,
                    r.dt
                );
            }
        }
        (
            solver.linear_solver_stats(),
            outputs,
            off_grid,
            solver.state().x[tip],
        )
    };
    let (free, _, _, x_free) = run(None);
    let (landed, outputs, off_grid, x_landed) = run(Some(0.03));
    assert!(outputs >= 33, "{outputs} output steps");
    // 1.0 is no multiple of 0.03: the last step alone is short.
    assert!(off_grid <= 1, "{off_grid} steps other than Δt");
    assert!(
        landed.factorisations <= free.factorisations + 1,
        "{landed:?} with {outputs} output steps against {free:?} without"
    );
    let d = (0..3)
        .map(|k| (x_free[k] - x_landed[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(d < 1e-9, "tip {x_free:?} vs {x_landed:?}");
}

/// A straight tension-only line in zero gravity, every element 1 % slack, fixed at one end
/// and towed at the other: the tightening runs from the towed end to the fixed one. Returns
/// the model and its nodes.
fn slack_towed_line(segments: usize) -> (Model, Vec<usize>) {
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

/// Line relaxation (docs/theory/fem.md#line-relaxation) changes the Newton path, not the
/// answer: with and without it the midpoint rule and HHT-α each land on the same states step
/// by step, and the step in which the slack line pulls taut takes a few iterations instead of
/// about one per element. (The uniformly slack line tightens everywhere at once, so HHT-α's
/// front rule does not fire; the stability matrix's chain at Δt = 1 s is the case where it
/// must, docs/theory/fem.md#line-relaxation-hht.)
#[test]
fn line_relaxation_settles_a_tightening_line_within_the_iteration() {
    for midpoint in [true, false] {
        tightening_line_with_and_without_relaxation(midpoint);
    }
}

fn tightening_line_with_and_without_relaxation(midpoint: bool) {
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
fn midpoint_fit(theta: f64, dt_over_t: f64, steps: usize) -> (f64, f64) {
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
