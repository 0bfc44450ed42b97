//! Priour's triangular net element (docs/theory/fem.md#net-triangle) against closed forms:
//! patch tests of irregular triangulations in square and diamond orientation, a diamond net
//! pulled along a diagonal (the net's kinematics, inextensible and elastic twines), the
//! tension-only law, the exact tangent and force against finite differences, and the energy of
//! a swinging net under the midpoint rule, HHT-α and the explicit scheme.

use aqua_fem::*;

fn no_gravity() -> Environment {
    Environment {
        gravity: 0.0,
        ..Default::default()
    }
}

/// A small deterministic generator (an LCG) for the jitter: uniform in [−1, 1).
struct Jitter(u64);

impl Jitter {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// An irregular triangulation of the rectangle [0, lx] × [0, ly]: a grid of nx × ny cells
/// whose interior nodes are moved by up to 30 % of a cell, whose edge nodes slide along their
/// edge, and whose cells are cut along a randomly chosen diagonal. Returns the points, the
/// triangles (counter-clockwise) and which points are on the boundary.
fn irregular_panel(
    nx: usize,
    ny: usize,
    lx: f64,
    ly: f64,
    seed: u64,
) -> (Vec<[f64; 2]>, Vec<[usize; 3]>, Vec<bool>) {
    let mut rng = Jitter(seed);
    let (hx, hy) = (lx / nx as f64, ly / ny as f64);
    let mut pts = Vec::new();
    let mut boundary = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let (on_x, on_y) = (i == 0 || i == nx, j == 0 || j == ny);
            let dx = if on_x { 0.0 } else { 0.3 * hx * rng.next() };
            let dy = if on_y { 0.0 } else { 0.3 * hy * rng.next() };
            pts.push([i as f64 * hx + dx, j as f64 * hy + dy]);
            boundary.push(on_x || on_y);
        }
    }
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut tris = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if rng.next() > 0.0 {
                tris.push([a, b, c]);
                tris.push([a, c, d]);
            } else {
                tris.push([a, b, d]);
                tris.push([b, c, d]);
            }
        }
    }
    (pts, tris, boundary)
}

