//! `[[farm.slot]]`: what one cell of a `[[farm]]` holds instead of `[farm.cage]`
//! (docs/theory/cages.md#farm-grid): a cage of its own, or nothing (`empty = true`).
//!
//! A slot's cage is the `[farm.cage]` TOML table with the slot's keys laid over it before
//! typing, so every cage key works in a slot and is checked as in `[farm.cage]`:
//!
//! * nested tables (`net`, `collar`, `groups.<name>`) are merged key by key;
//! * `circumference`, `diameter` and `side` are one size: a slot giving any of them replaces
//!   the farm cage's;
//! * a slot whose `type` differs from the farm cage's does not inherit the farm cage's keys
//!   its own type does not take (e.g. `diameter` for an SSM, `tube_depth` for a CSM).

use super::{CageSpec, Ctx, Located, NET_HYDRO_KEYS, NetHydro, line_of, split_keys};
use crate::error::Result;
use aqua_mesh::{CageParams, CageType, FarmParams};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use toml::{Spanned, Table, Value};

/// `[[farm.slot]]`: one cell of a farm.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlotSpec {
    /// Row r, 1..=rows (along y).
    pub row: u32,
    /// Column c, 1..=columns (along x).
    pub column: u32,
    /// The slot's cage (`[farm.cage]` with the slot's keys over it); `None` for an empty cell.
    pub cage: Option<CageSpec>,
}

/// The keys of a slot that are not cage keys.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SlotKeys {
    /// Integer, so that 0 or −1 get the range message rather than a type error.
    row: i64,
    column: i64,
    #[serde(default)]
    empty: bool,
}

pub(super) const SLOT_KEYS: &[&str] = &["row", "column", "empty"];

/// The cage keys that give the size: a slot's replaces all of the farm cage's.
const SIZE_KEYS: &[&str] = &["circumference", "diameter", "side"];

/// Lays `over` onto `base`, merging tables key by key.
fn merge_over(base: &mut Table, over: Table) {
    for (k, v) in over {
        match (base.get_mut(&k), v) {
            (Some(Value::Table(b)), Value::Table(o)) => merge_over(b, o),
            (_, v) => {
                base.insert(k, v);
            }
        }
    }
}

/// The canonical cage type of a raw `type` value, if it is one.
fn cage_type(v: Option<&Value>) -> Option<CageType> {
    v.and_then(|t| t.clone().try_into::<CageType>().ok())
        .map(CageType::canonical)
}

/// The raw cage table of a slot: `base` (`[farm.cage]`) with `slot` over it (module docs).
fn merged_cage(base: &Table, slot: Table) -> Table {
    let mut merged = base.clone();
    if SIZE_KEYS.iter().any(|k| slot.contains_key(*k)) {
        merged.retain(|k, _| !SIZE_KEYS.contains(&k));
    }
    if let Some(kind) = cage_type(slot.get("type"))
        && cage_type(base.get("type")) != Some(kind)
    {
        let valid = kind.valid_keys();
        merged.retain(|k, _| valid.contains(&k));
    }
    merge_over(&mut merged, slot);
    merged
}

/// The scene lines of the `[[farm.slot]]` tables of every farm (empty where the text does not
/// say, e.g. a slot array that is not of tables: the farm's line is used then).
fn slot_lines(text: &str) -> Vec<Vec<usize>> {
    #[derive(Deserialize)]
    struct Farm {
        #[serde(default)]
        slot: Vec<Spanned<Table>>,
        #[serde(flatten)]
        _rest: Table,
    }
    #[derive(Deserialize)]
    struct File {
        #[serde(default)]
        farm: Vec<Farm>,
        #[serde(flatten)]
        _rest: Table,
    }
    toml::from_str::<File>(text)
        .map(|f| {
            f.farm
                .iter()
                .map(|farm| {
                    farm.slot
                        .iter()
                        .map(|s| line_of(text, s.span().start))
                        .collect()
                })
                .collect()
        })
        .unwrap_or_default()
}

