//! Free 6-DOF rigid bodies (docs/theory/fem.md#rigid-bodies): a compound pendulum in statics
//! and dynamics, a free spin, a torque-driven tumble against an independent integration of
//! Ṙ = [ω]×R, the yaw frequency of a body on four springs, link stretch and the balance of a
//! loaded body, snapshot and restore, and bad input.

use aqua_fem::*;
use std::f64::consts::PI;

fn diag(a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]]
}

fn env(g: f64) -> Environment {
    Environment {
        gravity: g,
        ..Environment::default()
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn matvec(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2])
}

const G: f64 = 9.81;
const MASS: f64 = 1000.0;
const ARM: f64 = 2.0;
const I_YY: f64 = 800.0;

/// A body of mass MASS hung from a fixed pivot at the origin, its centre ARM away, built
/// tilted by `tilt` = (about y, about x) [rad]: returns the model (pivot node 0, body 0).
fn pendulum(tilt: [f64; 2]) -> Model {
    let mut b = ModelBuilder::new(env(G));
    let pivot = b.add_node([0.0; 3]).unwrap();
    b.fix(pivot, Dofs::ALL).unwrap();
    let (ty, tx) = (tilt[0], tilt[1]);
    // Hanging direction −ẑ turned by tx about x, then by ty about y.
    let d = [0.0, tx.sin(), -tx.cos()];
    let d = [
        d[2] * ty.sin() + d[0] * ty.cos(),
        d[1],
        d[2] * ty.cos() - d[0] * ty.sin(),
    ];
    b.add_rigid_body(RigidBodySpec {
        name: "bob".into(),
        centre: d.map(|c| ARM * c),
        mass: MASS,
        inertia: diag(600.0, I_YY, 300.0),
        points: vec![pivot],
    })
    .unwrap();
    b.build().unwrap()
}

/// The pendulum built tilted hangs with its centre straight below the pivot, turned back by
/// the tilt.
#[test]
fn compound_pendulum_hangs_straight_below_its_pivot() {
    let tilt = 0.3;
    let m = pendulum([tilt, 0.0]);
    let stat = solve_static(&m, &mut NoLoads, &StaticSettings::default()).unwrap();
    let body = &m.rigid_bodies()[0];
    let pose = stat.body_poses(&m)[0];
    let c = pose.centre;
    assert!(c[0].abs() < 1e-6 * ARM && c[1].abs() < 1e-6 * ARM, "{c:?}");
    // Below the pivot by the arm, the link's stretch (M·g/k) aside.
    assert!((c[2] + ARM).abs() < 1e-3 * ARM, "{c:?}");
    // The body turned back by the tilt about y: pitch = tilt, no roll or yaw.
    // The as-built offset of the pivot, ARM·(sin tilt, 0, cos tilt), turned upright: a turn
    // by −tilt about y.
    let a = pose.angles;
    assert!(
        (a[1] + tilt).abs() < 1e-6 && a[0].abs() < 1e-6 && a[2].abs() < 1e-6,
        "{a:?}"
    );
    // The pivot's offset, carried by R, points straight up.
    let up = matvec(&pose.rotation, body.points[0].1);
    assert!(up[0].abs() < 1e-6 && (up[2] - ARM).abs() < 1e-6, "{up:?}");
    assert_eq!(stat.state.x[body.node], c);
}

/// Times between successive upward zero crossings of a sampled signal [s].
fn periods(t: &[f64], y: &[f64]) -> Vec<f64> {
    let mut ups = Vec::new();
    for k in 1..y.len() {
        if y[k - 1] < 0.0 && y[k] >= 0.0 {
            ups.push(t[k - 1] + (t[k] - t[k - 1]) * y[k - 1] / (y[k - 1] - y[k]));
        }
    }
    ups.windows(2).map(|w| w[1] - w[0]).collect()
}

