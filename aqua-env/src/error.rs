//! Typed errors of the sea-state crate.

use thiserror::Error;

/// Everything that can be wrong with a sea description.
///
/// Messages name the key (as written in the scene's `[sea]` table), the offending value and what
/// would be valid, so the CLI can print them unchanged.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EnvError {
    /// A value is outside its valid range.
    #[error("{key} = {value}: {valid}")]
    OutOfRange {
        /// Scene key, e.g. `sea.waves.height`.
        key: String,
        /// The value as the user wrote it.
        value: String,
        /// What would be valid.
        valid: String,
    },
    /// A key is required by another setting but missing.
    #[error("{key} is missing: {why}")]
    Missing {
        /// Scene key that must be given.
        key: String,
        /// Why it is needed.
        why: String,
    },
    /// The dispersion relation did not converge (never expected for ω > 0, h > 0).
    #[error("dispersion relation did not converge for omega = {omega} rad/s, depth = {depth} m")]
    Dispersion {
        /// Angular frequency [rad/s].
        omega: f64,
        /// Water depth [m].
        depth: f64,
    },
}

impl EnvError {
    /// Shorthand for [`EnvError::OutOfRange`].
    pub fn range(key: impl Into<String>, value: impl ToString, valid: impl Into<String>) -> Self {
        Self::OutOfRange {
            key: key.into(),
            value: value.to_string(),
            valid: valid.into(),
        }
    }

    /// Shorthand for [`EnvError::Missing`].
    pub fn missing(key: impl Into<String>, why: impl Into<String>) -> Self {
        Self::Missing {
            key: key.into(),
            why: why.into(),
        }
    }
}
