//! Morison drag coefficients of lines: normal C_n and tangential C_t as functions of the
//! Reynolds number (docs/theory/hydrodynamics.md#morison-coefficients, #line-jacobians).

use crate::error::{HydroError, check_non_negative, check_solidity};
use crate::screen::clamp_re;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

/// Morison model ids as written in the scene (`morison = "M4"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum MorisonModelId {
    /// Bessonneau & Marichal 1998: C_n = 1.2, C_t = 0.1.
    M1,
    /// Wan 2002: C_n = 1.3, C_t = 0.
    M2,
    /// Takagi et al. 2004.
    M3,
    /// Choo & Casarella 1971 (corrected).
    M4,
    /// Cifuentes & Kim 2017 (net twines only).
    M5,
    /// User constants `cn`, `ct`.
    #[serde(rename = "const")]
    Const,
    /// No drag.
    #[serde(rename = "none")]
    None,
}

impl MorisonModelId {
    /// All ids, in catalogue order.
    pub const ALL: [MorisonModelId; 7] = [
        Self::M1,
        Self::M2,
        Self::M3,
        Self::M4,
        Self::M5,
        Self::Const,
        Self::None,
    ];
    /// The valid ids for error messages.
    pub const VALID: &'static str = "M1, M2, M3, M4, M5, const, none";

    /// The id as written in scene files.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::M1 => "M1",
            Self::M2 => "M2",
            Self::M3 => "M3",
            Self::M4 => "M4",
            Self::M5 => "M5",
            Self::Const => "const",
            Self::None => "none",
        }
    }

    /// The source of the model.
    pub fn reference(self) -> &'static str {
        match self {
            Self::M1 => "Bessonneau & Marichal 1998",
            Self::M2 => "Wan 2002",
            Self::M3 => "Takagi et al. 2004",
            Self::M4 => "Choo & Casarella 1971",
            Self::M5 => "Cifuentes & Kim 2017",
            Self::Const => "user constants",
            Self::None => "no drag",
        }
    }
}

impl fmt::Display for MorisonModelId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for MorisonModelId {
    type Err = HydroError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|id| id.as_str() == s)
            .ok_or_else(|| HydroError::UnknownModel {
                kind: "morison",
                given: s.to_string(),
                valid: Self::VALID,
            })
    }
}

/// A Morison drag model with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MorisonModel {
    /// C_n = 1.2, C_t = 0.1.
    M1,
    /// C_n = 1.3, C_t = 0.
    M2,
    /// C_n = 10^0.7·Re^(−0.3) below Re = 200, 1.2 above; C_t = 0.1.
    M3,
    /// Choo & Casarella piecewise C_n, C_t = π(0.55·Re^(−1/2) + 0.084·Re^(−1/3)).
    M4,
    /// Cifuentes & Kim: quadratic in X = min(Re·Sn², 100); C_t = 0.
    M5 {
        /// Solidity of the net the twine belongs to.
        solidity: f64,
    },
    /// User constants.
    Const {
        /// C_n ≥ 0.
        cn: f64,
        /// C_t ≥ 0.
        ct: f64,
    },
    /// No drag (inertia and buoyancy still act).
    None,
}

/// Coefficients and their Reynolds derivatives dC/dRe at one Reynolds number.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MorisonCoeffs {
    /// Normal drag coefficient C_n.
    pub cn: f64,
    /// Tangential drag coefficient C_t.
    pub ct: f64,
    /// dC_n/dRe.
    pub dcn: f64,
    /// dC_t/dRe.
    pub dct: f64,
    /// True when Re was clamped to 1e7.
    pub clamped: bool,
    /// True when M5's X was capped at 100.
    pub capped: bool,
}

/// M5 cap of X = Re·Sn².
pub const M5_X_CAP: f64 = 100.0;

impl MorisonModel {
    /// Builds a model from its scene id and the optional keys `cn`, `ct` (const only) and the
    /// net solidity (M5 only: net twines).
    pub fn new(
        id: MorisonModelId,
        cn: Option<f64>,
        ct: Option<f64>,
        net_solidity: Option<f64>,
    ) -> Result<Self, HydroError> {
        if id != MorisonModelId::Const {
            for (k, v) in [("cn", cn), ("ct", ct)] {
                if v.is_some() {
                    return Err(HydroError::key(
                        k,
                        format!(
                            "only used with morison = \"const\" (model is \"{id}\"); remove it"
                        ),
                    ));
                }
            }
        }
        Ok(match id {
            MorisonModelId::M1 => Self::M1,
            MorisonModelId::M2 => Self::M2,
            MorisonModelId::M3 => Self::M3,
            MorisonModelId::M4 => Self::M4,
            MorisonModelId::M5 => {
                let sn = net_solidity.ok_or_else(|| {
                    HydroError::key(
                        "morison",
                        "model \"M5\" needs the net solidity and is only valid for net twines",
                    )
                })?;
                check_solidity("net.solidity", sn)?;
                Self::M5 { solidity: sn }
            }
            MorisonModelId::Const => {
                let cn = cn.ok_or_else(|| {
                    HydroError::key(
                        "cn",
                        "morison = \"const\" needs cn (>= 0) and optionally ct",
                    )
                })?;
                check_non_negative("cn", cn, "-")?;
                let ct = ct.unwrap_or(0.0);
                check_non_negative("ct", ct, "-")?;
                Self::Const { cn, ct }
            }
            MorisonModelId::None => Self::None,
        })
    }

