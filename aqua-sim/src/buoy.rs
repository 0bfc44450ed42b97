//! `[[buoy]]`: buoys and coupling plates (docs/theory/farm.md#buoys).
//!
//! A buoy sits on one node: a new free node at `position` (an object of its own, node group
//! `buoy`, which lines can name as their fairlead), or every node of a `node` reference
//! (a line's joint, a grid plate, a collar node). Its shape gives the submerged volume and
//! the wet projected area as it goes under:
//!
//! - `sphere` of diameter D (or volume V = πD³/6): the exact spherical cap, drag on the wet
//!   circular segment of its silhouette, defaults C_d = 0.5, C_a = 0.5;
//! - `cylinder`, vertical, of diameter D and height H (or volume V = πD²H/4): volume and
//!   projected area D·H both linear in the submergence, defaults C_d = 1.0, C_a = 1.0;
//! - `point`: no volume, only mass and a drag area C_D·A (a coupling plate where lines meet).
//!
//! A farm builder makes buoys by pushing [`BuoySpec`]s (with a `node` reference) into a
//! [`crate::Scene`]'s `buoy` list; [`BuoySpec::resolve`] checks one and gives what the
//! structure and the water loads need.
//!
//! A `[[farm]]`'s `[farm.buoy]` is a [`BuoySpec`] too, with fewer keys
//! ([`FARM_BUOY_KEYS`]) and the farm's own defaults ([`BuoySpec::resolve_farm`]): a vertical
//! cylinder of `volume` V (required) and `height` (default V^(1/3)), `drag_area` (default 0)
//! instead of a drag coefficient, on the top of every plate's pendant.

use aqua_hydro::{PointProps, PointShape};
use aqua_mesh::MeshError;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// `shape` of a `[[buoy]]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BuoyShape {
    /// A sphere centred on its node.
    #[default]
    Sphere,
    /// A vertical cylinder centred on its node.
    Cylinder,
    /// No volume: mass and drag only (a coupling plate).
    Point,
}

impl BuoyShape {
    /// Default drag coefficient C_d on the projected area: 0.5 for a sphere (subcritical
    /// Reynolds numbers), 1.0 for a short vertical cylinder, 0 for a point (no area).
    pub fn default_drag_coefficient(self) -> f64 {
        match self {
            BuoyShape::Sphere => 0.5,
            BuoyShape::Cylinder => 1.0,
            BuoyShape::Point => 0.0,
        }
    }

    /// Default added-mass coefficient C_a (added mass C_a·ρ_w·V_sub): 0.5 for a sphere, 1.0
    /// for a vertical cylinder in horizontal motion (the 2-D potential-flow value), 0 for a
    /// point. The one default of each body kind: `[[buoy]]` and a farm's buoys (vertical
    /// cylinders) take it from here (docs/theory/farm.md#buoys).
    pub fn default_added_mass(self) -> f64 {
        match self {
            BuoyShape::Sphere => 0.5,
            BuoyShape::Cylinder => 1.0,
            BuoyShape::Point => 0.0,
        }
    }
}

/// One `[[buoy]]` table.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuoySpec {
    /// Name (default `buoy<k>`): the object of a free buoy, and the name in messages.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Centre of a free buoy [m] (a new node); exclusive with `node`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 3]>,
    /// Node reference: a buoy on every node it names; exclusive with `position`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<String>,
    /// Shape.
    #[serde(default)]
    pub shape: BuoyShape,
    /// Diameter D [m] (sphere, cylinder); or give `volume`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameter: Option<f64>,
    /// Height H of a cylinder [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Volume V [m³] (sphere, cylinder); or give `diameter`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume: Option<f64>,
    /// Mass [kg] (weight m·g downwards).
    #[serde(default)]
    pub mass: f64,
    /// Drag coefficient C_d on the projected area (sphere, cylinder).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag_coefficient: Option<f64>,
    /// Drag area C_D·A [m²] when fully submerged, instead of `drag_coefficient`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag_area: Option<f64>,
    /// Added-mass coefficient C_a (added mass C_a·ρ_w·V_sub).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub added_mass_coefficient: Option<f64>,
    /// Seabed contact stiffness of the body [N/m] (0 = none).
    #[serde(default)]
    pub seabed_stiffness: f64,
    /// The buoy is meant to be under water (a midwater buoy): no design warning when it is.
    #[serde(default)]
    pub submerged: bool,
}