/// Small swings of the compound pendulum have the period 2π·√((I_c + M·d²)/(M·g·d)), under
/// HHT-α and the midpoint rule.
#[test]
fn compound_pendulum_swings_with_its_closed_form_period() {
    let m = pendulum([0.02, 0.0]);
    let want = 2.0 * PI * ((I_YY + MASS * ARM * ARM) / (MASS * G * ARM)).sqrt();
    for midpoint in [false, true] {
        let mut s = DynamicSettings::new(0.01, 4.0 * want);
        s.midpoint = midpoint;
        let mut solver = DynamicSolver::new(&m, s, None, &mut NoLoads).unwrap();
        let (mut t, mut x) = (vec![0.0], vec![solver.body_poses()[0].centre[0]]);
        while !solver.is_finished() {
            solver.step(&mut NoLoads).unwrap();
            t.push(solver.time());
            x.push(solver.body_poses()[0].centre[0]);
        }
        let p = periods(&t, &x);
        eprintln!("pendulum, midpoint {midpoint}: periods {p:?} s, closed form {want} s");
        assert!(p.len() >= 3, "{p:?}");
        for got in &p {
            assert!(
                (got / want - 1.0).abs() < 5e-3,
                "midpoint {midpoint}: period {got} s, closed form {want} s"
            );
        }
        assert_eq!(
            solver.step_control().halvings,
            0,
            "midpoint {midpoint}: {:?}",
            solver.step_control().reasons
        );
    }
}

/// A free body spinning about a principal axis turns by ω·t over many revolutions and keeps
/// its kinetic energy (midpoint rule).
#[test]
fn free_spin_turns_at_constant_rate_and_keeps_its_energy() {
    let mut b = ModelBuilder::new(env(0.0));
    let (izz, w) = (3.0e4, 2.0);
    let id = b
        .add_rigid_body(RigidBodySpec {
            name: "spinner".into(),
            centre: [1.0, 2.0, -3.0],
            mass: 5000.0,
            inertia: diag(1.0e4, 2.0e4, izz),
            points: vec![],
        })
        .unwrap();
    let m = b.build().unwrap();
    let body = &m.rigid_bodies()[id];
    let mut init = State::as_built(&m, 0.0);
    init.v[body.rotation_node] = [0.0, 0.0, w];
    let mut s = DynamicSettings::new(0.01, 10.0);
    s.midpoint = true;
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let e0 = 0.5 * izz * w * w;
    while !solver.is_finished() {
        solver.step(&mut NoLoads).unwrap();
        let kin = solver.energies().kinetic;
        assert!((kin - e0).abs() < 1e-9 * e0, "{kin} vs {e0}");
    }
    let t = solver.time();
    assert!(w * t > 6.0 * PI);
    let pose = solver.body_poses()[0];
    let (sn, cs) = (w * t).sin_cos();
    let want = [[cs, -sn, 0.0], [sn, cs, 0.0], [0.0, 0.0, 1.0]];
    for i in 0..3 {
        for j in 0..3 {
            assert!((pose.rotation[i][j] - want[i][j]).abs() < 1e-9, "{pose:?}");
        }
    }
    assert!((pose.angular_velocity[2] - w).abs() < 1e-12);
    assert_eq!(pose.centre, [1.0, 2.0, -3.0]);
}