    /// The model's id.
    pub fn id(&self) -> MorisonModelId {
        match self {
            Self::M1 => MorisonModelId::M1,
            Self::M2 => MorisonModelId::M2,
            Self::M3 => MorisonModelId::M3,
            Self::M4 => MorisonModelId::M4,
            Self::M5 { .. } => MorisonModelId::M5,
            Self::Const { .. } => MorisonModelId::Const,
            Self::None => MorisonModelId::None,
        }
    }

    /// C_n, C_t and their derivatives at Reynolds number `re` (> 0; clamped to 1e7).
    pub fn coefficients(&self, re: f64) -> MorisonCoeffs {
        let (re, clamped) = clamp_re(re.max(f64::MIN_POSITIVE));
        let mut k = match *self {
            Self::M1 => MorisonCoeffs {
                cn: 1.2,
                ct: 0.1,
                ..Default::default()
            },
            Self::M2 => MorisonCoeffs {
                cn: 1.3,
                ..Default::default()
            },
            Self::M3 => {
                let (cn, dcn) = m3_normal(re);
                MorisonCoeffs {
                    cn,
                    ct: 0.1,
                    dcn,
                    ..Default::default()
                }
            }
            Self::M4 => {
                let (cn, dcn) = choo_casarella_normal(re);
                let r2 = re.sqrt();
                let r3 = re.cbrt();
                MorisonCoeffs {
                    cn,
                    dcn,
                    ct: PI * (0.55 / r2 + 0.084 / r3),
                    dct: PI * (-0.275 / (re * r2) - 0.028 / (re * r3)),
                    ..Default::default()
                }
            }
            Self::M5 { solidity } => {
                let s2 = solidity * solidity;
                let x = re * s2;
                if x < M5_X_CAP {
                    MorisonCoeffs {
                        cn: -3.2891e-5 * x * x + 6.8e-4 * x + 1.4253,
                        dcn: (-2.0 * 3.2891e-5 * x + 6.8e-4) * s2,
                        ..Default::default()
                    }
                } else {
                    let x = M5_X_CAP;
                    MorisonCoeffs {
                        cn: -3.2891e-5 * x * x + 6.8e-4 * x + 1.4253,
                        capped: true,
                        ..Default::default()
                    }
                }
            }
            Self::Const { cn, ct } => MorisonCoeffs {
                cn,
                ct,
                ..Default::default()
            },
            Self::None => MorisonCoeffs::default(),
        };
        if clamped {
            k.dcn = 0.0;
            k.dct = 0.0;
            k.clamped = true;
        }
        k
    }
}

/// Choo & Casarella normal coefficient (branches as published, with the corrected
/// 1 − exp(−Re/5.99e5) term) and its derivative on the active branch. `re` ≤ 1e7.
/// Half-width of the band around a joint of a piecewise C_n(Re) over which the two branches
/// are blended, relative to the joint's Re (docs/theory/hydrodynamics.md#joints-of-the-drag-laws).
pub const JOINT_BAND: f64 = 0.01;

/// C_n(Re) and dC_n/dRe of a piecewise law whose branch ends at `joint`: `left` below it,
/// `right` above, blended with a C¹ smoothstep in ln Re over Re ∈ joint·[1 − δ, 1 + δ]
/// (δ = [`JOINT_BAND`]), so the coefficient is continuous and the published branch holds
/// exactly outside the band. `None` outside the band.
fn across_joint(
    re: f64,
    joint: f64,
    left: impl Fn(f64) -> (f64, f64),
    right: impl Fn(f64) -> (f64, f64),
) -> Option<(f64, f64)> {
    let (lo, hi) = ((1.0 - JOINT_BAND).ln(), (1.0 + JOINT_BAND).ln());
    let u = (re / joint).ln();
    if u <= lo || u >= hi {
        return None;
    }
    let xi = (u - lo) / (hi - lo);
    let w = xi * xi * (3.0 - 2.0 * xi);
    let dw = 6.0 * xi * (1.0 - xi) / ((hi - lo) * re);
    let ((a, da), (b, db)) = (left(re), right(re));
    Some((a + w * (b - a), da + w * (db - da) + dw * (b - a)))
}

