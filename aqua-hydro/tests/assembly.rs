//! Load assembly checks against independent numbers:
//! docs/theory/hydrodynamics.md#worked-load-cases, closed forms, finite differences and symmetry.

use aqua_env::{
    Component, Constants, Current, Depth, LinearSum, Phase, Ramp, Sea, Stretching, Waves,
};
use aqua_hydro::assembly::{MAX_DOFS, MAX_NODES};
use aqua_hydro::{
    Block, ElementOutput, Elements, HydroError, LineElement, LineProps, LoadAssembly, MorisonModel,
    NetPanel, NetProps, Outputs, PanelNodes, PointElement, PointProps, PointShape, ScreenModel,
    TwineMap, Wake, WakeCell, WakeGroup, WakeModel, WakeUpdate, Want,
};
use proptest::prelude::*;
use std::f64::consts::PI;

const RHO: f64 = 1025.0;

fn current_sea(u: [f64; 3]) -> Sea {
    Sea::new(Constants::default(), Current::uniform(u), Waves::None)
}

fn net(model: ScreenModel, sn: f64) -> NetProps {
    NetProps {
        model,
        solidity: sn,
        twine_diameter: 0.0024,
    }
}

fn rope(model: MorisonModel, d: f64, l0: f64) -> LineProps {
    LineProps {
        model,
        hydro_diameter: d,
        reynolds_diameter: d,
        volume_diameter: d,
        rest_length: l0,
        added_mass: 1.0,
        added_mass_axial: 0.0,
        froude_krylov: true,
        knot_correction: false,
    }
}

struct Out {
    f: Vec<[f64; 3]>,
    m: Vec<Block>,
    dv: Vec<Block>,
    dx: Vec<Block>,
}

fn run(asm: &mut LoadAssembly, t: f64, x: &[[f64; 3]], v: &[[f64; 3]]) -> Out {
    run_in(asm, t, Phase::Dynamic, x, v)
}

fn run_in(asm: &mut LoadAssembly, t: f64, phase: Phase, x: &[[f64; 3]], v: &[[f64; 3]]) -> Out {
    let n = asm.n_nodes();
    let mut o = Out {
        f: vec![[0.0; 3]; n],
        m: vec![[[0.0; 3]; 3]; n],
        dv: vec![[[0.0; 3]; 3]; asm.n_velocity_blocks()],
        dx: vec![[[0.0; 3]; 3]; asm.n_position_blocks()],
    };
    asm.evaluate(
        t,
        phase,
        x,
        v,
        Outputs {
            forces: &mut o.f,
            added_mass: Some(&mut o.m),
            dfdv: Some(&mut o.dv),
            dfdx: Some(&mut o.dx),
        },
    )
    .unwrap();
    o
}

fn total(f: &[[f64; 3]]) -> [f64; 3] {
    f.iter()
        .fold([0.0; 3], |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]])
}

#[test]
fn worked_panel_force() {
    // docs/theory/hydrodynamics.md#worked-load-cases: S1, Sn = 0.2, U = (0.5, 0, 0), unit-square
    // quad with normal (cos 30°, sin 30°, 0)
    let x = vec![
        [0.25, -0.4330127019, -2.5],
        [-0.25, 0.4330127019, -2.5],
        [-0.25, 0.4330127019, -1.5],
        [0.25, -0.4330127019, -1.5],
    ];
    let els = Elements {
        panels: vec![NetPanel {
            nodes: PanelNodes::Quad([0, 1, 2, 3]),
            net: net(ScreenModel::S1, 0.2),
            wake_group: None,
            twines: None,
        }],
        ..Default::default()
    };
    let mut asm = LoadAssembly::new(current_sea([0.5, 0.0, 0.0]), 4, els).unwrap();
    let o = run(&mut asm, 0.0, &x, &[[0.0; 3]; 4]);
    let expect = [29.5360910692, 5.9030456585, 0.0];
    let tot = total(&o.f);
    for k in 0..3 {
        assert!((tot[k] - expect[k]).abs() < 5e-9, "{tot:?}");
        for f in &o.f {
            assert!((f[k] - expect[k] / 4.0).abs() < 2e-9, "{f:?}");
        }
    }
    // panels add no buoyancy and no added mass
    assert!(o.m.iter().all(|b| b.iter().flatten().all(|v| *v == 0.0)));
}

/// A flat 1 m × 1 m panel in the plane spanned by e1 = (cos β… ) rotated about z by θ,
/// divided into k × k quads (or 2k² triangles).
fn flat_panel(theta: f64, k: usize, triangles: bool, sn: f64) -> (Vec<[f64; 3]>, Elements) {
    // in-plane horizontal direction t = (−sin θ, cos θ, 0): normal (cos θ, sin θ, 0)
    let t = [-theta.sin(), theta.cos(), 0.0];
    let mut x = Vec::new();
    for j in 0..=k {
        for i in 0..=k {
            let a = i as f64 / k as f64 - 0.5;
            let b = j as f64 / k as f64;
            x.push([a * t[0], a * t[1], -2.0 - b]);
        }
    }
    let id = |i: usize, j: usize| j * (k + 1) + i;
    let mut panels = Vec::new();
    for j in 0..k {
        for i in 0..k {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if triangles {
                for tri in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
                    panels.push(NetPanel {
                        nodes: PanelNodes::Triangle(tri),
                        net: net(ScreenModel::S1, sn),
                        wake_group: None,
                        twines: None,
                    });
                }
            } else {
                panels.push(NetPanel {
                    nodes: PanelNodes::Quad(q),
                    net: net(ScreenModel::S1, sn),
                    wake_group: None,
                    twines: None,
                });
            }
        }
    }
    (
        x,
        Elements {
            panels,
            ..Default::default()
        },
    )
}

