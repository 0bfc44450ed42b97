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

/// A diamond net pulled along its x diagonal to a given length, its sides y = ±W/2 pulled
/// apart by a total force F_y each: with twines u = (c, s), v = (c, −s) the cell spans 2c
/// by 2s. The x diagonal fixes c = L_x/S (S the panel's extent in U + V); across the panel's
/// width S/2 U twines and S/2 V twines carry T·s/l each, so F_y = S·T·s/l with
/// l = √(c² + s²) and T = EA·(l/l_p − 1). Inextensible twines give s = √(l_p² − c²) whatever
/// F_y (the net's kinematics: α = acos(c/l_p)); elastic ones the root of that equation,
/// found here by bisection. Returns (s from the solve, s of the closed form, largest
/// deviation of a twine tension from T).
fn pulled_diamond(ea: f64, fy: f64) -> (f64, f64, f64) {
    let lp = 0.05;
    let alpha = 30f64.to_radians();
    let c = lp * alpha.cos();
    let (ns1, ns2, s_ext, d) = (6, 4, 12.0, 4.0);
    let (mut pts, tris, boundary) = irregular_panel(ns1, ns2, s_ext, 2.0 * d, 5);
    for p in &mut pts {
        p[1] -= d;
    }
    // The middle node of the left edge on the centre line: held in y (y = 0 there).
    let mid = (ns2 / 2) * (ns1 + 1);
    pts[mid][1] = 0.0;
    // Closed form.
    let l_of = |s: f64| (c * c + s * s).sqrt();
    let force = |s: f64| s_ext * ea * (l_of(s) / lp - 1.0) * s / l_of(s);
    let (mut lo, mut hi) = ((lp * lp - c * c).sqrt(), 2.0 * lp);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if force(m) < fy { lo = m } else { hi = m }
    }
    let s_exact = 0.5 * (lo + hi);
    let tension = ea * (l_of(s_exact) / lp - 1.0);
    // Model: started from a wider, unstretched guess.
    let s0 = 1.05 * (lp * lp - c * c).sqrt();
    let mut rng = Jitter(17);
    let mut b = ModelBuilder::new(no_gravity());
    let nodes: Vec<usize> = pts
        .iter()
        .zip(&boundary)
        .map(|(&p, &edge)| {
            let jit = if edge { 0.0 } else { 0.1 * rng.next() };
            b.add_node([c * p[0] + jit * c, s0 * p[1] + jit * s0, 0.0])
                .unwrap()
        })
        .collect();
    let g = b
        .add_net_triangle_group("net", NetTriangleSection::new(ea, lp, 1e-3))
        .unwrap();
    for t in &tris {
        // U = (s1 + s2)/2, V = (s1 − s2)/2: x = c·s1, y = s·s2.
        let uv = t.map(|k| [0.5 * (pts[k][0] + pts[k][1]), 0.5 * (pts[k][0] - pts[k][1])]);
        b.add_net_triangle(g, t.map(|k| nodes[k]), uv).unwrap();
    }
    let z_only = Dofs {
        x: false,
        y: false,
        z: true,
    };
    let x_z = Dofs {
        x: true,
        y: false,
        z: true,
    };
    for (k, p) in pts.iter().enumerate() {
        let end = p[0] == 0.0 || p[0] == s_ext;
        b.fix(nodes[k], if end { x_z } else { z_only }).unwrap();
    }
    b.fix(nodes[mid], Dofs::ALL).unwrap();
    // The side traction F_y/S per unit s1, lumped on the side nodes (half of each segment).
    for side in [-d, d] {
        let mut on: Vec<usize> = (0..pts.len()).filter(|&k| pts[k][1] == side).collect();
        on.sort_by(|&i, &j| pts[i][0].total_cmp(&pts[j][0]));
        for (j, &k) in on.iter().enumerate() {
            let left = if j > 0 {
                pts[k][0] - pts[on[j - 1]][0]
            } else {
                0.0
            };
            let right = if j + 1 < on.len() {
                pts[on[j + 1]][0] - pts[k][0]
            } else {
                0.0
            };
            let f = fy * 0.5 * (left + right) / s_ext * side.signum();
            b.add_point_body(PointBody {
                node: nodes[k],
                mass: 0.0,
                force: [0.0, f, 0.0],
                seabed_stiffness: 0.0,
            })
            .unwrap();
        }
    }
    let m = b.build().unwrap();
    let st = StaticSettings {
        tol: 1e-12,
        ..Default::default()
    };
    let sol = solve_static(&m, &mut NoLoads, &st).unwrap();
    // Every node on the affine map x = c·s1, y = s·s2: s from the top and bottom corners.
    let top = (0..pts.len()).find(|&k| pts[k][1] == d).unwrap();
    let s_got = sol.state.x[nodes[top]][1] / d;
    for (k, p) in pts.iter().enumerate() {
        let x = sol.state.x[nodes[k]];
        assert!(
            (x[0] - c * p[0]).abs() < 1e-9 * lp && (x[1] - s_got * p[1]).abs() < 1e-9 * lp,
            "node {k} off the affine map: {x:?}"
        );
    }
    let mut t_err = 0.0f64;
    for i in 0..m.net_triangles().len() {
        let tw = m.net_triangle_twines(i, &sol.state.x);
        t_err = t_err
            .max((tw.tension_u - tension).abs())
            .max((tw.tension_v - tension).abs());
    }
    (s_got, s_exact, t_err / tension)
}

