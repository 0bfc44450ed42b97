//! Load assembly input checks and properties: bad input names the value, diagnostics report
//! the Reynolds range, and property tests (docs/theory/hydrodynamics.md).

mod common;

use aqua_env::Phase;
use aqua_hydro::{
    Elements, HydroError, LineElement, LoadAssembly, MorisonModel, NetPanel, Outputs, PanelNodes,
    ScreenModel, WakeGroup, WakeModel, WakeUpdate,
};
use common::*;
use proptest::prelude::*;

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
