//! Scene overrides: `--set PATH=VALUE` on the command line, the ladders of `aqua study` and the
//! cases of `aqua sweep` all change a scene through dotted paths into its TOML tables.
//!
//! A path names tables by key and arrays of tables (`[[cage]]`, `[[line]]`, …) by a 0-based
//! index or `*` for every entry: `cage.0.element_length`, `analysis.dynamic.dt`,
//! `line.*.segments`, `sea.current.speed`. The last key may be new (a default the file left
//! out); whether it exists in the schema is decided by reading the changed scene exactly like a
//! file ([`crate::scene::read_scene`]), so an unknown or mistyped key is the same error as
//! in the file, prefixed with the override that caused it.
//!
//! Values are TOML (`5`, `0.05`, `[0, 0, -50]`, `"hht"`); a value that is not TOML is taken as a
//! string, so `scheme=rk4` needs no quotes.
//!
//! A few bare names stand for the paths users vary most ([`ALIASES`]).

use crate::error::{Result, SimError};
use std::fmt;
use std::str::FromStr;
use thiserror::Error;
use toml::{Table, Value};

/// One `PATH=VALUE` change of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Override {
    /// The dotted path as given (an alias stays an alias here).
    pub path: String,
    /// The value.
    pub value: Value,
}

/// Bare names and the dotted paths they stand for (`*` = every entry of that array).
pub const ALIASES: &[(&str, &[&str])] = &[
    ("dt", &["analysis.dynamic.dt"]),
    ("t_end", &["analysis.dynamic.t_end"]),
    ("scheme", &["analysis.dynamic.scheme"]),
    ("alpha", &["analysis.dynamic.alpha"]),
    ("theta", &["analysis.dynamic.theta"]),
    ("output_interval", &["analysis.dynamic.output_interval"]),
    ("paraview_interval", &["analysis.dynamic.paraview_interval"]),
    ("extreme_tolerance", &["analysis.dynamic.extreme_tolerance"]),
    (
        "element_length",
        &["cage.*.element_length", "panel.*.element_length"],
    ),
    ("segments", &["line.*.segments"]),
];

/// The paths a name stands for: an alias's paths, or the name itself.
pub fn expand(path: &str) -> Vec<&str> {
    ALIASES
        .iter()
        .find(|(name, _)| *name == path)
        .map(|(_, paths)| paths.to_vec())
        .unwrap_or_else(|| vec![path])
}

/// A value typed on the command line: TOML if it parses as a TOML value, else a string.
pub fn parse_value(text: &str) -> Value {
    let text = text.trim();
    toml::from_str::<Table>(&format!("v = {text}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| Value::String(text.to_string()))
}

impl FromStr for Override {
    type Err = SimError;

    /// `PATH=VALUE`.
    fn from_str(s: &str) -> Result<Self> {
        let Some((path, value)) = s.split_once('=') else {
            return Err(SimError::input(format!(
                "--set {s}: expected PATH=VALUE, e.g. analysis.dynamic.dt=0.05 or cage.0.element_length=5"
            )));
        };
        let path = path.trim();
        check_path_syntax(path).map_err(|m| {
            SimError::Input(crate::error::InputError {
                message: format!("--set {s}: {m}"),
                key: Some(path.to_string()),
                value: Some(value.trim().to_string()),
                file: None,
            })
        })?;
        Ok(Override {
            path: path.to_string(),
            value: parse_value(value),
        })
    }
}

impl fmt::Display for Override {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.value {
            Value::String(s) => write!(f, "{}={s}", self.path),
            v => write!(f, "{}={v}", self.path),
        }
    }
}

/// Why an override's path cannot be set in a scene's tables.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum OverrideError {
    /// `--set =5`.
    #[error("the path is empty")]
    EmptyPath,
    /// Empty segments or stray spaces.
    #[error(
        "\"{path}\" is not a dotted path: keys separated by single dots, array entries by index \
         or * (e.g. cage.0.element_length)"
    )]
    NotDotted {
        /// The path given.
        path: String,
    },
    /// Nothing in the scene matches (e.g. `line.*.segments` in a scene without lines).
    #[error("the scene has nothing to set at {paths}")]
    NothingToSet {
        /// The paths tried (an alias stands for several).
        paths: String,
    },
    /// An index into arrays of tables the scene does not have.
    #[error("the scene has no {at} entries ([[{at}]] tables) to index with {index}")]
    NoEntries {
        /// The path so far.
        at: String,
        /// The index given.
        index: String,
    },
    /// A key under a value that is not a table.
    #[error("{at} is the value {value}, not a table: {rest} cannot go under it")]
    NotATable {
        /// The path so far.
        at: String,
        /// The value there (TOML).
        value: String,
        /// The rest of the path.
        rest: String,
    },
    /// A list indexed by something else than an index or `*`.
    #[error("{at} is a list: the next part must be an index 0..{last} or *, not \"{index}\"")]
    NotAnIndex {
        /// The path so far.
        at: String,
        /// The last index.
        last: usize,
        /// What was given.
        index: String,
    },
    /// An index past the end of a list.
    #[error("{at} has {len} entries (indices 0..{last}): no entry {index}")]
    OutOfRange {
        /// The path so far.
        at: String,
        /// The list's length.
        len: usize,
        /// Its last index.
        last: usize,
        /// The index given.
        index: usize,
    },
}

