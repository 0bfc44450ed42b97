//! Panel and line builders over a range of parameters (docs/theory/cages.md#flat-net-panel,
//! #single-line).

use aqua_mesh::{Fairlead, LineParams, LineShape, PanelParams};
use nalgebra::{Point3, Vector3};
use proptest::prelude::*;

fn unit() -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-1.0f64..1.0).prop_filter("non-zero", |v| Vector3::from(*v).norm() > 0.1)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn panel_invariants(
        w in 0.1f64..50.0,
        h in 0.1f64..50.0,
        nw in 1u32..30,
        nh in 1u32..30,
        normal in unit(),
        up in unit(),
        centre in prop::array::uniform3(-100.0f64..100.0),
    ) {
        let e_n = Vector3::from(normal).normalize();
        let upv = Vector3::from(up);
        prop_assume!((upv - e_n * upv.dot(&e_n)).norm() > 1e-3 * upv.norm());
        let mut p = PanelParams::new(w, h);
        p.divisions = Some([nw, nh]);
        p.normal = Some(normal);
        p.up = Some(up);
        p.centre = Some(centre);
        p.net.half_mesh = Some(1e-3);
        p.net.twine_diameter = Some(1e-4);
        let m = p.build().unwrap();
        let (nw, nh) = (nw as usize, nh as usize);
        prop_assert_eq!(m.nodes.len(), (nw + 1) * (nh + 1));
        prop_assert_eq!(m.lines.len(), nw * (nh + 1) + (nw + 1) * nh);
        prop_assert_eq!(m.panels.len(), nw * nh);
        // Area vectors: positive, along +e_n, summing to W·H·e_n.
        let mut total = Vector3::zeros();
        for k in 0..m.panels.len() {
            let a = m.panel_area_vector(k);
            prop_assert!(a.dot(&e_n) > 0.0);
            prop_assert!((a.normalize() - e_n).norm() < 1e-9);
            total += a;
        }
        prop_assert!((total - w * h * e_n).norm() < 1e-9 * w * h);
        // Planar, centred, no zero-length element.
        let c = Vector3::from(centre);
        let mean: Vector3<f64> = m.nodes.iter().map(|q| q.coords).sum::<Vector3<f64>>()
            / m.nodes.len() as f64;
        prop_assert!((mean - c).norm() < 1e-9 * (1.0 + c.norm()));
        for q in &m.nodes {
            prop_assert!((q.coords - c).dot(&e_n).abs() < 1e-9 * (1.0 + c.norm()));
        }
        for e in 0..m.lines.len() {
            let l = m.line_length(e);
            prop_assert!(l > 0.0);
            prop_assert!((l - w / nw as f64).abs() < 1e-9 * w || (l - h / nh as f64).abs() < 1e-9 * h);
        }
        // Top row is highest along the projected up direction.
        let e_u = (upv - e_n * upv.dot(&e_n)).normalize();
        let top = &m.group(0, "panel_top").unwrap().nodes;
        let bottom = &m.group(0, "panel_bottom").unwrap().nodes;
        for (&t, &b) in top.iter().zip(bottom) {
            prop_assert!(((m.nodes[t] - m.nodes[b]).dot(&e_u) - h).abs() < 1e-9 * h);
        }
        prop_assert_eq!(m.fixed_nodes().len(), m.nodes.len());
    }

    #[test]
    fn line_invariants(
        a in prop::array::uniform3(-200.0f64..200.0),
        b in prop::array::uniform3(-200.0f64..200.0),
        ratio in 0.8f64..3.0,
        n in 1u32..80,
        straight in any::<bool>(),
    ) {
        let (pa, pb) = (Point3::from(a), Point3::from(b));
        let chord = (pb - pa).norm();
        prop_assume!(chord > 1.0);
        let l0 = ratio * chord;
        let p = LineParams {
            anchor: a,
            fairlead: Some(Fairlead::Point(b)),
            length: l0,
            segments: Some(n),
            shape: if straight { LineShape::Straight } else { LineShape::Catenary },
            diameter: Some(0.1),
            ea: Some(1e8),
            mass_per_length: Some(20.0),
            ..Default::default()
        };
        let m = p.build().unwrap();
        let n = n as usize;
        prop_assert_eq!(m.nodes.len(), n + 1);
        prop_assert_eq!(m.lines.len(), n);
        prop_assert!((m.nodes[0] - pa).norm() < 1e-9);
        prop_assert!((m.nodes[n] - pb).norm() < 1e-9);
        let mut sum = 0.0;
        for e in 0..n {
            let l = m.line_length(e);
            prop_assert!(l > 0.0);
            prop_assert_eq!(m.lines[e].rest_length, Some(l0 / n as f64));
            if straight || l0 <= chord {
                prop_assert!((l - chord / n as f64).abs() < 1e-9 * chord);
            } else {
                // Chord of an arc of length L0/N is never longer than the arc.
                prop_assert!(l <= l0 / n as f64 * (1.0 + 1e-9));
            }
            sum += l;
        }
        prop_assert!(sum >= chord * (1.0 - 1e-9));
        prop_assert!(sum <= l0.max(chord) * (1.0 + 1e-9));
        // All nodes lie in the vertical plane through both ends.
        let d = pb - pa;
        let h = Vector3::new(d.x, d.y, 0.0);
        if h.norm() > 1e-6 {
            let side = Vector3::new(-h.y, h.x, 0.0).normalize();
            for q in &m.nodes {
                prop_assert!((q - pa).dot(&side).abs() < 1e-6 * (1.0 + chord));
            }
        }
    }
}

#[test]
fn nearly_vertical_and_very_slack_lines_stay_finite() {
    for (b, l0) in [
        ([1e-3, 0.0, 0.0], 150.0),
        ([1e-7, 0.0, 0.0], 150.0),
        ([10.0, 0.0, 0.0], 5000.0),
        ([0.0, 0.0, 0.0], 150.0),
    ] {
        let p = LineParams {
            anchor: [0.0, 0.0, -100.0],
            fairlead: Some(Fairlead::Point(b)),
            length: l0,
            segments: Some(50),
            diameter: Some(0.1),
            ea: Some(1e8),
            mass_per_length: Some(20.0),
            ..Default::default()
        };
        let m = p.build_with(None, Some(-100.0)).unwrap();
        assert!(
            m.nodes.iter().all(|q| q.iter().all(|c| c.is_finite())),
            "{b:?}"
        );
        assert!((m.nodes[50] - Point3::from(b)).norm() < 1e-9);
        assert!(m.nodes.iter().all(|q| q.z >= -100.0));
    }
}
