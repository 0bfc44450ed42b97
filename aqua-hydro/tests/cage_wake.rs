//! Cage-to-cage wake (docs/theory/hydrodynamics.md#cage-to-cage-wake) against independent
//! numbers: the ratio on every element of a row of three cages follows the recovery law
//! written out here (a widening top-hat wake, deficits added in proportion to the current
//! reaching each cage); without spreading the downstream cage of two in line sees exactly the
//! current reduced by r_c², with r_c from Løland's formula written out here; a cage beside the
//! other and a switched-off wake see the free current.

use aqua_env::{Constants, Current, Phase, Sea, Waves};
use aqua_hydro::{
    CageWake, Elements, LoadAssembly, NetPanel, NetProps, Outputs, PanelNodes, ScreenModel, Wake,
    WakeGroup, WakeModel,
};
use std::f64::consts::PI;

const SN: f64 = 0.2;
const U: f64 = 0.5;

/// A rigid cylindrical net (radius 5 m, 16 sides, 4 rows of 1 m, fan bottom) centred at
/// (cx, cy), appended to `x` and `els` as wake group `group`.
fn add_cage(x: &mut Vec<[f64; 3]>, els: &mut Elements, cx: f64, cy: f64) -> std::ops::Range<usize> {
    let (ns, rows, r) = (16, 4, 5.0);
    let first = x.len();
    for j in 0..=rows {
        for i in 0..ns {
            let a = 2.0 * PI * i as f64 / ns as f64;
            x.push([cx + r * a.cos(), cy + r * a.sin(), -0.5 - j as f64]);
        }
    }
    let centre = x.len();
    x.push([cx, cy, -0.5 - rows as f64]);
    let group = els.wake_groups.len();
    let id = |i: usize, j: usize| first + j * ns + i % ns;
    let net = NetProps {
        model: ScreenModel::S1,
        solidity: SN,
        twine_diameter: 0.0024,
    };
    for j in 0..rows {
        for i in 0..ns {
            els.panels.push(NetPanel {
                nodes: PanelNodes::Quad([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]),
                net,
                wake_group: Some(group),
                twines: None,
            });
        }
    }
    for i in 0..ns {
        els.panels.push(NetPanel {
            nodes: PanelNodes::Triangle([id(i, rows), id(i + 1, rows), centre]),
            net,
            wake_group: Some(group),
            twines: None,
        });
    }
    els.wake_groups.push(WakeGroup {
        name: format!("cage {group}"),
        wake: Wake {
            model: WakeModel::Loland { cd0: None },
            ..Wake::none()
        },
        solidity: SN,
    });
    first..x.len()
}

/// Total force on each node range, current u along +x, cage-to-cage wake on or off, its
/// wakes spreading at rate 0 (no recovery).
fn forces(centres: &[[f64; 2]], u: f64, cage_wake: bool) -> Vec<[f64; 3]> {
    let mut x = Vec::new();
    let mut els = Elements::default();
    let ranges: Vec<_> = centres
        .iter()
        .map(|c| add_cage(&mut x, &mut els, c[0], c[1]))
        .collect();
    let groups = els.wake_groups.clone();
    let sea = Sea::new(
        Constants::default(),
        Current::uniform([u, 0.0, 0.0]),
        Waves::None,
    );
    let mut asm = LoadAssembly::new(sea, x.len(), els).unwrap();
    if cage_wake {
        let all: Vec<usize> = (0..groups.len()).collect();
        asm.set_cage_wake(CageWake {
            spreading: 0.0,
            ..CageWake::among(&groups, &all)
        })
        .unwrap();
    }
    let v = vec![[0.0; 3]; x.len()];
    let mut f = vec![[0.0; 3]; x.len()];
    asm.evaluate(
        0.0,
        Phase::Static,
        &x,
        &v,
        Outputs {
            forces: &mut f,
            added_mass: None,
            dfdv: None,
            dfdx: None,
        },
    )
    .unwrap();
    ranges
        .into_iter()
        .map(|r| {
            f[r].iter()
                .fold([0.0; 3], |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]])
        })
        .collect()
}

