//! Every file in `examples/` does what the example table of docs/guide/examples.md says it is for: scenes run
//! (dynamics shortened to 1 s), case files list their cases, sea-only files preview with
//! `aqua waves` and are refused by `aqua run` with a clear message. The list is read from the
//! folder, so a new example cannot be forgotten here.

use std::path::Path;
use std::process::Command;

fn aqua(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn every_example_runs_as_documented() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
    let guide = std::fs::read_to_string(dir.join("../docs/guide/examples.md")).unwrap();
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 5, "{files:?}");
    let tmp = std::env::temp_dir().join(format!("aqua-examples-{}", std::process::id()));
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            guide.contains(&format!("| `{name}` |")),
            "{name} has no line in the example table of docs/guide/examples.md"
        );
        let text = std::fs::read_to_string(f).unwrap();
        let table: toml::Table = toml::from_str(&text).unwrap();
        let path = f.to_str().unwrap();
        if name.contains("full-scale") {
            let (code, out, err) = aqua(&["check", path, "--json"]);
            assert_eq!(code, 0, "{name}: {err}");
            let report: serde_json::Value = serde_json::from_str(&out).unwrap();
            let dofs = report["cost"]["dofs"].as_u64().unwrap();
            assert!(dofs >= 80_000, "{name}: {dofs} free DOFs");
        } else if table.contains_key("scene") {
            let (code, out, err) = aqua(&["sweep", path]);
            assert_eq!(code, 0, "{name}: {err}");
            assert!(out.contains("cases of"), "{name}: {out}");
        } else if !["cage", "panel", "line", "mesh", "farm"]
            .iter()
            .any(|k| table.contains_key(*k))
        {
            let (code, _, err) = aqua(&["waves", "--scene", path]);
            assert_eq!(code, 0, "{name}: {err}");
            let (code, _, err) = aqua(&["run", path, "--out", tmp.to_str().unwrap()]);
            assert_eq!(code, 2, "{name}");
            assert!(err.contains("no structure"), "{name}: {err}");
        } else {
            let out = tmp.join(&name);
            let (code, _, err) = aqua(&[
                "run",
                path,
                "--quiet",
                "--set",
                "analysis.dynamic.t_end=1",
                "--set",
                "analysis.dynamic.output_interval=0.5",
                "--out",
                out.to_str().unwrap(),
            ]);
            assert_eq!(code, 0, "{name}: {err}");
            let run: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap())
                    .unwrap();
            assert_eq!(run["status"], "completed", "{name}");
        }
    }
}
