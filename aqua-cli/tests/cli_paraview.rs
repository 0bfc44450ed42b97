//! The ParaView outputs of `aqua run`, through the binary: the series is written every
//! `paraview_interval`, the multiblock outputs are read back by an independent VTK reader (the
//! `vtk` Python package, when `AQUA_VTK_PYTHON` names an interpreter that has it) and the ParaView
//! script runs in real ParaView (when `pvbatch` is installed).

mod run_helpers;

use run_helpers::*;
use std::path::PathBuf;
use std::process::Command;

/// `analysis.dynamic.paraview_interval` thins the ParaView series and nothing else: 3 s of the
/// chain with rows every 0.1 s and ParaView steps every 0.5 s gives 3/0.1 + 1 = 31
/// `summary.csv` rows, 3/0.5 + 1 = 7 `.vtm` files (each with its `.vtu` blocks) at t = 0, 0.5,
/// … 3, the same times as every fifth row; an interval that is not a whole multiple of the
/// output interval is refused naming the file, key, value and what is valid.
#[test]
fn paraview_series_is_written_every_paraview_interval() {
    let dir = scratch("paraview-interval");
    let scene = chain_scene(&dir, 3.0, "");
    let out = dir.join("out");
    let (code, _, err) = aqua(&[
        "run",
        scene.to_str().unwrap(),
        "--quiet",
        "--set",
        "analysis.dynamic.paraview_interval=0.5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let times: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(times.len(), 31, "{times:?}");
    let entries = assert_consistent(&out.join("mooring-chain.pvd"));
    assert_eq!(entries.len(), 7, "{entries:?}");
    for (k, (t, _)) in entries.iter().enumerate() {
        assert!((t - 0.5 * k as f64).abs() < 1e-9, "step {k} at t = {t}");
        assert!(
            (t - times[5 * k]).abs() < 1e-9,
            "step {k}: row {}",
            times[5 * k]
        );
    }
    // One block directory per ParaView step, each holding .vtu files.
    let step_dirs: Vec<PathBuf> = std::fs::read_dir(&out)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.is_dir() && !p.ends_with("mooring-chain_reference"))
        .collect();
    assert_eq!(step_dirs.len(), 7, "{step_dirs:?}");
    for d in &step_dirs {
        let vtu = std::fs::read_dir(d)
            .unwrap()
            .flatten()
            .filter(|e| e.path().extension().is_some_and(|x| x == "vtu"))
            .count();
        assert!(vtu > 0, "{} has no .vtu", d.display());
    }
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(run["output_steps"], 31);
    assert_eq!(run["paraview_steps"], 7);
    for bad in ["0.25", "0.05", "-1"] {
        let (code, _, err) = aqua(&[
            "check",
            scene.to_str().unwrap(),
            "--set",
            &format!("analysis.dynamic.paraview_interval={bad}"),
        ]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(
            err.contains("chain.toml")
                && err.contains(&format!("analysis.dynamic.paraview_interval = {bad}"))
                && err.contains("whole multiple")
                && err.contains("0.1 s"),
            "{err}"
        );
    }
}

#[test]
fn outputs_are_read_back_by_an_independent_vtk_reader() {
    let dir = scratch("vtk");
    let scene = chain_scene(&dir, 1.0, "");
    let out = dir.join("out");
    let (code, _, err) = aqua(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let entries = assert_consistent(&out.join("mooring-chain.pvd"));
    // static state at t = 0, then every 0.1 s to 1 s
    assert_eq!(entries.len(), 11);
    for (k, (t, _)) in entries.iter().enumerate() {
        assert!((t - 0.1 * k as f64).abs() < 1e-9, "time {t}");
    }
    let Some(python) = vtk_python() else { return };
    let times: Vec<f64> = entries.iter().map(|(t, _)| *t).collect();
    let expect = serde_json::json!({
        "blocks": ["chain/lines", "chain/points"],
        "points": 81,
        "cells": {"line": 80},
        "point_arrays": ["displacement", "velocity", "hydro_force", "reaction", "point_mass",
                         "supported", "node_id", "object_id", "fixed", "point_weight"],
        "line_arrays": ["tension", "slack", "axial_force", "strain", "wake_factor",
                        "group_id", "role_id", "element_id", "diameter"],
        "times": times,
        "run_json": out.join("run.json"),
        // The anchor is fixed by the line builder, the fairlead prescribed.
        "point_sums": {"supported": 2, "fixed": 1},
    });
    let (ok, msg) = check_series(&python, &out.join("mooring-chain.pvd"), &expect, None);
    assert!(ok, "VTK read-back failed: {msg}");
    // meshio, the usual Python reader, reads every block `.vtu` of every step (it stops at a
    // string array in the field data).
    let meshio_expect = serde_json::json!({
        "points": 81,
        "cells": {"line": 80},
        "point_arrays": {"displacement": 3, "velocity": 3, "node_id": 1},
        "line_arrays": {"tension": 1, "slack": 1, "axial_force": 1},
        "times": times,
    });
    let ef = out.join("meshio.expect.json");
    std::fs::write(&ef, meshio_expect.to_string()).unwrap();
    let res = Command::new(&python)
        .arg(root().join("tests/python/check_vtk.py"))
        .arg(out.join("mooring-chain.pvd"))
        .arg("--expect")
        .arg(&ef)
        .output()
        .expect("cannot run AQUA_VTK_PYTHON");
    let msg = format!(
        "{}{}",
        String::from_utf8_lossy(&res.stdout),
        String::from_utf8_lossy(&res.stderr)
    );
    assert!(res.status.success(), "meshio read-back failed: {msg}");
    assert!(msg.contains("2 blocks read by meshio"), "{msg}");
}

#[test]
fn multiblock_series_is_named_per_object_and_sums_to_the_mesh_geometry() {
    let dir = scratch("multiblock");
    let scene = moored_cage_scene(&dir);
    let out = dir.join("out");
    run_quiet(&scene, &out);
    let pvd = out.join("moored-cage.pvd");
    let entries = assert_consistent(&pvd);
    assert_eq!(entries.len(), 3, "t = 0, 0.5, 1");
    assert!(out.join("moored-cage_reference.vtm").is_file());
    assert!(out.join("open_in_paraview.py").is_file());
    // run.json maps ids to names.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    let names = &json["names"];
    assert_eq!(
        names["object_names"],
        serde_json::json!(["cage", "m_east", "m_north", "m_west", "m_south"])
    );
    assert_eq!(names["block_names"], serde_json::json!(MOORED_BLOCKS));
    let groups: Vec<&str> = names["group_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(groups.contains(&"cage/net_twines") && groups.contains(&"m_east/moorings"));
    assert_eq!(names["role_names"][0], "net_twines");
    // The same model written by `aqua mesh --scene` is the run's reference geometry, block
    // file by block file, and gives the counts the blocks of every step must add up to.
    let single = dir.join("mesh.vtm");
    let (code, _, err) = aqua(&[
        "mesh",
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        single.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let reference = out.join("moored-cage_reference");
    let mut files: Vec<_> = std::fs::read_dir(&reference)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    files.sort();
    assert_eq!(files.len(), MOORED_BLOCKS.len());
    for f in &files {
        assert_eq!(
            std::fs::read(dir.join("mesh").join(f)).ok(),
            Some(std::fs::read(reference.join(f)).unwrap()),
            "{f:?}: `aqua mesh --scene` differs from the run's reference step"
        );
    }
    let Some(python) = vtk_python() else { return };
    let expect = serde_json::json!({
        "blocks": MOORED_BLOCKS,
        "point_arrays": ["displacement", "velocity", "hydro_force", "reaction", "point_mass",
                         "node_id", "object_id", "copy_id", "fixed", "point_weight"],
        "line_arrays": ["tension", "slack", "axial_force", "strain", "wake_factor",
                        "group_id", "role_id", "object_id", "element_id", "diameter",
                        "elastic_diameter", "hydro_diameter"],
        "panel_arrays": ["wake_factor", "group_id", "role_id", "object_id", "panel_id",
                         "solidity", "twine_diameter"],
        "times": [0.0, 0.5, 1.0],
        "run_json": out.join("run.json"),
    });
    let (ok, msg) = check_series(&python, &pvd, &expect, Some(&single));
    assert!(ok, "VTK read-back failed: {msg}");
    assert!(
        msg.contains(&format!("{} points", moored_points())),
        "{msg}"
    );
    // The checker really checks: a wrong block list and a wrong count fail.
    let mut wrong = expect.clone();
    wrong["blocks"] = serde_json::json!(["cage/net"]);
    let (ok, msg) = check_series(&python, &pvd, &wrong, Some(&single));
    assert!(!ok && msg.contains("blocks"), "{msg}");
    let mut wrong = expect.clone();
    wrong["points"] = serde_json::json!(272);
    let (ok, msg) = check_series(&python, &pvd, &wrong, Some(&single));
    assert!(!ok && msg.contains("--single geometry"), "{msg}");
}

#[test]
fn paraview_script_opens_the_series_in_real_paraview() {
    let Some(pv) = pvbatch() else { return };
    let dir = scratch("paraview");
    let scene = moored_cage_scene(&dir);
    let out = dir.join("out");
    run_quiet(&scene, &out);
    let report = dir.join("report.json");
    let shot = dir.join("view.png");
    let picture = pvbatch_with_display(&pv);
    let with_picture = picture.is_some();
    let mut cmd = picture.unwrap_or_else(|| Command::new(&pv));
    cmd.arg(out.join("open_in_paraview.py"))
        .args(["--warp", "1", "--last", "--report"])
        .arg(&report);
    if with_picture {
        cmd.arg("--screenshot").arg(&shot);
    }
    run_ok(cmd);
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(r["blocks"], serde_json::json!(MOORED_BLOCKS));
    assert_eq!(r["times"], serde_json::json!([0.0, 0.5, 1.0]));
    assert_eq!(r["points"].as_u64(), Some(moored_points()), "{r}");
    let range = r["tension_range"].as_array().unwrap();
    assert_eq!(range[0].as_f64(), Some(0.0), "no negative tension: {r}");
    assert!(range[1].as_f64().unwrap() > 1e3, "{r}");
    let lines: Vec<&str> = r["line_arrays"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    for a in ["tension", "slack", "axial_force"] {
        assert!(lines.contains(&a), "{a} missing: {lines:?}");
    }
    // --warp 1 is the computed shape at the first and the last step.
    for w in r["warp"].as_array().unwrap() {
        let err = w["max_error_vs_series"].as_f64().unwrap();
        assert!(err <= 1e-9, "warp x1 is off the series by {err} m: {w}");
    }
    // The view is 1600 × 900 and the screenshot has that size, the colour bar inside it.
    assert_eq!(r["view_size"], serde_json::json!([1600, 900]), "{r}");
    let bar = &r["scalar_bar"];
    let (x, y) = (
        bar["position"][0].as_f64().unwrap(),
        bar["position"][1].as_f64().unwrap(),
    );
    let len = bar["length"].as_f64().unwrap();
    assert!(
        (0.0..0.95).contains(&x) && y >= 0.0 && y + len <= 1.0,
        "colour bar outside the view: {bar}"
    );
    if with_picture {
        let png = std::fs::read(&shot).unwrap();
        assert_eq!(png_size(&png), (1600, 900));
        assert!(png.len() > 10_000, "{} bytes", png.len());
        // Another size on request.
        let small = dir.join("small.png");
        let mut cmd = pvbatch_with_display(&pv).unwrap();
        cmd.arg(out.join("open_in_paraview.py"))
            .args(["--size", "800x600", "--screenshot"])
            .arg(&small);
        run_ok(cmd);
        assert_eq!(png_size(&std::fs::read(&small).unwrap()), (800, 600));
    }
    // As the GUI runs it (no __file__, empty argv[0], another working directory): the script
    // finds the run through the directory `aqua run` recorded in it.
    let wrapper = dir.join("as_gui.py");
    let report2 = dir.join("report_gui.json");
    std::fs::write(
        &wrapper,
        format!(
            "import sys\nsys.argv = ['', '--report', {:?}]\n\
             exec(compile(open({:?}).read(), 'open_in_paraview.py', 'exec'), \
             {{'__name__': '__main__'}})\n",
            report2.to_str().unwrap(),
            out.join("open_in_paraview.py").to_str().unwrap()
        ),
    )
    .unwrap();
    let res = Command::new(&pv)
        .arg(&wrapper)
        .current_dir(std::env::temp_dir())
        .output()
        .unwrap();
    assert!(
        res.status.success(),
        "{}",
        String::from_utf8_lossy(&res.stderr)
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report2).unwrap()).unwrap();
    assert_eq!(r["blocks"], serde_json::json!(MOORED_BLOCKS));
}

#[test]
fn paraview_warp_follows_the_time_step() {
    let Some(pv) = pvbatch() else { return };
    let dir = scratch("paraview-warp");
    let scene = moored_cage_in_waves(&dir);
    let out = dir.join("out");
    run_quiet(&scene, &out);
    let warp = |scale: &str| {
        let report = dir.join(format!("warp{scale}.json"));
        let mut cmd = Command::new(&pv);
        cmd.arg(out.join("open_in_paraview.py"))
            .args(["--warp", scale, "--last", "--report"])
            .arg(&report);
        run_ok(cmd);
        let r = read_json(&report);
        assert_eq!(r["times"], serde_json::json!([0.0, 1.0, 2.0]), "{r}");
        let w = r["warp"].as_array().unwrap().clone();
        assert_eq!(w.len(), 2, "{r}");
        assert_eq!(
            (w[0]["t"].as_f64(), w[1]["t"].as_f64()),
            (Some(0.0), Some(2.0))
        );
        w
    };
    // S = 1: the warped points are the series' points, at t = 0 and at t_end, and they move
    // between the two as the series does.
    let w1 = warp("1");
    for w in &w1 {
        let err = w["max_error_vs_series"].as_f64().unwrap();
        assert!(err <= 1e-9, "warp x1 off the series by {err} m: {w}");
    }
    let moved = w1[1]["series_moved_since_first"].as_f64().unwrap();
    assert!(
        moved > 0.05,
        "the series barely moves ({moved} m): no test of time"
    );
    let warp_moved = w1[1]["warp_moved_since_first"].as_f64().unwrap();
    assert!(
        (warp_moved - moved).abs() <= 1e-9,
        "{warp_moved} vs {moved}"
    );
    // S = 4: X + 4 d at both times, so the warped geometry moves 4 times as far as the
    // series (X does not move).
    let w4 = warp("4");
    for w in &w4 {
        let err = w["max_error_vs_reference_plus_scaled_displacement"]
            .as_f64()
            .unwrap();
        assert!(err <= 1e-9, "warp x4 off X + 4 d by {err} m: {w}");
    }
    let warp_moved = w4[1]["warp_moved_since_first"].as_f64().unwrap();
    assert!(
        (warp_moved - 4.0 * moved).abs() <= 1e-9 * (1.0 + moved),
        "warp x4 moved {warp_moved} m, the series {moved} m"
    );
}

#[test]
fn guide_block_selectors_work_for_a_farm_in_real_paraview() {
    // The selectors of the ParaView guide, literally.
    let guide = std::fs::read_to_string(root().join("docs/guide/paraview.md")).unwrap();
    let selectors: Vec<&str> = guide
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|s| s.starts_with("/Root/") || s.starts_with("//"))
        .collect();
    for want in [
        "/Root/farm_cage_r1c1",
        "/Root/farm_cage_r1c1/lines",
        "//panels",
    ] {
        assert!(
            selectors.contains(&want),
            "docs/guide/paraview.md lacks {want}: {selectors:?}"
        );
    }
    let dir = scratch("paraview-farm");
    let scene = small_farm(&dir);
    let out = dir.join("out");
    run_quiet(&scene, &out);
    let vtm = out.join("farm_000000.vtm");
    let cells = vtm_cells(&vtm);
    // run.json maps the blocks to the objects.
    let names = &read_json(&out.join("run.json"))["names"];
    let blocks: Vec<String> = cells.iter().map(|(b, _)| b.clone()).collect();
    assert_eq!(names["block_names"], serde_json::json!(blocks));
    let k = blocks
        .iter()
        .position(|b| b == "farm_cage_r1c1/lines")
        .unwrap();
    assert_eq!(names["block_objects"][k], "farm/cage_r1c1");
    let Some(pv) = pvbatch() else { return };
    let result = dir.join("selected.json");
    let farm_selectors: Vec<&str> = selectors
        .iter()
        .copied()
        .filter(|s| s.starts_with("//") || s.starts_with("/Root/farm"))
        .collect();
    let mut cmd = Command::new(&pv);
    cmd.arg(root().join("tests/python/paraview_select.py"))
        .arg(&vtm)
        .arg(&result)
        .args(&farm_selectors);
    run_ok(cmd);
    let r = read_json(&result);
    for sel in farm_selectors {
        // What the selector names: a block (all its datasets), a dataset, or a dataset kind
        // in every block.
        let want: u64 = if let Some(kind) = sel.strip_prefix("//") {
            cells
                .iter()
                .filter(|(b, _)| b.ends_with(&format!("/{kind}")))
                .map(|c| c.1)
                .sum()
        } else {
            let path = sel.strip_prefix("/Root/").unwrap();
            cells
                .iter()
                .filter(|(b, _)| b == path || b.starts_with(&format!("{path}/")))
                .map(|c| c.1)
                .sum()
        };
        assert!(want > 0, "{sel} names nothing in the farm's files");
        assert_eq!(r["cells"][sel].as_u64(), Some(want), "{sel}: {r}");
    }
}
