//! `[[body]]`: free rigid bodies in a scene — a feed barge, a service platform
//! (docs/theory/farm.md#rigid-bodies).
//!
//! A body has six degrees of freedom (aqua-fem's rigid body): its mass and its inertia tensor
//! about the centre of gravity, and the points it holds rigidly. Those points are:
//!
//! - its named points (`[[body.point]]`), given in the body frame (origin at the centre of
//!   gravity, axes the world's as built): the node group `<body>/<point>`, so a line's
//!   `fairlead = "barge/f1"` ends on it;
//! - the columns of a box hull (`[body.hull]`, aqua-mesh's [`aqua_mesh::BoxHull`]), each a
//!   vertical prism of the water loads (aqua-hydro's point body): buoyancy and waterplane
//!   stiffness exact for the box in heave, roll and pitch, Froude–Krylov and added mass
//!   C_a·ρ·V_wet, and quadratic drag on C_d times the mean side area, shared among the columns.

use aqua_hydro::{PointProps, PointShape};
use aqua_mesh::BoxHull;
use serde::{Deserialize, Serialize};

/// Default columns of a hull along its length and width.
pub const DEFAULT_HULL_COLUMNS: [usize; 2] = [4, 2];
/// Largest layer height of a hull by default [m]: `layers` = ⌈H/0.5⌉.
pub const DEFAULT_LAYER_HEIGHT: f64 = 0.5;
/// Default drag coefficient of a hull on its mean side area (a bluff box).
pub const DEFAULT_HULL_DRAG_COEFFICIENT: f64 = 1.0;
/// Default added-mass coefficient of a hull's columns (added mass C_a·ρ_w·V_wet).
pub const DEFAULT_HULL_ADDED_MASS: f64 = 1.0;

/// One `[[body]]` table.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name (default `body<k>`): the object holding the body's points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Centre of gravity as built [m].
    pub centre: [f64; 3],
    /// Mass [kg].
    pub mass: f64,
    /// Inertia about the centre of gravity [kg·m²]: `[Ixx, Iyy, Izz]` (principal, along the
    /// world axes as built) or `[Ixx, Iyy, Izz, Ixy, Ixz, Iyz]`.
    pub inertia: Vec<f64>,
    /// The hull, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hull: Option<HullSpec>,
    /// Named points held by the body (fairleads).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub point: Vec<BodyPointSpec>,
}

/// `[body.hull]`: a box hull.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HullSpec {
    /// Length L along the body's x axis [m].
    pub length: f64,
    /// Width B along the body's y axis [m].
    pub width: f64,
    /// Height H, keel to deck [m].
    pub height: f64,
    /// Centre of the box relative to the centre of gravity [m] (default [0, 0, 0]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre: Option<[f64; 3]>,
    /// Columns along L and B (default [`DEFAULT_HULL_COLUMNS`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub columns: Option<[usize; 2]>,
    /// Layers from keel to deck (default: layers of at most [`DEFAULT_LAYER_HEIGHT`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layers: Option<usize>,
    /// Drag coefficient on the mean side area (default [`DEFAULT_HULL_DRAG_COEFFICIENT`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag_coefficient: Option<f64>,
    /// Added-mass coefficient (default [`DEFAULT_HULL_ADDED_MASS`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub added_mass_coefficient: Option<f64>,
}

/// `[[body.point]]`: a named point held by the body.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyPointSpec {
    /// Name: the node group `<body>/<name>`.
    pub name: String,
    /// Position in the body frame, relative to the centre of gravity [m].
    pub position: [f64; 3],
}

/// What is wrong with a `[[body]]` table (the caller adds the file, line and table).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BodyError {
    /// A value outside its range.
    #[error("{key} = {value}: {valid}")]
    Value {
        /// The key.
        key: &'static str,
        /// The value given.
        value: String,
        /// What would be valid.
        valid: &'static str,
    },
    /// The hull's geometry (aqua-mesh's check, naming its key).
    #[error("{0}")]
    Hull(String),
}

fn value(key: &'static str, value: impl std::fmt::Debug, valid: &'static str) -> BodyError {
    BodyError::Value {
        key,
        value: format!("{value:?}"),
        valid,
    }
}

/// A checked hull: its geometry and the water-load data of each column.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hull {
    /// The box and its columns.
    pub shape: BoxHull,
    /// Each prism's (one layer of a column) water-load data.
    pub column: PointProps,
}

impl HullSpec {
    /// The box and its columns' water loads: volume A_c·H, a prism of height H, drag area
    /// C_d·(L + B)/2·H/n and added-mass coefficient C_a, n the number of prisms (columns ×
    /// layers), each of height H/n_z.
    pub fn resolve(&self) -> Result<Hull, BodyError> {
        let shape = BoxHull {
            length: self.length,
            width: self.width,
            height: self.height,
            centre: self.centre.unwrap_or([0.0; 3]),
            columns: self.columns.unwrap_or(DEFAULT_HULL_COLUMNS),
            layers: self.layers.unwrap_or_else(|| {
                if self.height.is_finite() && self.height > 0.0 {
                    ((self.height / DEFAULT_LAYER_HEIGHT).ceil() as usize).clamp(1, 50)
                } else {
                    1
                }
            }),
        };
        shape
            .validate("body")
            .map_err(|e| BodyError::Hull(e.to_string()))?;
        let cd = self
            .drag_coefficient
            .unwrap_or(DEFAULT_HULL_DRAG_COEFFICIENT);
        if !(cd.is_finite() && cd >= 0.0) {
            return Err(value("hull.drag_coefficient", cd, "a finite number >= 0"));
        }
        let ca = self
            .added_mass_coefficient
            .unwrap_or(DEFAULT_HULL_ADDED_MASS);
        if !(ca.is_finite() && ca >= 0.0) {
            return Err(value(
                "hull.added_mass_coefficient",
                ca,
                "a finite number >= 0",
            ));
        }
        let n = (shape.columns[0] * shape.columns[1] * shape.layers) as f64;
        let column = PointProps {
            volume: shape.column_area() * shape.layer_height(),
            shape: PointShape::Prism {
                height: shape.layer_height(),
            },
            drag_area: cd * 0.5 * (shape.length + shape.width) * shape.height / n,
            added_mass: ca,
        };
        Ok(Hull { shape, column })
    }
}

