//! Net parameters and mesh grouping (docs/theory/cages.md#cage-parameters `net.*`, #mesh-grouping;
//! docs/theory/fem.md#sections).
//!
//! One numerical twine of mean length L̄ stands for λ = L̄ / l_p physical twines
//! (l_p = half mesh = bar length). Diameters: dws = dwe = √λ·dw0 (structural, elastic),
//! dwh = λ·dw0 (hydrodynamic).

use crate::error::{MeshError, Result};
use crate::mesh::Section;
use serde::{Deserialize, Serialize};

/// Default physical twine diameter dw0 [m].
pub const DEFAULT_TWINE_DIAMETER: f64 = 2.85e-3;
/// Default half mesh (bar length) l_p [m].
pub const DEFAULT_HALF_MESH: f64 = 25.87e-3;
/// Default net Young's modulus [Pa] (nylon).
pub const DEFAULT_NET_YOUNGS_MODULUS: f64 = 2.0e9;
/// Default net density [kg/m³] (nylon).
pub const DEFAULT_NET_DENSITY: f64 = 1140.0;
/// λ above which a warning is issued.
pub const LAMBDA_WARN: f64 = 500.0;

/// `net.*` keys of a `[[cage]]`, `[[panel]]` or `[[mesh]]` table.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct NetParams {
    /// `twine_diameter`: physical twine diameter dw0 [m], > 0. Default 2.85e-3.
    pub twine_diameter: Option<f64>,
    /// `half_mesh`: bar length l_p [m], > `twine_diameter`. Default 25.87e-3.
    pub half_mesh: Option<f64>,
    /// `solidity`: Sn, 0 < Sn < 1. Default 2d/l − (d/l)².
    pub solidity: Option<f64>,
    /// `grouping_ratio`: λ override, ≥ 1. Default computed from the mesh.
    pub grouping_ratio: Option<f64>,
    /// `youngs_modulus` of the twine material [Pa], > 0. Default 2.0e9.
    pub youngs_modulus: Option<f64>,
    /// `density` of the twine material [kg/m³], > 0. Default 1140.
    pub density: Option<f64>,
}

/// Net parameters with defaults applied and validated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NetResolved {
    /// dw0 [m].
    pub twine_diameter: f64,
    /// l_p [m].
    pub half_mesh: f64,
    /// Sn.
    pub solidity: f64,
    /// λ override.
    pub grouping_ratio: Option<f64>,
    /// E [Pa].
    pub youngs_modulus: f64,
    /// ρ [kg/m³].
    pub density: f64,
}

/// The net of one object: inputs and the mesh-grouping numbers
/// (docs/theory/cages.md#mesh-grouping).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NetGrouping {
    /// Physical twine diameter dw0 [m] (screen panels, Reynolds numbers).
    pub twine_diameter: f64,
    /// Half mesh l_p [m].
    pub half_mesh: f64,
    /// Solidity Sn of the screen panels.
    pub solidity: f64,
    /// Mean as-built length of the object's `net_twines` elements [m].
    pub mean_twine_length: f64,
    /// Grouping ratio λ.
    pub lambda: f64,
    /// True when λ came from `net.grouping_ratio`.
    pub lambda_given: bool,
    /// Structural diameter dws = √λ·dw0 [m].
    pub structural_diameter: f64,
    /// Elastic diameter dwe = √λ·dw0 [m].
    pub elastic_diameter: f64,
    /// Hydrodynamic diameter dwh = λ·dw0 [m].
    pub hydro_diameter: f64,
    /// Twine Young's modulus [Pa].
    pub youngs_modulus: f64,
    /// Twine density [kg/m³].
    pub density: f64,
}

impl NetGrouping {
    /// The section of the `net_twines` group (cable, tension-only).
    pub fn twine_section(&self) -> Section {
        Section {
            material: "net twine".to_string(),
            diameter: self.structural_diameter,
            wall_thickness: None,
            elastic_diameter: self.elastic_diameter,
            hydro_diameter: self.hydro_diameter,
            volume_diameter: self.structural_diameter,
            youngs_modulus: self.youngs_modulus,
            density: self.density,
            compression_ratio: crate::mesh::TENSION_ONLY,
            ea: None,
            mass_per_length: None,
            axial_damping: None,
            axial_damping_ratio: None,
            initial_tension: 0.0,
            seabed: true,
            contact_diameter: None,
            bending: None,
            ei: None,
        }
    }
}

/// Solidity of a knotless square-mesh net from twine diameter and half mesh: 2d/l − (d/l)².
pub fn default_solidity(twine_diameter: f64, half_mesh: f64) -> f64 {
    let r = twine_diameter / half_mesh;
    2.0 * r - r * r
}

fn positive(object: &str, key: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(MeshError::param(
            object,
            key,
            v,
            "must be a finite number > 0",
        ))
    }
}

