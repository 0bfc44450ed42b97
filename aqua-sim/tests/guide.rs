//! docs/guide/scene.md documents every scene key: the key list is the schema's own
//! ([`aqua_sim::scene::scene_keys`], written out per schema type and checked against what the
//! parser accepts by the unit tests of `aqua-sim/src/scene/keys.rs`), so a key added to the schema without a line in the guide fails here, and so does a guide line for
//! a key the parser does not accept.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Table path → keys documented under it. A heading names its tables in backticks (`[sea]`,
/// `[[cage]]`, `[cage.net]`, several per heading allowed); a heading without one is the top
/// level. Rows are `| \`key\` | …`.
fn documented(text: &str) -> (BTreeMap<String, BTreeSet<String>>, BTreeSet<String>) {
    let mut tables: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut root = BTreeSet::new();
    let mut current: Vec<String> = Vec::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        if line.starts_with('#') {
            current = line
                .split('`')
                .skip(1)
                .step_by(2)
                .filter(|s| s.starts_with('[') && s.ends_with(']'))
                .map(|s| s.trim_matches(|c| c == '[' || c == ']').to_string())
                .collect();
            continue;
        }
        let Some(rest) = line.strip_prefix("| `") else {
            continue;
        };
        let Some(key) = rest.split('`').next() else {
            continue;
        };
        if current.is_empty() {
            root.insert(key.to_string());
        }
        for t in &current {
            tables.entry(t.clone()).or_default().insert(key.to_string());
        }
    }
    (tables, root)
}

/// Whether `key` (dotted) is documented: under the longest documented table that prefixes it,
/// with the rest of the path as the row key.
fn is_documented(
    key: &str,
    tables: &BTreeMap<String, BTreeSet<String>>,
    root: &BTreeSet<String>,
) -> bool {
    let parts: Vec<&str> = key.split('.').collect();
    for cut in (1..parts.len()).rev() {
        let table = parts[..cut].join(".");
        if let Some(rows) = tables.get(&table) {
            return rows.contains(&parts[cut..].join("."));
        }
    }
    root.contains(key)
}

#[test]
fn every_scene_key_is_in_the_guide_and_every_guide_key_in_the_schema() {
    let keys = aqua_sim::scene::scene_keys();
    // The derivation itself works: it sees keys of every section and nesting level.
    for k in [
        "name",
        "sea.depth",
        "sea.waves.spectrum.hs",
        "cage.circumference",
        "cage.net.solidity",
        "cage.net.screen_model",
        "cage.groups.<name>.diameter",
        "line.ea",
        "line.morison",
        "mesh.rename",
        "group.name",
        "group.cn",
        "group.diameter",
        "point.force",
        "fix.dofs",
        "prescribed.table",
        "analysis.static.tol",
        "analysis.dynamic.reuse_factor",
    ] {
        assert!(keys.iter().any(|x| x == k), "{k} not derived: {keys:?}");
    }
    assert!(keys.len() > 150, "{} keys", keys.len());
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/guide/scene.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let (tables, root) = documented(&text);
    let missing: Vec<&String> = keys
        .iter()
        .filter(|k| !is_documented(k, &tables, &root))
        .collect();
    assert!(
        missing.is_empty(),
        "scene keys missing from docs/guide/scene.md (add a row under the table's heading): \
         {missing:?}"
    );
    let schema: BTreeSet<&str> = keys.iter().map(String::as_str).collect();
    let mut stale = Vec::new();
    for (table, rows) in &tables {
        for r in rows {
            let full = format!("{table}.{r}");
            let nested = schema.iter().any(|k| k.starts_with(&format!("{full}.")));
            if !schema.contains(full.as_str()) && !nested {
                stale.push(full);
            }
        }
    }
    assert!(
        stale.is_empty(),
        "docs/guide/scene.md documents keys the parser does not accept: {stale:?}"
    );
}

#[test]
fn the_check_of_the_guide_catches_a_missing_key() {
    let text = "## `[sea]`\n| `gravity` | number |\n## Top\n| `name` | string |\n";
    let (tables, root) = documented(text);
    assert!(is_documented("sea.gravity", &tables, &root));
    assert!(is_documented("name", &tables, &root));
    assert!(!is_documented("sea.depth", &tables, &root));
    assert!(!is_documented("sea.water.density", &tables, &root));
}