/// Inextensible twines (EA → ∞, here 1e7 N against a tension of ~0.2 N): pulling the x
/// diagonal to 2·l_p·cos 30° per cell contracts the y diagonal to 2·l_p·sin 30° per cell, the
/// net's kinematics. Elastic twines (EA = 20 N, strain ~1 %): the width of the closed form
/// with the bars stretched by T/EA.
#[test]
fn diamond_net_pulled_along_a_diagonal_contracts_along_the_other() {
    let lp = 0.05;
    let kin = lp * 30f64.to_radians().sin();
    let (s, s_exact, t_err) = pulled_diamond(1e7, 1.2);
    eprintln!("EA 1e7: s = {s:.9e}, closed form {s_exact:.9e}, kinematics {kin:.9e}");
    assert!((s / s_exact - 1.0).abs() < 1e-9, "{s} vs {s_exact}");
    assert!(
        (s / kin - 1.0).abs() < 1e-6,
        "contraction {s} vs kinematic {kin}"
    );
    // T = EA·ε at ε = 1e-8: a length's round-off (ε_mach·|x|/l_p ~ 1e-14) is 1e-6 of it.
    assert!(t_err < 1e-4, "tensions off by {t_err:.3e}");
    let (s, s_exact, t_err) = pulled_diamond(20.0, 1.2);
    eprintln!("EA 20: s = {s:.9e}, closed form {s_exact:.9e}, kinematics {kin:.9e}");
    assert!((s / s_exact - 1.0).abs() < 1e-9, "{s} vs {s_exact}");
    // The twines' stretch is visible: wider than the inextensible net by more than 1 %.
    assert!(s / kin - 1.0 > 0.01, "{s} vs {kin}");
    assert!(t_err < 1e-8, "tensions off by {t_err:.3e}");
}

/// A net panel 0.6 m × 0.5 m (square mesh, l_p = 5 cm, on an irregular triangulation) hung in
/// the x-z plane from its two top corners, and its initial state: the panel turned by 30°
/// about its top edge (rigidly: no twine strained), at rest. Gravity swings it; its
/// horizontal twines go slack and taut as it sags and swings.
fn swinging_net() -> (Model, State) {
    let (lp, lx, lz) = (0.05, 0.6, 0.5);
    let (pts, tris, _) = irregular_panel(4, 3, lx, lz, 23);
    let mut b = ModelBuilder::new(Environment::default());
    let nodes: Vec<usize> = pts
        .iter()
        .map(|p| b.add_node([p[0], 0.0, -p[1]]).unwrap())
        .collect();
    let g = b
        .add_net_triangle_group("net", NetTriangleSection::new(40.0, lp, 2e-3))
        .unwrap();
    for t in &tris {
        let uv = t.map(|k| mesh_coordinates(pts[k], [1.0, 0.0], [0.0, 1.0], lp));
        b.add_net_triangle(g, t.map(|k| nodes[k]), uv).unwrap();
    }
    for (k, p) in pts.iter().enumerate() {
        if p[1] == 0.0 && (p[0] == 0.0 || p[0] == lx) {
            b.fix(nodes[k], Dofs::ALL).unwrap();
        }
    }
    let m = b.build().unwrap();
    let mut init = State::as_built(&m, 0.0);
    let th = 30f64.to_radians();
    for (k, p) in pts.iter().enumerate() {
        init.x[nodes[k]] = [p[0], p[1] * th.sin(), -p[1] * th.cos()];
    }
    (m, init)
}