/// Mesh coordinates of a point X of the panel for twine directions e_u, e_v (unit, in the
/// panel plane) and bar length l_p: X = l_p·(U·e_u + V·e_v).
fn mesh_coordinates(p: [f64; 2], eu: [f64; 2], ev: [f64; 2], lp: f64) -> [f64; 2] {
    let det = eu[0] * ev[1] - eu[1] * ev[0];
    [
        (p[0] * ev[1] - p[1] * ev[0]) / (det * lp),
        (eu[0] * p[1] - eu[1] * p[0]) / (det * lp),
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Uniform in-plane stretch F = diag(1 + ε1, 1 + ε2) of an irregularly triangulated panel
/// with twines along e_u, e_v: the edge nodes held at F·X, the interior started off the
/// affine positions (also out of plane). Statics must put every interior node at F·X and give
/// every triangle the twine tension EA·(|F·e| − 1) of its families; returns the largest
/// relative deviations (position, tension).
fn patch_test(eu: [f64; 2], ev: [f64; 2], eps: [f64; 2]) -> (f64, f64) {
    let (ea, lp, mu) = (800.0, 0.025, 2e-3);
    let (lx, ly) = (1.0, 0.7);
    let (pts, tris, boundary) = irregular_panel(6, 5, lx, ly, 7);
    let f = [1.0 + eps[0], 1.0 + eps[1]];
    let affine = |p: [f64; 2]| [f[0] * p[0], f[1] * p[1], 0.0];
    let mut b = ModelBuilder::new(no_gravity());
    let mut rng = Jitter(11);
    let nodes: Vec<usize> = pts
        .iter()
        .zip(&boundary)
        .map(|(&p, &edge)| {
            let mut x = affine(p);
            if !edge {
                x[0] += 0.02 * rng.next();
                x[1] += 0.02 * rng.next();
                x[2] += 0.01 * rng.next();
            }
            b.add_node(x).unwrap()
        })
        .collect();
    let g = b
        .add_net_triangle_group("net", NetTriangleSection::new(ea, lp, mu))
        .unwrap();
    for t in &tris {
        let uv = t.map(|k| mesh_coordinates(pts[k], eu, ev, lp));
        b.add_net_triangle(g, t.map(|k| nodes[k]), uv).unwrap();
    }
    for (k, &edge) in boundary.iter().enumerate() {
        if edge {
            b.fix(nodes[k], Dofs::ALL).unwrap();
        }
    }
    let m = b.build().unwrap();
    let st = StaticSettings {
        tol: 1e-12,
        ..Default::default()
    };
    let sol = solve_static(&m, &mut NoLoads, &st).unwrap();
    let mut pos_err = 0.0f64;
    for (k, &p) in pts.iter().enumerate() {
        let want = affine(p);
        let got = sol.state.x[nodes[k]];
        pos_err = pos_err.max(norm([got[0] - want[0], got[1] - want[1], got[2] - want[2]]) / lx);
    }
    // Closed form: u = ∂x/∂U = F·l_p·e_u, so one U bar is stretched to l_p·|F·e_u|.
    let stretch = |e: [f64; 2]| ((f[0] * e[0]).powi(2) + (f[1] * e[1]).powi(2)).sqrt();
    let (tu, tv) = (ea * (stretch(eu) - 1.0), ea * (stretch(ev) - 1.0));
    let mut t_err = 0.0f64;
    for i in 0..m.net_triangles().len() {
        let tw = m.net_triangle_twines(i, &sol.state.x);
        t_err = t_err
            .max((tw.tension_u - tu).abs() / tu)
            .max((tw.tension_v - tv).abs() / tv);
        assert!((norm(tw.u) - lp * stretch(eu)).abs() < 1e-9 * lp);
    }
    (pos_err, t_err)
}

/// Square mesh (twines along the panel's axes) on a triangulation whose edges do not follow
/// them: T_u = EA·ε1, T_v = EA·ε2 in every triangle, interior nodes at the affine positions.
#[test]
fn patch_test_square_mesh_gives_ea_times_strain_in_every_triangle() {
    let (pos, ten) = patch_test([1.0, 0.0], [0.0, 1.0], [0.02, 0.01]);
    eprintln!("square: position {pos:.3e}, tension {ten:.3e}");
    assert!(
        pos < 1e-9,
        "interior nodes off the affine positions by {pos:.3e}·L"
    );
    assert!(ten < 1e-8, "twine tensions off EA·ε by {ten:.3e}");
}

/// Diamond mesh: twines at ±35° to the panel's x axis (an opening angle of 70°). Each bar
/// stretches by |F·e| − 1, so T = EA·(√((1 + ε1)²cos²θ + (1 + ε2)²sin²θ) − 1).
#[test]
fn patch_test_diamond_mesh_gives_the_stretch_of_the_rotated_bars() {
    let th = 35f64.to_radians();
    let (eu, ev) = ([th.cos(), th.sin()], [th.cos(), -th.sin()]);
    let (pos, ten) = patch_test(eu, ev, [0.03, -0.005]);
    assert!(
        pos < 1e-9,
        "interior nodes off the affine positions by {pos:.3e}·L"
    );
    assert!(
        ten < 1e-8,
        "twine tensions off the closed form by {ten:.3e}"
    );
    // Twines at ±45° with a different stretch along x and y: the same closed form.
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let (pos, ten) = patch_test([s, s], [-s, s], [0.01, 0.025]);
    assert!(pos < 1e-9 && ten < 1e-8, "{pos:.3e} {ten:.3e}");
}

/// Tension-only twines: in a triangle compressed along U and stretched along V the U family
/// carries nothing (r_c = 0) or r_c·EA·ε_u (r_c > 0), and the V family EA·ε_v; the nodal forces
/// are A_uv·(a_k·T_u·û + b_k·T_v·v̂) with the shape gradients worked out here by hand.
#[test]
fn compressed_twines_carry_no_force_stretched_ones_do() {
    let (ea, lp) = (1e3, 0.1);
    // (U, V) corners (0, 0), (4, 0), (0, 3): A_uv = 6, a = (−1/4, 1/4, 0), b = (−1/3, 0, 1/3).
    let uv = [[0.0, 0.0], [4.0, 0.0], [0.0, 3.0]];
    let (a, bb) = ([-0.25, 0.25, 0.0], [-1.0 / 3.0, 0.0, 1.0 / 3.0]);
    // Deformed: u = l_p·0.9·x̂ (compressed 10 %), v = l_p·1.02·(ŷ rotated 10° towards ẑ).
    let (cu, cv) = (0.9, 1.02);
    let phi = 10f64.to_radians();
    let vdir = [0.0, phi.cos(), phi.sin()];
    let x = [
        [0.3, -0.1, 0.2],
        [0.3 + 4.0 * lp * cu, -0.1, 0.2],
        [
            0.3 + 3.0 * lp * cv * vdir[0],
            -0.1 + 3.0 * lp * cv * vdir[1],
            0.2 + 3.0 * lp * cv * vdir[2],
        ],
    ];
    for rc in [0.0, 0.05] {
        let mut b = ModelBuilder::new(no_gravity());
        let n: Vec<usize> = x.iter().map(|&p| b.add_node(p).unwrap()).collect();
        let sec = NetTriangleSection::new(ea, lp, 1e-3).with_compression_ratio(rc);
        let g = b.add_net_triangle_group("net", sec).unwrap();
        b.add_net_triangle(g, [n[0], n[1], n[2]], uv).unwrap();
        let m = b.build().unwrap();
        let t = &m.net_triangles()[0];
        assert!((t.uv_area() - 6.0).abs() < 1e-14);
        let tw = m.net_triangle_twines(0, &x);
        let (tu, tv) = (rc * ea * (cu - 1.0), ea * (cv - 1.0));
        assert!(
            (tw.tension_u - tu).abs() < 1e-9 * ea,
            "T_u {} vs {tu}",
            tw.tension_u
        );
        assert!(
            (tw.tension_v - tv).abs() < 1e-9 * ea,
            "T_v {} vs {tv}",
            tw.tension_v
        );
        assert!((tw.opening_angle - (std::f64::consts::FRAC_PI_2)).abs() < 1e-12);
        let f = t.internal_forces(&x);
        for k in 0..3 {
            for c in 0..3 {
                let u_part = 6.0 * a[k] * tu * [1.0, 0.0, 0.0][c];
                let want = u_part + 6.0 * bb[k] * tv * vdir[c];
                assert!(
                    (f[k][c] - want).abs() < 1e-9 * ea,
                    "r_c {rc}: node {k} component {c}: {} vs {want}",
                    f[k][c]
                );
            }
        }
        if rc == 0.0 {
            // Node 1 sits only on the U family (b_1 = 0): it feels nothing at all.
            assert!(f[1].iter().all(|c| c.abs() < 1e-12), "{:?}", f[1]);
        }
    }
}

/// Builds one free triangle (no supports needed for the element's own functions) at `x`.
fn one_triangle(x: [[f64; 3]; 3], uv: [[f64; 2]; 3], sec: NetTriangleSection) -> Model {
    let mut b = ModelBuilder::new(no_gravity());
    let n: Vec<usize> = x.iter().map(|&p| b.add_node(p).unwrap()).collect();
    let g = b.add_net_triangle_group("net", sec).unwrap();
    b.add_net_triangle(g, [n[0], n[1], n[2]], uv).unwrap();
    b.build().unwrap()
}

/// The tangent is the derivative of the force and the force the derivative of the energy
/// (central differences), for taut, slack and nearly slack twine families, for r_c = 0 and
/// r_c > 0, in either orientation of the (U, V) triangle.
#[test]
fn tangent_and_force_match_finite_differences() {
    let lp = 0.2;
    let uv = [[0.3, 0.1], [2.2, 0.9], [0.6, 2.4]];
    let mut rng = Jitter(3);
    let map = |s: [f64; 2], m: [[f64; 3]; 2]| -> [f64; 3] {
        std::array::from_fn(|c| 1.7 + s[0] * m[0][c] + s[1] * m[1][c])
    };
    // Twine vectors (stretch of U, stretch of V): both taut, U slack, U just taut (ε ~ 1e-4),
    // both slack.
    let cases = [(1.05, 1.02), (0.93, 1.04), (1.0001, 1.03), (0.95, 0.9)];
    let mut checked = 0;
    for (i, &(su, sv)) in cases.iter().enumerate() {
        for rc in [0.0, 0.2] {
            for flip in [false, true] {
                let uv = if flip { [uv[0], uv[2], uv[1]] } else { uv };
                // u and v of the given stretches, at an angle of 60°…120° in a tilted plane.
                let ang = 1.0 + 0.5 * rng.next();
                let tilt = 0.4 * rng.next();
                let du = [lp * su, 0.0, 0.0];
                let dv = [
                    lp * sv * ang.cos(),
                    lp * sv * ang.sin() * tilt.cos(),
                    lp * sv * ang.sin() * tilt.sin(),
                ];
                let x: [[f64; 3]; 3] = std::array::from_fn(|k| map(uv[k], [du, dv]));
                let sec = NetTriangleSection::new(3e3, lp, 1e-3).with_compression_ratio(rc);
                let m = one_triangle(x, uv, sec);
                let t = &m.net_triangles()[0];
                let tw = t.twines(&x);
                assert!((norm(tw.u) / lp - su).abs() < 1e-12, "case {i}");
                let k = t.tangent(&x);
                let f = t.internal_forces(&x);
                let h = 1e-7;
                for col in 0..9 {
                    let (mut xp, mut xm) = (x, x);
                    xp[col / 3][col % 3] += h;
                    xm[col / 3][col % 3] -= h;
                    let (fp, fm) = (t.internal_forces(&xp), t.internal_forces(&xm));
                    for row in 0..9 {
                        let fd = (fp[row / 3][row % 3] - fm[row / 3][row % 3]) / (2.0 * h);
                        let scale = 1.0 + k[row][col].abs();
                        assert!(
                            (fd - k[row][col]).abs() < 1e-5 * scale,
                            "case {i} r_c {rc}: K[{row}][{col}] fd {fd} vs {}",
                            k[row][col]
                        );
                        checked += 1;
                    }
                    let de = (t.strain_energy(&xp) - t.strain_energy(&xm)) / (2.0 * h);
                    let fc = f[col / 3][col % 3];
                    assert!(
                        (de - fc).abs() < 1e-6 * (1.0 + fc.abs()),
                        "case {i} r_c {rc}: force {fc} vs dE/dx {de}"
                    );
                }
                // Symmetric (a Hessian) and translation invariant: rows sum to zero over the
                // corners.
                for r in 0..9 {
                    for c in 0..9 {
                        assert!((k[r][c] - k[c][r]).abs() < 1e-9 * (1.0 + k[r][c].abs()));
                    }
                    for c in 0..3 {
                        let s: f64 = (0..3).map(|j| k[r][3 * j + c]).sum();
                        assert!(s.abs() < 1e-9 * (1.0 + k[r][c].abs()));
                    }
                }
            }
        }
    }
    assert_eq!(checked, 4 * 2 * 2 * 81);
}

/// Bad input is refused with a typed error naming what is wrong.
#[test]
fn bad_triangles_and_sections_are_refused() {
    let mut b = ModelBuilder::new(no_gravity());
    for p in [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        b.add_node(p).unwrap();
    }
    let e = b
        .add_net_triangle_group("net", NetTriangleSection::new(-1.0, 0.1, 1e-3))
        .unwrap_err();
    assert!(matches!(e, FemError::InvalidParameter { .. }), "{e}");
    assert!(e.to_string().contains("ea"), "{e}");
    let e = b
        .add_net_triangle_group("net", NetTriangleSection::new(1.0, 0.0, 1e-3))
        .unwrap_err();
    assert!(e.to_string().contains("bar_length"), "{e}");
    let g = b
        .add_net_triangle_group("net", NetTriangleSection::new(1e3, 0.1, 1e-3))
        .unwrap();
    let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let e = b.add_net_triangle(g, [0, 1, 7], uv).unwrap_err();
    assert!(matches!(e, FemError::UnknownNode { node: 7, .. }), "{e}");
    let e = b
        .add_net_triangle(g, [0, 1, 2], [[0.0, 0.0], [1.0, 1.0], [3.0, 3.0]])
        .unwrap_err();
    assert!(matches!(e, FemError::DegenerateNetTriangle { .. }), "{e}");
    let e = b.add_net_triangle(g, [0, 1, 1], uv).unwrap_err();
    assert!(e.to_string().contains("distinct"), "{e}");
    // Clockwise (U, V) corners are a triangle like any other.
    b.add_net_triangle(g, [0, 2, 1], [uv[0], uv[2], uv[1]])
        .unwrap();
}
