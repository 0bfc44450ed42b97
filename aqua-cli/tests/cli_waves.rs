//! `aqua waves` end to end: summary numbers against the worked values of
//! docs/theory/environment.md, CSV layout,
//! JSON, and bad input (exit code 2 with the key named).

use std::process::Command;

fn aqua(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args(args)
        .output()
        .expect("run aqua");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn json_summary_matches_spec_e1() {
    let (code, out, err) = aqua(&[
        "waves", "--kind", "airy", "--height", "2", "--period", "8", "--depth", "50", "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let r = &v["regular"][0];
    assert!((r["wave_number"].as_f64().unwrap() - 0.0631296721374).abs() < 5e-14);
    assert!((r["wavelength"].as_f64().unwrap() - 99.5282423375).abs() < 5e-11);
    let c = r["phase_speed"].as_f64().unwrap();
    assert!((c - 99.5282423375 / 8.0).abs() < 1e-9);
}

#[test]
fn irregular_summary_measures_hs_back() {
    let (code, out, err) = aqua(&[
        "waves",
        "--kind",
        "irregular",
        "--hs",
        "3",
        "--tp",
        "9",
        "--depth",
        "60",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let hs = v["measured"]["hs"].as_f64().unwrap();
    assert!((hs / 3.0 - 1.0).abs() < 0.03, "{hs}");
    assert_eq!(v["irregular"]["components"].as_u64(), Some(200));
    // Tp = 9 s, Hs = 3 m: phi = 5.2 -> gamma auto = 1 and a range warning.
    assert_eq!(v["irregular"]["gamma"].as_f64(), Some(1.0));
    assert!(v["warnings"][0].as_str().unwrap().contains("JONSWAP"));
}

#[test]
fn csv_series_has_the_documented_columns() {
    let dir = std::env::temp_dir().join(format!("aqua-waves-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("w.csv");
    let (code, _, err) = aqua(&[
        "waves",
        "--kind",
        "airy",
        "--height",
        "2",
        "--period",
        "8",
        "--depth",
        "50",
        "--ramp-time",
        "0",
        "--at",
        "0,0,0",
        "--at",
        "5,0,-10",
        "--duration",
        "8",
        "--dt",
        "0.5",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,x,y,z,eta,u,v,w,ax,ay,az"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2 * 17);
    // t = 0 at the origin: eta = a = 1 m, u = ωa·C(0) with g = 9.80665.
    assert!((rows[0][4] - 1.0).abs() < 1e-12);
    assert!(rows[0][5] > 0.7 && rows[0][5] < 0.8);
    // one period later the same values
    let last = &rows[rows.len() - 2];
    assert!((last[0] - 8.0).abs() < 1e-12 && (last[4] - 1.0).abs() < 1e-9);
}

#[test]
fn bad_input_exits_2_naming_the_key() {
    let (code, _, err) = aqua(&[
        "waves", "--kind", "airy", "--height", "-2", "--period", "8", "--depth", "50",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("sea.waves.height") && err.contains("-2"),
        "{err}"
    );
    let (code, _, err) = aqua(&["waves", "--kind", "airy", "--height", "2", "--period", "8"]);
    assert_eq!(code, 2);
    assert!(err.contains("sea.depth"), "{err}");
    let dir = std::env::temp_dir().join(format!("aqua-waves-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("bad.toml");
    std::fs::write(
        &scene,
        "[sea]\ndepth = 10\n[sea.waves]\nkind = \"airy\"\nheigth = 2\n",
    )
    .unwrap();
    let (code, _, err) = aqua(&["waves", "--scene", scene.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("bad.toml") && err.contains("line 5") && err.contains("heigth"),
        "{err}"
    );
    let (code, _, err) = aqua(&["waves", "--scene", "/nonexistent/x.toml"]);
    assert_eq!(code, 2);
    assert!(err.contains("/nonexistent/x.toml"), "{err}");
}

#[test]
fn bundled_sea_example_runs() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/sea-jonswap.toml");
    let (code, out, err) = aqua(&["waves", "--scene", root, "--record", "1200"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("spectrum jonswap"), "{out}");
}
