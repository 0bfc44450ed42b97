//! `aqua check` and `aqua run` end to end through the binary: every bundled example checks,
//! a mistake in each scene section gives exit code 2 with the file, line and key, a failed or
//! interrupted run leaves a consistent `.pvd`, the multiblock outputs are read back by an
//! independent VTK reader (the `vtk` Python package, when `AQUA_VTK_PYTHON` names an
//! interpreter that has it) and the ParaView script runs in real ParaView (when `pvbatch` is
//! installed).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("aqua-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn aqua(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The `.vtm` files a `.pvd` lists, with their times.
fn pvd_entries(pvd: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(pvd).unwrap();
    text.lines()
        .filter(|l| l.contains("<DataSet"))
        .map(|l| {
            let attr = |name: &str| {
                let start = l.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
                let end = start + l[start..].find('"').unwrap();
                l[start..end].to_string()
            };
            (attr("timestep").parse().unwrap(), attr("file"))
        })
        .collect()
}

/// Asserts the `.pvd` lists exactly the step `.vtm` files in its directory (not the undeformed
/// `_reference.vtm`), at increasing times, and that every block file each one names exists.
fn assert_consistent(pvd: &Path) -> Vec<(f64, String)> {
    let entries = pvd_entries(pvd);
    let dir = pvd.parent().unwrap();
    let mut on_disk: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".vtm") && !n.ends_with("_reference.vtm"))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = entries
        .iter()
        .map(|(_, f)| {
            Path::new(f)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    listed.sort();
    assert_eq!(listed, on_disk, "pvd and directory disagree");
    for f in &listed {
        let vtm = std::fs::read_to_string(dir.join(f)).unwrap();
        let blocks: Vec<&str> = vtm
            .split("file=\"")
            .skip(1)
            .map(|r| &r[..r.find('"').unwrap()])
            .collect();
        assert!(!blocks.is_empty(), "{f} names no block");
        for b in blocks {
            assert!(dir.join(b).is_file(), "{f} names {b}, which is not on disk");
        }
    }
    assert!(
        entries.windows(2).all(|w| w[1].0 > w[0].0),
        "times must increase"
    );
    entries
}

#[test]
fn every_example_checks() {
    for ex in [
        "reference-cage.toml",
        "moored-cage.toml",
        "mooring-chain.toml",
        "net-panel.toml",
    ] {
        let p = root().join("examples").join(ex);
        let (code, out, err) = aqua(&["check", p.to_str().unwrap()]);
        assert_eq!(code, 0, "{ex}: {err}");
        assert!(
            out.contains("valid") && out.contains("physics:") && out.contains("cost:"),
            "{out}"
        );
    }
    let p = root().join("examples/reference-cage.toml");
    let (code, out, _) = aqua(&["check", p.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["mesh"]["nodes"].as_u64(), Some(1057));
    let (code, out, err) = aqua(&["mesh", "--scene", p.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0, "{err}");
    let m: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        m["nodes"].as_u64(),
        Some(1057),
        "the worked SSM case of docs/theory/cages.md#worked-ssm-case"
    );
    let waves = v["physics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "waves")
        .unwrap();
    assert_eq!(
        waves["active"], false,
        "a current-only scene computes no waves"
    );
}

#[test]
fn a_mistake_in_each_section_is_reported_with_exit_code_2() {
    let dir = scratch("bad");
    let base = "[sea]\ndepth = 50\n\n[[line]]\nanchor = [0, 0, -50]\nfairlead = [40, 0, -5]\nlength = 70\nsegments = 10\ndiameter = 0.1\nmass_per_length = 50\nea = 1e8\n";
    let cases: &[(&str, &str, &[&str])] = &[
        ("sea", "[sea]\ndepth = -5\n", &["sea.depth", "-5"]),
        (
            "sea-key",
            "[sea]\ndepth = 50\ndepht = 3\n",
            &["line 3", "depht"],
        ),
        (
            "cage",
            "[[cage]]\ntype = \"SSM\"\ncircumference = -120\n",
            &["line 1", "[[cage]] #1", "circumference"],
        ),
        ("cage-type", "[[cage]]\ntype = \"XYZ\"\n", &["XYZ", "SSM"]),
        (
            "panel",
            "[[panel]]\nwidth = 1\nheight = 1\nnet.screen_model = \"S9\"\n",
            &["[[panel]] #1", "S9", "bi2014"],
        ),
        (
            "mesh",
            "[[mesh]]\nfile = \"missing.msh\"\n",
            &["[[mesh]] #1", "missing.msh"],
        ),
        (
            "line",
            &format!("{base}morison = \"M7\"\n"),
            &["[[line]] #1", "M7"],
        ),
        (
            "group",
            &format!("{base}\n[[group]]\nname = \"nothing\"\nmorison = \"M1\"\n"),
            &["[[group]]", "nothing"],
        ),
        (
            "point",
            &format!("{base}\n[[point]]\nnodes = \"nowhere\"\nmass = 10\n"),
            &["[[point]] #1", "nowhere"],
        ),
        (
            "fix",
            &format!("{base}\n[[fix]]\nnodes = \"line0/fairlead\"\ndofs = [\"w\"]\n"),
            &["[[fix]] #1", "\"w\""],
        ),
        (
            "prescribed",
            &format!("{base}\n[[prescribed]]\nnodes = \"line0/fairlead\"\nmotion = \"sine\"\n"),
            &["[[prescribed]] #1", "amplitude"],
        ),
        (
            "analysis",
            &format!("{base}\n[analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\nalpha = 0.5\n"),
            &["alpha", "0.5", "1/3"],
        ),
        (
            "theta-range",
            &format!(
                "{base}\n[analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\nscheme = \"midpoint\"\ntheta = 0.4\n"
            ),
            &["analysis.dynamic.theta", "0.4", "0.5 <= theta <= 1"],
        ),
        (
            "theta-hht",
            &format!("{base}\n[analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\ntheta = 0.75\n"),
            &["analysis.dynamic.theta", "0.75", "midpoint"],
        ),
        (
            "theta-rk4",
            &format!(
                "{base}\n[analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\nscheme = \"rk4\"\ntheta = 1\n"
            ),
            &[
                "analysis.dynamic.theta",
                "1",
                "midpoint",
                "explicit scheme has no theta",
            ],
        ),
        (
            "analysis-kind",
            "[analysis]\nkind = \"transient\"\n",
            &["line 2", "transient", "static+dynamic"],
        ),
        ("section", "[[cages]]\ntype = \"SSM\"\n", &["cages", "cage"]),
        ("empty", "[sea]\ndepth = 50\n", &["no structure"]),
    ];
    for (name, text, needles) in cases {
        let p = dir.join(format!("{name}.toml"));
        std::fs::write(&p, text).unwrap();
        for cmd in ["check", "run"] {
            let out = dir.join(format!("{name}-out"));
            let (code, _, err) = aqua(
                &[cmd, p.to_str().unwrap(), "--out", out.to_str().unwrap()]
                    [..if cmd == "check" { 2 } else { 4 }],
            );
            assert_eq!(code, 2, "{cmd} {name}: exit code, stderr: {err}");
            assert!(
                err.contains(&format!("{name}.toml")),
                "{cmd} {name}: file not named: {err}"
            );
            for n in *needles {
                assert!(err.contains(n), "{cmd} {name}: `{n}` missing from: {err}");
            }
            assert!(!err.contains("panicked"), "{err}");
        }
    }
}

fn chain_scene(dir: &Path, t_end: f64, extra: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/mooring-chain.toml"))
        .unwrap()
        .replace("t_end = 60.0", &format!("t_end = {t_end}"))
        .replace("output_interval = 0.5", "output_interval = 0.1")
        + extra;
    let p = dir.join("chain.toml");
    std::fs::write(&p, text).unwrap();
    p
}

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

/// `aqua run SCENE --out OUT --quiet` in the background, stderr captured.
fn spawn_quiet_run(scene: &Path, out: &Path) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args([
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Sends `signal` (`INT` as Ctrl-C in a terminal, `TERM` as `kill` and Slurm's time limit).
fn send_signal(child: &std::process::Child, signal: &str) {
    let status = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

#[test]
fn interrupted_run_leaves_a_consistent_pvd() {
    interrupt_dynamics("INT", 130);
}

#[test]
fn sigterm_in_dynamics_is_an_interruption_with_every_file_written() {
    interrupt_dynamics("TERM", 143);
}

/// A chain run stopped by `signal` after five output steps: exit 128 + the signal, run.json
/// `interrupted`, the `.pvd` consistent and one summary row per step it lists.
fn interrupt_dynamics(signal: &str, code: i32) {
    let dir = scratch(&format!("interrupt-{signal}"));
    let scene = chain_scene(&dir, 100_000.0, "");
    let out = dir.join("out");
    let child = spawn_quiet_run(&scene, &out);
    let pvd = out.join("mooring-chain.pvd");
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(120) {
        if pvd.exists() && pvd_entries(&pvd).len() >= 5 {
            break;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    send_signal(&child, signal);
    let result = child.wait_with_output().unwrap();
    assert_eq!(
        result.status.code(),
        Some(code),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let entries = assert_consistent(&pvd);
    assert!(entries.len() >= 5);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "interrupted");
    assert_eq!(json["output_steps"].as_u64(), Some(entries.len() as u64));
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(
        csv.lines().count(),
        entries.len() + 1,
        "one summary row per output step"
    );
    // The extremes reached before the signal: in extremes.csv and in run.json, the same, and
    // bounding those of the output steps written.
    let extremes = assert_extremes_agree(&out);
    assert!(extremes.len() >= 4, "{extremes:?}");
    for (c, max, min) in &extremes {
        let Some(k) = csv.lines().next().unwrap().split(',').position(|h| h == c) else {
            continue; // F_net, R: magnitudes, not summary columns
        };
        // The dynamic part: after the static row.
        for line in csv.lines().skip(2) {
            let v: f64 = line.split(',').nth(k).unwrap().parse().unwrap();
            assert!(*min <= v && v <= *max, "{c}: {v} outside [{min}, {max}]");
        }
    }
}

/// Asserts `DIR/extremes.csv` and `DIR/run.json`'s `extremes` hold the same columns and
/// numbers (to an ulp: serde_json's parser may round the last digit); returns (column, max,
/// min) of each.
fn assert_extremes_agree(dir: &Path) -> Vec<(String, f64, f64)> {
    let text = std::fs::read_to_string(dir.join("extremes.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("column,max,t_max,min,t_min"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap();
    let obj = json["extremes"].as_object().expect("run.json has extremes");
    let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs());
    let mut out = Vec::new();
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let e = &obj[f[0]];
        for (k, key) in ["max", "t_max", "min", "t_min"].iter().enumerate() {
            let v: f64 = f[k + 1].parse().unwrap();
            assert!(
                close(v, e[key].as_f64().unwrap()),
                "{} {key}: {v} vs {e}",
                f[0]
            );
        }
        out.push((
            f[0].to_string(),
            f[1].parse().unwrap(),
            f[3].parse().unwrap(),
        ));
    }
    assert_eq!(out.len(), obj.len());
    out
}

#[test]
fn failed_run_keeps_the_steps_written_and_says_why() {
    let dir = scratch("fail");
    // The fairlead is dragged 300 m away in 2 s: the chain would have to stretch far beyond
    // max_strain, so every step is rejected down to dt_min and the run stops.
    let scene = chain_scene(&dir, 20.0, "");
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace(
            "motion = \"sine\"\namplitude = [1.5, 0.0, 0.0]\nperiod = 10.0\nramp_time = 10.0",
            "motion = \"ramp\"\noffset = [300.0, 0.0, 0.0]\nramp_time = 2.0",
        )
        .replace(
            "[analysis.dynamic]",
            "[analysis.dynamic]\nmax_strain = 0.05\ndt_min = 0.01",
        );
    assert!(text.contains("offset = [300.0"));
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let (code, _, err) = aqua(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    if code == 2 {
        panic!("scene rejected instead of failing in the solver: {err}");
    }
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("kept in"), "{err}");
    let entries = assert_consistent(&out.join("mooring-chain.pvd"));
    assert!(!entries.is_empty(), "the static state at least is written");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "failed");
    assert!(json["error"].as_str().unwrap().len() > 10);
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

/// The Python interpreter with the `vtk` package (tests/python/requirements.txt), or a printed
/// note and `None`.
fn vtk_python() -> Option<String> {
    match std::env::var("AQUA_VTK_PYTHON") {
        Ok(p) => Some(p),
        Err(_) => {
            eprintln!(
                "note: AQUA_VTK_PYTHON is not set; the independent VTK read-back runs in CI \
                 (.ci/run installs tests/python/requirements.txt)"
            );
            None
        }
    }
}

/// Runs tests/python/check_series.py on a `.pvd` with expectations; (passed, output).
fn check_series(
    python: &str,
    pvd: &Path,
    expect: &serde_json::Value,
    single: Option<&Path>,
) -> (bool, String) {
    let ef = pvd.with_extension("expect.json");
    std::fs::write(&ef, expect.to_string()).unwrap();
    let mut cmd = Command::new(python);
    cmd.arg(root().join("tests/python/check_series.py"))
        .arg(pvd)
        .arg("--expect")
        .arg(&ef);
    if let Some(s) = single {
        cmd.arg("--single").arg(s);
    }
    let out = cmd.output().expect("cannot run AQUA_VTK_PYTHON");
    (
        out.status.success(),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    )
}

/// A small moored cage (CSM cage + four named chains) in current only, 1 s of dynamics.
fn moored_cage_scene(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/moored-cage.toml")).unwrap();
    let a = text.find("[sea.waves]").unwrap();
    let b = text.find("[[cage]]").unwrap();
    let text = format!("{}{}", &text[..a], &text[b..])
        .replace("element_length = 4.0", "element_length = 5.0")
        .replace("top_ring[6]", "top_ring[4]")
        .replace("top_ring[12]", "top_ring[8]")
        .replace("top_ring[18]", "top_ring[12]")
        .replace("t_end = 60.0", "t_end = 1.0")
        .replace("output_interval = 1.0", "output_interval = 0.5");
    assert!(text.contains("t_end = 1.0") && text.contains("top_ring[12]"));
    let p = dir.join("moored.toml");
    std::fs::write(&p, text).unwrap();
    p
}

fn run_quiet(scene: &Path, out: &Path) {
    let (code, _, err) = aqua(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
}

/// Nodes of examples/moored-cage.toml: the cage's 153 and, per line, one per segment (its
/// fairlead is a collar node).
fn moored_points() -> u64 {
    let scene = std::fs::read_to_string(root().join("examples/moored-cage.toml")).unwrap();
    let line_nodes: u64 = scene
        .lines()
        .filter_map(|l| l.trim().strip_prefix("segments = "))
        .map(|n| n.trim().parse::<u64>().unwrap())
        .sum();
    153 + line_nodes
}

const MOORED_BLOCKS: [&str; 11] = [
    "cage/lines",
    "cage/panels",
    "cage/points",
    "m_east/lines",
    "m_east/points",
    "m_north/lines",
    "m_north/points",
    "m_west/lines",
    "m_west/points",
    "m_south/lines",
    "m_south/points",
];

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

/// `pvbatch` (or `AQUA_PVBATCH`), or a printed note and `None`.
fn pvbatch() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("AQUA_PVBATCH") {
        return Some(PathBuf::from(p));
    }
    for name in ["pvbatch", "pvpython"] {
        if let Some(p) = std::env::var_os("PATH").and_then(|paths| {
            std::env::split_paths(&paths)
                .map(|d| d.join(name))
                .find(|p| p.is_file())
        }) {
            return Some(p);
        }
    }
    eprintln!(
        "note: skipped: ParaView is not installed (no pvbatch or pvpython on PATH, AQUA_PVBATCH \
         unset); the script open_in_paraview.py was not run"
    );
    None
}

fn on_path(name: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(name).is_file()))
}

/// `pvbatch` under a display (a real one, or a virtual one through xvfb-run), or `None` (and
/// a note) when neither is available.
fn pvbatch_with_display(pv: &Path) -> Option<Command> {
    if std::env::var_os("DISPLAY").is_some() {
        return Some(Command::new(pv));
    }
    if on_path("xvfb-run") {
        let mut c = Command::new("xvfb-run");
        c.arg("-a").arg(pv);
        return Some(c);
    }
    eprintln!("note: no display and no xvfb-run: the ParaView script runs without a picture");
    None
}

/// Width and height of a PNG file (its IHDR chunk).
fn png_size(png: &[u8]) -> (u32, u32) {
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n") && &png[12..16] == b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    (be(&png[16..20]), be(&png[20..24]))
}

/// Runs `cmd` and asserts it succeeds. `xvfb-run -a` can lose the race for a display number to
/// another X server starting at the same moment (another test, another user); ParaView then
/// reports "bad X server connection" before running anything, and the command is run again
/// (at most 3 times).
fn run_ok(mut cmd: Command) {
    for attempt in 1..=3 {
        let res = cmd.output().unwrap();
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&res.stdout),
            String::from_utf8_lossy(&res.stderr)
        );
        let lost_display =
            text.contains("bad X server connection") || text.contains("Xvfb failed to start");
        if res.status.success() || !lost_display || attempt == 3 {
            assert!(res.status.success(), "{text}");
            return;
        }
        eprintln!("note: the virtual display was lost to another X server; running again");
        std::thread::sleep(Duration::from_millis(500 * attempt));
    }
}

fn read_json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
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

/// The moored cage of [`moored_cage_scene`] in its waves, 2 s, an output every second: a series
/// whose shape changes from step to step.
fn moored_cage_in_waves(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/moored-cage.toml"))
        .unwrap()
        .replace("element_length = 4.0", "element_length = 5.0")
        .replace("top_ring[6]", "top_ring[4]")
        .replace("top_ring[12]", "top_ring[8]")
        .replace("top_ring[18]", "top_ring[12]")
        .replace("t_end = 60.0", "t_end = 2.0");
    assert!(text.contains("t_end = 2.0") && text.contains("[sea.waves]"));
    let p = dir.join("moored-waves.toml");
    std::fs::write(&p, text).unwrap();
    p
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

/// A 1 × 2 farm, statics only: block names from object names with `/`.
fn small_farm(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/farm.toml")).unwrap();
    let a = text.find("[sea.waves]").unwrap();
    let b = text.find("[[farm]]").unwrap();
    let c = text.find("[analysis]").unwrap();
    let text = format!(
        "{}{}[analysis]\nkind = \"static\"\n",
        &text[..a],
        &text[b..c]
    )
    .replace("rows = 2 ", "rows = 1 ")
    .replace("columns = 3 ", "columns = 2 ");
    assert!(text.contains("rows = 1 ") && text.contains("columns = 2 "));
    let p = dir.join("farm.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// The cells of every dataset a `.vtm` lists, by `block/dataset` path (read from the `.vtu`
/// files' `NumberOfCells`).
fn vtm_cells(vtm: &Path) -> Vec<(String, u64)> {
    let text = std::fs::read_to_string(vtm).unwrap();
    let attr = |line: &str, key: &str| -> String {
        let k = format!("{key}=\"");
        let i = line.find(&k).unwrap() + k.len();
        line[i..].split('"').next().unwrap().to_string()
    };
    let mut block = String::new();
    let mut out = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("<Block ") {
            block = attr(line, "name");
        } else if line.trim_start().starts_with("<DataSet ") {
            let vtu =
                std::fs::read_to_string(vtm.parent().unwrap().join(attr(line, "file"))).unwrap();
            let n: u64 = attr(&vtu, "NumberOfCells").parse().unwrap();
            out.push((format!("{block}/{}", attr(line, "name")), n));
        }
    }
    out
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

#[test]
fn interrupt_during_statics_keeps_the_best_state_as_step_0() {
    interrupt_statics("INT", 130);
}

#[test]
fn sigterm_during_statics_keeps_the_best_state_as_step_0() {
    interrupt_statics("TERM", 143);
}

fn interrupt_statics(signal: &str, code: i32) {
    // The reference cage at 1.25 m elements takes ~25 s of statics in release; a stop signal
    // during it must stop the solve promptly, write the last accepted state as step 0, say
    // that it is not converged, and exit 128 + the signal.
    let dir = scratch(&format!("interrupt-statics-{signal}"));
    let out = dir.join("out");
    let scene = dir.join("fine-cage.toml");
    let text = std::fs::read_to_string(root().join("examples/reference-cage.toml")).unwrap();
    std::fs::write(
        &scene,
        text.replace("element_length = 2.5", "element_length = 1.25"),
    )
    .unwrap();
    let child = spawn_quiet_run(&scene, &out);
    // Long enough for the iterate to have moved on a loaded machine (~20 iterations).
    std::thread::sleep(Duration::from_secs(6));
    let pvd = out.join("reference-cage.pvd");
    assert!(
        !pvd.exists() || pvd_entries(&pvd).is_empty(),
        "statics finished before the interrupt; the test needs a longer static solve"
    );
    let sent = Instant::now();
    send_signal(&child, signal);
    let result = child.wait_with_output().unwrap();
    let waited = sent.elapsed();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(code), "{stderr}");
    assert!(stderr.contains("NOT converged"), "{stderr}");
    // Generous bound (debug build, loaded CI): the solver polls between Newton iterations.
    assert!(waited < Duration::from_secs(20), "stopped after {waited:?}");
    let entries = assert_consistent(&pvd);
    assert_eq!(entries.len(), 1, "the static state is step 0");
    assert_eq!(entries[0].0, 0.0);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "interrupted");
    assert_eq!(json["output_steps"].as_u64(), Some(1));
    // The full load at once: the iterate is one of the full current.
    assert_eq!(json["static_load_factor"].as_f64(), Some(1.0));
    assert_eq!(json["static_converged"], false);
    assert!(
        json["static_relative_residual"]
            .as_f64()
            .is_some_and(|r| r > 0.0)
    );
    let hist = json["static_residual_history"].as_array().unwrap();
    assert!(!hist.is_empty());
    assert!(hist.iter().all(|v| v.as_f64().is_some_and(f64::is_finite)));
    // Step 0 is the last accepted iterate under the full current, not the as-built net (all
    // twines slack, no reaction, volume ratio 1), which is what the last converged load
    // increment would be when the full load is applied at once.
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap_or(f64::NAN))
        .collect();
    let col = |name: &str| row[head.iter().position(|h| *h == name).unwrap()];
    // An iterate, not an equilibrium: only that it has moved from the as-built net is sure.
    assert!(col("Fx_net") > 0.0, "Fx_net {}", col("Fx_net"));
    let reaction = col("Rx").abs() + col("Rz").abs();
    assert!(reaction > 0.0, "the as-built net, with no reactions");
    assert!(
        (col("volume_ratio") - 1.0).abs() > 1e-3,
        "the net has not moved: volume ratio {}",
        col("volume_ratio")
    );
    // The extremes are those of the one state reached, the iterate written as step 0.
    for (c, max, min) in assert_extremes_agree(&out) {
        if head.contains(&c.as_str()) {
            assert_eq!((max, min), (col(&c), col(&c)), "{c}");
        }
    }
}

#[test]
fn check_warns_about_a_line_end_held_by_nothing() {
    let dir = scratch("free-line-end");
    let scene = dir.join("free.toml");
    std::fs::write(
        &scene,
        "name = \"free\"\n[sea]\ndepth = 50.0\n[[line]]\nname = \"chain\"\n\
         anchor = [0.0, 0.0, -50.0]\nfairlead = [100.0, 0.0, -5.0]\nlength = 120.0\n\
         segments = 20\ndiameter = 0.1\nmass_per_length = 100.0\nea = 5e8\n",
    )
    .unwrap();
    let (code, stdout, stderr) = aqua(&["check", scene.to_str().unwrap()]);
    let all = format!("{stdout}{stderr}");
    assert_eq!(code, 0, "{all}");
    assert!(
        all.contains("line 'chain': its fairlead is neither fixed, prescribed nor attached"),
        "{all}"
    );
    assert!(!all.contains("its anchor is neither"), "{all}");
    // Fixing the fairlead removes the warning.
    let fixed = std::fs::read_to_string(&scene).unwrap().replace(
        "ea = 5e8\n",
        "ea = 5e8\nfixed = [\"anchor\", \"fairlead\"]\n",
    );
    std::fs::write(&scene, fixed).unwrap();
    let (code, stdout, stderr) = aqua(&["check", scene.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(!format!("{stdout}{stderr}").contains("neither fixed"));
    // A free anchor: an anchor is a position, so the advice cannot be to attach it to a node.
    let text = std::fs::read_to_string(&scene).unwrap().replace(
        "fixed = [\"anchor\", \"fairlead\"]",
        "fixed = [\"fairlead\"]",
    );
    std::fs::write(&scene, text).unwrap();
    let (code, stdout, stderr) = aqua(&["check", scene.to_str().unwrap()]);
    let all = format!("{stdout}{stderr}");
    assert_eq!(code, 0, "{all}");
    assert!(all.contains("its anchor is neither fixed"), "{all}");
    assert!(all.contains("fall to the seabed"), "{all}");
    assert!(!all.contains("set `fairlead`"), "{all}");
}

#[test]
fn check_on_a_sweep_file_points_to_aqua_sweep() {
    let file = root().join("examples/chain-cases.toml");
    let (code, stdout, stderr) = aqua(&["check", file.to_str().unwrap()]);
    let all = format!("{stdout}{stderr}");
    assert_ne!(code, 0, "{all}");
    assert!(all.contains("this is a sweep file"), "{all}");
    assert!(
        all.contains(&format!("aqua sweep {}", file.display())),
        "{all}"
    );
}

#[test]
fn a_closed_pipe_ends_quietly() {
    // `aqua check scene.toml | head`: the reader goes away; no panic, no backtrace, status 0.
    for args in [
        vec!["check", "examples/moored-cage.toml"],
        vec!["coeffs", "--model", "all"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_aqua"))
            .args(&args)
            .current_dir(root())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// Largest value of `column` over the rows of a `summary.csv` after the static row.
fn sampled_max(csv: &str, column: &str) -> (f64, f64) {
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = head.iter().position(|h| *h == column).unwrap();
    lines
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            (f[0], f[k])
        })
        .fold(
            (f64::NAN, f64::NEG_INFINITY),
            |a, b| if b.1 > a.1 { b } else { a },
        )
}

#[test]
fn collect_study_and_plot_report_a_peak_between_output_steps() {
    // A taut 10-segment line whose fairlead is surged at a 2 s period, written every 0.3 s:
    // its fairlead tension peaks between output steps. The reference is the same run written
    // at every step (output_interval = dt: the same steps).
    let dir = scratch("peak-between-samples");
    let scene = dir.join("taut.toml");
    std::fs::write(
        &scene,
        "name = \"taut\"\n[sea]\ndepth = 50.0\n[[line]]\nname = \"chain\"\n\
         anchor = [0.0, 0.0, -50.0]\nfairlead = [100.0, 0.0, -5.0]\nlength = 108.0\n\
         segments = 10\ndiameter = 0.1354\nmass_per_length = 113.0\nea = 5.4e7\n\
         [[prescribed]]\nnodes = \"chain/fairlead\"\nmotion = \"sine\"\n\
         amplitude = [1.0, 0.0, 0.3]\nperiod = 2.0\nramp_time = 0.5\n\
         [analysis]\nkind = \"static+dynamic\"\n[analysis.dynamic]\nscheme = \"midpoint\"\n\
         dt = 0.02\nt_end = 3.0\noutput_interval = 0.3\n",
    )
    .unwrap();
    let run = |out: &Path, interval: &str| {
        let (code, _, err) = aqua(&[
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--set",
            &format!("analysis.dynamic.output_interval={interval}"),
        ]);
        assert_eq!(code, 0, "{err}");
        std::fs::read_to_string(out.join("summary.csv")).unwrap()
    };
    let column = "chain_fairlead_element_tension";
    let (t_ref, reference) = sampled_max(&run(&dir.join("dense"), "0.02"), column);
    let coarse = dir.join("runs").join("coarse");
    let (_, sampled) = sampled_max(&run(&coarse, "0.3"), column);
    assert!(
        sampled < 0.99 * reference,
        "the test needs a peak between output steps: {sampled} vs {reference}"
    );
    let close = |v: f64| (v - reference).abs() <= 1e-8 * reference;

    // The run's own files.
    let extremes = assert_extremes_agree(&coarse);
    let (_, max, _) = extremes.iter().find(|e| e.0 == column).unwrap();
    assert!(
        close(*max),
        "extremes.csv {max} vs every step sampled {reference}"
    );

    // aqua collect: max over every step.
    let (code, stdout, err) = aqua(&["collect", dir.join("runs").to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("over every accepted step"), "{stdout}");
    let table = std::fs::read_to_string(dir.join("runs/collected.csv")).unwrap();
    let mut lines = table.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = head
        .iter()
        .position(|h| *h == format!("{column} max"))
        .unwrap();
    let collected: f64 = row[k].parse().unwrap();
    assert!(close(collected), "collect {collected} vs {reference}");

    // aqua study: its max metric is the per-step one, whatever the output interval.
    let out = dir.join("study");
    let (code, _, err) = aqua(&[
        "study",
        scene.to_str().unwrap(),
        "--vary",
        "analysis.dynamic.output_interval=0.3,0.06",
        "--metric",
        &format!("max:{column}"),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let study: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("study.json")).unwrap()).unwrap();
    for r in study["runs"].as_array().unwrap() {
        let v = r["values"][0].as_f64().unwrap();
        assert!(close(v), "study run {}: {v} vs {reference}", r["setting"]);
    }

    // aqua plot: the line-end picture marks the peak, above the sampled curve.
    let pictures = aqua_study::plot::plot_run(&coarse).unwrap();
    let ends = pictures
        .iter()
        .find(|p| p.path.ends_with("line_ends.png"))
        .unwrap();
    let s = ends.series.iter().find(|s| s.name == column).unwrap();
    let (t, peak) = s.peak.expect("the per-step peak is marked");
    assert!(close(peak) && (t - t_ref).abs() < 1e-9, "({t}, {peak})");
    assert_eq!(s.max, peak);
}

/// Every file under `dir`, relative, sorted.
fn files_under(dir: &Path) -> Vec<String> {
    fn walk(base: &Path, d: &Path, out: &mut Vec<String>) {
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            out.push(p.strip_prefix(base).unwrap().to_string_lossy().into_owned());
            if p.is_dir() {
                walk(base, &p, out);
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}

/// `aqua run` and the library's `run_scene` (what Python's `Scene.run` calls) write the same
/// files: a dynamic run in waves, so that the wave component table is among them.
#[test]
fn the_library_run_writes_the_files_of_aqua_run() {
    let dir = scratch("library-run");
    let text = std::fs::read_to_string(root().join("examples/moored-cage.toml")).unwrap();
    assert!(text.contains("t_end = 60.0"));
    let scene = dir.join("moored-cage.toml");
    std::fs::write(&scene, text.replace("t_end = 60.0", "t_end = 0.4")).unwrap();
    let (cli, lib) = (dir.join("cli"), dir.join("lib"));
    let (code, _, err) = aqua(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        cli.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    struct Quiet;
    impl aqua_sim::Observer for Quiet {}
    let outcome = aqua_sim::run_scene(
        aqua_sim::RunOptions {
            scene: aqua_sim::PrepareOptions::file(&scene),
            out: Some(&lib),
        },
        &mut Quiet,
    )
    .unwrap();
    assert!(outcome.result.is_ok());
    assert_eq!(outcome.record.ending, aqua_sim::Ending::Completed);

    let names = files_under(&cli);
    for f in [
        "run.json",
        "summary.csv",
        "extremes.csv",
        "wave_components.csv",
        "open_in_paraview.py",
        "moored-cage.pvd",
    ] {
        assert!(names.iter().any(|n| n == f), "{f} not in {names:?}");
    }
    assert_eq!(files_under(&lib), names);
    for f in ["summary.csv", "extremes.csv", "wave_components.csv"] {
        assert_eq!(
            std::fs::read_to_string(lib.join(f)).unwrap(),
            std::fs::read_to_string(cli.join(f)).unwrap(),
            "{f}"
        );
    }
    let json = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("run.json")).unwrap()).unwrap()
    };
    let (a, b) = (json(&cli), json(&lib));
    let keys = |v: &serde_json::Value| v.as_object().unwrap().keys().cloned().collect::<Vec<_>>();
    assert_eq!(keys(&b), keys(&a));
    for k in [
        "status",
        "output_steps",
        "paraview_steps",
        "steps",
        "final",
        "extremes",
        "resolved",
        "names",
        "diagnostics",
    ] {
        assert_eq!(b[k], a[k], "{k}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
