//! Diagnostics: what checking, building or running a scene has to tell the user besides an
//! error — a value outside a model's fit range, a physics effect skipped, a step reduced.

use serde::Serialize;
use std::fmt;

/// How much a diagnostic matters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Informative.
    Note,
    /// The run goes on, but a result may not mean what the user expects.
    Warning,
}

/// One diagnostic: a stable code, a severity, where it comes from, and the message.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Diagnostic {
    /// Stable code, `<source>/<kind>` (e.g. `sea/range`, `hydro/fit-range`).
    pub code: &'static str,
    /// Severity.
    pub severity: Severity,
    /// Where: a scene section or object, or the solver stage ("statics", "dynamics").
    pub location: String,
    /// What happened, in words (says what the user can change).
    pub message: String,
}

impl Diagnostic {
    /// A warning.
    pub fn warning(
        code: &'static str,
        location: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Self {
            code,
            severity: Severity::Warning,
            location: location.into(),
            message: message.into(),
        }
    }

    /// Diagnostics from the plain messages a lower crate returns: a `notice: ` message is a
    /// note, anything else a warning (a `warning: ` prefix is dropped).
    pub fn warnings<'a>(
        code: &'static str,
        location: &str,
        messages: impl IntoIterator<Item = &'a String>,
    ) -> Vec<Self> {
        messages
            .into_iter()
            .map(|m| {
                // Lower crates prefix their messages with `notice: ` or `warning: `; the
                // severity carries that here, so it is not printed twice.
                if let Some(rest) = m.strip_prefix("notice: ") {
                    Self {
                        severity: Severity::Note,
                        ..Self::warning(code, location, rest)
                    }
                } else {
                    Self::warning(code, location, m.strip_prefix("warning: ").unwrap_or(m))
                }
            })
            .collect()
    }
}

impl fmt::Display for Diagnostic {
    /// `warning: <message>` (the location and code are for programs; messages already name
    /// what they are about).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self.severity {
            Severity::Note => "note",
            Severity::Warning => "warning",
        };
        write!(f, "{s}: {}", self.message)
    }
}