/// Rejects empty segments and stray spaces (what is a key is the schema's business).
pub fn check_path_syntax(path: &str) -> std::result::Result<(), OverrideError> {
    if path.is_empty() {
        return Err(OverrideError::EmptyPath);
    }
    if path.split('.').any(|s| s.is_empty() || s.trim() != s) {
        return Err(OverrideError::NotDotted {
            path: path.to_string(),
        });
    }
    Ok(())
}

impl Override {
    /// Applies the change to a scene's table; returns how many places it set (an alias or a
    /// `*` can set several, and none when the scene has no entry to set).
    pub fn apply(&self, table: &mut Table) -> std::result::Result<usize, OverrideError> {
        let mut n = 0;
        for path in expand(&self.path) {
            let segs: Vec<&str> = path.split('.').collect();
            n += set_in_table(table, &segs, &self.value, "")?;
        }
        if n == 0 {
            return Err(OverrideError::NothingToSet {
                paths: expand(&self.path).join(", "),
            });
        }
        Ok(n)
    }
}

/// Sets `segs` under `table`; `at` is the path so far (for messages).
fn set_in_table(
    table: &mut Table,
    segs: &[&str],
    value: &Value,
    at: &str,
) -> std::result::Result<usize, OverrideError> {
    let (key, rest) = (segs[0], &segs[1..]);
    let here = if at.is_empty() {
        key.to_string()
    } else {
        format!("{at}.{key}")
    };
    if rest.is_empty() {
        table.insert(key.to_string(), value.clone());
        return Ok(1);
    }
    if !table.contains_key(key) {
        if rest[0] == "*" {
            return Ok(0);
        }
        if is_index(rest[0]) {
            return Err(OverrideError::NoEntries {
                at: here,
                index: rest[0].to_string(),
            });
        }
        table.insert(key.to_string(), Value::Table(Table::new()));
    }
    match table.get_mut(key) {
        Some(Value::Table(t)) => set_in_table(t, rest, value, &here),
        Some(Value::Array(a)) => set_in_array(a, rest, value, &here),
        Some(other) => Err(OverrideError::NotATable {
            at: here,
            value: other.to_string(),
            rest: rest.join("."),
        }),
        None => unreachable!("inserted above"),
    }
}

fn is_index(seg: &str) -> bool {
    seg == "*" || seg.parse::<usize>().is_ok()
}

