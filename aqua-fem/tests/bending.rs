//! Bending oracles (docs/theory/fem.md#bending): small-deflection cantilever, the large-deflection
//! elastica (solved here independently by shooting), the pinched ring, rigid rotation of a ring.

use aqua_fem::*;
use std::f64::consts::PI;

fn no_gravity() -> Environment {
    Environment {
        gravity: 0.0,
        ..Default::default()
    }
}

/// A beam section: axial stiffness EA [N], carries compression (a pipe, not a rope).
fn beam(ea: f64) -> CableSection {
    CableSection::new(ea, 1.0).with_compression_ratio(1.0)
}

fn tip_load(b: &mut ModelBuilder, node: usize, force: [f64; 3]) {
    b.add_point_body(PointBody {
        node,
        mass: 0.0,
        force,
        seabed_stiffness: 0.0,
    })
    .unwrap();
}

/// Cantilever along +x from the clamp at the origin, `n` elements over length `l` [m], bending
/// stiffness `ei` [N·m²], tip force `p` [N] along −z. The clamp holds the root node and a guide
/// node `guide` [m] behind it (the tangent is held; a short guide gives the root hinge half a
/// Voronoi length, as the clamped end of a beam has). Returns (tip position, static report).
fn cantilever(n: usize, l: f64, ei: f64, p: f64, guide: f64) -> ([f64; 3], StaticReport) {
    let mut b = ModelBuilder::new(no_gravity());
    let g = b.add_group("beam", beam(1e4 * ei / (l * l))).unwrap();
    let mut nodes = vec![b.add_node([-guide, 0.0, 0.0]).unwrap()];
    for i in 0..=n {
        nodes.push(b.add_node([l * i as f64 / n as f64, 0.0, 0.0]).unwrap());
    }
    for w in nodes.windows(2) {
        b.add_cable(
            w[0],
            w[1],
            g,
            UnstretchedLength::AsBuilt {
                initial_tension: 0.0,
            },
        )
        .unwrap();
    }
    b.add_bending_line(&nodes, ei, false).unwrap();
    b.fix(nodes[0], Dofs::ALL).unwrap();
    b.fix(nodes[1], Dofs::ALL).unwrap();
    let tip = *nodes.last().unwrap();
    tip_load(&mut b, tip, [0.0, 0.0, -p]);
    let m = b.build().unwrap();
    let st = StaticSettings {
        tol: 1e-10,
        ..Default::default()
    };
    let sol = solve_static(&m, &mut NoLoads, &st).unwrap();
    (sol.state.x[tip], sol.report)
}

#[test]
fn cantilever_small_tip_load_matches_beam_theory() {
    let (l, ei) = (2.0f64, 1e4);
    let delta = 1e-3 * l;
    let p = 3.0 * ei * delta / l.powi(3);
    let (tip, rep) = cantilever(20, l, ei, p, 1e-3 * l / 20.0);
    let err = (-tip[2] / delta - 1.0).abs();
    eprintln!(
        "cantilever n=20: error {:.4} %, {} iterations",
        100.0 * err,
        rep.iterations
    );
    assert!(
        err < 5e-3,
        "tip deflection {} vs PL^3/3EI = {delta}: {:.3} %",
        -tip[2],
        100.0 * err
    );
    // Measured 12: the Levenberg–Marquardt damping starts at 1e-3·EA/L0 per node, far above
    // the soft bending mode, and falls ×⅓ per accepted step before Newton takes over.
    assert!(rep.iterations <= 16, "{} iterations", rep.iterations);
    // Second-order convergence with the mesh (discrete moment-area sum is a trapezoid rule).
    let e = |n: usize| {
        let (t, _) = cantilever(n, l, ei, p, 1e-4 * l / n as f64);
        (-t[2] / delta - 1.0).abs()
    };
    let (e10, e40) = (e(10), e(40));
    let order = (e10 / e40).log2() / 2.0;
    eprintln!("cantilever errors n=10 {e10:.3e}, n=40 {e40:.3e}: order {order:.2}");
    assert!(
        order > 1.8,
        "observed order {order} (errors {e10:.3e}, {e40:.3e})"
    );
}