/// A checked buoy: what the structure and the water loads take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Buoy {
    /// Mass [kg].
    pub mass: f64,
    /// Seabed stiffness [N/m].
    pub seabed_stiffness: f64,
    /// Water-load data; `None` when the body has neither volume nor drag.
    pub props: Option<PointProps>,
    /// Vertical size [m]: a sphere's diameter, a cylinder's height, 0 for a point.
    pub size: f64,
}

/// What is wrong with a `[[buoy]]` table: each names the key, its value and what is valid
/// (the caller adds the file, line and table).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BuoyError {
    /// Both `position` and `node`.
    #[error(
        "both `position` and `node` given: a buoy is either a new node at `position` or sits \
         on the nodes `node` names; give one"
    )]
    PositionAndNode,
    /// Neither `position` nor `node`.
    #[error(
        "give `position = [x, y, z]` (a new free node) or `node = \"object/group[k]\"` (on \
         existing nodes)"
    )]
    NoPlace,
    /// A `position` with a non-finite coordinate.
    #[error("position = {0:?}: must be finite")]
    Position([f64; 3]),
    /// A value outside its range.
    #[error("{key} = {value}: {valid}")]
    Value {
        /// The key.
        key: &'static str,
        /// The value given.
        value: f64,
        /// What would be valid.
        valid: String,
    },
    /// Two keys of which one may be given.
    #[error("both `{0}` and `{1}` given; give one")]
    Both(&'static str, &'static str),
    /// Neither `diameter` nor `volume` (`key` = None), or one of them 0.
    #[error("{}{ZERO_VOLUME}", key.map(|k| format!("{k} = 0: ")).unwrap_or_default())]
    ZeroVolume {
        /// The key given as 0, if any.
        key: Option<&'static str>,
    },
    /// A sphere given a `height`.
    #[error("height = {0}: a sphere's height is its diameter; give `diameter` or `volume`")]
    SphereHeight(f64),
    /// A cylinder without `height`.
    #[error("height is missing: a cylinder needs its height [m] (vertical axis)")]
    CylinderHeight,
    /// A size or coefficient key given to a point.
    #[error(
        "{key} = {value}: shape = \"point\" has no volume or projected area (mass and \
         `drag_area` only); use shape = \"sphere\" or \"cylinder\" for a body with volume"
    )]
    PointKey {
        /// The key.
        key: &'static str,
        /// The value given.
        value: f64,
    },
    /// A point with neither mass nor drag.
    #[error("shape = \"point\" with neither `mass` nor `drag_area` does nothing; give one")]
    EmptyPoint,
}

fn check(key: &'static str, v: f64, ok: bool, valid: impl Into<String>) -> Result<f64, BuoyError> {
    if ok {
        Ok(v)
    } else {
        Err(BuoyError::Value {
            key,
            value: v,
            valid: valid.into(),
        })
    }
}

fn positive(key: &'static str, v: f64) -> Result<f64, BuoyError> {
    check(
        key,
        v,
        v.is_finite() && v > 0.0,
        "must be a finite number > 0",
    )
}

/// A length [m]: > 0 and at most aqua-mesh's [`aqua_mesh::MAX_LENGTH`].
fn length(key: &'static str, v: f64) -> Result<f64, BuoyError> {
    let ok = v.is_finite() && v > 0.0 && v <= aqua_mesh::MAX_LENGTH;
    check(
        key,
        v,
        ok,
        format!(
            "must be a finite number > 0 and <= {} m (lengths are in metres)",
            aqua_mesh::MAX_LENGTH
        ),
    )
}