/// Total energy of the net at a state, computed here: ½·Σ m_i·|v_i|² + Σ E_t + Σ m_i·g·z_i.
fn net_energy(m: &Model, s: &State) -> f64 {
    let g = m.environment().gravity;
    let mut e = 0.0;
    for (i, &mi) in m.lumped_mass().iter().enumerate() {
        let v = s.v[i];
        e += 0.5 * mi * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + mi * g * s.x[i][2];
    }
    e + m
        .net_triangles()
        .iter()
        .map(|t| t.strain_energy(&s.x))
        .sum::<f64>()
}

/// Whether some twine family of the net is slack and some taut.
fn slack_and_taut(m: &Model, x: &[[f64; 3]]) -> (bool, bool) {
    let (mut slack, mut taut) = (false, false);
    for i in 0..m.net_triangles().len() {
        let tw = m.net_triangle_twines(i, x);
        for t in [tw.tension_u, tw.tension_v] {
            slack |= t == 0.0;
            taut |= t > 0.0;
        }
    }
    (slack, taut)
}

/// The energy-consistent midpoint rule keeps the swinging net's energy (kinetic + twines +
/// gravity, computed from the state here) to the Newton tolerance over 10⁴ steps, through
/// every slack/taut switch of its twines: the twines' force is the discrete gradient of their
/// energy.
#[test]
fn midpoint_keeps_the_energy_of_a_swinging_net() {
    let (m, init) = swinging_net();
    let e0 = net_energy(&m, &init);
    let dt = 2e-3;
    let mut s = DynamicSettings::new(dt, 1e4 * dt);
    s.midpoint = true;
    s.tol = 1e-9;
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let (mut steps, mut worst, mut ledger, mut scale) = (0, 0.0f64, 0.0f64, 0.0f64);
    let (mut saw_slack, mut saw_taut, mut swing) = (false, false, 0.0f64);
    while !solver.is_finished() {
        let r = solver.step(&mut NoLoads).unwrap();
        let st = solver.state();
        let e = net_energy(&m, st);
        worst = worst.max((e - e0).abs());
        scale = scale.max(r.energies.kinetic);
        ledger = ledger.max(r.energies.numerical_dissipation.abs());
        let (sl, ta) = slack_and_taut(&m, &st.x);
        saw_slack |= sl;
        saw_taut |= ta;
        swing = swing.max(st.v.iter().map(|v| v[1].abs()).fold(0.0, f64::max));
        steps += 1;
    }
    eprintln!(
        "{steps} steps: |E − E0| ≤ {worst:.3e} J, ledger {ledger:.3e} J, peak kinetic {scale:.3e} J"
    );
    assert!(steps >= 10_000, "{steps} steps");
    assert!(saw_slack && saw_taut, "slack {saw_slack} taut {saw_taut}");
    assert!(swing > 0.3, "the net did not swing ({swing} m/s)");
    assert!(worst <= 1e-6 * scale, "energy error {worst} J of {scale} J");
    assert!(
        ledger <= 1e-6 * scale,
        "ledger's numerical dissipation {ledger} J"
    );
}

/// HHT-α carries the same swinging net with bounded energy: it never gains more than a
/// permille of the kinetic energy scale (its numerical damping only takes energy out, mostly
/// from the twines' axial vibration: about a quarter of the swing's energy in 3 s).
#[test]
fn hht_carries_the_swinging_net_with_bounded_energy() {
    let (m, init) = swinging_net();
    let e0 = net_energy(&m, &init);
    let s = DynamicSettings::new(2e-3, 3.0);
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let (mut gain, mut scale, mut loss) = (0.0f64, 0.0f64, 0.0f64);
    while !solver.is_finished() {
        let r = solver.step(&mut NoLoads).unwrap();
        let e = net_energy(&m, solver.state());
        gain = gain.max(e - e0);
        loss = loss.max(e0 - e);
        scale = scale.max(r.energies.kinetic);
    }
    eprintln!("HHT: gain {gain:.3e} J, loss {loss:.3e} J, peak kinetic {scale:.3e} J");
    assert!(scale > 0.01, "no swing: {scale} J");
    assert!(gain <= 1e-3 * scale, "energy grew by {gain} J of {scale} J");
    assert!(loss <= 0.5 * scale, "HHT took {loss} J of {scale} J");
}

