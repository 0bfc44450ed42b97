//! VTK export: written files read back by vtkio (in-process) and, when `AQUA_VTK_PYTHON` names a
//! python with meshio (tests/python/requirements.txt), by the independent checker
//! tests/python/check_vtk.py.

use aqua_mesh::vtk::VtuSeries;
use aqua_mesh::{CageParams, CageType, PvdWriter, VtkArray, VtkArrays, write_vtu};
use nalgebra::Vector3;
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

fn extra(m: &aqua_mesh::Mesh, t: f64) -> VtkArrays {
    VtkArrays {
        point: vec![VtkArray::vectors(
            "displacement",
            &vec![Vector3::new(t, 0.0, -0.5 * t); m.nodes.len()],
        )],
        cell: vec![VtkArray::scalar("tension", vec![100.0 * t; m.cell_count()])],
    }
}

#[test]
fn vtu_reads_back_with_vtkio() {
    use vtkio::model::{CellType, DataSet, VertexNumbers};
    let m = cct();
    let dir = tmpdir("vtkio");
    let f = dir.join("cct.vtu");
    write_vtu(&f, &m, None, &extra(&m, 1.0)).unwrap();
    // Atomic write leaves no temporary file behind.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
    let vtk = vtkio::Vtk::import(&f).unwrap();
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    let piece = pieces[0].load_piece_data(None).unwrap();
    assert_eq!(piece.num_points(), 913);
    let types = &piece.cells.types;
    // CCT defaults: 1056 net + 48 ring + 48 links + 336 ropes + 48 ties + 48 bottom ring lines,
    // 480 quads, 48 triangles (docs/theory/cages.md#worked-ssm-case).
    let nl = 1056 + 96 + 336 + 48 + 48;
    assert_eq!(types.iter().filter(|&&t| t == CellType::Line).count(), nl);
    assert_eq!(types.iter().filter(|&&t| t == CellType::Quad).count(), 480);
    assert_eq!(
        types.iter().filter(|&&t| t == CellType::Triangle).count(),
        48
    );
    let VertexNumbers::XML { connectivity, .. } = &piece.cells.cell_verts else {
        panic!("expected XML connectivity")
    };
    assert_eq!(connectivity.len(), 2 * nl + 4 * 480 + 3 * 48);
    let names: Vec<String> = piece
        .data
        .cell
        .iter()
        .map(|a| a.name().to_string())
        .collect();
    for n in [
        "group_id",
        "role_id",
        "diameter",
        "elastic_diameter",
        "hydro_diameter",
        "tension",
    ] {
        assert!(names.contains(&n.to_string()), "{n} missing in {names:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_arrays_are_rejected() {
    let m = cct();
    let dir = tmpdir("badarr");
    let f = dir.join("x.vtu");
    let mut e = extra(&m, 1.0);
    e.cell[0].values[3] = f64::NAN;
    let err = write_vtu(&f, &m, None, &e).unwrap_err().to_string();
    assert!(
        err.contains("tension") && err.contains("not finite"),
        "{err}"
    );
    let mut e = extra(&m, 1.0);
    e.point[0].values.pop();
    assert!(
        write_vtu(&f, &m, None, &e)
            .unwrap_err()
            .to_string()
            .contains("displacement")
    );
    let e = VtkArrays {
        point: vec![VtkArray::scalar("fixed", vec![0.0; m.nodes.len()])],
        cell: vec![],
    };
    assert!(
        write_vtu(&f, &m, None, &e)
            .unwrap_err()
            .to_string()
            .contains("already used")
    );
    assert!(!f.exists());
    let mut pvd = PvdWriter::new(dir.join("s.pvd"));
    assert!(pvd.add(0.0, &dir.join("missing.vtu")).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pvd_lists_exactly_the_written_steps() {
    let m = cct();
    let dir = tmpdir("pvd");
    let mut s = VtuSeries::new(&dir, "run").unwrap();
    let times = [0.0, 0.5, 1.25];
    for &t in &times {
        let pos: Vec<_> = m
            .nodes
            .iter()
            .map(|p| p + Vector3::new(t, 0.0, 0.0))
            .collect();
        s.write_step(t, &m, Some(&pos), &extra(&m, t)).unwrap();
        // After every step the collection lists exactly the files written so far.
        let text = std::fs::read_to_string(dir.join("run.pvd")).unwrap();
        assert_eq!(text.matches("<DataSet").count(), s.pvd().entries().len());
    }
    assert!(s.write_step(1.0, &m, None, &VtkArrays::default()).is_err());
    let entries = s.pvd().entries().to_vec();
    assert_eq!(entries.len(), 3);
    assert_eq!(entries[2].1, "run_000002.vtu");
    // Removing a file and retaining existing entries rewrites the list.
    let mut pvd = s.pvd().clone();
    std::fs::remove_file(dir.join("run_000002.vtu")).unwrap();
    pvd.retain_existing().unwrap();
    assert_eq!(pvd.entries().len(), 2);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Writes a cage, a gmsh import and a 3-step series, then runs the python checker.
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
    let point_arrays = "object_id:1,copy_id:1,fixed:1,point_weight:1,displacement:3";
    let cell_arrays = "group_id:1,role_id:1,object_id:1,copy_id:1,diameter:1,\
                       elastic_diameter:1,hydro_diameter:1,solidity:1,tension:1";

    // SSM worked case (docs/theory/cages.md#worked-ssm-case): 1057 nodes; 1344 + 336 + 144 + 96
    // lines; 624 quads, 48 triangles.
    let mut p = CageParams::new(CageType::Ssm);
    p.circumference = Some(120.0);
    let m = p.build().unwrap();
    let f = dir.join("ssm.vtu");
    write_vtu(&f, &m, None, &extra(&m, 1.0)).unwrap();
    let (ok, msg) = run(&[
        f.to_str().unwrap(),
        "--points",
        "1057",
        "--cells",
        "line=1920,quad=624,triangle=48",
        "--point-arrays",
        point_arrays,
        "--cell-arrays",
        cell_arrays,
    ]);
    assert!(ok, "{msg}");

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
    let f = dir.join("gmsh.vtu");
    write_vtu(&f, &g, None, &VtkArrays::default()).unwrap();
    let (ok, msg) = run(&[
        f.to_str().unwrap(),
        "--points",
        "31",
        "--cells",
        "line=54,quad=12,triangle=12",
    ]);
    assert!(ok, "{msg}");

    // Time series with real time values, expectations through a JSON file.
    let mut s = VtuSeries::new(dir.join("series"), "cct").unwrap();
    let m = cct();
    for t in [0.0, 0.1, 0.35] {
        s.write_step(t, &m, None, &extra(&m, t)).unwrap();
    }
    let expect = serde_json::json!({
        "points": 913,
        "cells": {"line": 1056 + 96 + 336 + 48 + 48, "quad": 480, "triangle": 48},
        "point_arrays": {"displacement": 3, "fixed": 1},
        "cell_arrays": {"tension": 1, "role_id": 1},
        "times": [0.0, 0.1, 0.35],
    });
    let ef = dir.join("expect.json");
    std::fs::write(&ef, expect.to_string()).unwrap();
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
    use aqua_mesh::{BlockArray, BlockKind, MultiblockSeries, StepArrays};
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
    use aqua_mesh::MultiblockSeries;
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