/// A free body of three different principal moments spinning off its axes keeps its
/// angular momentum R·I·Rᵀ·ω (world) and its kinetic energy to first order in Δt: the
/// gyroscopic moment ω×(I_w·ω) is in (without it the momentum turns 21 % off).
#[test]
fn torque_free_asymmetric_body_keeps_its_angular_momentum() {
    let inertia = diag(1.0e4, 2.0e4, 3.0e4);
    let mut b = ModelBuilder::new(env(0.0));
    b.add_rigid_body(RigidBodySpec {
        name: "wobbler".into(),
        centre: [0.0; 3],
        mass: 100.0,
        inertia,
        points: vec![],
    })
    .unwrap();
    let rot = b.rigid_bodies()[0].rotation_node;
    let m = b.build().unwrap();
    let mut init = State::as_built(&m, 0.0);
    let w0 = [0.3, 0.2, 2.0];
    init.v[rot] = w0;
    let l0 = matvec(&inertia, w0);
    let e0 = 0.5 * (0..3).map(|k| w0[k] * l0[k]).sum::<f64>();
    for midpoint in [true, false] {
        let mut errors = Vec::new();
        for dt in [0.005, 0.0025] {
            let mut s = DynamicSettings::new(dt, 10.0);
            s.midpoint = midpoint;
            let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
            let (mut worst_l, mut worst_e) = (0.0f64, 0.0f64);
            while !solver.is_finished() {
                solver.step(&mut NoLoads).unwrap();
                let pose = solver.body_poses()[0];
                let r = pose.rotation;
                let w = pose.angular_velocity;
                // Body-frame ω = Rᵀ·ω, L = R·I·Rᵀ·ω, E = ½·ωᵀ·I·ω in the body frame.
                let wb: [f64; 3] = std::array::from_fn(|j| (0..3).map(|i| r[i][j] * w[i]).sum());
                let lb = matvec(&inertia, wb);
                let l = matvec(&r, lb);
                let e = 0.5 * (0..3).map(|k| wb[k] * lb[k]).sum::<f64>();
                worst_l = worst_l.max(norm(sub(l, l0)) / norm(l0));
                worst_e = worst_e.max((e - e0).abs() / e0);
            }
            eprintln!(
                "midpoint {midpoint}, dt {dt}: |L - L0|/|L0| <= {worst_l:.3e}, \
                 |E - E0|/E0 <= {worst_e:.3e}"
            );
            errors.push((worst_l, worst_e));
        }
        let (coarse, fine) = (errors[0], errors[1]);
        assert!(
            coarse.0 < 1e-2 && coarse.1 < 1e-2,
            "midpoint {midpoint}: {errors:?}"
        );
        // First order: halving Δt halves the errors.
        assert!(
            fine.0 < 0.6 * coarse.0 && fine.1 < 0.6 * coarse.1,
            "midpoint {midpoint}: {errors:?}"
        );
    }
}

/// An isotropic body spinning about z under a constant torque about x (a force on its
/// rotation carrier) tumbles: ω(t) = ω₀ẑ + τ/I·t·x̂ exactly, and its orientation follows
/// Ṙ = [ω]×R, integrated here by RK4 with fine steps. The axis turns, so the rotations of
/// successive steps do not commute: only the reference-frame update keeps R right.
#[test]
fn tumbling_body_follows_an_independent_integration_of_its_orientation() {
    let (inertia, w0, tau, t_end) = (2.0e3, 3.0, 1.0e3, 4.0);
    let mut b = ModelBuilder::new(env(0.0));
    b.add_rigid_body(RigidBodySpec {
        name: "top".into(),
        centre: [0.0; 3],
        mass: 100.0,
        inertia: diag(inertia, inertia, inertia),
        points: vec![],
    })
    .unwrap();
    let rot = b.rigid_bodies()[0].rotation_node;
    b.add_point_body(PointBody {
        node: rot,
        mass: 0.0,
        force: [tau, 0.0, 0.0],
        seabed_stiffness: 0.0,
    })
    .unwrap();
    let m = b.build().unwrap();
    let mut init = State::as_built(&m, 0.0);
    init.v[rot] = [0.0, 0.0, w0];
    // Reference: RK4 on Ṙ = [ω(t)]×R.
    let omega = |t: f64| [tau / inertia * t, 0.0, w0];
    let rdot = |t: f64, r: &[[f64; 3]; 3]| -> [[f64; 3]; 3] {
        let w = omega(t);
        let mut out = [[0.0; 3]; 3];
        for j in 0..3 {
            let c = cross(w, [r[0][j], r[1][j], r[2][j]]);
            for i in 0..3 {
                out[i][j] = c[i];
            }
        }
        out
    };
    let axpy = |r: &[[f64; 3]; 3], h: f64, k: &[[f64; 3]; 3]| -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| r[i][j] + h * k[i][j]))
    };
    let mut r = diag(1.0, 1.0, 1.0);
    let n = 40_000;
    let h = t_end / n as f64;
    for k in 0..n {
        let t = k as f64 * h;
        let k1 = rdot(t, &r);
        let k2 = rdot(t + 0.5 * h, &axpy(&r, 0.5 * h, &k1));
        let k3 = rdot(t + 0.5 * h, &axpy(&r, 0.5 * h, &k2));
        let k4 = rdot(t + h, &axpy(&r, h, &k3));
        r = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                r[i][j] + h / 6.0 * (k1[i][j] + 2.0 * k2[i][j] + 2.0 * k3[i][j] + k4[i][j])
            })
        });
    }
    for midpoint in [true, false] {
        let mut s = DynamicSettings::new(0.005, t_end);
        s.midpoint = midpoint;
        let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
        while !solver.is_finished() {
            solver.step(&mut NoLoads).unwrap();
        }
        let pose = solver.body_poses()[0];
        let err = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| (pose.rotation[i][j] - r[i][j]).abs())
            .fold(0.0, f64::max);
        let werr = norm(sub(pose.angular_velocity, omega(t_end)));
        eprintln!("midpoint {midpoint}: |R - R_ref| = {err:.3e}, |w - w_ref| = {werr:.3e}");
        assert!(err < 1e-5, "midpoint {midpoint}: {err} {pose:?} vs {r:?}");
        assert!(werr < 1e-5 * w0, "midpoint {midpoint}: {werr}");
    }
}