/// M3 normal coefficient: 10^0.7·Re^(−0.3) below Re = 200, 1.2 above, blended at the joint.
fn m3_normal(re: f64) -> (f64, f64) {
    let low = |re: f64| {
        let cn = 10f64.powf(0.7) * re.powf(-0.3);
        (cn, -0.3 * cn / re)
    };
    let high = |_: f64| (1.2, 0.0);
    if let Some(k) = across_joint(re, 200.0, low, high) {
        k
    } else if re < 200.0 {
        low(re)
    } else {
        high(re)
    }
}

/// Choo & Casarella's normal coefficient, branch by branch, blended at the joints Re = 1, 30,
/// 2.33e5 and 4.92e5.
fn choo_casarella_normal(re: f64) -> (f64, f64) {
    const JOINTS: [f64; 4] = [1.0, 30.0, 2.33e5, 4.92e5];
    for (j, &joint) in JOINTS.iter().enumerate() {
        if let Some(k) = across_joint(re, joint, |r| cc_branch(j, r), |r| cc_branch(j + 1, r)) {
            return k;
        }
    }
    let branch = JOINTS.iter().take_while(|&&joint| re >= joint).count();
    cc_branch(branch, re)
}

/// Branch `b` (0 … 4, in increasing Re) of Choo & Casarella's normal coefficient, and its
/// derivative, at any Re > 0.
fn cc_branch(b: usize, re: f64) -> (f64, f64) {
    if b == 0 {
        let s = -0.07721565 + (8.0 / re).ln();
        let si = 1.0 / s;
        let cn = 8.0 * PI * (1.0 - 0.87 * si * si) * si / re;
        // d/dRe of (s⁻¹ − 0.87 s⁻³)/Re with ds/dRe = −1/Re
        let d = ((si * si - 2.61 * si.powi(4)) - (si - 0.87 * si.powi(3))) / (re * re);
        (cn, 8.0 * PI * d)
    } else if b == 1 {
        (1.45 + 8.55 * re.powf(-0.9), -0.9 * 8.55 * re.powf(-1.9))
    } else if b == 2 {
        (1.1 + 4.0 / re.sqrt(), -2.0 * re.powf(-1.5))
    } else if b == 3 {
        (-3.41e-6 * (re - 5.78e5), -3.41e-6)
    } else {
        let e = (-re / 5.99e5).exp();
        (0.401 * (1.0 - e), 0.401 * e / 5.99e5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) {
        assert!((a - b).abs() <= tol, "{a} vs {b}");
    }

    #[test]
    fn m4_reference_values() {
        let k = MorisonModel::M4.coefficients(1000.0);
        close(k.cn, 1.2264911064, 5e-11);
        close(k.ct, 0.0810296138, 5e-11);
        close(MorisonModel::M4.coefficients(5e5).cn, 0.2269684010, 5e-11);
        close(MorisonModel::M4.coefficients(0.5).cn, 16.4155785275, 5e-11);
        let c7 = MorisonModel::M4.coefficients(1e7);
        let c2e7 = MorisonModel::M4.coefficients(2e7);
        close(c7.cn, 0.4009999775, 5e-11);
        assert_eq!(c7.cn, c2e7.cn);
        assert!(c2e7.clamped && c2e7.dcn == 0.0);
    }

    #[test]
    fn m5_reference_and_cap() {
        let m = MorisonModel::M5 { solidity: 0.2 };
        close(m.coefficients(40.0 / 0.04).cn, 1.3998744, 5e-8);
        let capped = m.coefficients(1e6);
        assert!(capped.capped);
        close(capped.cn, 1.164, 5e-4);
        assert!(capped.cn > 0.0);
    }

    #[test]
    fn constant_models_and_m3_jump() {
        assert_eq!(MorisonModel::M1.coefficients(1e3).cn, 1.2);
        assert_eq!(MorisonModel::M1.coefficients(1e3).ct, 0.1);
        assert_eq!(MorisonModel::M2.coefficients(1e3).cn, 1.3);
        assert_eq!(MorisonModel::M2.coefficients(1e3).ct, 0.0);
        // Outside the joint's band the published branches hold exactly.
        close(
            MorisonModel::M3.coefficients(195.0).cn,
            5.0119 * 195f64.powf(-0.3),
            5e-5,
        );
        assert_eq!(MorisonModel::M3.coefficients(205.0).cn, 1.2);
    }

    /// The spec's branches, written out independently of the implementation.
    fn published(m: MorisonModel, re: f64) -> f64 {
        match m {
            MorisonModel::M3 if re < 200.0 => 10f64.powf(0.7) * re.powf(-0.3),
            MorisonModel::M3 => 1.2,
            _ if re < 1.0 => {
                let s = -0.07721565 + (8.0 / re).ln();
                8.0 * PI * (1.0 - 0.87 / (s * s)) / (s * re)
            }
            _ if re < 30.0 => 1.45 + 8.55 * re.powf(-0.9),
            _ if re < 2.33e5 => 1.1 + 4.0 * re.powf(-0.5),
            _ if re < 4.92e5 => -3.41e-6 * (re - 5.78e5),
            _ => 0.401 * (1.0 - (-re / 5.99e5).exp()),
        }
    }

    /// The joints of M3 and M4 are blended over ±1 % of Re: outside the bands the published
    /// values, inside them a continuous coefficient (no jump between neighbouring samples
    /// larger than the blend's and the branches' slopes allow), with dC_n/dRe matching
    /// finite differences. A jump would make Newton cycle (docs/theory/hydrodynamics.md).
    #[test]
    fn joints_are_continuous_and_published_values_hold_outside_them() {
        for (m, joints) in [
            (MorisonModel::M3, vec![200.0]),
            (MorisonModel::M4, vec![1.0, 30.0, 2.33e5, 4.92e5]),
        ] {
            for joint in joints {
                for f in [0.985, 0.988, 1.012, 1.015] {
                    let re = joint * f;
                    let cn = m.coefficients(re).cn;
                    assert!(
                        (cn - published(m, re)).abs() <= 1e-12 * cn.abs().max(1.0),
                        "{m:?} Re {re}: {cn} vs published {}",
                        published(m, re)
                    );
                }
                let (lo, hi) = (
                    published(m, joint * (1.0 - JOINT_BAND)),
                    published(m, joint * (1.0 + JOINT_BAND)),
                );
                let jump = (hi - lo).abs();
                let n = 4000;
                let mut prev = m.coefficients(joint * (1.0 - JOINT_BAND)).cn;
                for k in 1..=n {
                    let re = joint * (1.0 - JOINT_BAND + 2.0 * JOINT_BAND * k as f64 / n as f64);
                    let c = m.coefficients(re);
                    // A smoothstep rises at most 1.5× its mean slope; the branches' own slope
                    // adds to it.
                    let dre = 2.0 * JOINT_BAND * joint / n as f64;
                    assert!(
                        (c.cn - prev).abs() <= 2.0 * jump / n as f64 + 2.0 * c.dcn.abs() * dre,
                        "{m:?} jump near Re {re}: {prev} -> {}",
                        c.cn
                    );
                    prev = c.cn;
                    if k % 97 == 0 {
                        let h = 1e-6 * re;
                        let fd =
                            (m.coefficients(re + h).cn - m.coefficients(re - h).cn) / (2.0 * h);
                        assert!(
                            (fd - c.dcn).abs() <= 1e-5 * c.dcn.abs().max(jump / re),
                            "{m:?} Re {re}: dcn {} vs fd {fd}",
                            c.dcn
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let models = [
            MorisonModel::M3,
            MorisonModel::M4,
            MorisonModel::M5 { solidity: 0.25 },
        ];
        for m in models {
            for re in [0.2, 0.7, 3.0, 25.0, 150.0, 1000.0, 5e4, 3e5, 7e5, 5e6] {
                let h = 1e-4 * re;
                let (p, q) = (m.coefficients(re + h), m.coefficients(re - h));
                let k = m.coefficients(re);
                for (fd, d) in [
                    ((p.cn - q.cn) / (2.0 * h), k.dcn),
                    ((p.ct - q.ct) / (2.0 * h), k.dct),
                ] {
                    assert!(
                        (fd - d).abs() <= 1e-6 * d.abs().max(1e-9 / re),
                        "{m:?} Re {re}: {d} vs fd {fd}"
                    );
                }
            }
        }
    }

    #[test]
    fn tangential_is_dimensionless_form() {
        // π(0.55/√Re + 0.084/∛Re) stays below 1 at high Re (the μ-form exceeds 1 at 1e5)
        for re in [1e3, 1e5, 1e7] {
            assert!(MorisonModel::M4.coefficients(re).ct < 0.1);
        }
    }

    #[test]
    fn constructor_errors() {
        assert!(MorisonModel::new(MorisonModelId::M5, None, None, None).is_err());
        assert!(MorisonModel::new(MorisonModelId::M5, None, None, Some(1.2)).is_err());
        assert!(MorisonModel::new(MorisonModelId::Const, Some(-1.0), None, None).is_err());
        assert!(MorisonModel::new(MorisonModelId::M4, Some(1.0), None, None).is_err());
        let e = "M9".parse::<MorisonModelId>().unwrap_err().to_string();
        assert!(e.contains("M9") && e.contains("M1, M2"), "{e}");
    }
}