/// The explicit scheme (RK4 at its stable step) swings the net like the midpoint rule at a
/// small step: same position of the bottom corner after 0.3 s, energy kept to 1e-3.
#[test]
fn explicit_scheme_swings_the_net_like_the_midpoint_rule() {
    let (m, init) = swinging_net();
    let e0 = net_energy(&m, &init);
    let t_end = 0.3;
    let mut es = ExplicitSettings::new(t_end);
    es.scheme = ExplicitScheme::Rk4;
    let mut ex = ExplicitSolver::new(&m, es, Some(&init), &mut NoLoads).unwrap();
    let mut n_ex = 0;
    while !ex.is_finished() {
        ex.step(&mut NoLoads).unwrap();
        n_ex += 1;
    }
    let mut s = DynamicSettings::new(1e-4, t_end);
    s.midpoint = true;
    // The round-off of (x1 − x_n)/Δt bounds the relative residual near 1e-9 at this step.
    s.tol = 1e-8;
    let mut mid = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    mid.run(&mut NoLoads, |_, _| true).unwrap();
    let corner = m
        .nodes()
        .iter()
        .position(|p| p[0] == 0.0 && p[2] == -0.5)
        .unwrap();
    let (a, b) = (ex.state().x[corner], mid.state().x[corner]);
    let d = norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]]);
    let de = (net_energy(&m, ex.state()) - e0).abs();
    let kinetic: f64 = m
        .lumped_mass()
        .iter()
        .zip(&ex.state().v)
        .map(|(mi, v)| 0.5 * mi * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
        .sum();
    let fall = norm([
        a[0] - init.x[corner][0],
        a[1] - init.x[corner][1],
        a[2] - init.x[corner][2],
    ]);
    eprintln!(
        "explicit: {n_ex} steps, corner {a:?} vs midpoint {b:?} ({d:.3e} m), |ΔE| {de:.3e} J, moved {fall:.3e} m"
    );
    assert!(fall > 0.05, "the corner hardly moved ({fall} m)");
    assert!(
        d < 2e-3 * fall,
        "explicit and midpoint differ by {d} m of {fall} m"
    );
    assert!(
        de < 1e-3 * kinetic,
        "explicit energy changed by {de} J of {kinetic} J"
    );
}

/// Axial damping of the twines takes energy out, and the ledger's damping dissipation is
/// what the net lost (computed from the state), to the trapezoidal rule's accuracy.
#[test]
fn twine_damping_dissipates_what_the_ledger_says() {
    let (lp, lx, lz) = (0.05, 0.6, 0.5);
    let (pts, tris, _) = irregular_panel(4, 3, lx, lz, 23);
    let mut b = ModelBuilder::new(Environment::default());
    let nodes: Vec<usize> = pts
        .iter()
        .map(|p| b.add_node([p[0], 0.0, -p[1]]).unwrap())
        .collect();
    let sec = NetTriangleSection::new(40.0, lp, 2e-3).with_axial_damping(AxialDamping::Ratio(0.5));
    let g = b.add_net_triangle_group("net", sec).unwrap();
    for t in &tris {
        let uv = t.map(|k| mesh_coordinates(pts[k], [1.0, 0.0], [0.0, 1.0], lp));
        b.add_net_triangle(g, t.map(|k| nodes[k]), uv).unwrap();
    }
    for (k, p) in pts.iter().enumerate() {
        if p[1] == 0.0 && (p[0] == 0.0 || p[0] == lx) {
            b.fix(nodes[k], Dofs::ALL).unwrap();
        }
    }
    let m = b.build().unwrap();
    let (_, init) = swinging_net();
    let e0 = net_energy(&m, &init);
    // The ledger integrates the damping power by the trapezoidal rule: 13 % off at Δt = 2 ms
    // (the damped axial vibration of the twines is not resolved), 2.7 % at 0.5 ms, 0.3 % here.
    let mut s = DynamicSettings::new(2.5e-4, 0.2);
    s.midpoint = true;
    s.tol = 1e-8;
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    solver.run(&mut NoLoads, |_, _| true).unwrap();
    let lost = e0 - net_energy(&m, solver.state());
    let d = solver.energies().damping_dissipation;
    eprintln!("damped net: lost {lost:.4e} J, ledger's damping dissipation {d:.4e} J");
    assert!(d > 1e-5, "no damping dissipation: {d} J");
    assert!(
        (lost - d).abs() < 0.02 * d,
        "lost {lost} J, dissipated {d} J"
    );
}