const HALF: f64 = 5.0;
const EA: f64 = 1.0e6;
const SPAN: f64 = 10.0;
const MU: f64 = 1.0;
const PRETENSION: f64 = 1.0e4;
const I_ZZ: f64 = 2.0e6;

/// A square body (corners at (±HALF, ±HALF, 0)) held by four horizontal springs of length
/// SPAN tangent to its corners' circle, two pulling one way round and two the other so that
/// they balance; gravity off. Returns the builder and the corner nodes.
fn moored_square() -> (ModelBuilder, Vec<usize>) {
    let mut b = ModelBuilder::new(env(0.0));
    let g = b
        .add_group(
            "spring",
            CableSection::new(EA, MU).with_compression_ratio(1.0),
        )
        .unwrap();
    let corners = [[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]];
    let mut nodes = Vec::new();
    for (k, c) in corners.iter().enumerate() {
        let r = [HALF * c[0], HALF * c[1], 0.0];
        // Anticlockwise tangent for corners 0 and 2, clockwise for 1 and 3.
        let t = cross([0.0, 0.0, 1.0], r).map(|v| v / norm(r));
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let p = b.add_node(r).unwrap();
        let anchor = b
            .add_node([r[0] + sign * SPAN * t[0], r[1] + sign * SPAN * t[1], 0.0])
            .unwrap();
        b.fix(anchor, Dofs::ALL).unwrap();
        b.add_cable(
            p,
            anchor,
            g,
            UnstretchedLength::AsBuilt {
                initial_tension: PRETENSION,
            },
        )
        .unwrap();
        nodes.push(p);
    }
    b.add_rigid_body(RigidBodySpec {
        name: "barge".into(),
        centre: [0.0; 3],
        mass: 1.0e5,
        inertia: diag(1.0e6, 1.5e6, I_ZZ),
        points: nodes.clone(),
    })
    .unwrap();
    (b, nodes)
}

