//! `aqua run --plot` and `aqua plot`: the PNG files are valid pictures of the documented size,
//! and the series drawn have the extremes of the CSV columns they come from (read back from
//! the plotted data, not from the pixels).

use std::path::{Path, PathBuf};
use std::process::Command;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name)
}

/// Width and height from a PNG's signature and IHDR chunk.
fn png_size(path: &Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap();
    assert_eq!(
        &b[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    assert_eq!(&b[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    (be(16), be(20))
}

/// Column `name` of a CSV read here (no quoting in summary.csv).
fn column(csv: &str, name: &str) -> Vec<f64> {
    let mut lines = csv.lines();
    let k = lines
        .next()
        .unwrap()
        .split(',')
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

/// (t_max, max) of `column` in `DIR/extremes.csv`.
fn extreme_max(dir: &Path, column: &str) -> (f64, f64) {
    let text = std::fs::read_to_string(dir.join("extremes.csv")).unwrap();
    let f: Vec<&str> = text
        .lines()
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|f| f[0] == column)
        .unwrap_or_else(|| panic!("no {column} in extremes.csv"));
    (f[2].parse().unwrap(), f[1].parse().unwrap())
}

#[test]
fn run_plot_draws_the_summary_columns_and_the_static_convergence() {
    let out = std::env::temp_dir().join(format!("aqua-plot-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args([
            "run",
            example("mooring-chain.toml").to_str().unwrap(),
            "--plot",
        ])
        .args(["--set", "analysis.dynamic.t_end=12", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    for f in ["forces", "tensions", "line_ends", "static_convergence"] {
        let png = out.join("plots").join(format!("{f}.png"));
        assert_eq!(png_size(&png), aqua_study::plot::SIZE, "{f}");
        assert!(stdout.contains(&format!("{f}.png")), "{stdout}");
    }
    // A chain has no net: no volume picture.
    assert!(!out.join("plots/volume.png").exists());

    // The plotted data against the CSV.
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let pictures = aqua_study::plot::plot_run(&out).unwrap();
    let mut checked = 0;
    let mut peaks = 0;
    for p in &pictures {
        // Every title names the scene (run.json's scene.name).
        assert!(p.title.starts_with("mooring-chain: "), "{}", p.title);
        for s in &p.series {
            if p.path.ends_with("static_convergence.png") {
                continue;
            }
            let v = column(&csv, &s.name);
            let (lo, hi) = (
                v.iter().copied().fold(f64::INFINITY, f64::min),
                v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            );
            // The tension and line-end curves carry their largest value over every step
            // (extremes.csv), at or above the sampled curve.
            let hi = match s.peak {
                Some((t, peak)) => {
                    let (t_max, max) = extreme_max(&out, &s.name);
                    assert_eq!((t, peak), (t_max, max), "{}", s.name);
                    assert!(peak >= hi, "{}: {peak} below the sampled {hi}", s.name);
                    peaks += 1;
                    peak
                }
                None => hi,
            };
            assert_eq!((s.min, s.max), (lo, hi), "{}", s.name);
            assert_eq!(s.points.len(), v.len());
            checked += 1;
        }
    }
    assert!(checked >= 8, "{checked} series checked");
    assert!(
        peaks >= 3,
        "Tmax and the line-end curves are marked: {peaks}"
    );
    // The convergence picture holds every static iterate of run.json.
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    let history = run["static_residual_history"].as_array().unwrap();
    let conv = pictures
        .iter()
        .find(|p| p.path.ends_with("static_convergence.png"))
        .unwrap();
    assert_eq!(conv.series[0].points.len(), history.len());
    let last = history.last().unwrap().as_f64().unwrap();
    assert_eq!(conv.series[0].points.last().unwrap().1, last);
}

#[test]
fn plot_of_a_folder_without_a_run_is_an_input_error() {
    let o = Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args(["plot", "/nonexistent/aqua-run"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("summary.csv"));
}
