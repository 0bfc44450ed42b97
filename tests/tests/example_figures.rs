//! The figures of docs/guide/examples.md hold for a run of each example: the test reads the
//! table (example, figure, value, tolerance), runs the example unchanged and compares.
//!
//! Each run must also end without a warning that its extremes are uncertain (`fem/time-step`,
//! `fem/extremes-unresolved`, `fem/energy-guard`, `fem/seabed-contact`, `fem/snap`), except the
//! farm's time-step and snap warnings, which must name a slack lee group and not the loaded
//! upstream lines (docs/theory/fem.md#choice-of-the-default-scheme), and the seabed-contact
//! warning of the examples whose chains land on the bed at a step that does not resolve the
//! contact (docs/guide/examples.md).
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

/// The examples allowed to end with an uncertainty warning, each with the group names the
/// warning must not give (the loaded lines, whose extremes are converged): the farm's slack lee
/// chains and pendants snap taut within single steps and have no converged peak at any step
/// tried (docs/theory/fem.md#choice-of-the-default-scheme).
const SNAPPING: &[(&str, &str)] = &[("farm.toml", "`farm/anchor_w")];

/// The examples that keep a step at which their chains' seabed contact is not resolved and say
/// so (docs/theory/fem.md#seabed-contact-resolution, docs/guide/examples.md).
const CONTACT_UNRESOLVED: &[&str] = &["moored-cage.toml", "farm.toml"];

/// The examples whose side and lee anchors' extremes are not resolved at their step and say so
/// in words that name anchors only: a step-to-step ripple near their top (`fem/step-ripple`,
/// docs/theory/fem.md#step-ripple-indicator) or an extreme reached as the element at the anchor
/// snapped taut within a step (`fem/snap`, docs/theory/fem.md#snap-resolution). The moored
/// cage's south anchor moves by 11 % from dt 0.1 to 0.05 s, its east anchor, which snaps, by 109 %.
const ANCHORS_UNRESOLVED: &[&str] = &["moored-cage.toml"];

/// The warnings of a run that say its extremes are uncertain: the time-step indicator's
/// (`fem/time-step`), the unmet `extreme_tolerance` (`fem/extremes-unresolved`), HHT-α's
/// energy guard (`fem/energy-guard`), the unresolved seabed contact (`fem/seabed-contact`),
/// the snaps absorbed inside one step and their ringing (`fem/snap`); run.json lists
/// diagnostics as `severity: message`.
fn uncertainty_warnings(run: &serde_json::Value) -> Vec<String> {
    run["diagnostics"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|d| d.as_str())
        .filter(|d| {
            d.starts_with("warning")
                && (d.contains("are uncertain by about")
                    || d.contains("extreme_tolerance")
                    || d.contains("energy guard")
                    || d.contains("seabed-contact-resolution")
                    || d.contains("snap-resolution")
                    || d.contains("snap-ringing"))
        })
        .map(str::to_string)
        .collect()
}