/// Yaw of the square on its four springs: ω = √(k_θ/I), k_θ = 4·(EA/L0)·|r|² (tangent springs
/// stretch by |r|·θ and their pretension has no moment arm to change), I = I_zz plus the
/// springs' lumped end masses μ·L0/2 at |r|.
#[test]
fn yaw_on_four_springs_has_the_closed_form_frequency() {
    let (b, corners) = moored_square();
    let m = b.build().unwrap();
    let stat = solve_static(&m, &mut NoLoads, &StaticSettings::default()).unwrap();
    let l0 = m.elements()[0].l0;
    let r2 = 2.0 * HALF * HALF;
    let k_theta = 4.0 * EA / l0 * r2;
    let inertia = I_ZZ + 4.0 * 0.5 * MU * l0 * r2;
    let want = 2.0 * PI * (inertia / k_theta).sqrt();
    let body = m.rigid_bodies()[0].clone();
    let w0 = 0.01;
    let mut init = stat.state.clone();
    init.v[body.rotation_node] = [0.0, 0.0, w0];
    for &p in &corners {
        init.v[p] = cross([0.0, 0.0, w0], stat.state.x[p]);
    }
    for midpoint in [false, true] {
        let mut s = DynamicSettings::new(want / 200.0, 4.0 * want);
        s.midpoint = midpoint;
        let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
        let (mut t, mut y) = (vec![0.0], vec![solver.body_poses()[0].angles[2]]);
        while !solver.is_finished() {
            solver.step(&mut NoLoads).unwrap();
            t.push(solver.time());
            y.push(solver.body_poses()[0].angles[2]);
        }
        let p = periods(&t, &y);
        eprintln!("yaw, midpoint {midpoint}: periods {p:?} s, closed form {want} s");
        assert!(p.len() >= 3, "{p:?}");
        for got in &p {
            assert!(
                (got / want - 1.0).abs() < 1e-2,
                "midpoint {midpoint}: yaw period {got} s, closed form {want} s"
            );
        }
    }
}

/// A loaded square: each link stretches 1/LINK_STIFFNESS_FACTOR of its spring's elastic
/// stretch (the link and the spring carry the same force), and the springs' forces, computed
/// here from the positions, balance the force and the moment put on the body.
#[test]
fn loaded_body_balances_and_its_links_hardly_stretch() {
    let (mut b, corners) = moored_square();
    let body = b.rigid_bodies()[0].clone();
    let (force, moment) = ([3.0e3, -2.0e3, 0.0], [0.0, 0.0, 4.0e4]);
    for (node, f) in [(body.node, force), (body.rotation_node, moment)] {
        b.add_point_body(PointBody {
            node,
            mass: 0.0,
            force: f,
            seabed_stiffness: 0.0,
        })
        .unwrap();
    }
    let m = b.build().unwrap();
    let stat = solve_static(&m, &mut NoLoads, &StaticSettings::default()).unwrap();
    let x = &stat.state.x;
    let pose = stat.body_poses(&m)[0];
    let (mut sum_f, mut sum_m) = (force, moment);
    let mut scale = norm(force) + norm(moment) / HALF;
    for (e, &p) in m.elements().iter().zip(&corners) {
        assert_eq!(e.a, p);
        let d = sub(x[e.b], x[e.a]);
        let l = norm(d);
        let tension = EA * (l - e.l0) / e.l0;
        let f = d.map(|c| tension * c / l);
        let arm = sub(x[p], pose.centre);
        let mom = cross(arm, f);
        for k in 0..3 {
            sum_f[k] += f[k];
            sum_m[k] += mom[k];
        }
        scale += tension;
        // The link's stretch against the spring's.
        let offset = m.rigid_bodies()[0]
            .points
            .iter()
            .find(|(q, _)| *q == p)
            .unwrap()
            .1;
        let held = matvec(&pose.rotation, offset);
        let stretch = norm(sub(arm, held));
        let ratio = stretch / (l - e.l0);
        eprintln!("corner {p}: link stretch / spring stretch = {ratio:.4e}");
        assert!(
            ratio < 1.001 / LINK_STIFFNESS_FACTOR && ratio > 0.5 / LINK_STIFFNESS_FACTOR,
            "corner {p}: link stretch {stretch} m, spring stretch {} m",
            l - e.l0
        );
    }
    assert!(norm(sum_f) < 1e-8 * scale, "{sum_f:?} of {scale}");
    assert!(norm(sum_m) < 1e-8 * scale * HALF, "{sum_m:?} of {scale}");
    // The body turned and moved.
    assert!(pose.angles[2] > 1e-4 && pose.centre[0] > 1e-4, "{pose:?}");
}

