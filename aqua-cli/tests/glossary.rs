//! Every abbreviation and symbol that `aqua check` prints on the bundled examples has a row in
//! docs/guide/glossary.md: a new one printed without a definition fails here.
//!
//! What counts as an abbreviation or symbol in the output: words in capitals (`NT`, `CSM`,
//! `DOFs`), Greek letters (`λ`), the left side of an assignment `X = …` when it is not a plain
//! lower-case word (`dws`, `l_p`, `R_top`, `z`), a short name before a unit (`d_e [m]`) and a
//! subscripted name in a formula (`r_c^2`).

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

/// The units printed in brackets after a name.
const UNITS: [&str; 12] = [
    "[m]", "[N]", "[kg]", "[s]", "[Pa]", "[m/s]", "[m²]", "[m³]", "[N·m]", "[-]", "[kN]", "[MPa]",
];

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// The terms the glossary defines: every `backticked` name in the first cell of a table row.
fn glossary_terms(text: &str) -> BTreeSet<String> {
    text.lines()
        .filter(|l| l.starts_with("| `"))
        .filter_map(|l| l.split('|').nth(1))
        .flat_map(|cell| {
            cell.split('`')
                .skip(1)
                .step_by(2)
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The abbreviations and symbols in a text printed by `aqua check` (see the module comment).
fn abbreviations(text: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for line in text.lines() {
        let tokens: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || ",;:()'\"`".contains(c))
            .filter(|t| !t.is_empty())
            .collect();
        for (i, raw) in tokens.iter().enumerate() {
            let t = raw.trim_end_matches('.');
            let letters: Vec<char> = t.chars().collect();
            // Capitals: two or more, an optional plural s ("DOFs").
            let stem = t.strip_suffix('s').unwrap_or(t);
            if stem.chars().count() >= 2
                && stem
                    .chars()
                    .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit())
                && stem.chars().next().is_some_and(|c| c.is_ascii_uppercase())
            {
                found.insert(t.to_string());
            }
            // Greek letters, alone or leading a symbol.
            for c in &letters {
                if ('\u{0370}'..='\u{03ff}').contains(c) {
                    found.insert(c.to_string());
                }
            }
            // A subscripted name in a formula: r_c^2, r_c².
            if let Some(pos) = t.find(['^', '²']) {
                let name = &t[..pos];
                if name.contains('_') {
                    found.insert(name.trim_start_matches(['(', '[']).to_string());
                }
            }
            let next = tokens.get(i + 1).copied();
            let symbol_like = |s: &str| {
                !s.contains('.')
                    && !s.contains('[')
                    && (s.chars().count() <= 3
                        || s.chars().any(|c| {
                            c.is_ascii_uppercase()
                                || c.is_ascii_digit()
                                || c == '_'
                                || !c.is_ascii()
                        }))
            };
            // The left side of an assignment.
            if next == Some("=") && symbol_like(t) && t.chars().any(char::is_alphabetic) {
                found.insert(t.to_string());
            }
            // A short name before a unit: "d_e [m]".
            if next.is_some_and(|n| UNITS.contains(&n))
                && t.chars().count() <= 3
                && t.chars().all(|c| c.is_alphanumeric() || c == '_')
            {
                found.insert(t.to_string());
            }
        }
    }
    found
}

#[test]
fn every_abbreviation_aqua_check_prints_is_in_the_glossary() {
    let glossary = std::fs::read_to_string(root().join("docs/guide/glossary.md")).unwrap();
    let terms = glossary_terms(&glossary);
    let mut files: Vec<_> = std::fs::read_dir(root().join("examples"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    let mut checked = 0;
    let mut missing = BTreeSet::new();
    let mut seen = BTreeSet::new();
    for f in &files {
        let o = Command::new(env!("CARGO_BIN_EXE_aqua"))
            .arg("check")
            .arg(f)
            .output()
            .unwrap();
        // Case files and sea-only files are not scenes `aqua check` accepts.
        if !o.status.success() {
            continue;
        }
        checked += 1;
        let out = String::from_utf8_lossy(&o.stdout);
        for a in abbreviations(&out) {
            if !terms.contains(&a) {
                missing.insert(format!(
                    "{a} ({})",
                    f.file_name().unwrap().to_string_lossy()
                ));
            }
            seen.insert(a);
        }
    }
    assert!(checked >= 6, "only {checked} examples passed aqua check");
    // The scan finds what the cage reports are known to print (it is not blind).
    for want in ["λ", "NT", "dws", "l_p", "R_top", "d_e", "CSM", "DOFs"] {
        assert!(
            seen.contains(want),
            "{want} not found in the check output: {seen:?}"
        );
    }
    assert!(
        missing.is_empty(),
        "aqua check prints abbreviations docs/guide/glossary.md does not define (add a row): \
         {missing:?}"
    );
}

#[test]
fn the_scan_catches_an_undefined_abbreviation() {
    let terms =
        glossary_terms(&std::fs::read_to_string(root().join("docs/guide/glossary.md")).unwrap());
    let printed = "cage0 (CSM; 1 copy)\n  XQ = 3 widgets, kb_2 = 0.4 m, μ = 1\n  q_x [m]  r_s^2";
    let found = abbreviations(printed);
    let undefined: BTreeSet<_> = found.difference(&terms).cloned().collect();
    let want: BTreeSet<String> = ["XQ", "kb_2", "μ", "q_x", "r_s"]
        .into_iter()
        .map(String::from)
        .collect();
    assert_eq!(undefined, want, "found {found:?}");
}
