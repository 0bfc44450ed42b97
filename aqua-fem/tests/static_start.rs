//! Statics from a given start shape (`solve_static_from`, docs/theory/fem.md#mesh-sequencing):
//! the equilibrium is the one from the as-built shape, it balances the weight, the supports
//! stay where they are held, and a start of the wrong size is refused.

mod common;
use aqua_fem::*;
use common::*;

/// A 40 m line of 20 segments hung between two supports 30 m apart, 2 m sag as built.
fn hanging_line() -> (Model, Vec<usize>, f64) {
    let w = 20.0; // N/m
    let mut b = ModelBuilder::new(Environment::default());
    let g = b
        .add_group("line", CableSection::new(1e7, w / DEFAULT_GRAVITY))
        .unwrap();
    let nodes = add_line(&mut b, [0.0, 0.0, 0.0], [30.0, 0.0, 0.0], 20, 40.0, g, 2.0);
    b.fix(nodes[0], Dofs::ALL).unwrap();
    b.fix(*nodes.last().unwrap(), Dofs::ALL).unwrap();
    (b.build().unwrap(), nodes, w * 40.0)
}

#[test]
fn a_start_shape_reaches_the_same_equilibrium_in_balance() {
    let (m, nodes, weight) = hanging_line();
    let st = StaticSettings::default();
    let plain = solve_static(&m, &mut NoLoads, &st).unwrap();
    // A start far from both: the line swung 5 m sideways and 8 m down, the ends displaced
    // too (the supports must be put back where they are held).
    let start: Vec<[f64; 3]> = m
        .nodes()
        .iter()
        .map(|p| {
            let s = p[0] / 30.0;
            let bulge = 4.0 * s * (1.0 - s);
            [p[0], p[1] + 5.0 * bulge + 0.3, p[2] - 8.0 * bulge]
        })
        .collect();
    let sol = solve_static_from(&m, &mut NoLoads, &st, Some(&start), &mut |_| {
        StaticControl::Continue
    })
    .unwrap();
    assert!(!sol.report.interrupted);
    let mut dmax: f64 = 0.0;
    for (a, b) in sol.state.x.iter().zip(&plain.state.x) {
        for k in 0..3 {
            dmax = dmax.max((a[k] - b[k]).abs());
        }
    }
    assert!(dmax < 1e-6, "equilibria {dmax} m apart");
    // Supports held at their as-built positions.
    for &n in [nodes[0], *nodes.last().unwrap()].iter() {
        assert_eq!(sol.state.x[n], m.nodes()[n]);
    }
    // The reactions carry the weight, and nothing sideways.
    let (a, b) = (nodes[0], *nodes.last().unwrap());
    let rz = sol.outputs.reaction[a][2] + sol.outputs.reaction[b][2];
    let ry = sol.outputs.reaction[a][1] + sol.outputs.reaction[b][1];
    let rx = sol.outputs.reaction[a][0] + sol.outputs.reaction[b][0];
    assert!(
        (rz - weight).abs() < 1e-6 * weight,
        "Rz {rz} for {weight} N"
    );
    assert!(
        ry.abs() < 1e-6 * weight && rx.abs() < 1e-6 * weight,
        "{rx} {ry}"
    );
}

#[test]
fn a_start_of_the_wrong_size_is_refused() {
    let (m, _, _) = hanging_line();
    let start = vec![[0.0; 3]; m.n_nodes() - 1];
    let err = solve_static_from(
        &m,
        &mut NoLoads,
        &StaticSettings::default(),
        Some(&start),
        &mut |_| StaticControl::Continue,
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("start positions"), "{err}");
    let bad = vec![[f64::NAN; 3]; m.n_nodes()];
    assert!(
        solve_static_from(
            &m,
            &mut NoLoads,
            &StaticSettings::default(),
            Some(&bad),
            &mut |_| StaticControl::Continue,
        )
        .is_err()
    );
}
