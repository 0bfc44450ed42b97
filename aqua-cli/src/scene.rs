//! Reading scene files (TOML). Every error names the file and, through the TOML parser, the
//! line and key.

use crate::InputError;
use aqua_env::SeaSpec;
use std::path::Path;

/// Reads a file to a string, with an input error naming it.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    std::fs::read_to_string(path)
        .map_err(|e| InputError::new(format!("{}: cannot read: {e}", path.display())))
}

/// Reads the `[sea]` table of a scene file (a file holding only sea keys at top level is
/// accepted too, so a bare sea description can be shared between scenes).
pub fn read_sea(path: &Path) -> Result<SeaSpec, InputError> {
    /// A scene seen only for its `[sea]` table; the other sections are checked elsewhere.
    #[derive(serde::Deserialize)]
    struct SeaOnly {
        sea: SeaSpec,
        #[serde(flatten)]
        _rest: toml::Table,
    }
    let text = read_text(path)?;
    let table: toml::Table =
        toml::from_str(&text).map_err(|e| InputError::new(format!("{}: {e}", path.display())))?;
    let err = |e: toml::de::Error| InputError::new(format!("{}: {e}", path.display()));
    if table.contains_key("sea") {
        toml::from_str::<SeaOnly>(&text).map(|s| s.sea).map_err(err)
    } else {
        toml::from_str::<SeaSpec>(&text).map_err(err)
    }
}