/// The element kernels run in parallel from 512 triangles; the results are the same bit for
/// bit on 1 and 2 threads (statics and midpoint steps of a 560-triangle panel).
#[test]
fn same_result_on_one_and_two_threads() {
    let (lp, lx, ly) = (0.02, 1.0, 0.7);
    let (pts, tris, boundary) = irregular_panel(20, 14, lx, ly, 31);
    assert!(tris.len() >= 512);
    let mut b = ModelBuilder::new(Environment::default());
    let nodes: Vec<usize> = pts
        .iter()
        .map(|p| b.add_node([1.01 * p[0], 1.02 * p[1], 0.0]).unwrap())
        .collect();
    let g = b
        .add_net_triangle_group("net", NetTriangleSection::new(500.0, lp, 1e-3))
        .unwrap();
    for t in &tris {
        let uv = t.map(|k| mesh_coordinates(pts[k], [0.8, 0.6], [-0.6, 0.8], lp));
        b.add_net_triangle(g, t.map(|k| nodes[k]), uv).unwrap();
    }
    for (k, &edge) in boundary.iter().enumerate() {
        if edge {
            b.fix(nodes[k], Dofs::ALL).unwrap();
        }
    }
    let m = b.build().unwrap();
    let run = || {
        let sol = solve_static(&m, &mut NoLoads, &StaticSettings::default()).unwrap();
        let mut init = sol.state.clone();
        for (k, x) in init.x.iter_mut().enumerate() {
            if !boundary[k] {
                x[2] += 0.01;
            }
        }
        let mut s = DynamicSettings::new(1e-3, 5e-3);
        s.midpoint = true;
        let mut d = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
        d.run(&mut NoLoads, |_, _| true).unwrap();
        (sol.state.x, d.state().x.clone())
    };
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let one = pool(1).install(run);
    let two = pool(2).install(run);
    assert!(one == two, "results differ between 1 and 2 threads");
}

