//! Cage builders against docs/theory/cages.md#worked-ssm-case (worked case and defaults table),
//! geometry invariants (proptest) and bad-input errors (docs/theory/cages.md#input-validation).

use aqua_mesh::{CageParams, CageType, Mesh, PanelNodes, Role};
use nalgebra::Vector3;
use proptest::prelude::*;

fn count(m: &Mesh, name: &str) -> (usize, usize, usize) {
    let g = m
        .groups_named(name)
        .next()
        .unwrap_or_else(|| panic!("no group {name}"));
    (g.lines.len(), g.panels.len(), g.nodes.len())
}

fn ssm_worked() -> CageParams {
    let mut p = CageParams::new(CageType::Ssm);
    p.circumference = Some(120.0);
    p.depth = Some(15.0);
    p.cone_depth = Some(3.0);
    p.element_length = Some(2.5);
    p.rope_depth = Some(2.5);
    p.frame_offset = Some(1.0);
    p.net.twine_diameter = Some(2.85e-3);
    p.net.half_mesh = Some(25.87e-3);
    p
}

#[test]
fn worked_ssm_counts_exact() {
    let m = ssm_worked().build().unwrap();
    let c = m.objects[0].counts().cloned().unwrap();
    assert_eq!((c.nt, c.nn, c.bn, c.n_ext), (48, 6, 8, 1));
    assert_eq!(m.nodes.len(), 1057);
    assert_eq!(count(&m, "net_nodes").2, 673);
    assert_eq!(count(&m, "frame_nodes").2, 384);
    let quads = m
        .panels
        .iter()
        .filter(|p| matches!(p.nodes, PanelNodes::Quad(_)))
        .count();
    assert_eq!((m.panels.len(), quads), (672, 624));
    assert_eq!(count(&m, "net_panels").1, 672);
    assert_eq!(count(&m, "net_twines").0, 1344);
    assert_eq!(count(&m, "ropes").0, 336);
    assert_eq!(count(&m, "tie_lines").0, 144);
    assert_eq!(count(&m, "top_ring").0, 48);
    assert_eq!(count(&m, "top_links").0, 48);
    assert_eq!(count(&m, "sinkers").2, 48);
    assert_eq!(count(&m, "tip").2, 1);
    assert_eq!(count(&m, "fixed").2, 48);
    assert_eq!(m.fixed_nodes(), m.group(0, "top_ring").unwrap().nodes);
    assert!(m.groups_named("bottom_ring").next().is_none());
    assert_eq!(m.lines.len(), 1344 + 336 + 144 + 96);
}

