//! Load assembly against worked cases and closed forms: a net panel, a line, a half-submerged
//! collar and the inertia in an Airy wave (docs/theory/hydrodynamics.md#worked-load-cases).

mod common;

use aqua_env::{Component, Constants, Current, Depth, LinearSum, Ramp, Sea, Stretching, Waves};
use aqua_hydro::{
    Elements, LineElement, LineProps, LoadAssembly, MorisonModel, NetPanel, PanelNodes, ScreenModel,
};
use common::*;
use std::f64::consts::PI;

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