fn rel(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    d / (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt()
}

/// Løland's net reduction factor, from the spec's formula.
fn loland(sn: f64) -> f64 {
    1.0 - 0.46 * (sn - 1.24 * sn * sn + 13.7 * sn.powi(3))
}

#[test]
fn without_spreading_the_downstream_cage_sees_the_current_reduced_by_r_squared() {
    let rc = loland(SN);
    let pair = forces(&[[0.0, 0.0], [30.0, 0.0]], U, true);
    let alone_up = forces(&[[0.0, 0.0]], U, false)[0];
    let alone_down_slow = forces(&[[30.0, 0.0]], rc * rc * U, false)[0];
    assert!(
        rel(pair[0], alone_up) < 1e-12,
        "{:?} vs {alone_up:?}",
        pair[0]
    );
    assert!(
        rel(pair[1], alone_down_slow) < 1e-9,
        "{:?} vs {alone_down_slow:?}",
        pair[1]
    );
    assert!(pair[1][0] < pair[0][0] && pair[1][0] > 0.0);
    // Drag goes with the square of the speed: the ratio is close to r_c⁴ (Re effects aside).
    let ratio = pair[1][0] / pair[0][0];
    assert!(
        (ratio / rc.powi(4) - 1.0).abs() < 0.05,
        "{ratio} vs {}",
        rc.powi(4)
    );
    // Three in line: the factors multiply.
    let three = forces(&[[0.0, 0.0], [30.0, 0.0], [60.0, 0.0]], U, true);
    let third = forces(&[[60.0, 0.0]], rc.powi(4) * U, false)[0];
    assert!(rel(three[2], third) < 1e-9);
}

#[test]
fn side_by_side_and_switched_off_cages_see_the_free_current() {
    let alone = |c: [f64; 2]| forces(&[c], U, false)[0];
    // Beside each other across the current (lateral offset 30 m > R = 5 m).
    let side = forces(&[[0.0, 0.0], [0.0, 30.0]], U, true);
    assert!(rel(side[0], alone([0.0, 0.0])) < 1e-12);
    assert!(rel(side[1], alone([0.0, 30.0])) < 1e-12);
    // In line but switched off: two isolated cages.
    let off = forces(&[[0.0, 0.0], [30.0, 0.0]], U, false);
    assert!(rel(off[0], alone([0.0, 0.0])) < 1e-12);
    assert!(rel(off[1], alone([30.0, 0.0])) < 1e-12);
    // The upstream cage is never shadowed by the downstream one.
    let on = forces(&[[0.0, 0.0], [30.0, 0.0]], U, true);
    assert!(rel(on[0], alone([0.0, 0.0])) < 1e-12);
}

#[test]
fn repeated_updates_do_not_compound() {
    let mut x = Vec::new();
    let mut els = Elements::default();
    add_cage(&mut x, &mut els, 0.0, 0.0);
    add_cage(&mut x, &mut els, 30.0, 0.0);
    let groups = els.wake_groups.clone();
    let sea = Sea::new(
        Constants::default(),
        Current::uniform([U, 0.0, 0.0]),
        Waves::None,
    );
    let mut asm = LoadAssembly::new(sea, x.len(), els).unwrap();
    asm.set_cage_wake(CageWake {
        spreading: 0.0,
        ..CageWake::among(&groups, &[0, 1])
    })
    .unwrap();
    let downstream = asm.n_elements() - 1;
    asm.update_wake(0.0, &x).unwrap();
    let first = asm.cage_wake_factor(downstream);
    for _ in 0..5 {
        asm.update_wake(0.0, &x).unwrap();
    }
    let rc = loland(SN);
    assert!((first - rc * rc).abs() < 1e-15);
    assert_eq!(asm.cage_wake_factor(downstream), first);
    // Moving the downstream cage sideways out of the shadow lifts it.
    let moved: Vec<[f64; 3]> = x
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if i >= x.len() / 2 {
                [p[0], p[1] + 20.0, p[2]]
            } else {
                *p
            }
        })
        .collect();
    asm.update_wake(0.0, &moved).unwrap();
    assert_eq!(asm.cage_wake_factor(downstream), 1.0);
    // Bad input names the key.
    let e = asm
        .set_cage_wake(CageWake {
            sources: vec![aqua_hydro::CageWakeSource {
                group: 7,
                factor: 0.9,
            }],
            spreading: 0.1,
        })
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("cage_wake.sources[0].group") && e.contains('7'),
        "{e}"
    );
}

/// The recovery law of docs/theory/hydrodynamics.md#cage-to-cage-wake, written out: the wake
/// of a cage of half-width R widens as R + k·x behind its rear (x = s − R), keeping the
/// deficit flux, and overlapping deficits add in proportion to the current reaching each cage.
#[test]
fn a_row_of_three_cages_follows_the_recovery_law() {
    let (k, r_half) = (0.1, 5.0);
    let rc = loland(SN);
    let d0 = 1.0 - rc * rc;
    let deficit = |cx: f64, p: [f64; 2]| {
        let s = p[0] - cx;
        let w = r_half + k * (s - r_half).max(0.0);
        if s <= 0.0 || p[1].abs() >= w {
            0.0
        } else {
            d0 * (r_half / w).powi(2)
        }
    };
    let centres = [0.0, 30.0, 60.0];
    let mut x = Vec::new();
    let mut els = Elements::default();
    for &c in &centres {
        add_cage(&mut x, &mut els, c, 0.0);
    }
    let panels = els.panels.clone();
    let groups = els.wake_groups.clone();
    let sea = Sea::new(
        Constants::default(),
        Current::uniform([U, 0.0, 0.0]),
        Waves::None,
    );
    let mut asm = LoadAssembly::new(sea, x.len(), els).unwrap();
    asm.set_cage_wake(CageWake::among(&groups, &[0, 1, 2]))
        .unwrap();
    asm.update_wake(0.0, &x).unwrap();
    // The current reaching the 2nd cage (at its centre) and the 3rd.
    let u1 = 1.0;
    let u2 = 1.0 - u1 * deficit(0.0, [30.0, 0.0]);
    let u3 = 1.0 - u1 * deficit(0.0, [60.0, 0.0]) - u2 * deficit(30.0, [60.0, 0.0]);
    // The wake recovers: the 3rd cage gets more than the product of the near-wake factors.
    assert!(u3 > rc.powi(4) + 0.05, "{u3} vs r_c^4 = {}", rc.powi(4));
    assert!(u2 > rc * rc && u2 < 1.0);
    for (e, p) in panels.iter().enumerate() {
        let nodes: Vec<usize> = match p.nodes {
            PanelNodes::Quad(q) => q.to_vec(),
            PanelNodes::Triangle(t) => t.to_vec(),
        };
        let c = nodes.iter().fold([0.0, 0.0], |a, &n| {
            [
                a[0] + x[n][0] / nodes.len() as f64,
                a[1] + x[n][1] / nodes.len() as f64,
            ]
        });
        let want = match p.wake_group {
            Some(0) => 1.0,
            Some(1) => 1.0 - u1 * deficit(0.0, c),
            Some(2) => 1.0 - u1 * deficit(0.0, c) - u2 * deficit(30.0, c),
            _ => unreachable!(),
        };
        let got = asm.cage_wake_factor(e);
        assert!((got - want).abs() < 1e-12, "panel {e}: {got} vs {want}");
    }
}
