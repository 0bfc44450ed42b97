//! Why a Newton attempt, a static increment or a time step was rejected: a typed reason, its
//! kind (the key the step control counts halvings by) and the hint that fits the reason and the
//! scheme that met it (docs/theory/fem.md#step-control).

use crate::error::{FemError, LoadError};
use serde::{Deserialize, Serialize};
use std::fmt;
use thiserror::Error;

/// Why an attempt failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FailureReason {
    /// The residual became NaN or infinite.
    #[error("non-finite residual")]
    NonFiniteResidual,
    /// The residual grew by more than 1e4 over the attempt's first.
    #[error("residual grew by more than 1e4")]
    ResidualGrew,
    /// The iteration limit was reached.
    #[error("no convergence in {iterations} Newton iterations")]
    NoConvergence {
        /// The limit (`max_iter`).
        iterations: usize,
    },
    /// A member's strain passed the `max_strain` guard.
    #[error("strain {strain:.3e} beyond max_strain {max_strain}")]
    StrainLimit {
        /// The strain found.
        strain: f64,
        /// The guard.
        max_strain: f64,
    },
    /// Line relaxation carried a slack-to-taut front across more elements than the scheme
    /// resolves in one step (docs/theory/fem.md#line-relaxation-hht).
    #[error("a line tightened across more than {limit} elements within the step")]
    LineFront {
        /// The scheme's limit.
        limit: usize,
    },
    /// A loaded element reversed its direction within one step.
    #[error(
        "element {element} turned over in one step (its direction reversed while it carried load)"
    )]
    ElementTurnedOver {
        /// Element index.
        element: usize,
    },
    /// A net triangle's twine family reversed its direction within one step.
    #[error(
        "net triangle {triangle}: its {family} twines turned over in one step (their direction \
         reversed while they carried load)"
    )]
    TwinesTurnedOver {
        /// Triangle index.
        triangle: usize,
        /// "U" or "V".
        family: &'static str,
    },
    /// The converged step created energy beyond the guard's tolerance.
    #[error(
        "the step created energy ({created:.3e} J, {:.1} % of {scale:.3e} J)",
        100.0 * created / scale
    )]
    EnergyCreated {
        /// Energy created [J].
        created: f64,
        /// The energy scale it is compared with [J].
        scale: f64,
    },
    /// A converged step sampled the crest of a group's peak tension too coarsely for
    /// `extreme_tolerance` (docs/theory/fem.md#extremes-to-a-tolerance).
    #[error(
        "group {group}'s peak tension would be resolved to {:.2} % only (extreme_tolerance {:.2} %)",
        100.0 * error,
        100.0 * tolerance
    )]
    ExtremeUnresolved {
        /// Element group index.
        group: usize,
        /// Estimated relative crest error.
        error: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// No damped static step lowers the energy.
    #[error("no step lowers the energy (damping exhausted): the structure may have no equilibrium")]
    DampingExhausted,
    /// The observer asked to stop.
    #[error("interrupted")]
    Interrupted,
    /// The load provider failed.
    #[error("{0}")]
    Load(LoadError),
    /// Evaluating, factorising or solving the system failed.
    #[error("{0}")]
    Solver(Box<FemError>),
}

impl From<FemError> for FailureReason {
    fn from(e: FemError) -> Self {
        Self::Solver(Box::new(e))
    }
}

/// The kind of a [`FailureReason`], without its numbers: what the step control counts
/// halvings by (`step_control.reasons` in run.json, as its text).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FailureKind {
    /// [`FailureReason::NonFiniteResidual`].
    #[serde(rename = "non-finite residual")]
    NonFiniteResidual,
    /// [`FailureReason::ResidualGrew`].
    #[serde(rename = "residual grew by more than …")]
    ResidualGrew,
    /// [`FailureReason::NoConvergence`].
    #[serde(rename = "no convergence in … Newton iterations")]
    NoConvergence,
    /// [`FailureReason::StrainLimit`].
    #[serde(rename = "strain … beyond max_strain …")]
    StrainLimit,
    /// [`FailureReason::LineFront`].
    #[serde(rename = "a line tightened across more than … elements within the step")]
    LineFront,
    /// [`FailureReason::ElementTurnedOver`].
    #[serde(rename = "element … turned over in one step")]
    ElementTurnedOver,
    /// [`FailureReason::TwinesTurnedOver`].
    #[serde(rename = "net triangle …: its … twines turned over in one step")]
    TwinesTurnedOver,
    /// [`FailureReason::EnergyCreated`].
    #[serde(rename = "the step created energy")]
    EnergyCreated,
    /// [`FailureReason::ExtremeUnresolved`].
    #[serde(rename = "a peak tension would not be resolved to extreme_tolerance")]
    ExtremeUnresolved,
    /// [`FailureReason::DampingExhausted`].
    #[serde(rename = "no step lowers the energy")]
    DampingExhausted,
    /// [`FailureReason::Interrupted`].
    #[serde(rename = "interrupted")]
    Interrupted,
    /// [`FailureReason::Load`].
    #[serde(rename = "load provider")]
    Load,
    /// [`FailureReason::Solver`].
    #[serde(rename = "linear algebra or evaluation")]
    Solver,
}

