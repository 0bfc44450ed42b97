//! Net-to-net wake: the current (never the waves) on the downstream part of a cage is reduced
//! by a factor r ∈ [0, 1] (docs/theory/hydrodynamics.md#wake-models).
//!
//! Models: `none` (r = 1), `factor` (r = clamp(f, 0, 1)), `loland`
//! (r = 1 − 0.46·C_D0, C_D0 = Sn − 1.24Sn² + 13.7Sn³ unless given), `cheng`
//! (r = clamp((c + 0.05 − 0.38Sn)/(c + 0.05), 0, 1), c = |n·û_c| with the oriented normal).
//! An element is in the shadow iff (c_e − o)_h·û_h > margin, o the horizontal centroid of the
//! cage's net nodes and û_h the horizontal direction of the unramped current at c_e.

use crate::error::{HydroError, check_non_negative};
use aqua_env::Sea;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Wake model ids as written in the scene (`net.wake.model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WakeModelId {
    /// No wake.
    None,
    /// Constant factor.
    Factor,
    /// Løland 1991.
    Loland,
    /// Cheng et al. (angle dependent).
    Cheng,
}

impl WakeModelId {
    /// All ids.
    pub const ALL: [WakeModelId; 4] = [Self::None, Self::Factor, Self::Loland, Self::Cheng];
    /// The valid ids for error messages.
    pub const VALID: &'static str = "none, factor, loland, cheng";

    /// The id as written in scene files.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Factor => "factor",
            Self::Loland => "loland",
            Self::Cheng => "cheng",
        }
    }
}

impl fmt::Display for WakeModelId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for WakeModelId {
    type Err = HydroError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|id| id.as_str() == s)
            .ok_or_else(|| HydroError::UnknownModel {
                kind: "wake",
                given: s.to_string(),
                valid: Self::VALID,
            })
    }
}

/// When shadow membership and factors are recomputed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WakeUpdate {
    /// At the start of every time step, and in statics near and at the equilibrium (re-solved
    /// while it changes; docs/theory/fem.md#static-solver).
    #[default]
    Step,
    /// Once, from the initial geometry.
    Frozen,
}

/// The scene table `net.wake = { model = "loland", update = "step", ... }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WakeSpec {
    /// Model id.
    pub model: WakeModelId,
    /// Factor of the `factor` model.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factor: Option<f64>,
    /// Normal-incidence drag coefficient of the `loland` model (default: S1's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cd0: Option<f64>,
    /// Update policy.
    #[serde(default)]
    pub update: WakeUpdate,
    /// Shadow margin δ [m].
    #[serde(default)]
    pub margin: f64,
    /// Also reduce the current on the cage's ropes and pipes.
    #[serde(default)]
    pub apply_to_lines: bool,
}

/// A wake model with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WakeModel {
    /// r = 1.
    None,
    /// r = clamp(f, 0, 1).
    Factor(f64),
    /// r = 1 − 0.46·C_D0.
    Loland {
        /// C_D0 override.
        cd0: Option<f64>,
    },
    /// r = clamp((c + 0.05 − 0.38Sn)/(c + 0.05), 0, 1).
    Cheng,
}

impl WakeModel {
    /// The model's id.
    pub fn id(&self) -> WakeModelId {
        match self {
            Self::None => WakeModelId::None,
            Self::Factor(_) => WakeModelId::Factor,
            Self::Loland { .. } => WakeModelId::Loland,
            Self::Cheng => WakeModelId::Cheng,
        }
    }

    /// The factor r for a net of solidity `sn` and c = |n·û_c| (1 for twines and lines).
    pub fn factor(&self, sn: f64, c: f64) -> f64 {
        match *self {
            Self::None => 1.0,
            Self::Factor(f) => f.clamp(0.0, 1.0),
            Self::Loland { cd0 } => {
                let cd0 = cd0.unwrap_or_else(|| loland_cd0(sn));
                (1.0 - 0.46 * cd0).clamp(0.0, 1.0)
            }
            Self::Cheng => {
                let c = c.clamp(0.0, 1.0);
                ((c + 0.05 - 0.38 * sn) / (c + 0.05)).clamp(0.0, 1.0)
            }
        }
    }
}

/// S1's normal-incidence drag coefficient Sn − 1.24Sn² + 13.7Sn³ (Løland's C_D0).
pub fn loland_cd0(sn: f64) -> f64 {
    sn - 1.24 * sn * sn + 13.7 * sn * sn * sn
}

