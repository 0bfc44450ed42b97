//! The numerical net carries the physical net's twine (docs/theory/cages.md#mesh-grouping): its
//! twine volume, mass, axial stiffness and Morison area equal those of a square-mesh net of the
//! same area, half mesh and twine, computed here independently from the net's area in closed
//! form; and the rope columns of CCT/CCS cages carry the design's ropes whatever the element
//! length (docs/theory/cages.md#frame-ropes-and-weights).

use aqua_mesh::{CageParams, CageType, GmshParams, Mesh, PanelParams, Role, import_gmsh};
use std::f64::consts::{FRAC_PI_4, PI};
use std::path::Path;

const D: f64 = 2.85e-3;
const LP: f64 = 25.87e-3;
const E: f64 = 2.0e9;
const RHO: f64 = 1140.0;

/// Twine totals of a net: length [m], volume [m³], mass [kg], Σ EA·L [N·m], Morison area [m²].
#[derive(Debug)]
struct Totals([f64; 5]);

/// The physical net of area `area` [m²]: a square mesh of bar l_p holds 2/l_p metres of twine of
/// diameter d per square metre.
fn physical(area: f64) -> Totals {
    let length = 2.0 * area / LP;
    let volume = FRAC_PI_4 * D * D * length;
    Totals([length, volume, RHO * volume, E * volume, D * length])
}

/// The numerical net of object 0, copy 0: each element stands for `section_scale` of its
/// group's section.
fn numerical(m: &Mesh) -> Totals {
    let mut t = [0.0; 5];
    for (e, l) in m.iter_lines() {
        let g = &m.groups[l.group];
        if g.role != Role::NetTwines || l.copy != 0 || l.object != 0 {
            continue;
        }
        let s = g.section.as_ref().unwrap();
        let (len, k) = (m.line_length(e), l.section_scale);
        let twine_area = FRAC_PI_4 * D * D;
        t[0] += s.mass_area() / twine_area * k * len;
        t[1] += s.mass_area() * k * len;
        t[2] += s.linear_mass() * k * len;
        t[3] += s.axial_stiffness() * k * len;
        t[4] += s.hydro_diameter * k * len;
    }
    Totals(t)
}

fn assert_equivalent(what: &str, m: &Mesh, area: f64) {
    let (n, p) = (numerical(m), physical(area));
    let names = ["length", "volume", "mass", "EA·L", "Morison area"];
    for i in 0..5 {
        let ratio = n.0[i] / p.0[i];
        assert!(
            (ratio - 1.0).abs() < 1e-3,
            "{what}: twine {} numerical/physical = {ratio:.5} ({} vs {})",
            names[i],
            n.0[i],
            p.0[i]
        );
    }
}

/// Lateral area of the frustum of a regular n-gon pyramid between circumradii r1 ≥ r2 over a
/// height h [m²] (r2 = 0: the pyramid).
fn frustum(n: usize, r1: f64, r2: f64, h: f64) -> f64 {
    let (s, c) = (PI / n as f64).sin_cos();
    let slant = (h * h + ((r1 - r2) * c).powi(2)).sqrt();
    n as f64 * 0.5 * 2.0 * (r1 + r2) * s * slant
}

/// Net area of a circular cage: the side frustum and the cone below it.
fn circular_area(m: &Mesh, depth: f64, cone: f64) -> f64 {
    let c = m.objects[0].counts().unwrap();
    frustum(c.nt, c.top_radius, c.bottom_radius, depth) + frustum(c.nt, c.bottom_radius, 0.0, cone)
}

fn cage(kind: CageType, el: f64) -> CageParams {
    let mut p = CageParams::new(kind);
    p.element_length = Some(el);
    p
}

#[test]
fn cage_nets_carry_the_physical_twine() {
    for kind in [CageType::Cct, CageType::Ccs, CageType::Csm] {
        for el in [5.0, 2.5, 1.77] {
            let m = cage(kind, el).build().unwrap();
            let what = format!("{kind:?} el {el}");
            assert_equivalent(&what, &m, circular_area(&m, 15.0, 3.0));
        }
    }
    // A tapered wall (trapezoidal cells) and two copies.
    let mut p = cage(CageType::Cct, 2.0);
    p.bottom_ratio = Some(0.7);
    p.origins = Some(vec![[0.0; 3], [100.0, 0.0, 0.0]]);
    let m = p.build().unwrap();
    assert_equivalent("tapered CCT", &m, circular_area(&m, 15.0, 3.0));
    // SSM: four a × H sides and four triangles of base a and slant height √(h_c² + (a/2)²).
    for el in [5.0, 2.5, 1.77] {
        let m = cage(CageType::Ssm, el).build().unwrap();
        let a = 30.0;
        let area = 4.0 * a * 15.0 + 4.0 * 0.5 * a * (9.0 + (a / 2.0f64).powi(2)).sqrt();
        assert_equivalent(&format!("SSM el {el}"), &m, area);
    }
}

#[test]
fn gmsh_and_panel_nets_carry_the_physical_twine() {
    // The fixture's net: 4 m × 3 m of quads and 2 m × 3 m of triangles (their diagonals become
    // twines), 18 m² (tests/fixtures/README.md).
    let m = import_gmsh(&GmshParams {
        file: Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/net_v41.msh"),
        ..Default::default()
    })
    .unwrap();
    assert_equivalent("gmsh", &m, 18.0);
    let p = PanelParams {
        divisions: Some([6, 10]),
        ..PanelParams::new(3.0, 2.0)
    };
    assert_equivalent("panel", &p.build().unwrap(), 6.0);
}

