//! VTK export: written files read back in-process (the XML and its base64 arrays decoded here)
//! and, when `AQUA_VTK_PYTHON` names a python with meshio (tests/python/requirements.txt), by
//! the independent checker tests/python/check_vtk.py.

use aqua_mesh::{BlockArray, CageParams, CageType, MultiblockSeries, StepArrays, write_geometry};
use base64::Engine;
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("aqua-mesh-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn cct() -> aqua_mesh::Mesh {
    CageParams::new(CageType::Cct).build().unwrap()
}

fn extra(m: &aqua_mesh::Mesh, t: f64) -> StepArrays {
    StepArrays {
        point: vec![BlockArray::vectors(
            "displacement",
            &vec![[t, 0.0, -0.5 * t]; m.nodes.len()],
        )],
        line: vec![BlockArray::scalar(
            "tension",
            vec![100.0 * t; m.lines.len()],
        )],
        panel: vec![],
    }
}

/// The `file="…"` attributes of a `.vtm`, in order.
fn vtm_files(vtm: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(vtm).unwrap();
    text.split("file=\"")
        .skip(1)
        .map(|s| s[..s.find('"').unwrap()].to_string())
        .collect()
}

/// The bytes of the inline binary `DataArray` named `name` of a `.vtu` (after the UInt64 byte
/// count, which is checked).
fn data_array(vtu: &str, name: &str) -> Vec<u8> {
    let at = vtu
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("array {name} missing"));
    let body = &vtu[at..];
    let body = &body[body.find('>').unwrap() + 1..];
    let b64 = body[..body.find('<').unwrap()].trim();
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(b64)
        .unwrap();
    let n = u64::from_le_bytes(bytes[..8].try_into().unwrap()) as usize;
    assert_eq!(n, bytes.len() - 8, "{name}: byte count");
    bytes[8..].to_vec()
}