impl Ctx<'_> {
    /// The `[[farm.slot]]` tables of farm #i (header at `line`), checked against the grid of
    /// `params`; each cage is `base` (the raw `[farm.cage]`) with the slot's keys over it.
    pub(super) fn farm_slots(
        &self,
        i: usize,
        line: usize,
        slots: Option<Value>,
        base: &Table,
        params: &FarmParams,
    ) -> Result<Vec<Located<SlotSpec>>> {
        let list = match slots {
            None => return Ok(Vec::new()),
            Some(Value::Array(a)) => a,
            Some(other) => {
                return Err(self.err(
                    "farm",
                    i,
                    line,
                    format!(
                        "slot = {other}: slot must be an array of tables ([[farm.slot]] with row, \
                         column and either empty = true or [farm.cage] keys)"
                    ),
                ));
            }
        };
        let lines = slot_lines(self.text).get(i).cloned().unwrap_or_default();
        let mut seen: BTreeMap<(u32, u32), (usize, usize)> = BTreeMap::new();
        let mut out = Vec::new();
        for (k, v) in list.into_iter().enumerate() {
            let at = lines.get(k).copied().unwrap_or(line);
            let err =
                |msg: String| self.err("farm", i, at, format!("[[farm.slot]] #{}: {msg}", k + 1));
            let Value::Table(mut t) = v else {
                return Err(err(format!(
                    "{v}: a slot must be a table with row, column and cage keys or empty = true"
                )));
            };
            let keys: SlotKeys = Value::Table(split_keys(&mut t, SLOT_KEYS))
                .try_into()
                .map_err(|e: toml::de::Error| err(e.to_string().trim().to_string()))?;
            let grid_err = |e: GridIndexError| err(e.to_string());
            let row = in_grid("row", keys.row, params.rows, "rows").map_err(grid_err)?;
            let column =
                in_grid("column", keys.column, params.columns, "columns").map_err(grid_err)?;
            if let Some((first, first_line)) = seen.insert((row, column), (k, at)) {
                return Err(err(format!(
                    "row = {row}, column = {column}: the cell is already given by [[farm.slot]] \
                     #{} at line {first_line}; give each cell at most one slot",
                    first + 1
                )));
            }
            let cage = if keys.empty {
                if !t.is_empty() {
                    let given: Vec<&str> = t.keys().map(String::as_str).collect();
                    return Err(err(format!(
                        "empty = true with cage keys ({}): an empty slot holds no cage; remove \
                         them or empty",
                        given.join(", ")
                    )));
                }
                None
            } else {
                let at_cell = |m: String| {
                    let m = format!(" (row {row}, column {column}): {m}");
                    self.err("farm", i, at, format!("[[farm.slot]] #{}{m}", k + 1))
                };
                let cage = self
                    .slot_cage(base, t)
                    .map_err(|e| at_cell(e.to_string()))?;
                params
                    .check_cage("cage", &cage.params)
                    .map_err(|e| at_cell(format!("{e}")))?;
                Some(cage)
            };
            out.push(Located {
                line: at,
                value: SlotSpec { row, column, cage },
            });
        }
        Ok(out)
    }

    /// A slot's cage typed from `base` with `slot` over it; the error of a bad key.
    fn slot_cage(&self, base: &Table, slot: Table) -> std::result::Result<CageSpec, SlotError> {
        let msg = |prefix: &'static str, e: toml::de::Error| SlotError::Key {
            prefix,
            message: e.to_string().trim().to_string(),
        };
        let mut t = merged_cage(base, slot);
        let hydro = match t.get_mut("net") {
            Some(Value::Table(net)) => split_keys(net, NET_HYDRO_KEYS),
            Some(other) => return Err(SlotError::NetNotTable(other.to_string())),
            None => Table::new(),
        };
        let net_hydro: NetHydro = Value::Table(hydro)
            .try_into()
            .map_err(|e| msg("in net: ", e))?;
        let params: CageParams = Value::Table(t).try_into().map_err(|e| msg("", e))?;
        Ok(CageSpec { params, net_hydro })
    }
}

/// A slot's cage keys that cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
enum SlotError {
    /// `net` given as something else than a table.
    #[error("net = {0}: net must be a table of net.* keys")]
    NetNotTable(String),
    /// A key the cage does not take or a value of the wrong type (the reader's message).
    #[error("{prefix}{message}{}", if message.contains("unknown field") {
        " (a slot takes row, column, empty and the [farm.cage] keys, which override \
         [farm.cage] in that cell)"
    } else {
        ""
    })]
    Key {
        /// `in net: ` for the net's keys.
        prefix: &'static str,
        /// The TOML reader's message.
        message: String,
    },
}

/// A slot's `row` or `column` outside the farm's grid.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{key} = {value}: must be 1..={n} (the farm has {count_key} = {n})")]
struct GridIndexError {
    key: &'static str,
    value: i64,
    n: u32,
    count_key: &'static str,
}

/// `v` as a 1-based grid index up to `n` (the farm's `count_key`), or what is valid.
fn in_grid(
    key: &'static str,
    v: i64,
    n: u32,
    count_key: &'static str,
) -> std::result::Result<u32, GridIndexError> {
    if v >= 1 && v <= i64::from(n) {
        Ok(v as u32)
    } else {
        Err(GridIndexError {
            key,
            value: v,
            n,
            count_key,
        })
    }
}