/// A checked body: what the structure and the water loads take.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Centre of gravity as built [m].
    pub centre: [f64; 3],
    /// Mass [kg].
    pub mass: f64,
    /// Inertia tensor about the centre of gravity [kg·m²].
    pub inertia: [[f64; 3]; 3],
    /// The hull, if any.
    pub hull: Option<Hull>,
    /// Named points and their body-frame positions [m].
    pub points: Vec<(String, [f64; 3])>,
}

impl BodySpec {
    /// Checks the table. The inertia must be symmetric positive definite (a physical body also
    /// satisfies the triangle inequality of its principal moments; checked here too).
    pub fn resolve(&self) -> Result<Body, BodyError> {
        if !self.centre.iter().all(|c| c.is_finite()) {
            return Err(value("centre", self.centre, "three finite numbers [m]"));
        }
        if !(self.mass.is_finite() && self.mass > 0.0) {
            return Err(value("mass", self.mass, "a finite number > 0 [kg]"));
        }
        let i = &self.inertia;
        let inertia = match i.len() {
            3 => [[i[0], 0.0, 0.0], [0.0, i[1], 0.0], [0.0, 0.0, i[2]]],
            6 => [[i[0], i[3], i[4]], [i[3], i[1], i[5]], [i[4], i[5], i[2]]],
            _ => {
                return Err(value(
                    "inertia",
                    i,
                    "[Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] [kg m^2] about the centre of gravity",
                ));
            }
        };
        if !i.iter().all(|v| v.is_finite()) || !physical(&inertia) {
            return Err(value(
                "inertia",
                i,
                "a physical inertia tensor: positive definite, each principal moment at most \
                 the sum of the other two",
            ));
        }
        let hull = self.hull.as_ref().map(HullSpec::resolve).transpose()?;
        if hull.is_none() && self.point.is_empty() {
            return Err(value(
                "hull",
                "none",
                "a body holds a [body.hull] or at least one [[body.point]]",
            ));
        }
        Ok(Body {
            centre: self.centre,
            mass: self.mass,
            inertia,
            hull,
            points: self
                .point
                .iter()
                .map(|p| (p.name.clone(), p.position))
                .collect(),
        })
    }
}

/// Positive definite with principal moments obeying the triangle inequality.
fn physical(m: &[[f64; 3]; 3]) -> bool {
    let a = nalgebra::Matrix3::from_fn(|r, c| m[r][c]);
    let e = a.symmetric_eigenvalues();
    let tol = 1e-12 * e.amax();
    e.iter().all(|&v| v > 0.0)
        && e[0] <= e[1] + e[2] + tol
        && e[1] <= e[0] + e[2] + tol
        && e[2] <= e[0] + e[1] + tol
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> BodySpec {
        BodySpec {
            name: Some("barge".into()),
            centre: [0.0, 0.0, 0.0],
            mass: 4.0e5,
            inertia: vec![6.0e6, 2.0e7, 2.4e7],
            hull: Some(HullSpec {
                length: 24.0,
                width: 12.0,
                height: 3.0,
                ..Default::default()
            }),
            point: vec![],
        }
    }

    #[test]
    fn a_hull_keeps_the_volume_and_the_side_area() {
        let b = spec().resolve().unwrap();
        let h = b.hull.unwrap();
        let n = 8.0 * 6.0;
        assert!((h.column.volume * n - 24.0 * 12.0 * 3.0).abs() < 1e-9);
        assert!((h.column.drag_area * n - 18.0 * 3.0).abs() < 1e-9);
    }

    #[test]
    fn unphysical_inertia_and_bad_keys_are_refused() {
        let mut s = spec();
        s.inertia = vec![1.0, 1.0, 3.0];
        let e = s.resolve().unwrap_err().to_string();
        assert!(e.contains("inertia") && e.contains("principal"), "{e}");
        s.inertia = vec![1.0, 1.0];
        assert!(
            s.resolve()
                .unwrap_err()
                .to_string()
                .contains("[Ixx, Iyy, Izz]")
        );
        let mut s = spec();
        s.mass = 0.0;
        assert!(s.resolve().unwrap_err().to_string().contains("mass = 0.0"));
        let mut s = spec();
        s.hull.as_mut().unwrap().drag_coefficient = Some(-1.0);
        assert!(
            s.resolve()
                .unwrap_err()
                .to_string()
                .contains("hull.drag_coefficient")
        );
        let mut s = spec();
        s.hull = None;
        assert!(s.resolve().unwrap_err().to_string().contains("hull"));
    }
}