/// Tip (x, z) of the elastica θ'' = (P/EI)·cos θ, θ(0) = 0, θ'(L) = 0 (θ the tangent angle
/// from +x, the tip force P along −z): bisection on θ'(0) with RK4 over the arc length.
fn elastica_tip(p_over_ei: f64, l: f64) -> (f64, f64) {
    let integrate = |m0: f64| {
        let steps = 4000;
        let h = l / steps as f64;
        let f = |y: [f64; 4]| [y[1], p_over_ei * y[0].cos(), y[0].cos(), y[0].sin()];
        let mut y = [0.0, m0, 0.0, 0.0];
        for _ in 0..steps {
            let k1 = f(y);
            let k2 = f(std::array::from_fn(|i| y[i] + 0.5 * h * k1[i]));
            let k3 = f(std::array::from_fn(|i| y[i] + 0.5 * h * k2[i]));
            let k4 = f(std::array::from_fn(|i| y[i] + h * k3[i]));
            y = std::array::from_fn(|i| {
                y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
        }
        y
    };
    // θ'(L) > 0 at θ'(0) = 0 and ≤ 0 at θ'(0) = −PL/EI.
    let (mut lo, mut hi) = (-p_over_ei * l, 0.0);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if integrate(mid)[1] > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let y = integrate(0.5 * (lo + hi));
    (y[2], y[3])
}

#[test]
fn cantilever_large_deflection_matches_the_elastica() {
    let (l, ei) = (2.0f64, 1e4);
    let p = 2.0 * ei / (l * l);
    let (xe, ze) = elastica_tip(p / ei, l);
    // Independent check of the shooting: PL²/EI = 2 gives a tip deflection ≈ 0.49·L.
    assert!((-ze / l - 0.49).abs() < 0.01, "elastica tip {xe}, {ze}");
    let (tip, rep) = cantilever(40, l, ei, p, 1e-4 * l / 40.0);
    let ez = (tip[2] / ze - 1.0).abs();
    let ex = ((tip[0] - l) / (xe - l) - 1.0).abs();
    eprintln!(
        "elastica tip ({xe:.6}, {ze:.6}), FEM ({:.6}, {:.6}): errors {:.3} %, {:.3} %, {} iterations",
        tip[0],
        tip[2],
        100.0 * ez,
        100.0 * ex,
        rep.iterations
    );
    assert!(
        ez < 0.01 && ex < 0.01,
        "tip ({}, {}) vs elastica ({xe}, {ze}): deflection error {:.3} %, shortening error {:.3} %",
        tip[0],
        tip[2],
        100.0 * ez,
        100.0 * ex
    );
    // Measured 30.
    assert!(rep.iterations <= 40, "{} iterations", rep.iterations);
}

/// Ring of `n` nodes (multiple of 4), radius `r` [m] in the x-y plane, bending stiffness `ei`,
/// pinched by ±`p` [N] at (0, ±r). Returns (change of the loaded diameter, change of the other,
/// report).
fn pinched_ring(n: usize, r: f64, ei: f64, p: f64) -> (f64, f64, StaticReport) {
    let mut b = ModelBuilder::new(no_gravity());
    let g = b.add_group("ring", beam(1e6 * ei / (r * r))).unwrap();
    let nodes: Vec<usize> = (0..n)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / n as f64;
            b.add_node([r * a.cos(), r * a.sin(), 0.0]).unwrap()
        })
        .collect();
    for i in 0..n {
        let (a, c) = (nodes[i], nodes[(i + 1) % n]);
        b.add_cable(
            a,
            c,
            g,
            UnstretchedLength::AsBuilt {
                initial_tension: 0.0,
            },
        )
        .unwrap();
    }
    b.add_bending_line(&nodes, ei, true).unwrap();
    let (right, top, left, bottom) = (nodes[0], nodes[n / 4], nodes[n / 2], nodes[3 * n / 4]);
    // In-plane problem; rigid modes held on the symmetry axes (no reactions by symmetry).
    for &nd in &nodes {
        b.fix(
            nd,
            Dofs {
                x: false,
                y: false,
                z: true,
            },
        )
        .unwrap();
    }
    for nd in [top, bottom] {
        b.fix(
            nd,
            Dofs {
                x: true,
                y: false,
                z: false,
            },
        )
        .unwrap();
    }
    b.fix(
        right,
        Dofs {
            x: false,
            y: true,
            z: false,
        },
    )
    .unwrap();
    tip_load(&mut b, top, [0.0, -p, 0.0]);
    tip_load(&mut b, bottom, [0.0, p, 0.0]);
    let m = b.build().unwrap();
    let st = StaticSettings {
        tol: 1e-10,
        ..Default::default()
    };
    let sol = solve_static(&m, &mut NoLoads, &st).unwrap();
    let x = &sol.state.x;
    let loaded = (x[top][1] - x[bottom][1]) - 2.0 * r;
    let other = (x[right][0] - x[left][0]) - 2.0 * r;
    (loaded, other, sol.report)
}