#[test]
fn worked_ssm_geometry_and_grouping() {
    let m = ssm_worked().build().unwrap();
    let net = &m.group(0, "net_nodes").unwrap().nodes;
    let frame = &m.group(0, "frame_nodes").unwrap().nodes;
    let half = |ids: &[usize]| {
        ids.iter()
            .map(|&i| m.nodes[i].x.abs().max(m.nodes[i].y.abs()))
            .fold(0.0, f64::max)
    };
    assert!((half(net) - 15.0).abs() < 1e-9);
    assert!((half(frame) - 16.0).abs() < 1e-9);
    for &s in &m.group(0, "sinkers").unwrap().nodes {
        assert!((m.nodes[s].z + 17.5).abs() < 1e-9);
    }
    let tip = m.group(0, "tip").unwrap().nodes[0];
    assert!((m.nodes[tip].z + 18.0).abs() < 1e-9);

    // Net line lengths: 2820.17 m with the top edge, 2700.17 m without
    // (docs/theory/cages.md#mesh-grouping, 2 decimals).
    let tw = m.group(0, "net_twines").unwrap();
    let top: std::collections::BTreeSet<usize> = m
        .group(0, "net_top")
        .unwrap()
        .nodes
        .iter()
        .copied()
        .collect();
    let mut total = 0.0;
    let mut no_top = 0.0;
    for &e in &tw.lines {
        let l = m.line_length(e);
        total += l;
        let [a, b] = m.lines[e].nodes;
        if !(top.contains(&a) && top.contains(&b)) {
            no_top += l;
        }
    }
    assert!((total - 2820.17).abs() < 0.005, "{total}");
    assert!((no_top - 2700.17).abs() < 0.005, "{no_top}");

    // Net area: four 30 m × 15 m sides and four triangles of base 30 m and slant height
    // √(15² + 3²) m: 2717.82 m². The twine of that area, 2·A/l_p, over the 2820.17 m of
    // numerical twine: λ = 74.50, dws = 0.02460 m, dwh = 0.2123 m (relative 1e-3).
    let g = m.objects[0].net.clone().unwrap();
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    let area = 4.0 * 30.0 * 15.0 + 4.0 * 0.5 * 30.0 * (15f64.powi(2) + 9.0).sqrt();
    assert!(rel(g.net_area, area) < 1e-12, "{}", g.net_area);
    assert!(rel(g.mean_twine_length, 2.09834) < 1e-5);
    assert!(
        rel(g.lambda, 2.0 * area / (25.87e-3 * total)) < 1e-12,
        "{}",
        g.lambda
    );
    assert!(rel(g.lambda, 74.50) < 1e-3, "{}", g.lambda);
    assert!(rel(g.structural_diameter, 0.02460) < 1e-3);
    assert!(rel(g.elastic_diameter, 0.02460) < 1e-3);
    assert!(rel(g.hydro_diameter, 0.2123) < 1e-3);
    let s = tw.section.as_ref().unwrap();
    assert_eq!(s.diameter, g.structural_diameter);
    assert_eq!(s.hydro_diameter, g.hydro_diameter);

    // Sinkers: 981.0 N each at 392.4 N/m; 47.09 kN in total; tip 981 N.
    let sink = m.group_index(0, "sinkers").unwrap();
    let ws: Vec<f64> = m
        .weights
        .iter()
        .filter(|w| w.group == sink)
        .map(|w| w.weight)
        .collect();
    assert_eq!(ws.len(), 48);
    assert!(ws.iter().all(|w| (w - 981.0).abs() < 1e-9));
    assert!((ws.iter().sum::<f64>() - 47088.0).abs() < 1e-6);
    let tipw = m.group_index(0, "tip").unwrap();
    assert!(
        m.weights
            .iter()
            .any(|w| w.group == tipw && w.weight == 981.0)
    );
}

