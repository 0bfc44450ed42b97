//! The cage wake in the load assembly: only downstream elements are shielded, the wake follows
//! the deformation unless frozen, Cheng's model uses the oriented normal, and every change of a
//! wake factor is counted.

mod common;

use aqua_hydro::{LoadAssembly, ScreenModel, Wake, WakeCell, WakeModel, WakeUpdate};
use common::*;

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