#[test]
fn pinched_ring_diameters_match_curved_beam_theory() {
    let (r, ei) = (1.5f64, 2e3);
    let p = 1e-3 * ei / (r * r);
    let (loaded, other, rep) = pinched_ring(128, r, ei, p);
    let s = p * r.powi(3) / ei;
    let loaded_th = -(PI / 4.0 - 2.0 / PI) * s;
    let other_th = (2.0 / PI - 0.5) * s;
    let (e1, e2) = (
        (loaded / loaded_th - 1.0).abs(),
        (other / other_th - 1.0).abs(),
    );
    eprintln!(
        "ring: loaded {:.6}·PR³/EI (theory {:.6}), other {:.6} (theory {:.6}); errors {:.3} %, {:.3} %, {} iterations",
        loaded / s,
        loaded_th / s,
        other / s,
        other_th / s,
        100.0 * e1,
        100.0 * e2,
        rep.iterations
    );
    assert!(
        e1 < 0.01,
        "loaded diameter {loaded:.6e} vs {loaded_th:.6e}: {:.3} %",
        100.0 * e1
    );
    assert!(
        e2 < 0.01,
        "other diameter {other:.6e} vs {other_th:.6e}: {:.3} %",
        100.0 * e2
    );
    // Measured 15.
    assert!(rep.iterations <= 20, "{} iterations", rep.iterations);
}

#[test]
fn rigidly_rotated_ring_is_force_free() {
    let (n, r, ei) = (24, 3.0, 5e3);
    // Rotation by 1.1 rad about the oblique unit axis k (Rodrigues), plus a translation.
    let k = {
        let v = [1.0f64, -2.0, 0.5];
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|c| c / l)
    };
    let (s, c) = (1.1f64.sin(), 1.1f64.cos());
    let rotate = |p: [f64; 3]| {
        let kxp = [
            k[1] * p[2] - k[2] * p[1],
            k[2] * p[0] - k[0] * p[2],
            k[0] * p[1] - k[1] * p[0],
        ];
        let kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
        std::array::from_fn::<f64, 3, _>(|i| p[i] * c + kxp[i] * s + k[i] * kp * (1.0 - c) + 0.7)
    };
    let mut b = ModelBuilder::new(no_gravity());
    let g = b.add_group("ring", beam(1e6)).unwrap();
    let pos: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / n as f64;
            [r * a.cos(), r * a.sin(), 0.0]
        })
        .collect();
    let nodes: Vec<usize> = pos.iter().map(|&p| b.add_node(p).unwrap()).collect();
    for i in 0..n {
        b.add_cable(
            nodes[i],
            nodes[(i + 1) % n],
            g,
            UnstretchedLength::AsBuilt {
                initial_tension: 0.0,
            },
        )
        .unwrap();
    }
    b.add_bending_line(&nodes, ei, true).unwrap();
    // Every node carried rigidly to its rotated position: the reactions are the internal forces.
    for (&nd, &p) in nodes.iter().zip(&pos) {
        let q = rotate(p);
        b.prescribe(nd, Motion::Constant(std::array::from_fn(|i| q[i] - p[i])))
            .unwrap();
    }
    let m = b.build().unwrap();
    let sol = solve_static(&m, &mut NoLoads, &StaticSettings::default()).unwrap();
    let scale = ei / (r * r);
    for (i, f) in sol.outputs.reaction.iter().enumerate() {
        for v in f {
            assert!(v.abs() < 1e-9 * scale, "node {i} reaction {f:?}");
        }
    }
    // The bent ring is not: a small in-plane pinch of one node costs force.
    assert_eq!(m.hinges().len(), n);
}

#[test]
fn invalid_bending_input_is_a_typed_error() {
    let mut b = ModelBuilder::new(no_gravity());
    let n: Vec<usize> = (0..3)
        .map(|i| b.add_node([i as f64, 0.0, 0.0]).unwrap())
        .collect();
    match b.add_bending(n[0], n[1], n[2], -1.0) {
        Err(FemError::InvalidParameter { what, value, .. }) => {
            assert!(what.contains("bending_stiffness"), "{what}");
            assert_eq!(value, -1.0);
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        b.add_bending(n[0], n[1], n[2], f64::NAN),
        Err(FemError::InvalidParameter { .. })
    ));
    assert!(matches!(
        b.add_bending(n[0], n[1], n[0], 1.0),
        Err(FemError::InvalidModel(_))
    ));
    assert!(matches!(
        b.add_bending(n[0], n[1], 7, 1.0),
        Err(FemError::UnknownNode { node: 7, .. })
    ));
    let m = b.add_node([1.0, 0.0, 0.0]).unwrap();
    assert!(matches!(
        b.add_bending(n[0], n[1], m, 1.0),
        Err(FemError::InvalidModel(_))
    ));
}