#[test]
fn worked_ssm_three_origins() {
    let mut p = ssm_worked();
    p.origins = Some(vec![[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [150.0, 10.0, 0.0]]);
    let m = p.build().unwrap();
    assert_eq!(m.nodes.len(), 3171);
    assert_eq!(count(&m, "net_twines").0, 4032);
    assert_eq!(m.panels.len(), 2016);
    assert_eq!(count(&m, "ropes").0 + count(&m, "tie_lines").0, 1440);
    assert_eq!(count(&m, "top_ring").0 + count(&m, "top_links").0, 288);
    assert_eq!(count(&m, "fixed").2, 144);
    // Copy k is copy 0 translated; entities record their copy.
    for i in 0..1057 {
        let d = m.nodes[2 * 1057 + i] - m.nodes[i];
        assert!((d - Vector3::new(150.0, 10.0, 0.0)).norm() < 1e-9);
        assert_eq!(m.node_owner[1057 + i], (0, 1));
    }
    assert_eq!(m.lines[1920].copy, 1);
    assert_eq!(m.panels[1343].copy, 1);
    assert_eq!(
        m.resolve_nodes("cage0#2/tip").unwrap(),
        vec![2 * 1057 + 672]
    );
    // λ shared by all copies.
    assert!((m.objects[0].net.as_ref().unwrap().lambda - 74.50).abs() / 74.50 < 1e-3);
}

#[test]
fn defaults_table() {
    // docs/theory/cages.md#worked-ssm-case: type, NT NN BN, nodes, net lines, panels, ropes, ties,
    // ring+links, bottom, λ.
    let rows = [
        (
            CageType::Ssm,
            (48, 6, 8),
            1057,
            1344,
            672,
            336,
            144,
            96,
            0,
            74.50,
        ),
        (
            CageType::Csm,
            (48, 6, 5),
            913,
            1056,
            528,
            336,
            144,
            96,
            0,
            83.78,
        ),
        (
            CageType::Cct,
            (48, 6, 5),
            913,
            1056,
            528,
            336,
            48,
            96,
            48,
            83.78,
        ),
        (
            CageType::Ccs,
            (48, 6, 5),
            1490,
            1056,
            528,
            960,
            144,
            96,
            0,
            83.78,
        ),
    ];
    for (t, (nt, nn, bn), nodes, net, panels, ropes, ties, ring, bottom, lambda) in rows {
        let m = CageParams::new(t).build().unwrap();
        let c = m.objects[0].counts().cloned().unwrap();
        assert_eq!((c.nt, c.nn, c.bn), (nt, nn, bn), "{t:?}");
        assert_eq!(m.nodes.len(), nodes, "{t:?}");
        assert_eq!(count(&m, "net_twines").0, net, "{t:?}");
        assert_eq!(m.panels.len(), panels, "{t:?}");
        assert_eq!(count(&m, "ropes").0, ropes, "{t:?}");
        assert_eq!(count(&m, "tie_lines").0, ties, "{t:?}");
        assert_eq!(count(&m, "top_ring").0 + count(&m, "top_links").0, ring);
        let b = m
            .groups_named("bottom_ring")
            .next()
            .map_or(0, |g| g.lines.len());
        assert_eq!(b, bottom, "{t:?}");
        let l = m.objects[0].net.as_ref().unwrap().lambda;
        assert!((l - lambda).abs() < 0.006, "{t:?}: λ = {l}");
    }
}

#[test]
fn ccs_centre_weight_and_cct_tube() {
    let m = CageParams::new(CageType::Ccs).build().unwrap();
    let c = m.group(0, "centre_weight").unwrap().nodes[0];
    assert_eq!(c, m.nodes.len() - 1);
    assert!((m.nodes[c].z + 45.0).abs() < 1e-9); // −H − 2H
    assert_eq!(m.group(0, "sinkers").unwrap().nodes, vec![c]);
    let w: f64 = m
        .weights
        .iter()
        .filter(|w| w.node == c)
        .map(|w| w.weight)
        .sum();
    assert!((w - 392.4 * 120.0).abs() < 1e-6);
    // Every bottom rope ends at the centre node.
    let ropes = &m.group(0, "ropes").unwrap().lines;
    assert_eq!(
        ropes.iter().filter(|&&e| m.lines[e].nodes[1] == c).count(),
        48
    );

    let m = CageParams::new(CageType::Cct).build().unwrap();
    let ring = m.group(0, "bottom_ring").unwrap();
    assert_eq!(ring.nodes, m.group(0, "sinkers").unwrap().nodes);
    for &n in &ring.nodes {
        assert!((m.nodes[n].z + 17.5).abs() < 1e-9);
    }
}

#[test]
fn rounding_not_truncation() {
    // 119.9/2.5 = 47.96 → 48 (truncation would give 47); 14.9/2.5 = 5.96 → 6.
    let mut p = CageParams::new(CageType::Csm);
    p.circumference = Some(119.9);
    p.depth = Some(14.9);
    let c = p.build().unwrap().objects[0].counts().cloned().unwrap();
    assert_eq!((c.nt, c.nn), (48, 6));
    let mut p = CageParams::new(CageType::Ssm);
    p.side = Some(29.9);
    let c = p.build().unwrap().objects[0].counts().cloned().unwrap();
    assert_eq!(c.nt, 48);
}

fn err(p: &CageParams) -> String {
    p.build().unwrap_err().to_string()
}

#[test]
fn bad_inputs_name_key_value_and_range() {
    let mut p = CageParams::new(CageType::Ssm);
    p.depth = Some(-3.0);
    let e = err(&p);
    assert!(
        e.contains("depth") && e.contains("-3") && e.contains("> 0"),
        "{e}"
    );

    let mut p = CageParams::new(CageType::Ssm);
    p.element_length = Some(40.0);
    let e = err(&p);
    assert!(
        e.contains("NN = round(15/40) = 0") && e.contains("element_length <= 30"),
        "{e}"
    );

    let mut p = CageParams::new(CageType::Csm);
    p.element_length = Some(60.0);
    let e = err(&p);
    assert!(
        e.contains("NT") && e.contains("element_length <= 48"),
        "{e}"
    );

    let mut p = CageParams::new(CageType::Cct);
    p.bottom_ratio = Some(1.5);
    let e = err(&p);
    assert!(e.contains("bottom_ratio") && e.contains("(0, 1]"), "{e}");

    let mut p = CageParams::new(CageType::Cct);
    p.frame_offset = Some(25.0);
    assert!(err(&p).contains("frame_offset"));

    let mut p = CageParams::new(CageType::Csm);
    p.circumference = Some(100.0);
    p.diameter = Some(30.0);
    assert!(err(&p).contains("both"));

    let mut p = CageParams::new(CageType::Ccs);
    p.weight_depth = Some(2.0);
    let e = err(&p);
    assert!(
        e.contains("weight_depth") && e.contains("cone_depth"),
        "{e}"
    );

    let mut p = CageParams::new(CageType::Csm);
    p.sinker_weight_per_metre = Some(-1.0);
    assert!(err(&p).contains("buoys"));

    let mut p = CageParams::new(CageType::Csm);
    p.fixed = Some(vec!["collar".into()]);
    let e = err(&p);
    assert!(
        e.contains("collar") && e.contains("top_ring") && e.contains("sinkers"),
        "{e}"
    );

    let mut p = CageParams::new(CageType::Csm);
    p.origins = Some(vec![[0.0, 0.0, 0.0], [30.0, 0.0, 0.0]]);
    assert!(err(&p).contains("overlap"));
    p.origins = Some(vec![]);
    assert!(err(&p).contains("origins"));

    let mut p = CageParams::new(CageType::Csm);
    p.element_length = Some(0.01);
    p.circumference = Some(2000.0);
    assert!(err(&p).contains("2000000"));

    let mut p = CageParams::new(CageType::Csm);
    p.groups.insert("collar".into(), Default::default());
    assert!(err(&p).contains("groups.collar"));

    let mut p = CageParams::new(CageType::Csm);
    p.element_length = Some(f64::NAN);
    assert!(err(&p).contains("element_length"));

    // λ < 1: a numerical twine shorter than a bar.
    let mut p = CageParams::new(CageType::Csm);
    p.net.half_mesh = Some(5.0);
    assert!(err(&p).contains("λ"));
}

#[test]
fn scene_table_deserialises_and_rejects_unknown_keys() {
    let p: CageParams = toml::from_str(
        r#"
        type = "SSM"
        circumference = 120
        depth = 15
        origins = [[0, 0, 0], [100, 0, 0]]
        fixed = ["top_ring", "sinkers"]
        [net]
        twine_diameter = 2.85e-3
        half_mesh = 25.87e-3
        [groups.ropes]
        diameter = 0.04
        "#,
    )
    .unwrap();
    let m = p.build().unwrap();
    assert_eq!(m.nodes.len(), 2 * 1057);
    assert_eq!(count(&m, "fixed").2, 2 * 96);
    assert_eq!(
        m.group(0, "ropes")
            .unwrap()
            .section
            .as_ref()
            .unwrap()
            .diameter,
        0.04
    );
    let e = toml::from_str::<CageParams>("type = \"SSM\"\ndepht = 15\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("depht") && e.contains("depth"), "{e}");
    assert!(toml::from_str::<CageParams>("type = \"XYZ\"\n").is_err());
    let e = toml::from_str::<CageParams>("type = \"SSM\"\n[net]\nmesh = 1\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("mesh"), "{e}");
}

/// Geometry invariants shared by all cage types.
fn check_invariants(m: &Mesh, p: &CageParams, square: bool) {
    let o = p.origins.as_ref().map_or([0.0; 3], |o| o[0]);
    let c = p.circumference.unwrap();
    let h = p.depth.unwrap();
    let hc = p.cone_depth.unwrap();
    let r_t = if square {
        c / 8.0
    } else {
        c / (2.0 * std::f64::consts::PI)
    };
    let r_b = r_t * p.bottom_ratio.unwrap_or(1.0);
    let radial = |i: usize| {
        let q = m.nodes[i];
        let (dx, dy) = (q.x - o[0], q.y - o[1]);
        if square {
            dx.abs().max(dy.abs())
        } else {
            dx.hypot(dy)
        }
    };
    // No duplicate nodes (grid hash on 1 µm cells).
    let mut seen = std::collections::HashMap::new();
    for (i, q) in m.nodes.iter().enumerate() {
        let k = (
            (q.x * 1e6).round() as i64,
            (q.y * 1e6).round() as i64,
            (q.z * 1e6).round() as i64,
        );
        if let Some(j) = seen.insert(k, i) {
            panic!("nodes {j} and {i} coincide at {q:?}");
        }
    }
    // No zero-length element.
    for e in 0..m.lines.len() {
        assert!(m.line_length(e) > 1e-6, "element {e} has zero length");
    }
    // Positive panel areas, normals out of the cage.
    let centre = Vector3::new(o[0], o[1], o[2] - h / 2.0);
    for (k, pan) in m.panels.iter().enumerate() {
        let a = m.panel_area_vector(k);
        assert!(a.norm() > 1e-9, "panel {k} area {}", a.norm());
        let ns = pan.nodes.as_slice();
        let cen: Vector3<f64> =
            ns.iter().map(|&i| m.nodes[i].coords).sum::<Vector3<f64>>() / ns.len() as f64;
        assert!(
            a.dot(&(cen - centre)) > 0.0,
            "panel {k} normal points inwards"
        );
    }
    // Closed circumference: every net node except the tip is on exactly two ring lines, and
    // every collar node on two top_ring lines.
    let (nt, l) = {
        let cc = m.objects[0].counts().unwrap();
        (cc.nt, cc.nn + cc.bn)
    };
    let mut deg = vec![0usize; m.nodes.len()];
    for e in 0..nt * l {
        for n in m.lines[e].nodes {
            deg[n] += 1;
        }
    }
    assert!(deg[..nt * l].iter().all(|&d| d == 2));
    let ring = m.group(0, "top_ring").unwrap();
    let mut deg = vec![0usize; m.nodes.len()];
    for &e in &ring.lines {
        for n in m.lines[e].nodes {
            deg[n] += 1;
        }
    }
    assert!(ring.nodes.iter().all(|&n| deg[n] == 2));
    // Top at z = origin z, depth and radius as asked.
    for &i in &m.group(0, "net_top").unwrap().nodes {
        assert!((m.nodes[i].z - o[2]).abs() < 1e-9);
        assert!((radial(i) - r_t).abs() < 1e-9 * r_t.max(1.0));
    }
    for &i in &ring.nodes {
        assert!((m.nodes[i].z - o[2]).abs() < 1e-9);
    }
    for &i in &m.group(0, "net_bottom").unwrap().nodes {
        assert!((m.nodes[i].z - o[2] + h).abs() < 1e-9);
        assert!((radial(i) - r_b).abs() < 1e-9 * r_b.max(1.0));
    }
    let tip = m.group(0, "tip").unwrap().nodes[0];
    assert!((m.nodes[tip].z - o[2] + h + hc).abs() < 1e-9);
    assert!(radial(tip) < 1e-9);
    // Net nodes never outside the top radius; all at or below the top.
    for &i in &m.group(0, "net_nodes").unwrap().nodes {
        assert!(radial(i) <= r_t * (1.0 + 1e-12));
        assert!(m.nodes[i].z <= o[2] + 1e-12);
    }
    assert!(m.groups_with_role(Role::Fixed).next().is_some());
}

fn cage_strategy() -> impl Strategy<Value = (usize, CageParams)> {
    (
        0usize..4,
        20.0f64..200.0,
        3.0f64..30.0,
        0.0f64..8.0,
        0.3f64..1.0,
        0.08f64..0.25,
        0.2f64..1.0,
        prop::array::uniform3(-500.0f64..500.0),
    )
        .prop_map(|(t, c, h, hc, br, el_frac, f, o)| {
            let kind = [CageType::Cct, CageType::Ccs, CageType::Csm, CageType::Ssm][t];
            let mut p = CageParams::new(kind);
            p.circumference = Some(c);
            p.depth = Some(h);
            p.cone_depth = Some(hc);
            // element length as a fraction of the smaller of depth and radius: counts ≥ 1.
            let r = c / (2.0 * std::f64::consts::PI);
            p.element_length = Some(el_frac * h.min(r));
            p.frame_offset = Some(f);
            if matches!(kind, CageType::Cct | CageType::Ccs) {
                p.bottom_ratio = Some(br);
            }
            if kind == CageType::Ccs {
                p.weight_depth = Some(hc + 1.0 + h);
            }
            p.origins = Some(vec![o]);
            // Keep λ ≥ 1 for short elements.
            p.net.half_mesh = Some(0.01);
            p.net.twine_diameter = Some(0.001);
            (t, p)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn cage_invariants((t, p) in cage_strategy()) {
        let m = p.build().unwrap();
        check_invariants(&m, &p, t == 3);
        // Counts follow the formulas.
        let cc = m.objects[0].counts().cloned().unwrap();
        let l = cc.nn + cc.bn;
        prop_assert_eq!(m.group(0, "net_nodes").unwrap().nodes.len(), cc.nt * l + 1);
        prop_assert_eq!(m.group(0, "net_twines").unwrap().lines.len(), 2 * cc.nt * l);
        prop_assert_eq!(m.panels.len(), cc.nt * l);
        prop_assert_eq!(cc.nn, (p.depth.unwrap() / p.element_length.unwrap()).round() as usize);
    }
}
