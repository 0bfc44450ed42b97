//! Load assembly Jacobians and paths: damping and stiffness blocks against central differences,
//! the element path against the bulk path, and the reuse of the flow at the same state.

mod common;

use aqua_env::Phase;
use aqua_hydro::assembly::{MAX_DOFS, MAX_NODES};
use aqua_hydro::{ElementOutput, LoadAssembly, Want};
use common::*;

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