/// A wake configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wake {
    /// Model.
    pub model: WakeModel,
    /// Update policy.
    pub update: WakeUpdate,
    /// Shadow margin δ [m].
    pub margin: f64,
    /// Also reduce ropes and pipes of the cage.
    pub apply_to_lines: bool,
}

impl Wake {
    /// No wake.
    pub fn none() -> Self {
        Self {
            model: WakeModel::None,
            update: WakeUpdate::Step,
            margin: 0.0,
            apply_to_lines: false,
        }
    }
}

impl WakeSpec {
    /// Validates the table.
    pub fn build(&self) -> Result<Wake, HydroError> {
        if self.factor.is_some() && self.model != WakeModelId::Factor {
            return Err(HydroError::key(
                "net.wake.factor",
                format!(
                    "only used with model = \"factor\" (model is \"{}\"); remove it",
                    self.model
                ),
            ));
        }
        if self.cd0.is_some() && self.model != WakeModelId::Loland {
            return Err(HydroError::key(
                "net.wake.cd0",
                format!(
                    "only used with model = \"loland\" (model is \"{}\"); remove it",
                    self.model
                ),
            ));
        }
        if !self.margin.is_finite() {
            return Err(HydroError::range(
                "net.wake.margin",
                self.margin,
                "a finite distance in m",
            ));
        }
        let model = match self.model {
            WakeModelId::None => WakeModel::None,
            WakeModelId::Factor => {
                let f = self.factor.ok_or_else(|| {
                    HydroError::key(
                        "net.wake.factor",
                        "model = \"factor\" needs factor (0 <= factor <= 1, e.g. 0.8)",
                    )
                })?;
                if !f.is_finite() {
                    return Err(HydroError::range(
                        "net.wake.factor",
                        f,
                        "a number in [0, 1]",
                    ));
                }
                WakeModel::Factor(f)
            }
            WakeModelId::Loland => {
                if let Some(c) = self.cd0 {
                    check_non_negative("net.wake.cd0", c, "-")?;
                }
                WakeModel::Loland { cd0: self.cd0 }
            }
            WakeModelId::Cheng => WakeModel::Cheng,
        };
        Ok(Wake {
            model,
            update: self.update,
            margin: self.margin,
            apply_to_lines: self.apply_to_lines,
        })
    }
}

/// The wake state of one element, for output: shadowed or not, and its factor r.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WakeCell {
    /// True if the element is in its cage's shadow.
    pub in_shadow: bool,
    /// Current reduction factor r ∈ [0, 1] (1 outside the shadow).
    pub factor: f64,
}

impl Default for WakeCell {
    fn default() -> Self {
        Self {
            in_shadow: false,
            factor: 1.0,
        }
    }
}

/// The unramped current [m/s] at point p and time t (for the shadow direction only).
pub(crate) fn unramped_current(sea: &Sea, p: [f64; 3], t: f64) -> [f64; 3] {
    sea.current().unramped_velocity(p[2], t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_values() {
        let sn: f64 = 0.2056;
        assert!((loland_cd0(sn) - 0.2722500987).abs() < 5e-11);
        let r = WakeModel::Loland { cd0: None }.factor(sn, 1.0);
        assert!((r - 0.8747649546).abs() < 5e-11);
        let c = WakeModel::Cheng;
        assert!((c.factor(0.15, 1.0) - 0.9457142857).abs() < 5e-11);
        assert!((c.factor(0.15, 60f64.to_radians().cos()) - 0.8963636364).abs() < 5e-11);
        assert_eq!(c.factor(0.3, 0.0), 0.0);
        assert_eq!(WakeModel::Factor(1.4).factor(0.2, 1.0), 1.0);
    }

    #[test]
    fn spec_errors() {
        let s = WakeSpec {
            model: WakeModelId::Factor,
            factor: None,
            cd0: None,
            update: WakeUpdate::Step,
            margin: 0.0,
            apply_to_lines: false,
        };
        assert!(
            s.build()
                .unwrap_err()
                .to_string()
                .contains("net.wake.factor")
        );
        let s = WakeSpec {
            model: WakeModelId::Cheng,
            factor: Some(0.5),
            ..s
        };
        assert!(s.build().is_err());
        let e = "wake9".parse::<WakeModelId>().unwrap_err().to_string();
        assert!(e.contains("loland") && e.contains("cheng"));
    }
}