fn non_negative(key: &'static str, v: f64) -> Result<f64, BuoyError> {
    check(
        key,
        v,
        v.is_finite() && v >= 0.0,
        "must be a finite number >= 0",
    )
}

/// The keys of `[farm.buoy]`, in the order messages list them: the others of [`BuoySpec`]
/// (shape, diameter, position, …) do not apply to a farm's buoys.
pub const FARM_BUOY_KEYS: &[&str] = &[
    "volume",
    "mass",
    "height",
    "drag_area",
    "added_mass_coefficient",
];

const ZERO_VOLUME: &str = "a buoy with zero volume: give `diameter` or `volume` > 0, or \
                           shape = \"point\" for a node with mass and drag only (a coupling plate)";

impl BuoySpec {
    /// Checks the keys; the error message names the key, its value and what is valid
    /// (the caller adds the file, line and table).
    pub fn resolve(&self) -> Result<Buoy, BuoyError> {
        match (&self.position, &self.node) {
            (Some(_), Some(_)) => return Err(BuoyError::PositionAndNode),
            (None, None) => return Err(BuoyError::NoPlace),
            _ => {}
        }
        if let Some(p) = self.position
            && !p.iter().all(|c| c.is_finite())
        {
            return Err(BuoyError::Position(p));
        }
        let mass = non_negative("mass", self.mass)?;
        let seabed_stiffness = non_negative("seabed_stiffness", self.seabed_stiffness)?;
        if self.drag_coefficient.is_some() && self.drag_area.is_some() {
            return Err(BuoyError::Both("drag_coefficient", "drag_area"));
        }
        let (props, size) = match self.shape {
            BuoyShape::Sphere => self.sphere()?,
            BuoyShape::Cylinder => self.cylinder()?,
            BuoyShape::Point => (self.point()?, 0.0),
        };
        Ok(Buoy {
            mass,
            seabed_stiffness,
            props,
            size,
        })
    }

    /// The volume or diameter, exactly one of them, > 0.
    fn size_keys(&self) -> Result<(Option<f64>, Option<f64>), BuoyError> {
        let zero = |key| BuoyError::ZeroVolume { key };
        match (self.diameter, self.volume) {
            (Some(_), Some(_)) => Err(BuoyError::Both("diameter", "volume")),
            (None, None) => Err(zero(None)),
            (Some(d), None) => match d {
                0.0 => Err(zero(Some("diameter"))),
                _ => Ok((Some(length("diameter", d)?), None)),
            },
            (None, Some(v)) => match v {
                0.0 => Err(zero(Some("volume"))),
                _ => Ok((None, Some(positive("volume", v)?))),
            },
        }
    }

    fn coefficients(&self, area: f64) -> Result<(f64, f64), BuoyError> {
        let drag_area = match (self.drag_area, self.drag_coefficient) {
            (Some(a), _) => non_negative("drag_area", a)?,
            (None, c) => {
                let c = c.unwrap_or(self.shape.default_drag_coefficient());
                non_negative("drag_coefficient", c)? * area
            }
        };
        let ca = non_negative(
            "added_mass_coefficient",
            self.added_mass_coefficient
                .unwrap_or(self.shape.default_added_mass()),
        )?;
        Ok((drag_area, ca))
    }

    fn sphere(&self) -> Result<(Option<PointProps>, f64), BuoyError> {
        if let Some(h) = self.height {
            return Err(BuoyError::SphereHeight(h));
        }
        let r = match self.size_keys()? {
            (Some(d), _) => 0.5 * d,
            (_, Some(v)) => (3.0 * v / (4.0 * PI)).cbrt(),
            _ => unreachable!("size_keys gives one of them"),
        };
        let (drag_area, added_mass) = self.coefficients(PI * r * r)?;
        let props = PointProps {
            volume: 4.0 / 3.0 * PI * r * r * r,
            shape: PointShape::Sphere { radius: r },
            drag_area,
            added_mass,
        };
        Ok((Some(props), 2.0 * r))
    }

