//! Parametric cage builders CCT, CCS, CSM, SSM (docs/theory/cages.md#cage-types to
//! #multiple-cages).
//!
//! Discretisation (round half away from zero): NT = round(C/el) (square: 4·round(a/el)),
//! NN = round(H/el), BN = round(R_b/(√2·el)) (square: round(a/(√2·el))). Net node (i, ℓ) =
//! origin + ρ_ℓ·u_i + z_ℓ·ẑ with id i·L + ℓ, L = NN + BN; tip id NT·L; then the rope columns.

mod build;
mod params;

pub use params::{CageParams, ResolvedCage, default_frame_section};

use crate::model::CageType;

/// Default sinker weight per metre of circumference [N/m]: a submerged weight, specified in
/// newtons (docs/theory/cages.md#cage-parameters); its mass is W/g with the sea's g.
pub const DEFAULT_SINKER_WEIGHT_PER_METRE: f64 = 392.4;
/// Default tip weight [N].
pub const DEFAULT_TIP_WEIGHT: f64 = 981.0;
/// Default spacing of the vertical ropes of CCT and CCS cages along the circumference [m]
/// (`ropes` = round(C / 2.5 m), at least 3).
pub const DEFAULT_ROPE_SPACING: f64 = 2.5;

/// Keys of the `[[cage]]` table of each cage type (the cage builder's schema).
impl CageType {
    /// Keys of the `[[cage]]` table this type accepts.
    pub fn valid_keys(self) -> Vec<&'static str> {
        let t = self.canonical();
        let mut k = vec![
            "type",
            "name",
            "origins",
            "circumference",
            "depth",
            "cone_depth",
            "element_length",
            "frame_offset",
            "tip_weight",
            "fixed",
            "net",
            "groups",
            "collar",
        ];
        match t {
            CageType::Ssm => k.push("side"),
            _ => k.push("diameter"),
        }
        if matches!(t, CageType::Cct | CageType::Ccs) {
            k.push("bottom_ratio");
            k.push("ropes");
        }
        if matches!(t, CageType::Csm | CageType::Ssm) {
            k.push("rope_depth");
        }
        if t == CageType::Cct {
            k.push("tube_depth");
        }
        if t == CageType::Ccs {
            k.push("weight_depth");
            k.push("centre_weight");
        } else {
            k.push("sinker_weight_per_metre");
        }
        k
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_not_for_type() {
        let mut p = CageParams::new(CageType::Ssm);
        p.tube_depth = Some(2.0);
        let e = p.resolve().unwrap_err().to_string();
        assert!(e.contains("tube_depth") && e.contains("SSM"), "{e}");
        let mut p = CageParams::new(CageType::Cct);
        p.side = Some(30.0);
        assert!(p.resolve().is_err());
    }

    #[test]
    fn cst_is_cct_with_notice() {
        let m = CageParams::new(CageType::Cst).build().unwrap();
        let c = CageParams::new(CageType::Cct).build().unwrap();
        assert_eq!(m.nodes, c.nodes);
        assert_eq!(m.lines.len(), c.lines.len());
        assert!(m.notices.iter().any(|n| n.contains("CST")));
    }
}