#[test]
fn geometry_holds_every_node_and_cell_once_as_the_reference_step() {
    let m = cct();
    let dir = tmpdir("geometry");
    let vtm = dir.join("cct.vtm");
    assert_eq!(write_geometry(&vtm, &m).unwrap(), vtm);
    // The atomic write of the .vtm leaves no temporary file behind.
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["cct", "cct.vtm"]);
    let (mut points, mut lines, mut quads, mut triangles, mut conn) = (0, 0, 0, 0, 0);
    for f in vtm_files(&vtm) {
        let text = std::fs::read_to_string(dir.join(&f)).unwrap();
        let types = data_array(&text, "types");
        let count = |t: u8| types.iter().filter(|&&x| x == t).count();
        if f.ends_with("_points.vtu") {
            assert_eq!(count(1), types.len());
            points += types.len();
            continue;
        }
        lines += count(3);
        quads += count(9);
        triangles += count(5);
        conn += data_array(&text, "connectivity").len() / 8;
        if f.ends_with("_lines.vtu") {
            for a in [
                "group_id",
                "role_id",
                "diameter",
                "elastic_diameter",
                "hydro_diameter",
            ] {
                assert!(
                    text.contains(&format!("Name=\"{a}\"")),
                    "{a} missing in {f}"
                );
            }
        }
        assert!(!text.contains("TimeValue"), "{f}: the geometry has no time");
    }
    // CCT defaults: 913 nodes; 1056 net + 48 ring + 48 links + 336 ropes + 48 ties + 48 bottom
    // ring lines, 480 quads, 48 triangles (docs/theory/cages.md#worked-ssm-case).
    let nl = 1056 + 96 + 336 + 48 + 48;
    assert_eq!(points, 913);
    assert_eq!((lines, quads, triangles), (nl, 480, 48));
    assert_eq!(conn, 2 * nl + 4 * 480 + 3 * 48);
    // The same block files as a run's reference step of the same mesh.
    let run = dir.join("run");
    let s = MultiblockSeries::new(&run, "cct", &m).unwrap();
    let reference = s.write_reference(&m).unwrap();
    let ours = vtm_files(&vtm);
    let theirs = vtm_files(&reference);
    assert_eq!(ours.len(), theirs.len());
    for (a, b) in ours.iter().zip(&theirs) {
        assert_eq!(
            std::fs::read(dir.join(a)).unwrap(),
            std::fs::read(run.join(b)).unwrap(),
            "{a} differs from the reference step's {b}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn geometry_file_names_are_checked() {
    let m = cct();
    let dir = tmpdir("geometry-names");
    let err = write_geometry(&dir.join("cct.vtu"), &m)
        .unwrap_err()
        .to_string();
    assert!(err.contains(".vtm"), "{err}");
    // A folder of the block files' name that holds other files is left alone.
    std::fs::create_dir_all(dir.join("notes")).unwrap();
    std::fs::write(dir.join("notes/keep.txt"), "keep").unwrap();
    let err = write_geometry(&dir.join("notes.vtm"), &m)
        .unwrap_err()
        .to_string();
    assert!(err.contains("other than .vtu"), "{err}");
    assert!(dir.join("notes/keep.txt").exists() && !dir.join("notes.vtm").exists());
    // Writing again replaces the blocks of the earlier file.
    write_geometry(&dir.join("cct.vtm"), &m).unwrap();
    std::fs::write(dir.join("cct/stale.vtu"), "").unwrap();
    write_geometry(&dir.join("cct.vtm"), &m).unwrap();
    assert!(!dir.join("cct/stale.vtu").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_arrays_are_rejected() {
    let m = cct();
    let dir = tmpdir("badarr");
    let mut s = MultiblockSeries::new(&dir, "x", &m).unwrap();
    let mut e = extra(&m, 1.0);
    let mut tension = vec![100.0; m.lines.len()];
    tension[3] = f64::NAN;
    e.line[0] = BlockArray::scalar("tension", tension);
    let err = s.write_step(0.0, &m, &m.nodes, &e).unwrap_err().to_string();
    assert!(
        err.contains("tension") && err.contains("not finite"),
        "{err}"
    );
    let mut e = extra(&m, 1.0);
    e.point[0] = BlockArray::vectors("displacement", &vec![[0.0; 3]; m.nodes.len() - 1]);
    let err = s.write_step(0.0, &m, &m.nodes, &e).unwrap_err().to_string();
    assert!(err.contains("displacement"), "{err}");
    let e = StepArrays {
        point: vec![BlockArray::scalar("fixed", vec![0.0; m.nodes.len()])],
        ..Default::default()
    };
    let err = s.write_step(0.0, &m, &m.nodes, &e).unwrap_err().to_string();
    assert!(err.contains("already used"), "{err}");
    // Nothing of a rejected step is written.
    assert!(s.entries().is_empty());
    assert!(!dir.join("x_000000.vtm").exists() && !dir.join("x_000000").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Writes the geometry of a cage and of a gmsh import and a 3-step series, then runs the
/// python checker (meshio reads every block file).
#[test]
fn independent_reader_python_meshio() {
    let Ok(python) = std::env::var("AQUA_VTK_PYTHON") else {
        eprintln!(
            "note: AQUA_VTK_PYTHON is not set; skipping the independent meshio check of the VTK \
             files (set it to a python with tests/python/requirements.txt installed)"
        );
        return;
    };
    let checker = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/python/check_vtk.py");
    let dir = tmpdir("python");
    let run = |args: &[&str]| {
        let out = Command::new(&python)
            .arg(&checker)
            .args(args)
            .output()
            .expect("cannot run AQUA_VTK_PYTHON");
        let msg = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        (out.status.success(), msg)
    };
    let with_expect = |name: &str, expect: serde_json::Value| {
        let ef = dir.join(format!("{name}.expect.json"));
        std::fs::write(&ef, expect.to_string()).unwrap();
        ef
    };

    // SSM worked case (docs/theory/cages.md#worked-ssm-case): 1057 nodes; 1344 + 336 + 144 + 96
    // lines; 624 quads, 48 triangles.
    let mut p = CageParams::new(CageType::Ssm);
    p.circumference = Some(120.0);
    let m = p.build().unwrap();
    let f = write_geometry(&dir.join("ssm.vtm"), &m).unwrap();
    let ef = with_expect(
        "ssm",
        serde_json::json!({
            "points": 1057,
            "cells": {"line": 1920, "quad": 624, "triangle": 48},
            "point_arrays": {"node_id": 1, "object_id": 1, "copy_id": 1, "fixed": 1,
                             "point_weight": 1},
            "line_arrays": {"group_id": 1, "role_id": 1, "object_id": 1, "copy_id": 1,
                            "diameter": 1, "elastic_diameter": 1, "hydro_diameter": 1},
        }),
    );
    let (ok, msg) = run(&[f.to_str().unwrap(), "--expect", ef.to_str().unwrap()]);
    assert!(ok, "{msg}");
    assert!(msg.contains("3 blocks read by meshio"), "{msg}");

    // A wrong expectation must fail (the checker really checks).
    let (ok, msg) = run(&[
        f.to_str().unwrap(),
        "--cells",
        "line=1920,quad=623,triangle=48",
    ]);
    assert!(!ok, "checker accepted a wrong count: {msg}");

    // gmsh import (fixture counts: 51 derived twines + 3 ropes, 12 quads, 12 triangles).
    let g = aqua_mesh::import_gmsh(&aqua_mesh::GmshParams {
        file: Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/net_v41.msh"),
        ..Default::default()
    })
    .unwrap();
    let f = write_geometry(&dir.join("gmsh.vtm"), &g).unwrap();
    let (ok, msg) = run(&[
        f.to_str().unwrap(),
        "--points",
        "31",
        "--cells",
        "line=54,quad=12,triangle=12",
    ]);
    assert!(ok, "{msg}");

    // Time series with real time values, expectations through a JSON file.
    let m = cct();
    let mut s = MultiblockSeries::new(dir.join("series"), "cct", &m).unwrap();
    for t in [0.0, 0.1, 0.35] {
        s.write_step(t, &m, &m.nodes, &extra(&m, t)).unwrap();
    }
    let ef = with_expect(
        "series",
        serde_json::json!({
            "points": 913,
            "cells": {"line": 1056 + 96 + 336 + 48 + 48, "quad": 480, "triangle": 48},
            "point_arrays": {"displacement": 3, "fixed": 1},
            "line_arrays": {"tension": 1, "role_id": 1},
            "times": [0.0, 0.1, 0.35],
        }),
    );
    let pvd = dir.join("series/cct.pvd");
    let (ok, msg) = run(&[pvd.to_str().unwrap(), "--expect", ef.to_str().unwrap()]);
    assert!(ok, "{msg}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The multiblock layout: one block per object copy and kind, named; the points blocks
/// partition the nodes and the lines/panels blocks hold every cell once; the `.pvd` grows by one
/// valid entry per step and rejects a time that does not increase.
#[test]
fn multiblock_series_names_objects_copies_and_kinds() {
    use aqua_mesh::BlockKind;
    let mut p = CageParams::new(CageType::Cct);
    p.name = Some("pen".into());
    p.origins = Some(vec![[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]]);
    let m = p.build().unwrap();
    let dir = tmpdir("vtm");
    let mut s = MultiblockSeries::new(&dir, "farm", &m).unwrap();
    let names: Vec<String> = s.layout().blocks.iter().map(|b| b.name()).collect();
    assert_eq!(
        names,
        [
            "pen_0/lines",
            "pen_0/panels",
            "pen_0/points",
            "pen_1/lines",
            "pen_1/panels",
            "pen_1/points"
        ]
    );
    assert_eq!(
        s.names().block_objects,
        ["pen#0", "pen#0", "pen#0", "pen#1", "pen#1", "pen#1"]
    );
    let mut nodes: Vec<usize> = s
        .layout()
        .blocks
        .iter()
        .filter(|b| b.kind == BlockKind::Points)
        .flat_map(|b| b.nodes.clone())
        .collect();
    nodes.sort_unstable();
    assert_eq!(nodes, (0..m.nodes.len()).collect::<Vec<_>>());
    let count = |k: BlockKind| -> usize {
        s.layout()
            .blocks
            .iter()
            .filter(|b| b.kind == k)
            .map(|b| b.cells.len())
            .sum()
    };
    assert_eq!(count(BlockKind::Lines), m.lines.len());
    assert_eq!(count(BlockKind::Panels), m.panels.len());
    let tables = s.names().clone();
    assert_eq!(tables.object_names, ["pen"]);
    assert_eq!(tables.group_names[m.lines[0].group], "pen/net_twines");
    let arrays = |t: f64| StepArrays {
        point: vec![BlockArray::vectors(
            "displacement",
            &vec![[t, 0.0, 0.0]; m.nodes.len()],
        )],
        line: vec![BlockArray::int("slack", vec![0; m.lines.len()])],
        panel: vec![],
    };
    s.write_reference(&m).unwrap();
    for (k, t) in [0.0, 0.5, 2.0].into_iter().enumerate() {
        s.write_step(t, &m, &m.nodes, &arrays(t)).unwrap();
        let pvd = std::fs::read_to_string(dir.join("farm.pvd")).unwrap();
        assert_eq!(pvd.matches("<DataSet").count(), k + 1, "{pvd}");
        assert!(pvd.ends_with("  </Collection>\n</VTKFile>\n"), "{pvd}");
        let vtm = std::fs::read_to_string(dir.join(format!("farm_{k:06}.vtm"))).unwrap();
        assert!(vtm.contains("<Block index=\"1\" name=\"pen_1\">"), "{vtm}");
        assert!(vtm.contains(&format!(
            "name=\"panels\" file=\"farm_{k:06}/pen_1_panels.vtu\""
        )));
    }
    assert!(s.write_step(2.0, &m, &m.nodes, &arrays(2.0)).is_err());
    let mut bad = arrays(3.0);
    bad.line[0] = BlockArray::int("slack", vec![0; 3]);
    let err = s
        .write_step(3.0, &m, &m.nodes, &bad)
        .unwrap_err()
        .to_string();
    assert!(err.contains("slack") && err.contains("expected"), "{err}");
    let mut bad = arrays(3.0);
    bad.point[0] = BlockArray::scalar("fixed", vec![0.0; m.nodes.len()]);
    let err = s
        .write_step(3.0, &m, &m.nodes, &bad)
        .unwrap_err()
        .to_string();
    assert!(err.contains("already used"), "{err}");
    assert_eq!(s.entries().len(), 3);
    // A new series with the same stem clears the old steps (and only those).
    std::fs::write(dir.join("notes.txt"), "keep").unwrap();
    let _ = MultiblockSeries::new(&dir, "farm", &m).unwrap();
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("farm_0") || n == "farm.pvd")
        .collect();
    assert!(left.is_empty(), "{left:?}");
    assert!(dir.join("notes.txt").exists() && dir.join("farm_reference.vtm").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Block names use only the characters ParaView 5.11 keeps in its hierarchy (ASCII letters,
/// digits, `_`; it drops `/`, `#`, `-`, `.`, `:` and prefixes a leading digit with `_`), stay
/// unique, and `block_objects` maps them back to the object names.
#[test]
fn block_names_are_names_paraview_keeps() {
    let cage = |name: &str| {
        let mut p = CageParams::new(CageType::Cct);
        p.name = Some(name.into());
        p.build().unwrap()
    };
    let mut m = cage("farm/cage_r1c1");
    for name in ["farm_cage_r1c1", "1st-cage.a:b"] {
        m.append(cage(name));
    }
    let dir = tmpdir("vtm-names");
    let s = MultiblockSeries::new(&dir, "farm", &m).unwrap();
    let tops: Vec<&str> = s
        .layout()
        .blocks
        .iter()
        .map(|b| b.object_label.as_str())
        .collect();
    let mut unique = tops.clone();
    unique.dedup();
    assert_eq!(
        unique,
        ["farm_cage_r1c1", "farm_cage_r1c1_2", "_1st_cage_a_b"]
    );
    for b in &s.names().block_names {
        assert!(
            b.split('/').all(
                |part| part.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                    && !part.starts_with(|c: char| c.is_ascii_digit())
            ),
            "{b}"
        );
    }
    let objects = &s.names().block_objects;
    assert_eq!(objects.len(), s.names().block_names.len());
    assert_eq!(objects[0], "farm/cage_r1c1");
    assert_eq!(objects.last().unwrap(), "1st-cage.a:b");
    let _ = std::fs::remove_dir_all(&dir);
}