#[test]
fn rotated_flat_panel_independent_of_subdivision_and_mirror_symmetric() {
    let u = 0.7;
    let q = 0.5 * RHO * 1.0 * u * u;
    for deg in (0..=90).step_by(10) {
        let th = (deg as f64).to_radians();
        let (cd, cl) = ScreenModel::S1.cd_cl(th, 0.25, 1.0);
        // lift along e_L: in the (U, n) plane, ⟂ U, on the side of n → +y for θ > 0
        let expect = [q * cd, q * cl, 0.0];
        for k in [1, 2, 5] {
            for triangles in [false, true] {
                for mirror in [1.0, -1.0] {
                    let (x, els) = flat_panel(mirror * th, k, triangles, 0.25);
                    let n = x.len();
                    let mut asm = LoadAssembly::new(current_sea([u, 0.0, 0.0]), n, els).unwrap();
                    let o = run(&mut asm, 0.0, &x, &vec![[0.0; 3]; n]);
                    let tot = total(&o.f);
                    let want = [expect[0], mirror * expect[1], 0.0];
                    for c in 0..3 {
                        assert!(
                            (tot[c] - want[c]).abs() < 1e-10 * q,
                            "θ {deg}° k {k} tri {triangles} mirror {mirror}: {tot:?} vs {want:?}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn worked_line_force_half_per_node() {
    let x = vec![[0.0, 0.0, -5.0], [1.0, 0.0, -5.0 - 3f64.sqrt()]];
    let mut p = rope(MorisonModel::M1, 0.05, 2.0);
    p.added_mass = 0.0;
    p.froude_krylov = false;
    let els = Elements {
        lines: vec![LineElement {
            nodes: [0, 1],
            props: p,
            net_twine: false,
            wake_group: None,
        }],
        ..Default::default()
    };
    let sea = current_sea([0.4, 0.0, 0.0]);
    let g = sea.gravity();
    let mut asm = LoadAssembly::new(sea, 2, els).unwrap();
    let o = run(&mut asm, 0.0, &x, &[[0.0; 3]; 2]);
    let buoy = RHO * g * PI / 4.0 * 0.05 * 0.05 * 2.0;
    let expect = [6.4937674799, 0.0, 3.5124647922 + buoy];
    for f in &o.f {
        for c in 0..3 {
            assert!((f[c] - expect[c] / 2.0).abs() < 5e-10, "{f:?}");
        }
    }
}

#[test]
fn floating_collar_half_submerged() {
    // docs/theory/hydrodynamics.md#wetted-fraction-of-a-line: horizontal pipe d_v = 0.35 m at z = 0
    // → φ̄ = ½, 483.549029 N/m
    let x = vec![[0.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
    let els = Elements {
        lines: vec![LineElement {
            nodes: [0, 1],
            props: rope(MorisonModel::M4, 0.35, 3.0),
            net_twine: false,
            wake_group: None,
        }],
        ..Default::default()
    };
    let mut asm = LoadAssembly::new(Sea::still(Constants::default()), 2, els).unwrap();
    let o = run(&mut asm, 0.0, &x, &[[0.0; 3]; 2]);
    assert!((total(&o.f)[2] - 3.0 * 483.549029).abs() < 3.0 * 5e-7);
    // added mass: ½ of C_a·ρ·A_v·L0 in the normal directions, per node
    let ma = 0.5 * RHO * PI / 4.0 * 0.35 * 0.35 * 3.0 * 0.5;
    assert!((o.m[0][1][1] - ma).abs() < 1e-9 && (o.m[0][2][2] - ma).abs() < 1e-9);
    assert!(o.m[0][0][0].abs() < 1e-12);
}

#[test]
fn inertia_in_airy_wave_matches_closed_form() {
    let c = Constants::default();
    let (a, period, phase) = (1.0, 8.0, 0.3);
    let comp = Component::new(a, period, 0.0, phase, Depth::Infinite, c.gravity).unwrap();
    let sea = Sea::new(
        c,
        Current::none(),
        Waves::Linear {
            sum: LinearSum::new(vec![comp], Depth::Infinite, c.gravity),
            stretching: Stretching::None,
            ramp: Ramp::off(),
        },
    );
    let (d, l0, z, x0) = (0.1, 2.0, -4.0, 3.0);
    let mut p = rope(MorisonModel::None, d, l0);
    p.added_mass = 1.0;
    // a rope along y (normal to the wave) and one along x (axial: only C_at acts)
    let mut p_axial = p;
    p_axial.added_mass_axial = 0.3;
    let x = vec![[x0, 0.0, z], [x0, l0, z], [x0, 5.0, z], [x0 + 1e-3, 5.0, z]];
    let els = Elements {
        lines: vec![
            LineElement {
                nodes: [0, 1],
                props: p,
                net_twine: false,
                wake_group: None,
            },
            LineElement {
                nodes: [2, 3],
                props: LineProps {
                    rest_length: 1e-3,
                    ..p_axial
                },
                net_twine: false,
                wake_group: None,
            },
        ],
        ..Default::default()
    };
    let mut asm = LoadAssembly::new(sea, 4, els).unwrap();
    let w = 2.0 * PI / period;
    let k = w * w / c.gravity;
    let av = PI / 4.0 * d * d;
    for i in 0..12 {
        let t = 0.7 * i as f64;
        let o = run(&mut asm, t, &x, &[[0.0; 3]; 4]);
        let th = k * x0 - w * t + phase;
        let ax = w * w * a * (k * z).exp() * th.sin();
        let az = -w * w * a * (k * z).exp() * th.cos();
        let m = RHO * av * l0;
        let fx = m * 2.0 * ax;
        let fz = m * 2.0 * az + RHO * c.gravity * av * l0;
        let f = [
            o.f[0][0] + o.f[1][0],
            o.f[0][1] + o.f[1][1],
            o.f[0][2] + o.f[1][2],
        ];
        let scale = m * w * w;
        assert!((f[0] - fx).abs() < 1e-9 * scale, "t {t}: {} vs {fx}", f[0]);
        assert!(f[1].abs() < 1e-12 * scale);
        assert!((f[2] - fz).abs() < 1e-9 * scale, "t {t}: {} vs {fz}", f[2]);
        // axial element: x-acceleration × C_at only (no axial Froude–Krylov)
        let ma = RHO * av * 1e-3;
        let fa = o.f[2][0] + o.f[3][0];
        let ax2 = w * w * a * (k * z).exp() * (k * (x0 + 5e-4) - w * t + phase).sin();
        assert!(
            (fa - ma * 0.3 * ax2).abs() < 1e-6 * ma * w * w,
            "axial {fa}"
        );
    }
}

/// Dense global matrix from the compact blocks.
fn global(asm: &LoadAssembly, blocks: &[Block], position: bool) -> Vec<Vec<f64>> {
    let n = 3 * asm.n_nodes();
    let mut g = vec![vec![0.0; n]; n];
    let mut dense = [[0.0; MAX_DOFS]; MAX_DOFS];
    for e in 0..asm.n_elements() {
        asm.expand(e, blocks, position, &mut dense);
        let nodes = asm.element_nodes(e);
        for (i, &ni) in nodes.iter().enumerate() {
            for (j, &nj) in nodes.iter().enumerate() {
                for r in 0..3 {
                    for c in 0..3 {
                        g[3 * ni + r][3 * nj + c] += dense[3 * i + r][3 * j + c];
                    }
                }
            }
        }
    }
    g
}

/// A mixed model: a warped quad, a triangle crossing the surface, a rope, a twine and a buoy.
fn mixed() -> (Vec<[f64; 3]>, Elements) {
    let x = vec![
        [0.0, 0.0, -2.0],
        [1.0, 0.2, -2.1],
        [1.1, 0.1, -1.0],
        [0.1, -0.1, -0.9],
        [0.5, 1.0, 0.3],
        [2.0, 0.5, -3.0],
        [2.2, 1.5, -0.05],
    ];
    let els = Elements {
        panels: vec![
            NetPanel {
                nodes: PanelNodes::Quad([0, 1, 2, 3]),
                net: net(ScreenModel::S3 { cyl_cd: None }, 0.2),
                wake_group: None,
                twines: None,
            },
            NetPanel {
                nodes: PanelNodes::Triangle([2, 3, 4]),
                net: net(ScreenModel::Bi2014, 0.2),
                wake_group: None,
                twines: None,
            },
            // A net triangle (twines of ~2–4 cm, Sn ≈ 0.2 and changing with the positions).
            NetPanel {
                nodes: PanelNodes::Triangle([2, 3, 4]),
                net: net(ScreenModel::S1, 0.2),
                wake_group: None,
                twines: TwineMap::new([[0.0, 0.0], [50.0, 5.0], [10.0, 60.0]]),
            },
        ],
        lines: vec![
            LineElement {
                nodes: [1, 5],
                props: rope(MorisonModel::M4, 0.03, 2.0),
                net_twine: false,
                wake_group: None,
            },
            LineElement {
                nodes: [5, 6],
                props: rope(MorisonModel::M1, 0.2, 3.2),
                net_twine: false,
                wake_group: None,
            },
        ],
        points: vec![
            PointElement {
                node: 6,
                props: PointProps {
                    volume: 0.5,
                    shape: PointShape::Prism { height: 0.4 },
                    drag_area: 0.3,
                    added_mass: 0.5,
                },
            },
            PointElement {
                // partly wet: centre 0.3 m above still water, radius 0.5 m
                node: 4,
                props: PointProps {
                    volume: 4.0 / 3.0 * PI * 0.125,
                    shape: PointShape::Sphere { radius: 0.5 },
                    drag_area: 0.5 * PI * 0.25,
                    added_mass: 0.5,
                },
            },
        ],
        ..Default::default()
    };
    (x, els)
}

fn rel(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale
}

#[test]
fn damping_and_stiffness_match_central_differences() {
    let (x, els) = mixed();
    let n = x.len();
    let mut asm = LoadAssembly::new(current_sea([0.6, 0.2, 0.0]), n, els).unwrap();
    let v: Vec<[f64; 3]> = (0..n)
        .map(|i| [0.05 * i as f64, -0.03, 0.02 * (i % 3) as f64])
        .collect();
    let o = run(&mut asm, 1.0, &x, &v);
    let gv = global(&asm, &o.dv, false);
    let gx = global(&asm, &o.dx, true);
    let scale_v = gv.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let scale_x = gx.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let richardson = |f: &mut dyn FnMut(f64) -> Vec<[f64; 3]>, h: f64| {
        let d = |f: &mut dyn FnMut(f64) -> Vec<[f64; 3]>, h: f64| {
            let (p, m) = (f(h), f(-h));
            p.iter()
                .zip(&m)
                .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]) / (2.0 * h)))
                .collect::<Vec<_>>()
        };
        let (d1, d2) = (d(f, h), d(f, 0.5 * h));
        d1.iter()
            .zip(&d2)
            .map(|(a, b)| (4.0 * b - a) / 3.0)
            .collect::<Vec<_>>()
    };
    for j in 0..n {
        for c in 0..3 {
            let col = richardson(
                &mut |h| {
                    let mut vp = v.clone();
                    vp[j][c] += h;
                    run(&mut asm, 1.0, &x, &vp).f
                },
                1e-4,
            );
            for (r, fd) in col.iter().enumerate() {
                let e = rel(gv[r][3 * j + c], *fd, scale_v);
                assert!(
                    e < 1e-6,
                    "dv row {r} col {}: {} vs {fd}",
                    3 * j + c,
                    gv[r][3 * j + c]
                );
            }
            let col = richardson(
                &mut |h| {
                    let mut xp = x.clone();
                    xp[j][c] += h;
                    run(&mut asm, 1.0, &xp, &v).f
                },
                1e-5,
            );
            for (r, fd) in col.iter().enumerate() {
                let e = rel(gx[r][3 * j + c], *fd, scale_x);
                assert!(
                    e < 1e-6,
                    "dx row {r} col {}: {} vs {fd}",
                    3 * j + c,
                    gx[r][3 * j + c]
                );
            }
        }
    }
}

#[test]
fn element_path_equals_bulk_path() {
    let (x, els) = mixed();
    let n = x.len();
    let mut asm = LoadAssembly::new(current_sea([0.6, 0.2, 0.0]), n, els).unwrap();
    let v = vec![[0.01, 0.02, -0.03]; n];
    let o = run(&mut asm, 0.5, &x, &v);
    asm.prepare(0.5, Phase::Dynamic, &x).unwrap();
    let mut f = vec![[0.0; 3]; n];
    let mut m = vec![[[0.0; 3]; 3]; n];
    let mut out = ElementOutput::default();
    let mut dense = [[0.0; MAX_DOFS]; MAX_DOFS];
    let want = Want {
        dfdv: true,
        dfdx: true,
    };
    for e in 0..asm.n_elements() {
        let nodes = asm.element_nodes(e).to_vec();
        let xl: Vec<[f64; 3]> = nodes.iter().map(|&i| x[i]).collect();
        let vl: Vec<[f64; 3]> = nodes.iter().map(|&i| v[i]).collect();
        asm.element_load(e, &xl, &vl, want, &mut out);
        for (i, &nd) in nodes.iter().enumerate() {
            for c in 0..3 {
                f[nd][c] += out.force[i][c];
                for d in 0..3 {
                    m[nd][c][d] += out.added_mass[i][c][d];
                }
            }
        }
        assert!(nodes.len() <= MAX_NODES);
        for (blocks, pos, mat) in [(&o.dv, false, &out.dfdv), (&o.dx, true, &out.dfdx)] {
            asm.expand(e, blocks, pos, &mut dense);
            for r in 0..3 * nodes.len() {
                for c in 0..3 * nodes.len() {
                    assert!((dense[r][c] - mat[r][c]).abs() <= 1e-12 * (1.0 + mat[r][c].abs()));
                }
            }
        }
    }
    for i in 0..n {
        for c in 0..3 {
            assert!((f[i][c] - o.f[i][c]).abs() < 1e-10 * (1.0 + o.f[i][c].abs()));
            for d in 0..3 {
                assert!((m[i][c][d] - o.m[i][c][d]).abs() < 1e-10 * (1.0 + o.m[i][c][d].abs()));
            }
        }
    }
}

/// A sea with one Airy wave (8 s, 1 m) and a current: its flow depends on time and position.
fn wave_sea() -> Sea {
    let c = Constants::default();
    let comp = Component::new(1.0, 8.0, 0.4, 0.3, Depth::Infinite, c.gravity).unwrap();
    Sea::new(
        c,
        Current::uniform([0.4, 0.1, 0.0]),
        Waves::Linear {
            sum: LinearSum::new(vec![comp], Depth::Infinite, c.gravity),
            stretching: Stretching::None,
            ramp: Ramp::off(),
        },
    )
}

#[test]
fn flow_is_reused_only_at_the_same_state() {
    // `prepare` keeps the sea of the last state it saw; a state that differs in time, phase or
    // a single coordinate of a used node must see its own flow, i.e. equal what a fresh
    // assembly computes. Run with every node used, and with an extra node no element uses
    // (the assembly then keeps the used nodes' positions only).
    let (x, els) = mixed();
    for unused in [false, true] {
        let mut x = x.clone();
        if unused {
            x.push([9.0, 9.0, -1.0]);
        }
        let n = x.len();
        let v = vec![[0.01, 0.02, -0.03]; n];
        let fresh = |t: f64, phase: Phase, x: &[[f64; 3]]| {
            let mut asm = LoadAssembly::new(wave_sea(), n, els.clone()).unwrap();
            run_in(&mut asm, t, phase, x, &v).f
        };
        let mut asm = LoadAssembly::new(wave_sea(), n, els.clone()).unwrap();
        // Statics first, then dynamics at the same time and positions (how every run starts).
        let st = run_in(&mut asm, 0.0, Phase::Static, &x, &v).f;
        let dy = run_in(&mut asm, 0.0, Phase::Dynamic, &x, &v).f;
        assert_eq!(
            dy,
            fresh(0.0, Phase::Dynamic, &x),
            "a new phase must re-evaluate"
        );
        assert_ne!(dy, st);
        let at_1 = run(&mut asm, 1.0, &x, &v).f;
        assert_eq!(asm.sea_evaluations(), (3, 0));
        assert_eq!(run(&mut asm, 1.0, &x, &v).f, at_1, "same state, same loads");
        assert_eq!(
            asm.sea_evaluations(),
            (3, 1),
            "the repeated state reuses the flow"
        );
        let at_2 = run(&mut asm, 2.0, &x, &v).f;
        assert_eq!(
            at_2,
            fresh(2.0, Phase::Dynamic, &x),
            "a new time must re-evaluate"
        );
        assert_ne!(at_2, at_1);
        // Node 0 is 2 m under water: the flow there depends on its depth and on x.
        for (c, d) in [(2, -0.2), (0, 0.3)] {
            let mut moved = x.clone();
            moved[0][c] += d;
            let at_moved = run(&mut asm, 2.0, &moved, &v).f;
            assert_eq!(at_moved, fresh(2.0, Phase::Dynamic, &moved), "a moved node");
            assert_ne!(at_moved, at_2);
        }
        if unused {
            let mut moved = x.clone();
            moved[n - 1][0] += 1.0;
            assert_eq!(
                run(&mut asm, 2.0, &moved, &v).f,
                at_2,
                "an unused node is not read"
            );
        }
        assert_eq!(
            run(&mut asm, 1.0, &x, &v).f,
            at_1,
            "back to the first state"
        );
    }
}

/// A rigid cylindrical cage: radius 5 m, 16 sides, 5 rows of 1 m, fan-triangle bottom.
fn cage(wake: Wake, sn: f64) -> (Vec<[f64; 3]>, Elements) {
    let (ns, rows, r) = (16, 5, 5.0);
    let mut x = Vec::new();
    for j in 0..=rows {
        for i in 0..ns {
            let a = 2.0 * PI * i as f64 / ns as f64;
            x.push([r * a.cos(), r * a.sin(), -0.5 - j as f64]);
        }
    }
    let centre = x.len();
    x.push([0.0, 0.0, -0.5 - rows as f64]);
    let id = |i: usize, j: usize| j * ns + i % ns;
    let mut panels = Vec::new();
    for j in 0..rows {
        for i in 0..ns {
            panels.push(NetPanel {
                nodes: PanelNodes::Quad([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]),
                net: net(ScreenModel::S1, sn),
                wake_group: Some(0),
                twines: None,
            });
        }
    }
    for i in 0..ns {
        panels.push(NetPanel {
            nodes: PanelNodes::Triangle([id(i, rows), id(i + 1, rows), centre]),
            net: net(ScreenModel::S1, sn),
            wake_group: Some(0),
            twines: None,
        });
    }
    let els = Elements {
        panels,
        wake_groups: vec![WakeGroup {
            name: "cage 0".into(),
            wake,
            solidity: sn,
        }],
        ..Default::default()
    };
    (x, els)
}

fn wake(model: WakeModel, update: WakeUpdate) -> Wake {
    Wake {
        model,
        update,
        ..Wake::none()
    }
}

fn centroid(asm: &LoadAssembly, x: &[[f64; 3]], e: usize) -> [f64; 3] {
    let nodes = asm.element_nodes(e);
    let mut c = [0.0; 3];
    for &n in nodes {
        for k in 0..3 {
            c[k] += x[n][k] / nodes.len() as f64;
        }
    }
    c
}

/// Per-element total forces via the element path.
fn element_forces(asm: &LoadAssembly, x: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut out = ElementOutput::default();
    (0..asm.n_elements())
        .map(|e| {
            let nodes = asm.element_nodes(e);
            let xl: Vec<[f64; 3]> = nodes.iter().map(|&i| x[i]).collect();
            let vl = vec![[0.0; 3]; nodes.len()];
            asm.element_load(e, &xl, &vl, Want::default(), &mut out);
            total(&out.force[..nodes.len()])
        })
        .collect()
}

#[test]
fn cage_wake_only_downstream_and_quarter_force() {
    let u = 0.5;
    let (x, els) = cage(wake(WakeModel::Factor(0.5), WakeUpdate::Step), 0.2);
    let n = x.len();
    let mut asm = LoadAssembly::new(current_sea([u, 0.0, 0.0]), n, els.clone()).unwrap();
    let o = run(&mut asm, 0.0, &x, &vec![[0.0; 3]; n]);
    let ef = element_forces(&asm, &x);
    let (mut fplus, mut fminus) = (0.0, 0.0);
    let mut sum = [0.0; 3];
    for e in 0..asm.n_elements() {
        let c = centroid(&asm, &x, e);
        let cell = asm.wake()[e];
        if c[0] > 0.0 {
            assert!(
                cell.in_shadow && cell.factor == 0.5,
                "element {e} at x {}",
                c[0]
            );
            fplus += ef[e][0];
        } else {
            assert!(
                !cell.in_shadow && cell.factor == 1.0,
                "element {e} at x {}",
                c[0]
            );
            fminus += ef[e][0];
        }
        // each panel against ½ρA(rU)²(C_D û + C_L e_L), computed independently
        let p = |i: usize| x[asm.element_nodes(e)[i]];
        let (area, nrm) = if e < 80 {
            let (a, b, d) = (p(0), p(1), p(3));
            let ab = [b[0] - a[0], b[1] - a[1], 0.0];
            let len = (ab[0] * ab[0] + ab[1] * ab[1]).sqrt();
            let h = (a[2] - d[2]).abs();
            (len * h, [-ab[1] / len, ab[0] / len, 0.0])
        } else {
            let (a, b, d) = (p(0), p(1), p(2));
            let cr = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
            (0.5 * cr.abs(), [0.0, 0.0, 1.0])
        };
        let cth = nrm[0].abs();
        let th = cth.min(1.0).acos();
        let (cd, cl) = ScreenModel::S1.cd_cl(th, 0.2, 1.0);
        let s = u * cell.factor;
        let q = 0.5 * RHO * area * s * s;
        // lift direction: (n − c x̂)/σ with n oriented downstream
        let sg = if nrm[0] >= 0.0 { 1.0 } else { -1.0 };
        let on = [sg * nrm[0], sg * nrm[1], sg * nrm[2]];
        let l = [on[0] - cth, on[1], on[2]];
        let ln = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
        let el = if ln > 1e-9 {
            [l[0] / ln, l[1] / ln, l[2] / ln]
        } else {
            [0.0; 3]
        };
        let expect = [q * cd + q * cl * el[0], q * cl * el[1], q * cl * el[2]];
        for k in 0..3 {
            assert!(
                (ef[e][k] - expect[k]).abs() < 1e-9 * (1.0 + q),
                "e {e}: {:?} vs {expect:?}",
                ef[e]
            );
            sum[k] += expect[k];
        }
    }
    assert!(
        (fplus - 0.25 * fminus).abs() < 1e-12 * fminus,
        "{fplus} vs {fminus}"
    );
    let tot = total(&o.f);
    for k in 0..3 {
        assert!(
            (tot[k] - sum[k]).abs() < 1e-9 * sum[0],
            "{tot:?} vs {sum:?}"
        );
    }
    assert!(tot[1].abs() < 1e-9 * tot[0]);

    // wake none: fore-aft and mirror symmetric
    let (x, mut els) = cage(Wake::none(), 0.2);
    els.panels.iter_mut().for_each(|p| p.wake_group = None);
    let mut asm = LoadAssembly::new(current_sea([u, 0.0, 0.0]), n, els).unwrap();
    let _ = run(&mut asm, 0.0, &x, &vec![[0.0; 3]; n]);
    let ef = element_forces(&asm, &x);
    let (mut fp, mut fm, mut fy) = (0.0, 0.0, 0.0);
    for e in 0..asm.n_elements() {
        let c = centroid(&asm, &x, e);
        assert!(!asm.wake()[e].in_shadow);
        if c[0] > 0.0 {
            fp += ef[e][0];
        } else {
            fm += ef[e][0];
        }
        fy += ef[e][1];
    }
    assert!((fp - fm).abs() < 1e-10 * fm, "{fp} vs {fm}");
    assert!(fy.abs() < 1e-10 * fm);
}

#[test]
fn wake_follows_deformation_unless_frozen() {
    for (update, expect_change) in [(WakeUpdate::Step, true), (WakeUpdate::Frozen, false)] {
        let (x, els) = cage(wake(WakeModel::Loland { cd0: None }, update), 0.2);
        let n = x.len();
        let mut asm = LoadAssembly::new(current_sea([0.0, 0.4, 0.0]), n, els).unwrap();
        let _ = run(&mut asm, 0.0, &x, &vec![[0.0; 3]; n]);
        let before: Vec<bool> = asm.wake().iter().map(|c| c.in_shadow).collect();
        // shadow along +y for a current in +y
        for e in 0..asm.n_elements() {
            assert_eq!(before[e], centroid(&asm, &x, e)[1] > 0.0);
        }
        // the net is swept far downstream on one side: the centroid moves
        let mut x2 = x.clone();
        for p in x2.iter_mut().filter(|p| p[0] > 0.0) {
            p[1] += 30.0;
        }
        let changed = asm.update_wake(1.0, &x2).unwrap();
        assert_eq!(changed, expect_change, "{update:?}");
        let r = asm.wake().iter().find(|c| c.in_shadow).unwrap().factor;
        assert!((r - (1.0 - 0.46 * (0.2 - 1.24 * 0.04 + 13.7 * 0.008))).abs() < 1e-14);
    }
}

#[test]
fn cheng_wake_uses_oriented_normal() {
    let (x, els) = cage(wake(WakeModel::Cheng, WakeUpdate::Step), 0.15);
    let n = x.len();
    let mut asm = LoadAssembly::new(current_sea([0.5, 0.0, 0.0]), n, els).unwrap();
    asm.update_wake(0.0, &x).unwrap();
    for e in 0..asm.n_elements() {
        let cell = asm.wake()[e];
        assert!((0.0..=1.0).contains(&cell.factor));
        if cell.in_shadow && e >= 80 {
            // horizontal bottom: c = 0 < 0.38·Sn − 0.05 → r = 0
            assert_eq!(cell.factor, 0.0);
        }
    }
}

/// Every change of a wake factor counts, not only a change of membership: tilting the
/// shadowed panels of a Cheng cage changes their factors (no element leaves the shadow), and
/// the update must say so; a change below `WAKE_TOLERANCE` leaves the loads as they were, to
/// the bit, and says no change (docs/theory/hydrodynamics.md#wake-update).
#[test]
fn every_wake_factor_change_counts_and_none_is_applied_silently() {
    let (x, els) = cage(wake(WakeModel::Cheng, WakeUpdate::Step), 0.15);
    let n = x.len();
    let mut asm = LoadAssembly::new(current_sea([0.5, 0.0, 0.0]), n, els).unwrap();
    asm.update_wake(0.0, &x).unwrap();
    let before: Vec<WakeCell> = asm.wake().to_vec();
    // Tilt the net's bottom (z += a·x): horizontal positions, hence membership, stay.
    let tilt =
        |a: f64| -> Vec<[f64; 3]> { x.iter().map(|p| [p[0], p[1], p[2] + a * p[0]]).collect() };
    let x2 = tilt(0.05);
    assert!(asm.update_wake(0.0, &x2).unwrap());
    let after: Vec<WakeCell> = asm.wake().to_vec();
    for (e, (b, a)) in before.iter().zip(&after).enumerate() {
        assert_eq!(b.in_shadow, a.in_shadow, "element {e} changed membership");
    }
    assert!(
        before
            .iter()
            .zip(&after)
            .any(|(b, a)| (b.factor - a.factor).abs() > 1e-3)
    );
    // Cheng's factor written out for every shadowed panel of the tilted net.
    for e in 0..asm.n_elements() {
        let cell = asm.wake()[e];
        if !cell.in_shadow {
            continue;
        }
        let nodes = asm.element_nodes(e).to_vec();
        let p = |i: usize| x2[nodes[i]];
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let (d1, d2) = if nodes.len() == 3 {
            (sub(p(1), p(0)), sub(p(2), p(0)))
        } else {
            (sub(p(2), p(0)), sub(p(3), p(1)))
        };
        let a = [
            d1[1] * d2[2] - d1[2] * d2[1],
            d1[2] * d2[0] - d1[0] * d2[2],
            d1[0] * d2[1] - d1[1] * d2[0],
        ];
        let c = a[0].abs() / (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let r = ((c + 0.05 - 0.38 * 0.15) / (c + 0.05)).clamp(0.0, 1.0);
        assert!((cell.factor - r).abs() < 1e-12, "element {e}");
    }
    // A change far below the tolerance: nothing applied, nothing reported.
    let x3 = tilt(0.05 + 1e-9);
    assert!(!asm.update_wake(0.0, &x3).unwrap());
    for (a, b) in asm.wake().iter().zip(&after) {
        assert_eq!(a.factor.to_bits(), b.factor.to_bits());
    }
}

#[test]
fn bad_input_errors_name_the_value() {
    let sea = || current_sea([0.5, 0.0, 0.0]);
    let (x, mut els) = flat_panel(0.0, 1, false, 0.2);
    let n = x.len();
    els.panels[0].net.solidity = 1.2;
    let e = LoadAssembly::new(sea(), n, els.clone())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("solidity") && e.contains("1.2") && e.contains("0 < Sn < 1"),
        "{e}"
    );
    els.panels[0].net.solidity = 0.2;
    els.panels[0].net.twine_diameter = -0.001;
    let e = LoadAssembly::new(sea(), n, els.clone())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("twine_diameter") && e.contains("-0.001") && e.contains("> 0"),
        "{e}"
    );
    els.panels[0].net.twine_diameter = 0.002;
    els.panels[0].net.model = ScreenModel::Const { cd: -0.2, cl: 0.0 };
    let e = LoadAssembly::new(sea(), n, els.clone())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("cd") && e.contains("-0.2") && e.contains(">= 0"),
        "{e}"
    );
    els.panels[0].net.model = ScreenModel::S1;
    els.panels[0].nodes = PanelNodes::Quad([0, 1, 2, 99]);
    let e = LoadAssembly::new(sea(), n, els.clone())
        .unwrap_err()
        .to_string();
    assert!(e.contains("99"), "{e}");

    let line = |d: f64| Elements {
        lines: vec![LineElement {
            nodes: [0, 1],
            props: rope(MorisonModel::M4, d, 1.0),
            net_twine: false,
            wake_group: None,
        }],
        ..Default::default()
    };
    let e = LoadAssembly::new(sea(), 2, line(0.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("hydro_diameter = 0"), "{e}");
    let mut m5 = line(0.01);
    m5.lines[0].props.model = MorisonModel::M5 { solidity: 0.2 };
    assert!(LoadAssembly::new(sea(), 2, m5).is_err());

    // a wake model on a group with only ropes: nothing to shadow
    let mut ropes = line(0.02);
    ropes.lines[0].wake_group = Some(0);
    ropes.wake_groups.push(WakeGroup {
        name: "flat sheet".into(),
        wake: wake(WakeModel::Factor(0.8), WakeUpdate::Step),
        solidity: 0.2,
    });
    let e = LoadAssembly::new(sea(), 2, ropes).unwrap_err();
    assert!(matches!(e, HydroError::WakeWithoutNet { .. }));
    assert!(e.to_string().contains("factor") && e.to_string().contains("none"));

    // wrong array lengths are errors, not panics
    let (x, els) = flat_panel(0.0, 1, false, 0.2);
    let mut asm = LoadAssembly::new(sea(), x.len(), els).unwrap();
    let mut f = vec![[0.0; 3]; 2];
    let r = asm.evaluate(
        0.0,
        Phase::Static,
        &x,
        &vec![[0.0; 3]; x.len()],
        Outputs {
            forces: &mut f,
            added_mass: None,
            dfdv: None,
            dfdx: None,
        },
    );
    assert!(r.unwrap_err().to_string().contains("forces length"));
}

#[test]
fn diagnostics_report_reynolds_range() {
    let (x, els) = flat_panel(0.3, 2, false, 0.2);
    let n = x.len();
    let mut asm = LoadAssembly::new(current_sea([0.5, 0.0, 0.0]), n, els).unwrap();
    let _ = run(&mut asm, 0.0, &x, &vec![[0.0; 3]; n]);
    let d = asm.diagnostics();
    let re = 0.5 * 0.0024 / 1.19e-6;
    let [lo, hi] = d.panel_reynolds.unwrap();
    assert!((lo - re).abs() < 1e-9 * re && (hi - re).abs() < 1e-9 * re);
    assert!(d.line_reynolds.is_none() && !d.reynolds_clamped);
    let s = asm.net_summary(&x);
    assert!((s.area - 1.0).abs() < 1e-12);
    // docs/theory/hydrodynamics.md#buoyancy: twine volume of 1 m² of net, dw0 = 2.4 mm, Sn = 0.2
    assert!((s.expected_twine_volume - 3.7699112e-4).abs() < 5e-11);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn quad_force_independent_of_node_order(
        shift in 0usize..4, reverse in any::<bool>(),
        wz in -0.3f64..0.3, ux in -1.0f64..1.0, uy in -1.0f64..1.0,
    ) {
        prop_assume!(ux.abs() + uy.abs() > 0.1);
        // a warped quad
        let x = vec![[0.0, 0.0, -2.0], [1.0, 0.1, -2.0 + wz], [1.1, 1.0, -1.0], [0.0, 0.9, -1.1 - wz]];
        let mut order = [0usize, 1, 2, 3];
        order.rotate_left(shift);
        if reverse { order.reverse(); }
        let eval = |nodes: [usize; 4]| {
            let els = Elements {
                panels: vec![NetPanel {
                    nodes: PanelNodes::Quad(nodes),
                    net: net(ScreenModel::S2, 0.25),
                    wake_group: None,
                    twines: None,
                }],
                ..Default::default()
            };
            let mut asm = LoadAssembly::new(current_sea([ux, uy, 0.1]), 4, els).unwrap();
            run(&mut asm, 0.0, &x, &[[0.0; 3]; 4]).f
        };
        let a = eval([0, 1, 2, 3]);
        let b = eval(order);
        for i in 0..4 {
            for c in 0..3 {
                prop_assert!((a[i][c] - b[i][c]).abs() < 1e-12 * (1.0 + a[i][c].abs()));
            }
        }
    }
}