    fn cylinder(&self) -> Result<(Option<PointProps>, f64), BuoyError> {
        let h = match self.height {
            Some(h) => length("height", h)?,
            None => return Err(BuoyError::CylinderHeight),
        };
        let d = match self.size_keys()? {
            (Some(d), _) => d,
            (_, Some(v)) => (4.0 * v / (PI * h)).sqrt(),
            _ => unreachable!("size_keys gives one of them"),
        };
        let (drag_area, added_mass) = self.coefficients(d * h)?;
        let props = PointProps {
            volume: 0.25 * PI * d * d * h,
            shape: PointShape::Prism { height: h },
            drag_area,
            added_mass,
        };
        Ok((Some(props), h))
    }

    fn point(&self) -> Result<Option<PointProps>, BuoyError> {
        for (key, v) in [
            ("diameter", self.diameter),
            ("volume", self.volume),
            ("height", self.height),
            ("drag_coefficient", self.drag_coefficient),
            ("added_mass_coefficient", self.added_mass_coefficient),
        ] {
            if let Some(value) = v {
                return Err(BuoyError::PointKey { key, value });
            }
        }
        let drag_area = non_negative("drag_area", self.drag_area.unwrap_or(0.0))?;
        if self.mass == 0.0 && drag_area == 0.0 {
            return Err(BuoyError::EmptyPoint);
        }
        Ok((drag_area > 0.0).then_some(PointProps {
            volume: 0.0,
            shape: PointShape::Prism { height: 0.0 },
            drag_area,
            added_mass: 0.0,
        }))
    }
}

