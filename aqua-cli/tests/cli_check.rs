//! `aqua check` end to end through the binary: every bundled example checks, a mistake in each
//! scene section gives exit code 2 with the file, line and key, and the warnings of a check.

mod run_helpers;

use run_helpers::*;
use std::process::{Command, Stdio};

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
