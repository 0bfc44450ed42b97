//! gmsh import against fixtures written by real gmsh (see tests/fixtures/README.md); the
//! expected counts follow from the structured geometry of make_fixtures.py by hand.

use aqua_mesh::io::gmsh::{import_raw, parse_msh};
use aqua_mesh::{GmshParams, Mesh, PanelNodes, Role, import_gmsh};
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

fn import(name: &str) -> Mesh {
    import_gmsh(&GmshParams {
        file: fixture(name),
        ..Default::default()
    })
    .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn check_fixture(m: &Mesh) {
    // 20 quad-net nodes + 12 triangle-net nodes − 4 shared + 3 rope nodes.
    assert_eq!(m.nodes.len(), 31);
    let quads = m
        .panels
        .iter()
        .filter(|p| matches!(p.nodes, PanelNodes::Quad(_)))
        .count();
    assert_eq!((m.panels.len(), quads), (24, 12));
    let g = |n: &str| m.group(0, n).unwrap_or_else(|| panic!("no group {n}"));
    assert_eq!(g("net_panels").role, Role::NetPanels);
    // Derived twines: 16 + 15 edges of the 4×3 quads, 8 + 9 − 3 of the 2×3 triangle cells,
    // 6 diagonals.
    assert_eq!(g("net_twines").lines.len(), 51);
    assert_eq!(g("ropes").lines.len(), 3);
    assert_eq!(g("ropes").role, Role::Ropes);
    assert_eq!(g("fixed").nodes.len(), 5);
    assert_eq!(g("sinkers").nodes.len(), 7);
    assert_eq!(g("float").role, Role::UserNodes);
    let f = g("float").nodes[0];
    assert!((m.nodes[f].coords - nalgebra::Vector3::new(0.0, 0.0, 2.0)).norm() < 1e-12);
    for &n in &g("fixed").nodes {
        assert!(m.nodes[n].z.abs() < 1e-9);
    }
    for &n in &g("sinkers").nodes {
        assert!((m.nodes[n].z + 3.0).abs() < 1e-9);
    }
    // Panel areas: 4×3 + 2×3 = 18 m².
    let area: f64 = (0..m.panels.len()).map(|p| m.panel_area(p)).sum();
    assert!((area - 18.0).abs() < 1e-9);
    // λ: the twine of 18 m² of net, 2·18/l_p, over the numerical twine (45 unit edges, 6
    // diagonals of √2).
    let net = m.objects[0].net.as_ref().unwrap();
    let total = 45.0 + 6.0 * 2f64.sqrt();
    assert!((net.mean_twine_length - total / 51.0).abs() < 1e-9);
    assert!((net.lambda - 2.0 * 18.0 / (25.87e-3 * total)).abs() < 1e-6);
    assert_eq!(m.fixed_nodes().len(), 5);
    assert!(
        m.notices
            .iter()
            .any(|n| n.contains("51 net twines derived"))
    );
}

#[test]
fn msh22_ascii() {
    let m = import("net_v22.msh");
    check_fixture(&m);
    // Dense renumbering keeps the original tags.
    assert_eq!(
        m.objects[0].source_node_tags(),
        (1..=31).collect::<Vec<u64>>()
    );
}

#[test]
fn msh41_ascii() {
    check_fixture(&import("net_v41.msh"));
}

#[test]
fn msh41_binary() {
    check_fixture(&import("net_v41_bin.msh"));
}

#[test]
fn all_formats_agree() {
    let a = import("net_v22.msh");
    for other in ["net_v41.msh", "net_v41_bin.msh"] {
        let b = import(other);
        assert_eq!(a.nodes.len(), b.nodes.len());
        for (p, q) in a.nodes.iter().zip(&b.nodes) {
            assert!((p - q).norm() < 1e-12, "{other}");
        }
        // Element order differs between 2.2 (by type) and 4.1 (by entity): compare as sets.
        let lines = |m: &Mesh| {
            let mut v: Vec<(String, [usize; 2])> = m
                .lines
                .iter()
                .map(|l| {
                    let mut n = l.nodes;
                    n.sort();
                    (m.groups[l.group].name.clone(), n)
                })
                .collect();
            v.sort();
            v
        };
        let panels = |m: &Mesh| {
            let mut v: Vec<Vec<usize>> = m
                .panels
                .iter()
                .map(|p| p.nodes.as_slice().to_vec())
                .collect();
            v.sort();
            v
        };
        assert_eq!(lines(&a), lines(&b), "{other}");
        assert_eq!(panels(&a), panels(&b), "{other}");
    }
}

#[test]
fn transform_and_copies() {
    let m = import_gmsh(&GmshParams {
        file: fixture("net_v41.msh"),
        scale: Some(2.0),
        rotate_deg: Some([0.0, 0.0, 90.0]),
        translate: Some([1.0, 2.0, 3.0]),
        origins: Some(vec![[0.0, 0.0, 0.0], [50.0, 0.0, 0.0]]),
        ..Default::default()
    })
    .unwrap();
    assert_eq!(m.nodes.len(), 62);
    assert_eq!(m.panels.len(), 48);
    // File node 2 at (4, 0, 0): ×2 → (8, 0, 0), 90° about z → (0, 8, 0), + (1, 2, 3).
    assert!((m.nodes[1].coords - nalgebra::Vector3::new(1.0, 10.0, 3.0)).norm() < 1e-9);
    assert!((m.nodes[32].coords - nalgebra::Vector3::new(51.0, 10.0, 3.0)).norm() < 1e-9);
    assert_eq!(m.node_owner[32], (0, 1));
}

fn text(name: &str) -> String {
    std::fs::read_to_string(fixture(name)).unwrap()
}

fn parse_err(name: &str, bytes: &[u8]) -> String {
    let p = Path::new(name);
    match parse_msh(p, bytes) {
        Err(e) => e.to_string(),
        Ok(raw) => import_raw(
            &GmshParams {
                file: p.to_path_buf(),
                ..Default::default()
            },
            &raw,
        )
        .map(|_| String::from("no error"))
        .unwrap_or_else(|e| e.to_string()),
    }
}

#[test]
fn unknown_name_lists_valid_names_and_rename_fixes_it() {
    let s = text("net_v22.msh").replace("2 1 \"net\"", "2 1 \"netting\"");
    let e = parse_err("bad.msh", s.as_bytes());
    assert!(e.contains("line 10") && e.contains("netting"), "{e}");
    assert!(
        e.contains("valid names") && e.contains("twines") && e.contains("rename"),
        "{e}"
    );
    let raw = parse_msh(Path::new("bad.msh"), s.as_bytes()).unwrap();
    let m = import_raw(
        &GmshParams {
            file: "bad.msh".into(),
            rename: [("netting".to_string(), "net".to_string())].into(),
            ..Default::default()
        },
        &raw,
    )
    .unwrap();
    check_fixture(&m);
    // Wrong dimension for a role.
    let s = text("net_v22.msh").replace("1 4 \"ropes\"", "1 4 \"tip\"");
    assert_eq!(parse_err("ok.msh", s.as_bytes()), "no error");
    let s = text("net_v22.msh").replace("1 4 \"ropes\"", "1 4 \"net_panels\"");
    let e = parse_err("dim.msh", s.as_bytes());
    assert!(
        e.contains("dimension 1") && e.contains("needs dimension 2"),
        "{e}"
    );
    // A physical tag without a name.
    let s = text("net_v22.msh")
        .replace("$PhysicalNames\n5\n", "$PhysicalNames\n4\n")
        .replace("1 4 \"ropes\"\n", "");
    let e = parse_err("noname.msh", s.as_bytes());
    assert!(
        e.contains("physical group 4") && e.contains("no name"),
        "{e}"
    );
}

#[test]
fn truncated_files_report_position() {
    let s = text("net_v22.msh");
    let cut = s.find("\n27 3 2 1 1").unwrap();
    let e = parse_err("cut22.msh", &s.as_bytes()[..cut]);
    assert!(e.contains("line ") && e.contains("truncated"), "{e}");

    let s = std::fs::read(fixture("net_v41.msh")).unwrap();
    let e = parse_err("cut41.msh", &s[..s.len() * 2 / 3]);
    assert!(e.contains("cut41.msh: line "), "{e}");

    let s = std::fs::read(fixture("net_v41_bin.msh")).unwrap();
    let e = parse_err("cut41b.msh", &s[..s.len() * 2 / 3]);
    assert!(e.contains("byte offset"), "{e}");
    let e = parse_err("cut41b.msh", &s[..s.len() - 20]);
    assert!(e.contains("cut41b.msh: "), "{e}");

    let e = parse_err("empty.msh", b"");
    assert!(e.contains("$MeshFormat"), "{e}");
}

#[test]
fn unsupported_inputs() {
    let e = parse_err("b22.msh", b"$MeshFormat\n2.2 1 8\n");
    assert!(e.contains("2.2 binary") && e.contains("re-export"), "{e}");
    let e = parse_err("v3.msh", b"$MeshFormat\n3.0 0 8\n$EndMeshFormat\n");
    assert!(e.contains("version 3.0"), "{e}");
    // Second-order line (type 8) is rejected naming the type and line.
    let s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0.5 0 0\n\
             $EndNodes\n$Elements\n1\n1 8 2 1 1 1 2 3\n$EndElements\n";
    let e = parse_err("o2.msh", s.as_bytes());
    assert!(
        e.contains("line 12") && e.contains("type 8") && e.contains("second-order"),
        "{e}"
    );
    // No physical groups at all → no usable group.
    let s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n\
             $Elements\n1\n1 1 2 0 1 1 2\n$EndElements\n";
    let e = parse_err("nogroup.msh", s.as_bytes());
    assert!(e.contains("no usable physical group"), "{e}");
    // Zero-length line.
    let s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n1 1 \"ropes\"\n\
             $EndPhysicalNames\n$Nodes\n2\n1 0 0 0\n2 0 0 0\n$EndNodes\n\
             $Elements\n1\n7 1 2 1 1 1 2\n$EndElements\n";
    let e = parse_err("zero.msh", s.as_bytes());
    assert!(
        e.contains("line 15") && e.contains("element 7") && e.contains("zero length"),
        "{e}"
    );
    // Missing file.
    let e = import_gmsh(&GmshParams {
        file: "/nonexistent/net.msh".into(),
        ..Default::default()
    })
    .unwrap_err()
    .to_string();
    assert!(e.contains("/nonexistent/net.msh"), "{e}");
}