/// Triangles whose corners are the knots of a square mesh (each cell cut in two, A_uv = ½)
/// hold, per triangle, half of two bars of the cell: each interior bar is shared by two cells
/// and counted whole, each bar on the panel's edge counted half (the other half of that twine
/// belongs to netting beyond the edge). So they are exactly the bar network with edge bars at
/// half EA: under the same point loads (a net hung from its top corners, pulled down and aside,
/// with slack twines) statics put every knot at the same place.
#[test]
fn knot_triangles_are_the_bar_network_with_half_edge_bars() {
    let (nx, nz, lp, ea) = (6, 5, 0.1, 300.0);
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let solve = |triangles: bool| {
        let mut b = ModelBuilder::new(no_gravity());
        for j in 0..=nz {
            for i in 0..=nx {
                // As built a little off the knots' rest positions (the solver must move them).
                let w = 0.002 * ((i * 7 + j * 3) % 5) as f64;
                b.add_node([i as f64 * lp + w, w, -(j as f64) * lp])
                    .unwrap();
            }
        }
        if triangles {
            let g = b
                .add_net_triangle_group("net", NetTriangleSection::new(ea, lp, 1e-3))
                .unwrap();
            for j in 0..nz {
                for i in 0..nx {
                    let c = |a: usize, bb: usize| ([a as f64, bb as f64], id(a, bb));
                    let (p00, p10, p11, p01) = (c(i, j), c(i + 1, j), c(i + 1, j + 1), c(i, j + 1));
                    // Alternate the diagonal: the bars are the same either way.
                    let halves = if (i + j) % 2 == 0 {
                        [[p00, p10, p11], [p00, p11, p01]]
                    } else {
                        [[p00, p10, p01], [p10, p11, p01]]
                    };
                    for h in halves {
                        b.add_net_triangle(g, h.map(|p| p.1), h.map(|p| p.0))
                            .unwrap();
                    }
                }
            }
        } else {
            let inner = b.add_group("inner", CableSection::new(ea, 1e-3)).unwrap();
            let edge = b
                .add_group("edge", CableSection::new(0.5 * ea, 0.5e-3))
                .unwrap();
            let len = UnstretchedLength::Given(lp);
            for j in 0..=nz {
                for i in 0..=nx {
                    if i < nx {
                        let g = if j == 0 || j == nz { edge } else { inner };
                        b.add_cable(id(i, j), id(i + 1, j), g, len).unwrap();
                    }
                    if j < nz {
                        let g = if i == 0 || i == nx { edge } else { inner };
                        b.add_cable(id(i, j), id(i, j + 1), g, len).unwrap();
                    }
                }
            }
        }
        b.fix(id(0, 0), Dofs::ALL).unwrap();
        b.fix(id(nx, 0), Dofs::ALL).unwrap();
        for j in 0..=nz {
            for i in 0..=nx {
                let side = if j == nz && i == nx { 0.3 } else { 0.0 };
                b.add_point_body(PointBody {
                    node: id(i, j),
                    mass: 0.0,
                    force: [side, 0.05 * side, -0.1],
                    seabed_stiffness: 0.0,
                })
                .unwrap();
            }
        }
        let m = b.build().unwrap();
        let st = StaticSettings {
            tol: 1e-11,
            ..Default::default()
        };
        let sol = solve_static(&m, &mut NoLoads, &st).unwrap();
        let slack = (0..m.net_triangles().len())
            .map(|i| m.net_triangle_twines(i, &sol.state.x))
            .filter(|t| t.tension_u == 0.0 || t.tension_v == 0.0)
            .count();
        (sol.state.x, sol.report.iterations, slack)
    };
    let (xt, it_t, slack) = solve(true);
    let (xc, it_c, _) = solve(false);
    let d = xt
        .iter()
        .zip(&xc)
        .map(|(a, b)| norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]]))
        .fold(0.0, f64::max);
    let sag = -xt[id(nx / 2, nz)][2] - nz as f64 * lp;
    eprintln!(
        "triangles vs bars: {d:.3e} m apart; {it_t} vs {it_c} iterations; {slack} triangles with a slack family; bottom stretched/sagged by {sag:.3e} m"
    );
    assert!(
        slack > 0,
        "no slack twines: the test would not exercise the slack law"
    );
    assert!(d < 1e-9, "triangles and bars differ by {d} m");
}

/// With the consistent mass (m/12·[2 1 1; 1 2 1; 1 1 2] per triangle and component) the
/// midpoint rule keeps the swinging net's energy too, its kinetic energy ½·vᵀ·M·v formed here
/// triangle by triangle.
#[test]
fn midpoint_keeps_the_energy_with_the_consistent_mass() {
    let (m, init) = swinging_net();
    let g = m.environment().gravity;
    let energy = |s: &State| {
        let mut e = 0.0;
        for t in m.net_triangles() {
            let mt = t.mass();
            let [p, q, r] = t.nodes;
            for k in 0..3 {
                let (a, b, c) = (s.v[p][k], s.v[q][k], s.v[r][k]);
                e += 0.5 * mt / 12.0
                    * (2.0 * (a * a + b * b + c * c) + 2.0 * (a * b + b * c + a * c));
            }
            let zc = (s.x[p][2] + s.x[q][2] + s.x[r][2]) / 3.0;
            e += mt * g * zc + t.strain_energy(&s.x);
        }
        e
    };
    let e0 = energy(&init);
    let mut s = DynamicSettings::new(2e-3, 4.0);
    s.midpoint = true;
    s.tol = 1e-9;
    s.mass_matrix = MassMatrix::Consistent;
    let mut solver = DynamicSolver::new(&m, s, Some(&init), &mut NoLoads).unwrap();
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    while !solver.is_finished() {
        let r = solver.step(&mut NoLoads).unwrap();
        worst = worst.max((energy(solver.state()) - e0).abs());
        scale = scale.max(r.energies.kinetic);
    }
    eprintln!("consistent mass: |E − E0| ≤ {worst:.3e} J of {scale:.3e} J");
    assert!(scale > 0.005, "no swing: {scale} J");
    assert!(worst <= 1e-6 * scale, "energy error {worst} J of {scale} J");
}