/// EA of each twine: n physical twines side by side, n = (width of net it represents)/l_p. In
/// rectangular cells a × b (a along the twine) the physical bars run along the twines, so this
/// is the stiffness of the net strip of width b.
#[test]
fn twine_stiffness_is_the_strip_of_net_it_represents() {
    let ea_twine = E * FRAC_PI_4 * D * D;
    let ea = |m: &Mesh, e: usize| {
        let l = &m.lines[e];
        m.groups[l.group]
            .section
            .as_ref()
            .unwrap()
            .axial_stiffness()
            * l.section_scale
    };
    // Flat panel of 0.5 m × 0.2 m cells: interior horizontal twines carry a 0.2 m strip,
    // vertical ones a 0.5 m strip; edge twines half of that.
    let p = PanelParams {
        divisions: Some([6, 10]),
        ..PanelParams::new(3.0, 2.0)
    };
    let m = p.build().unwrap();
    for (e, l) in m.iter_lines() {
        let [a, b] = l.nodes.map(|n| m.nodes[n]);
        let horizontal = (a.z - b.z).abs() < 1e-12;
        let edge = if horizontal {
            a.z.abs() < 1e-9 || (a.z + 2.0).abs() < 1e-9
        } else {
            // The panel's default plane is x = 0, width along y.
            (a.y.abs() - 1.5).abs() < 1e-9
        };
        let width = if horizontal { 0.2 } else { 0.5 } * if edge { 0.5 } else { 1.0 };
        let want = ea_twine * width / LP;
        assert!(
            (ea(&m, e) - want).abs() < 1e-9 * want,
            "line {e}: EA {} vs {want}",
            ea(&m, e)
        );
    }
    // The side of a CSM cage: rings at the inner side levels carry H/NN of net, meridians of the
    // side the chord 2R·sin(π/NT).
    for el in [5.0, 2.5] {
        let m = cage(CageType::Csm, el).build().unwrap();
        let c = m.objects[0].counts().cloned().unwrap();
        let (nt, nn, l) = (c.nt, c.nn, c.nn + c.bn);
        let chord = 2.0 * c.top_radius * (PI / nt as f64).sin();
        let tw = &m.groups[m.group_index(0, "net_twines").unwrap()].lines;
        for i in 0..nt {
            for lv in 1..nn {
                // Ring lines come first, level by level: line lv·NT + i.
                let want = ea_twine * (15.0 / nn as f64) / LP;
                let got = ea(&m, tw[lv * nt + i]);
                assert!(
                    (got - want).abs() < 1e-9 * want,
                    "ring {lv}: {got} vs {want}"
                );
            }
            for lv in 0..nn {
                let want = ea_twine * chord / LP;
                let got = ea(&m, tw[nt * l + lv * nt + i]);
                assert!(
                    (got - want).abs() < 1e-9 * want,
                    "meridian {lv}: {got} vs {want}"
                );
            }
        }
    }
}

/// Rope length [m] and Morison drag area [m²] of the `ropes` group, each element counted
/// `section_scale` times.
fn rope_totals(m: &Mesh) -> (f64, f64) {
    let g = &m.groups[m.group_index(0, "ropes").unwrap()];
    let s = g.section.as_ref().unwrap();
    g.lines.iter().fold((0.0, 0.0), |(l, a), &e| {
        let k = m.lines[e].section_scale;
        let len = m.line_length(e);
        (l + k * len, a + k * len * s.hydro_diameter)
    })
}

#[test]
fn rope_count_and_length_are_the_designs() {
    // Defaults: C = 120 m, H = 15 m, f = 1 m, tube 2.5 m below the net, CCS weight 2H below it;
    // ropes = round(120/2.5) = 48, whatever the element length.
    let r = 120.0 / (2.0 * PI);
    let rope = |kind| match kind {
        CageType::Cct => 15.0 + 2.5,
        _ => 15.0 + ((r + 1.0).powi(2) + 30.0f64.powi(2)).sqrt(),
    };
    for kind in [CageType::Cct, CageType::Ccs] {
        for (ropes, set) in [(48, None), (16, Some(16))] {
            for el in [5.0, 2.5, 1.77] {
                let mut p = cage(kind, el);
                p.ropes = set;
                let m = p.build().unwrap();
                assert_eq!(m.objects[0].counts().unwrap().ropes, ropes);
                let (len, area) = rope_totals(&m);
                let want = ropes as f64 * rope(kind);
                assert!(
                    (len - want).abs() < 1e-9 * want,
                    "{kind:?} el {el}: rope length {len} vs {want}"
                );
                assert!((area - 0.05 * want).abs() < 1e-9 * want, "{kind:?} el {el}");
            }
        }
    }
    let mut p = cage(CageType::Cct, 2.5);
    p.ropes = Some(2);
    let e = p.build().unwrap_err().to_string();
    assert!(e.contains("ropes") && e.contains(">= 3"), "{e}");
    let mut p = cage(CageType::Csm, 2.5);
    p.ropes = Some(12);
    let e = p.build().unwrap_err().to_string();
    assert!(e.contains("ropes") && e.contains("CSM"), "{e}");
}