/// Sets `segs` (starting with an index or `*`) under the array `a` at path `at`.
fn set_in_array(
    a: &mut [Value],
    segs: &[&str],
    value: &Value,
    at: &str,
) -> std::result::Result<usize, OverrideError> {
    let (index, rest) = (segs[0], &segs[1..]);
    let range = if index == "*" {
        0..a.len()
    } else {
        let i: usize = index.parse().map_err(|_| OverrideError::NotAnIndex {
            at: at.to_string(),
            last: a.len().saturating_sub(1),
            index: index.to_string(),
        })?;
        if i >= a.len() {
            return Err(OverrideError::OutOfRange {
                at: at.to_string(),
                len: a.len(),
                last: a.len().saturating_sub(1),
                index: i,
            });
        }
        i..i + 1
    };
    let mut n = 0;
    for i in range {
        let here = format!("{at}.{i}");
        if rest.is_empty() {
            a[i] = value.clone();
            n += 1;
            continue;
        }
        match &mut a[i] {
            Value::Table(t) => n += set_in_table(t, rest, value, &here)?,
            Value::Array(inner) => n += set_in_array(inner, rest, value, &here)?,
            other => {
                return Err(OverrideError::NotATable {
                    at: here,
                    value: other.to_string(),
                    rest: rest.join("."),
                });
            }
        }
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> Table {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn values_are_toml_or_strings() {
        assert_eq!(parse_value("5"), Value::Integer(5));
        assert_eq!(parse_value("0.05"), Value::Float(0.05));
        assert_eq!(parse_value("rk4"), Value::String("rk4".into()));
        assert_eq!(parse_value("\"rk4\""), Value::String("rk4".into()));
        assert!(matches!(parse_value("[0, 0, -50]"), Value::Array(a) if a.len() == 3));
    }

    #[test]
    fn paths_index_arrays_create_tables_and_expand_aliases() {
        let mut t = table("[[cage]]\ntype = \"SSM\"\n[[cage]]\ntype = \"CSM\"\n");
        let o: Override = "cage.1.element_length=5".parse().unwrap();
        assert_eq!(o.apply(&mut t).unwrap(), 1);
        assert_eq!(t["cage"][1]["element_length"], Value::Integer(5));
        assert!(t["cage"][0].get("element_length").is_none());
        let o: Override = "element_length=2.5".parse().unwrap();
        assert_eq!(o.apply(&mut t).unwrap(), 2);
        assert_eq!(t["cage"][0]["element_length"], Value::Float(2.5));
        let o: Override = "dt=0.05".parse().unwrap();
        o.apply(&mut t).unwrap();
        assert_eq!(t["analysis"]["dynamic"]["dt"], Value::Float(0.05));
        let o: Override = "cage.*.net.solidity=0.2".parse().unwrap();
        assert_eq!(o.apply(&mut t).unwrap(), 2);
        assert_eq!(t["cage"][1]["net"]["solidity"], Value::Float(0.2));
    }

    #[test]
    fn bad_paths_say_what_is_there() {
        let mut t = table("[[cage]]\ntype = \"SSM\"\n[sea]\ndepth = 60\n");
        let e = "cage.3.x=1".parse::<Override>().unwrap().apply(&mut t);
        assert!(e.unwrap_err().to_string().contains("cage has 1 entries"));
        let e = "line.0.segments=1"
            .parse::<Override>()
            .unwrap()
            .apply(&mut t);
        assert!(e.unwrap_err().to_string().contains("no line entries"));
        let e = "sea.depth.x=1".parse::<Override>().unwrap().apply(&mut t);
        assert!(
            e.unwrap_err()
                .to_string()
                .contains("sea.depth is the value 60")
        );
        let e = "segments=10".parse::<Override>().unwrap().apply(&mut t);
        assert!(
            e.unwrap_err()
                .to_string()
                .contains("nothing to set at line.*.segments")
        );
        assert!("cage..x=1".parse::<Override>().is_err());
        assert!("cage.0.x".parse::<Override>().is_err());
    }
}
