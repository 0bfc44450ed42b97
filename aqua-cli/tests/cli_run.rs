//! `aqua run` end to end through the binary: the load extremes between output steps reach
//! `aqua collect`, `aqua study` and `aqua plot`, and the library's run writes the files of `aqua run`.

mod run_helpers;

use run_helpers::*;
use std::path::Path;

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
