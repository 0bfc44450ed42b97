//! The caller's arrays: values given for every node, line element or panel of the whole mesh,
//! and their checks (names, lengths, finite values).

use crate::error::MeshError;
use crate::error::Result;

/// Values of a block array.
#[derive(Debug, Clone, PartialEq)]
pub enum ArrayValues {
    /// Floating-point values, `components` per entry, entry-major.
    F64 {
        /// Values per entry (1 scalar, 3 vector).
        components: usize,
        /// `components × count` values.
        values: Vec<f64>,
    },
    /// Integer flags or ids, one per entry.
    I32(Vec<i32>),
}

/// A named array given for every node, every line element or every panel of the whole mesh;
/// the writer hands each block its part.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockArray {
    /// Array name as shown in ParaView.
    pub name: String,
    /// The values.
    pub values: ArrayValues,
}

impl BlockArray {
    /// Scalar floating-point array.
    pub fn scalar(name: impl Into<String>, values: Vec<f64>) -> Self {
        BlockArray {
            name: name.into(),
            values: ArrayValues::F64 {
                components: 1,
                values,
            },
        }
    }

    /// 3-vector array from `[x, y, z]` entries.
    pub fn vectors(name: impl Into<String>, values: &[[f64; 3]]) -> Self {
        BlockArray {
            name: name.into(),
            values: ArrayValues::F64 {
                components: 3,
                values: values.iter().flatten().copied().collect(),
            },
        }
    }

    /// Integer array (flags, ids).
    pub fn int(name: impl Into<String>, values: Vec<i32>) -> Self {
        BlockArray {
            name: name.into(),
            values: ArrayValues::I32(values),
        }
    }

    pub(super) fn components(&self) -> usize {
        match &self.values {
            ArrayValues::F64 { components, .. } => *components,
            ArrayValues::I32(_) => 1,
        }
    }

    pub(super) fn len(&self) -> usize {
        match &self.values {
            ArrayValues::F64 { values, .. } => values.len(),
            ArrayValues::I32(v) => v.len(),
        }
    }
}

/// Caller arrays of one step: per node, per line element, per panel (whole-mesh order).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepArrays {
    /// One entry per mesh node.
    pub point: Vec<BlockArray>,
    /// One entry per mesh line element.
    pub line: Vec<BlockArray>,
    /// One entry per mesh panel.
    pub panel: Vec<BlockArray>,
}

pub(super) fn check_arrays(arrays: &[BlockArray], n: usize, location: &'static str) -> Result<()> {
    for (k, a) in arrays.iter().enumerate() {
        let err = |m: String| MeshError::VtkArray {
            location,
            name: a.name.clone(),
            message: m,
        };
        if a.name.is_empty() || a.name.contains(['"', '<', '>', '&']) {
            return Err(err("name must be non-empty without \" < > &".into()));
        }
        if BUILTIN.contains(&a.name.as_str()) || arrays[..k].iter().any(|b| b.name == a.name) {
            return Err(err(format!(
                "name is already used (built-in: {})",
                BUILTIN.join(", ")
            )));
        }
        let want = a.components() * n;
        if a.components() == 0 || a.len() != want {
            return Err(err(format!(
                "has {} values; expected {} components × {n} = {want}",
                a.len(),
                a.components()
            )));
        }
        if let ArrayValues::F64 { values, components } = &a.values
            && let Some(i) = values.iter().position(|v| !v.is_finite())
        {
            return Err(err(format!(
                "value {} (entry {}) is not finite",
                values[i],
                i / components
            )));
        }
    }
    Ok(())
}

/// Array names the writer sets itself.
pub const BUILTIN: [&str; 16] = [
    "node_id",
    "object_id",
    "copy_id",
    "fixed",
    "point_weight",
    "element_id",
    "panel_id",
    "group_id",
    "role_id",
    "diameter",
    "elastic_diameter",
    "hydro_diameter",
    "twine_diameter",
    "solidity",
    "TimeValue",
    "block_name",
];
