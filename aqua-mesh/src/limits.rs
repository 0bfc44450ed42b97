//! The bounds every builder applies to lengths (docs/theory/cages.md#input-validation): a
//! length must be finite and at most [`MAX_LENGTH`], so that derived lengths, areas and node
//! counts stay finite, and a value in millimetres entered as metres is named as such.

use crate::error::{MeshError, Result};

/// Most nodes a builder accepts (more is likely a unit mistake).
pub const MAX_NODES: usize = 2_000_000;

/// Longest length a builder accepts [m] (100 km; more is likely a unit mistake).
pub const MAX_LENGTH: f64 = 1.0e5;

/// `v` [m] if it is a length > 0 and <= [`MAX_LENGTH`]; else an error naming `obj`, `key`
/// and `v`.
pub fn length(obj: &str, key: &str, v: f64, what: &str) -> Result<f64> {
    if v.is_finite() && v > 0.0 && v <= MAX_LENGTH {
        Ok(v)
    } else {
        Err(MeshError::param(
            obj,
            key,
            v,
            format!(
                "must be a finite number > 0{what} and <= {MAX_LENGTH} m (lengths are in metres)"
            ),
        ))
    }
}

/// `v` [m] if it is a length >= 0 and <= [`MAX_LENGTH`]; else an error naming `obj`, `key`
/// and `v`.
pub fn length_or_zero(obj: &str, key: &str, v: f64) -> Result<f64> {
    if v.is_finite() && (0.0..=MAX_LENGTH).contains(&v) {
        Ok(v)
    } else {
        Err(MeshError::param(
            obj,
            key,
            v,
            format!("must be a finite number >= 0 and <= {MAX_LENGTH} m (lengths are in metres)"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_outside_the_bounds_are_named() {
        assert_eq!(length("o", "k", 2.5, "").unwrap(), 2.5);
        assert_eq!(length_or_zero("o", "k", 0.0).unwrap(), 0.0);
        for v in [
            0.0,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            1.0e300,
            MAX_LENGTH * 1.001,
        ] {
            let e = length("cage0", "depth", v, "").unwrap_err().to_string();
            assert!(e.contains("cage0") && e.contains("`depth`"), "{e}");
        }
        for v in [-1.0, f64::NAN, 1.0e300] {
            assert!(length_or_zero("o", "cone_depth", v).is_err(), "{v}");
        }
    }
}
