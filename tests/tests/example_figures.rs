//! The figures of docs/guide/examples.md hold for a run of each example: the test reads the
//! table (example, figure, value, tolerance), runs the example unchanged and compares.
//!
//! The fast examples run in `cargo test --workspace`; `moored-cage.toml` and `farm.toml`
//! (about 30 s each in release) in `cargo test --release -p aqua-tests --test example_figures
//! -- --ignored` (a step of `.ci/run`).

mod common;

use common::{root, run_file, run_json, scratch};

/// One checked figure of the table.
#[derive(Debug, Clone, PartialEq)]
struct Figure {
    example: String,
    /// `static iterations`, `steps`, `max:COLUMN`, `min:COLUMN` or `final:volume_ratio`.
    what: String,
    /// In SI units.
    value: f64,
    /// Relative.
    tolerance: f64,
}

/// "34.3 kN" → 34 300, "2 500" → 2 500, "10.7 MPa" → 1.07e7.
fn parse_value(cell: &str) -> Option<f64> {
    let digits: String = cell
        .chars()
        .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | ' ' | '-' | '\u{2009}'))
        .filter(|c| !c.is_whitespace())
        .collect();
    let number: f64 = digits.parse().ok()?;
    let unit = cell.trim_start_matches(|c: char| {
        c.is_ascii_digit() || matches!(c, '.' | ' ' | '-' | '\u{2009}')
    });
    let scale = match unit.chars().next() {
        Some('k') => 1e3,
        Some('M') => 1e6,
        _ => 1.0,
    };
    Some(number * scale)
}

/// The checked figures of the table in `text`.
fn figures(text: &str) -> Vec<Figure> {
    let mut out = Vec::new();
    let mut example = String::new();
    for line in text.lines().filter(|l| l.starts_with('|')) {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        if cells.len() < 6 {
            continue;
        }
        if let Some(name) = cells[1].strip_prefix('`').and_then(|s| s.strip_suffix('`')) {
            example = name.to_string();
        }
        let Some(what) = cells[3].split('`').nth(1) else {
            continue;
        };
        let value = parse_value(cells[4])
            .unwrap_or_else(|| panic!("{example}: value {:?} is not a number", cells[4]));
        let tolerance = cells[5]
            .strip_suffix('%')
            .and_then(|t| t.trim().parse::<f64>().ok())
            .unwrap_or_else(|| panic!("{example}: tolerance {:?} is not `N %`", cells[5]))
            / 100.0;
        out.push(Figure {
            example: example.clone(),
            what: what.to_string(),
            value,
            tolerance,
        });
    }
    out
}

fn table() -> Vec<Figure> {
    figures(&std::fs::read_to_string(root().join("docs/guide/examples.md")).unwrap())
}

/// The run's number for a figure.
fn measured(run: &serde_json::Value, what: &str) -> f64 {
    let number = |v: &serde_json::Value| {
        v.as_f64()
            .unwrap_or_else(|| panic!("{what}: run.json has no number there ({v})"))
    };
    match what.split_once(':') {
        None if what == "static iterations" => number(&run["static_newton_iterations"]),
        None if what == "steps" => number(&run["steps"]),
        Some(("max", col)) => number(&run["extremes"][col]["max"]),
        Some(("min", col)) => number(&run["extremes"][col]["min"]),
        Some(("final", col)) => number(&run["final"][col]),
        _ => panic!("unknown figure {what:?} in docs/guide/examples.md"),
    }
}

/// Runs each example once and lists the figures outside their tolerance.
fn check(examples: &[&str]) {
    let all = table();
    let dir = scratch("example-figures");
    let mut wrong = Vec::new();
    for name in examples {
        let rows: Vec<&Figure> = all.iter().filter(|f| f.example == *name).collect();
        assert!(
            !rows.is_empty(),
            "docs/guide/examples.md has no figure of {name}"
        );
        let out = run_file(&root().join("examples").join(name), &dir.join(name));
        let run = run_json(&out);
        assert_eq!(run["status"], "completed", "{name}");
        for f in rows {
            let got = measured(&run, &f.what);
            let rel = (got - f.value).abs() / f.value.abs().max(1e-12);
            if rel > f.tolerance + 1e-12 {
                wrong.push(format!(
                    "{name} {}: the table says {} ± {} %, the run gives {got:.6e}",
                    f.what,
                    f.value,
                    100.0 * f.tolerance
                ));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "docs/guide/examples.md is stale:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_table_lists_figures_of_every_runnable_example() {
    let all = table();
    for name in [
        "reference-cage.toml",
        "net-panel.toml",
        "mooring-chain.toml",
        "buoy-mooring.toml",
        "feed-barge.toml",
        "moored-cage.toml",
        "farm.toml",
    ] {
        assert!(all.iter().any(|f| f.example == name), "{name}: {all:?}");
    }
    assert!(all.iter().all(|f| f.value != 0.0 && f.tolerance <= 0.15));
}

#[test]
fn the_table_parser_reads_values_units_and_tolerances() {
    let text = "| `a.toml` | x | `max:Fx_net` (drag) | 34.3 kN | 1 % |\n\
                | | | `steps` | 2 500 | 10 % |\n\
                | `b.toml` | y | — | | |\n";
    let f = figures(text);
    assert_eq!(f.len(), 2, "{f:?}");
    assert_eq!(f[0].example, "a.toml");
    assert_eq!(f[0].what, "max:Fx_net");
    assert!((f[0].value - 34_300.0).abs() < 1e-9 && (f[0].tolerance - 0.01).abs() < 1e-15);
    assert_eq!((f[1].example.as_str(), f[1].value), ("a.toml", 2_500.0));
    assert_eq!(parse_value("10.7 MPa"), Some(10.7e6));
}

#[test]
fn fast_examples_give_the_figures_of_the_guide() {
    check(&[
        "net-panel.toml",
        "buoy-mooring.toml",
        "feed-barge.toml",
        "mooring-chain.toml",
        "reference-cage.toml",
    ]);
}

#[test]
#[ignore = "about a minute in release: cargo test --release -p aqua-tests --test example_figures -- --ignored"]
fn slow_examples_give_the_figures_of_the_guide() {
    check(&["moored-cage.toml", "farm.toml"]);
}