impl FailureKind {
    /// The kind's text (as written in run.json).
    pub fn as_str(self) -> &'static str {
        match self {
            Self::NonFiniteResidual => "non-finite residual",
            Self::ResidualGrew => "residual grew by more than …",
            Self::NoConvergence => "no convergence in … Newton iterations",
            Self::StrainLimit => "strain … beyond max_strain …",
            Self::LineFront => "a line tightened across more than … elements within the step",
            Self::ElementTurnedOver => "element … turned over in one step",
            Self::TwinesTurnedOver => "net triangle …: its … twines turned over in one step",
            Self::EnergyCreated => "the step created energy",
            Self::ExtremeUnresolved => "a peak tension would not be resolved to extreme_tolerance",
            Self::DampingExhausted => "no step lowers the energy",
            Self::Interrupted => "interrupted",
            Self::Load => "load provider",
            Self::Solver => "linear algebra or evaluation",
        }
    }
}

impl fmt::Display for FailureKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The time scheme a failure met, for the hint that fits it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SchemeKind {
    /// The static solver.
    Statics,
    /// HHT-α.
    Hht,
    /// The energy-consistent midpoint rule.
    Midpoint,
}

impl FailureReason {
    /// The reason's kind.
    pub fn kind(&self) -> FailureKind {
        match self {
            Self::NonFiniteResidual => FailureKind::NonFiniteResidual,
            Self::ResidualGrew => FailureKind::ResidualGrew,
            Self::NoConvergence { .. } => FailureKind::NoConvergence,
            Self::StrainLimit { .. } => FailureKind::StrainLimit,
            Self::LineFront { .. } => FailureKind::LineFront,
            Self::ElementTurnedOver { .. } => FailureKind::ElementTurnedOver,
            Self::TwinesTurnedOver { .. } => FailureKind::TwinesTurnedOver,
            Self::EnergyCreated { .. } => FailureKind::EnergyCreated,
            Self::ExtremeUnresolved { .. } => FailureKind::ExtremeUnresolved,
            Self::DampingExhausted => FailureKind::DampingExhausted,
            Self::Interrupted => FailureKind::Interrupted,
            Self::Load(_) => FailureKind::Load,
            Self::Solver(_) => FailureKind::Solver,
        }
    }

    /// What a user can change about this failure under `scheme`: the knobs named are those
    /// the scheme has (HHT-α's `alpha`/`rho_inf`, the midpoint rule's `theta`, the static
    /// solver's `load_steps`/`max_iter`).
    pub fn hint(&self, scheme: SchemeKind) -> String {
        let damping = match scheme {
            SchemeKind::Hht => {
                "a larger `alpha` or a smaller `rho_inf` (HHT-α's high-frequency damping), or \
                 the midpoint rule"
            }
            SchemeKind::Midpoint => {
                "`theta` above 0.5 (the energy-decaying midpoint rule, e.g. 0.6 to 0.75)"
            }
            SchemeKind::Statics => "more `load_steps` or `max_iter`",
        };
        let step = match scheme {
            SchemeKind::Statics => "smaller load increments",
            _ => "a smaller dt",
        };
        match self {
            Self::StrainLimit { .. } => format!(
                "a strain this large is not physical for a rope or net: check the section's \
                 stiffness (EA) and the loads; raise `max_strain` only if it is meant; or {step}"
            ),
            Self::EnergyCreated { .. } => format!("{step}, {damping}"),
            Self::ElementTurnedOver { .. } | Self::TwinesTurnedOver { .. } => format!(
                "{step} (the member would pass through zero length within the step), or {damping}"
            ),
            Self::LineFront { .. } => format!("{step}, or the midpoint rule"),
            Self::ExtremeUnresolved { .. } => {
                "a larger `extreme_tolerance` or a smaller `dt_min`".into()
            }
            Self::DampingExhausted => "check that the structure is held (supports, anchors, \
                 buoyancy against weight) and that the loads can be carried"
                .into(),
            Self::Interrupted => "none: the run was stopped on request".into(),
            Self::Load(_) => "check the sea and load input the message names".into(),
            Self::NonFiniteResidual
            | Self::ResidualGrew
            | Self::NoConvergence { .. }
            | Self::Solver(_) => {
                format!("{step}, {damping}, check supports and slack parts")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hints_name_only_the_schemes_own_knobs() {
        let reasons = [
            FailureReason::NonFiniteResidual,
            FailureReason::EnergyCreated {
                created: 1.0,
                scale: 10.0,
            },
            FailureReason::NoConvergence { iterations: 20 },
        ];
        for r in &reasons {
            let hht = r.hint(SchemeKind::Hht);
            let mid = r.hint(SchemeKind::Midpoint);
            let st = r.hint(SchemeKind::Statics);
            assert!(hht.contains("alpha") && !hht.contains("theta"), "{hht}");
            assert!(mid.contains("theta") && !mid.contains("alpha"), "{mid}");
            assert!(
                !st.contains("theta") && !st.contains("alpha") && !st.contains("dt"),
                "{st}"
            );
        }
    }

    #[test]
    fn every_kind_text_is_its_serde_name() {
        use FailureKind::*;
        for k in [
            NonFiniteResidual,
            ResidualGrew,
            NoConvergence,
            StrainLimit,
            LineFront,
            ElementTurnedOver,
            TwinesTurnedOver,
            EnergyCreated,
            ExtremeUnresolved,
            DampingExhausted,
            Interrupted,
            Load,
            Solver,
        ] {
            let json = serde_json::to_string(&k).unwrap();
            assert_eq!(json, format!("\"{}\"", k.as_str()));
        }
    }
}