/// Whether `name`'s run may end with `warnings`, and why not.
fn warnings_allowed(name: &str, warnings: &[String]) -> Result<(), String> {
    let contact = |w: &String| w.contains("seabed-contact-resolution");
    // A ripple warning on an anchor alone (no tension ripple in the same words), or a snap
    // at supports that are all anchors.
    let anchor_only = |w: &String| {
        let ripple = w.contains("step-ripple-indicator")
            && w.contains("the anchor reaction of")
            && !w.contains("the largest tension carries");
        let snap = w.starts_with("warning: the anchor reaction of")
            && w.contains("snap-resolution")
            && !w.contains("fairlead reaction");
        ripple || snap
    };
    let warnings: Vec<&String> = warnings
        .iter()
        .filter(|w| !(CONTACT_UNRESOLVED.contains(&name) && contact(w)))
        .filter(|w| !(ANCHORS_UNRESOLVED.contains(&name) && anchor_only(w)))
        .collect();
    if warnings.is_empty() {
        return Ok(());
    }
    let Some((_, loaded)) = SNAPPING.iter().find(|(n, _)| *n == name) else {
        return Err(format!("{name} ends with {warnings:?}"));
    };
    for w in warnings {
        let snap = w.contains("snaps taut") || w.contains("snapped taut");
        if !snap || w.contains(loaded) {
            return Err(format!(
                "{name}: the warning must name a slack group, not {loaded}…: {w}"
            ));
        }
    }
    Ok(())
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
        if let Err(why) = warnings_allowed(name, &uncertainty_warnings(&run)) {
            wrong.push(why);
        }
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
        "docs/guide/examples.md is stale or an example warns:\n{}",
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
fn only_a_snap_of_a_slack_group_may_warn() {
    let snap = "warning: near its largest values the peak tension changed by up to 5200 N within \
                one step (range 1 … 2 N), in `farm/anchor_e1/chain` (a slack member that snaps \
                taut within a step may have no converged peak …): tension extremes at this time \
                step are uncertain by about 3.1 %";
    let run = serde_json::json!({ "diagnostics": [snap, "warning: something else"] });
    let w = uncertainty_warnings(&run);
    assert_eq!(w, vec![snap.to_string()]);
    assert!(warnings_allowed("farm.toml", &w).is_ok());
    assert!(warnings_allowed("moored-cage.toml", &w).is_err());
    let loaded = vec![snap.replace("anchor_e1", "anchor_w2")];
    assert!(warnings_allowed("farm.toml", &loaded).is_err());
    assert!(warnings_allowed("moored-cage.toml", &[]).is_ok());
    let contact = "warning: anchor and touchdown tension extremes may be up to 25.5 % low: … \
                   (docs/theory/fem.md#seabed-contact-resolution) …"
        .to_string();
    let run = serde_json::json!({ "diagnostics": [contact.as_str()] });
    assert_eq!(uncertainty_warnings(&run), vec![contact.clone()]);
    assert!(warnings_allowed("moored-cage.toml", std::slice::from_ref(&contact)).is_ok());
    assert!(warnings_allowed("mooring-chain.toml", std::slice::from_ref(&contact)).is_err());
    assert!(warnings_allowed("feed-barge.toml", std::slice::from_ref(&contact)).is_err());
    assert!(warnings_allowed("buoy-mooring.toml", &[contact]).is_err());
    let absorbed = "warning: the largest tension of this run (24484 N over every step) is too \
                    low, …: 12 times a slack element snapped taut within a single step; the \
                    largest, element 1590 of `farm/anchor_e1/chain` … \
                    (docs/theory/fem.md#snap-resolution) …";
    let run = serde_json::json!({ "diagnostics": [absorbed] });
    let w = uncertainty_warnings(&run);
    assert_eq!(w, vec![absorbed.to_string()]);
    assert!(warnings_allowed("farm.toml", &w).is_ok());
    assert!(warnings_allowed("feed-barge.toml", &w).is_err());
    let loaded = vec![absorbed.replace("anchor_e1", "anchor_w2")];
    assert!(warnings_allowed("farm.toml", &loaded).is_err());
    let anchors = "warning: the anchor reaction of `m_south`, the anchor reaction of `m_east` are \
                   not resolved at this time step: … snapped taut within a single step … \
                   (docs/theory/fem.md#snap-resolution) …";
    let run = serde_json::json!({ "diagnostics": [anchors] });
    let w = uncertainty_warnings(&run);
    assert_eq!(w, vec![anchors.to_string()]);
    assert!(warnings_allowed("moored-cage.toml", &w).is_ok());
    assert!(warnings_allowed("feed-barge.toml", &w).is_err());
    let fairlead = vec![anchors.replace(
        ", the anchor reaction of `m_east`",
        ", the fairlead reaction of `m_east`",
    )];
    assert!(warnings_allowed("moored-cage.toml", &fairlead).is_err());
}

#[test]
fn fast_examples_give_the_figures_of_the_guide() {
    check(&[
        "net-panel.toml",
        "buoy-mooring.toml",
        "mooring-chain.toml",
        "reference-cage.toml",
    ]);
}

#[test]
#[ignore = "about a minute in release: cargo test --release -p aqua-tests --test example_figures -- --ignored"]
fn slow_examples_give_the_figures_of_the_guide() {
    check(&["feed-barge.toml", "moored-cage.toml", "farm.toml"]);
}

/// The feed barge's chains, axially damped, converge with the step: a lee chain lifted off the
/// bed snatches taut, and undamped its peak grows with every refinement (docs/theory/fem.md,
/// #snatch-of-a-lifted-chain: 64 kN at Δt = 0.1 s, 74 kN at 5 ms). Over the first 40 s the
/// largest tension of each chain at 5 ms must be within 3 % of 0.1 s, and the two lee chains,
/// mirror images in a scene symmetric about y = 0, must agree.
#[test]
#[ignore = "about a minute in release: cargo test --release -p aqua-tests --test example_figures -- --ignored"]
fn feed_barge_chain_peaks_converge_with_the_step() {
    let dir = scratch("feed-barge-snatch");
    let text = std::fs::read_to_string(root().join("examples/feed-barge.toml"))
        .unwrap()
        .replace("t_end = 60.0", "t_end = 40.0");
    let peaks = |dt: &str| {
        let out = common::run_text(
            &dir,
            &format!("dt-{dt}"),
            &text.replace("dt = 0.0025\n", &format!("dt = {dt}\n")),
        );
        let run = run_json(&out);
        assert_eq!(run["status"], "completed", "dt {dt}");
        ["ne", "nw", "sw", "se"].map(|c| {
            run["extremes"][format!("Tmax_chain_{c}/chain_{c}")]["max"]
                .as_f64()
                .unwrap()
        })
    };
    let coarse = peaks("0.1");
    let fine = peaks("0.005");
    eprintln!("chains ne, nw, sw, se: Δt 0.1 s {coarse:.0?} N, 5 ms {fine:.0?} N");
    for (c, f) in coarse.iter().zip(&fine) {
        assert!((c - f).abs() <= 0.03 * f, "{coarse:?} against {fine:?}");
    }
    for p in [coarse, fine] {
        assert!(
            (p[0] - p[3]).abs() <= 1e-3 * p[0],
            "lee chains ne, se: {p:?}"
        );
        assert!((p[1] - p[2]).abs() <= 1e-3 * p[1], "upstream nw, sw: {p:?}");
    }
}