/// Save → step → restore → step repeats the steps bit for bit with a tumbling body (its
/// reference frames are in the snapshot), under HHT-α and the midpoint rule.
#[test]
fn restore_repeats_a_swinging_body_bit_for_bit() {
    let m = pendulum([0.4, 0.3]);
    let init = {
        let mut s = State::as_built(&m, 0.0);
        s.v[m.rigid_bodies()[0].rotation_node] = [0.0, 0.0, 1.5];
        s
    };
    for midpoint in [false, true] {
        let mut s = DynamicSettings::new(0.01, 2.0);
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
            (solver.state().clone(), solver.body_poses())
        };
        let first = after(&mut solver);
        solver.restore(&saved).unwrap();
        let again = after(&mut solver);
        assert!(
            first == again,
            "midpoint {midpoint}: the steps after restore differ"
        );
        // The body turned through far more than a step's rotation.
        assert!(first.1[0].angles[2].abs() > 0.3, "{:?}", first.1);
    }
}

fn spec(mass: f64, inertia: [[f64; 3]; 3], points: Vec<usize>) -> RigidBodySpec {
    RigidBodySpec {
        name: "hull".into(),
        centre: [0.0; 3],
        mass,
        inertia,
        points,
    }
}

/// Bad input is refused with a typed error naming the body and the key.
#[test]
fn bad_rigid_bodies_are_refused_by_name() {
    let good = diag(1.0, 2.0, 2.5);
    let cases: Vec<(RigidBodySpec, &str)> = vec![
        (spec(0.0, good, vec![0]), "mass"),
        (spec(-3.0, good, vec![0]), "mass"),
        (spec(f64::NAN, good, vec![0]), "mass"),
        (
            spec(
                1.0,
                [[1.0, 0.5, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]],
                vec![0],
            ),
            "inertia",
        ),
        (spec(1.0, diag(1.0, -2.0, 1.0), vec![0]), "inertia"),
        (
            spec(
                1.0,
                [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                vec![0],
            ),
            "inertia",
        ),
        (spec(1.0, good, vec![7]), "points[0]"),
        (spec(1.0, good, vec![0, 0]), "points[1]"),
    ];
    for (s, key) in cases {
        let mut b = ModelBuilder::new(env(G));
        b.add_node([1.0, 0.0, 0.0]).unwrap();
        match b.add_rigid_body(s.clone()) {
            Err(FemError::RigidBody { body, key: k, .. }) => {
                assert_eq!(body, "hull");
                assert!(k.starts_with(key), "{k} for {s:?}");
            }
            other => panic!("{s:?}: {other:?}"),
        }
    }
    // A rotation carrier or another body's point cannot be held; names are unique.
    let mut b = ModelBuilder::new(env(G));
    let p = b.add_node([1.0, 0.0, 0.0]).unwrap();
    b.add_rigid_body(spec(1.0, good, vec![p])).unwrap();
    let rot = b.rigid_bodies()[0].rotation_node;
    for (points, name, key) in [
        (vec![rot], "other", "points[0]"),
        (vec![p], "other", "points[0]"),
        (vec![], "hull", "name"),
    ] {
        let s = RigidBodySpec {
            name: name.into(),
            ..spec(1.0, good, points)
        };
        match b.add_rigid_body(s) {
            Err(FemError::RigidBody { body, key: k, .. }) => {
                assert_eq!(body, name);
                assert_eq!(k, key);
            }
            other => panic!("{other:?}"),
        }
    }
    // The explicit solver refuses bodies.
    let m = b.build().unwrap();
    assert!(m.is_rotation_carrier(rot) && m.is_auxiliary(rot) && !m.is_twist_carrier(rot));
    let err = ExplicitSolver::new(&m, ExplicitSettings::new(1.0), None, &mut NoLoads);
    assert!(
        matches!(err, Err(FemError::RigidBodyNeedsImplicit { ref body }) if body == "hull"),
        "{err:?}"
    );
}
