//! Typed errors of the water-load crate.

use thiserror::Error;

/// Everything that can be wrong with a load-model description.
///
/// Messages name the key (as written in the scene), the offending value and what would be
/// valid, so the CLI can print them unchanged.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum HydroError {
    /// A model id that does not exist.
    #[error("unknown {kind} model \"{given}\"; valid models: {valid}")]
    UnknownModel {
        /// Which catalogue: "screen", "morison" or "wake".
        kind: &'static str,
        /// What the user wrote.
        given: String,
        /// The valid ids, comma separated.
        valid: &'static str,
    },
    /// A value outside its valid range.
    #[error("{key} = {value}: {valid}")]
    OutOfRange {
        /// Scene key or parameter name, e.g. `net.solidity` or `panel 12 solidity`.
        key: String,
        /// The offending value.
        value: String,
        /// What would be valid.
        valid: String,
    },
    /// A key that the chosen model needs is missing, or a key the model does not use is given.
    #[error("{key}: {why}")]
    Key {
        /// Scene key.
        key: String,
        /// What is wrong and how to fix it.
        why: String,
    },
    /// A wake model is set on a group that has no net to shadow.
    #[error(
        "wake group {group} (\"{name}\"): wake model \"{model}\" needs a cage net to shadow, but the group has no net panels or net twines; use model = \"none\""
    )]
    WakeWithoutNet {
        /// Index of the wake group.
        group: usize,
        /// Its name.
        name: String,
        /// The wake model id.
        model: &'static str,
    },
}

impl HydroError {
    /// Shorthand for [`HydroError::OutOfRange`].
    pub fn range(key: impl Into<String>, value: impl ToString, valid: impl Into<String>) -> Self {
        Self::OutOfRange {
            key: key.into(),
            value: value.to_string(),
            valid: valid.into(),
        }
    }

    /// Shorthand for [`HydroError::Key`].
    pub fn key(key: impl Into<String>, why: impl Into<String>) -> Self {
        Self::Key {
            key: key.into(),
            why: why.into(),
        }
    }
}

/// Checks 0 < value < 1 (solidity).
pub(crate) fn check_solidity(key: &str, sn: f64) -> Result<(), HydroError> {
    if sn > 0.0 && sn < 1.0 {
        Ok(())
    } else {
        Err(HydroError::range(
            key,
            sn,
            "solidity must satisfy 0 < Sn < 1 (typical nets 0.1-0.35)",
        ))
    }
}

/// Checks value > 0 and finite.
pub(crate) fn check_positive(key: &str, v: f64, unit: &str) -> Result<(), HydroError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(HydroError::range(
            key,
            v,
            format!("must be a finite number > 0 [{unit}]"),
        ))
    }
}

/// Checks value >= 0 and finite.
pub(crate) fn check_non_negative(key: &str, v: f64, unit: &str) -> Result<(), HydroError> {
    if v >= 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(HydroError::range(
            key,
            v,
            format!("must be a finite number >= 0 [{unit}]"),
        ))
    }
}