impl BuoySpec {
    /// `[farm.buoy]` of the farm `obj` (only [`FARM_BUOY_KEYS`] given, `volume` among them;
    /// the reader sees to both): a vertical cylinder of volume V > 0 and height H (default
    /// V^(1/3)), drag area C_D·A (default 0), added-mass coefficient (default a cylinder's,
    /// [`BuoyShape::default_added_mass`]). Errors name `buoy.KEY`, its value and what is valid.
    pub fn resolve_farm(&self, obj: &str) -> Result<Buoy, MeshError> {
        let volume = self.volume.unwrap_or(0.0);
        if !(volume.is_finite() && volume > 0.0) {
            return Err(MeshError::param(
                obj,
                "buoy.volume",
                volume,
                "must be a finite number > 0",
            ));
        }
        let height = match self.height {
            Some(h) => aqua_mesh::limits::length(obj, "buoy.height", h, "")?,
            None => volume.cbrt(),
        };
        let drag_area = self.drag_area.unwrap_or(0.0);
        for (k, v) in [
            ("buoy.mass", self.mass),
            ("buoy.drag_area", drag_area),
            (
                "buoy.added_mass_coefficient",
                self.added_mass_coefficient.unwrap_or(0.0),
            ),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(MeshError::param(obj, k, v, "must be a finite number >= 0"));
            }
        }
        Ok(Buoy {
            mass: self.mass,
            seabed_stiffness: 0.0,
            props: Some(PointProps {
                volume,
                shape: PointShape::Prism { height },
                drag_area,
                added_mass: self
                    .added_mass_coefficient
                    .unwrap_or(BuoyShape::Cylinder.default_added_mass()),
            }),
            size: height,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(shape: BuoyShape) -> BuoySpec {
        BuoySpec {
            position: Some([0.0, 0.0, 0.0]),
            shape,
            ..Default::default()
        }
    }

    #[test]
    fn sphere_from_diameter_or_volume() {
        let mut s = at(BuoyShape::Sphere);
        s.diameter = Some(1.2);
        let b = s.resolve().unwrap();
        let p = b.props.unwrap();
        assert!((p.volume - PI * 1.2f64.powi(3) / 6.0).abs() < 1e-12);
        assert!((p.drag_area - 0.5 * PI * 0.36).abs() < 1e-12);
        assert_eq!(p.added_mass, 0.5);
        assert_eq!(b.size, 1.2);
        let mut s = at(BuoyShape::Sphere);
        s.volume = Some(PI * 1.2f64.powi(3) / 6.0);
        let q = s.resolve().unwrap().props.unwrap();
        assert!((q.volume - p.volume).abs() < 1e-12);
        assert_eq!(q.shape, PointShape::Sphere { radius: 0.6 });
    }

    #[test]
    fn cylinder_is_a_prism_of_its_height() {
        let mut s = at(BuoyShape::Cylinder);
        s.diameter = Some(0.8);
        s.height = Some(2.0);
        s.drag_coefficient = Some(0.9);
        let p = s.resolve().unwrap().props.unwrap();
        assert!((p.volume - 0.25 * PI * 0.64 * 2.0).abs() < 1e-12);
        assert_eq!(p.shape, PointShape::Prism { height: 2.0 });
        assert!((p.drag_area - 0.9 * 0.8 * 2.0).abs() < 1e-12);
    }

    #[test]
    fn bad_input_is_named() {
        let e = at(BuoyShape::Sphere).resolve().unwrap_err();
        assert_eq!(e, BuoyError::ZeroVolume { key: None });
        let mut s = at(BuoyShape::Cylinder);
        s.volume = Some(1.0);
        assert_eq!(s.resolve().unwrap_err(), BuoyError::CylinderHeight);
        let e = at(BuoyShape::Sphere).resolve().unwrap_err().to_string();
        assert!(e.contains("a buoy with zero volume"), "{e}");
        let mut s = at(BuoyShape::Sphere);
        s.volume = Some(0.0);
        let e = s.resolve().unwrap_err().to_string();
        assert!(e.contains("volume = 0") && e.contains("zero volume"), "{e}");
        let mut s = at(BuoyShape::Sphere);
        s.diameter = Some(-1.0);
        assert!(
            s.resolve()
                .unwrap_err()
                .to_string()
                .contains("diameter = -1")
        );
        let mut s = at(BuoyShape::Cylinder);
        s.diameter = Some(1.0);
        assert!(s.resolve().unwrap_err().to_string().contains("height"));
        let mut s = at(BuoyShape::Point);
        s.diameter = Some(1.0);
        assert!(
            s.resolve()
                .unwrap_err()
                .to_string()
                .contains("shape = \"point\"")
        );
        let e = at(BuoyShape::Point).resolve().unwrap_err().to_string();
        assert!(e.contains("neither"), "{e}");
        let mut s = at(BuoyShape::Point);
        s.mass = 50.0;
        s.drag_area = Some(0.4);
        let b = s.resolve().unwrap();
        assert_eq!(b.props.unwrap().volume, 0.0);
        let mut s = at(BuoyShape::Point);
        s.mass = 5.0;
        s.node = Some("a/b".into());
        assert!(
            s.resolve()
                .unwrap_err()
                .to_string()
                .contains("both `position` and `node`")
        );
    }

    #[test]
    fn a_farm_buoy_is_a_cylinder_with_the_farm_defaults() {
        let s = BuoySpec {
            volume: Some(2.0),
            mass: 150.0,
            ..Default::default()
        };
        let b = s.resolve_farm("farm").unwrap();
        let p = b.props.unwrap();
        // height V^(1/3), no drag, a vertical cylinder's C_a = 1 (docs/guide/scene.md)
        assert_eq!(p.volume, 2.0);
        assert_eq!(
            p.shape,
            PointShape::Prism {
                height: 2f64.cbrt()
            }
        );
        assert_eq!((p.drag_area, p.added_mass, b.mass), (0.0, 1.0, 150.0));
        let bad = BuoySpec {
            volume: Some(-1.0),
            ..Default::default()
        };
        let e = bad.resolve_farm("farm").unwrap_err().to_string();
        assert_eq!(
            e,
            "farm: `buoy.volume` = -1 is invalid: must be a finite number > 0"
        );
    }
}