impl NetParams {
    /// Apply defaults and validate (docs/theory/cages.md#input-validation). Warnings (solidity far
    /// from the formula) are pushed to `notices`.
    pub fn resolve(&self, object: &str, notices: &mut Vec<String>) -> Result<NetResolved> {
        let d = positive(
            object,
            "net.twine_diameter",
            self.twine_diameter.unwrap_or(DEFAULT_TWINE_DIAMETER),
        )?;
        let l = positive(
            object,
            "net.half_mesh",
            self.half_mesh.unwrap_or(DEFAULT_HALF_MESH),
        )?;
        if l <= d {
            return Err(MeshError::param(
                object,
                "net.half_mesh",
                l,
                format!("must be > net.twine_diameter = {d} m"),
            ));
        }
        let formula = default_solidity(d, l);
        let sn = match self.solidity {
            None => formula,
            Some(s) => {
                if !(s.is_finite() && s > 0.0 && s < 1.0) {
                    return Err(MeshError::param(
                        object,
                        "net.solidity",
                        s,
                        "must be in (0, 1)",
                    ));
                }
                if ((s - formula) / formula).abs() > 0.2 {
                    notices.push(format!(
                        "warning: {object}: net.solidity = {s} differs by more than 20 % from \
                         2d/l - (d/l)^2 = {formula:.4} for twine_diameter {d} m, half_mesh {l} m"
                    ));
                }
                s
            }
        };
        if let Some(g) = self.grouping_ratio
            && !(g.is_finite() && g >= 1.0)
        {
            return Err(MeshError::param(
                object,
                "net.grouping_ratio",
                g,
                "must be >= 1 (a numerical twine stands for at least one physical twine)",
            ));
        }
        Ok(NetResolved {
            twine_diameter: d,
            half_mesh: l,
            solidity: sn,
            grouping_ratio: self.grouping_ratio,
            youngs_modulus: positive(
                object,
                "net.youngs_modulus",
                self.youngs_modulus.unwrap_or(DEFAULT_NET_YOUNGS_MODULUS),
            )?,
            density: positive(
                object,
                "net.density",
                self.density.unwrap_or(DEFAULT_NET_DENSITY),
            )?,
        })
    }
}

impl NetResolved {
    /// Mesh grouping from the mean as-built twine element length [m]
    /// (docs/theory/cages.md#mesh-grouping). λ < 1 is an error; λ > 500 a warning pushed to
    /// `notices`.
    pub fn grouping(
        &self,
        object: &str,
        mean_twine_length: f64,
        notices: &mut Vec<String>,
    ) -> Result<NetGrouping> {
        let (lambda, given) = match self.grouping_ratio {
            Some(g) => (g, true),
            None => (mean_twine_length / self.half_mesh, false),
        };
        if !(lambda.is_finite() && lambda >= 1.0) {
            return Err(MeshError::param(
                object,
                "net.half_mesh",
                self.half_mesh,
                format!(
                    "gives grouping ratio λ = mean twine element length {mean_twine_length:.6} m / \
                     half_mesh = {lambda:.4} < 1 (a numerical twine would be shorter than a real \
                     one); use a longer element_length or set net.grouping_ratio"
                ),
            ));
        }
        if lambda > LAMBDA_WARN {
            notices.push(format!(
                "warning: {object}: grouping ratio λ = {lambda:.2} > {LAMBDA_WARN}; consider a \
                 shorter element_length"
            ));
        }
        let s = lambda.sqrt() * self.twine_diameter;
        Ok(NetGrouping {
            twine_diameter: self.twine_diameter,
            half_mesh: self.half_mesh,
            solidity: self.solidity,
            mean_twine_length,
            lambda,
            lambda_given: given,
            structural_diameter: s,
            elastic_diameter: s,
            hydro_diameter: lambda * self.twine_diameter,
            youngs_modulus: self.youngs_modulus,
            density: self.density,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn worked_case_diameters() {
        // docs/theory/cages.md#mesh-grouping: λ = 81.11, dw0 = 2.85 mm -> dws = 0.02567 m, dwh =
        // 0.2312 m.
        let net = NetParams::default().resolve("t", &mut vec![]).unwrap();
        let g = net
            .grouping("t", 81.11 * DEFAULT_HALF_MESH, &mut vec![])
            .unwrap();
        assert!((g.structural_diameter - 0.02567).abs() / 0.02567 < 1e-3);
        assert!((g.hydro_diameter - 0.2312).abs() / 0.2312 < 1e-3);
        // μ = 0.590 kg/m and EA = 1.035e6 N with ρ = 1140, E = 2e9.
        let s = g.twine_section();
        assert!((s.linear_mass() - 0.590).abs() < 1e-3);
        assert!((s.axial_stiffness() - 1.035e6).abs() / 1.035e6 < 1e-3);
    }

    #[test]
    fn bad_net_inputs() {
        let mut n = NetParams {
            half_mesh: Some(1e-3),
            ..Default::default()
        };
        let e = n.resolve("cage0", &mut vec![]).unwrap_err().to_string();
        assert!(
            e.contains("net.half_mesh") && e.contains("twine_diameter"),
            "{e}"
        );
        n.half_mesh = None;
        n.solidity = Some(1.2);
        let e = n.resolve("cage0", &mut vec![]).unwrap_err().to_string();
        assert!(e.contains("net.solidity") && e.contains("(0, 1)"), "{e}");
        n.solidity = Some(0.5);
        let mut notes = vec![];
        n.resolve("cage0", &mut notes).unwrap();
        assert_eq!(notes.len(), 1);
        let r = NetParams::default().resolve("c", &mut vec![]).unwrap();
        assert!(r.grouping("c", 0.01, &mut vec![]).is_err());
        let mut notes = vec![];
        r.grouping("c", 600.0 * DEFAULT_HALF_MESH, &mut notes)
            .unwrap();
        assert_eq!(notes.len(), 1);
    }
}
