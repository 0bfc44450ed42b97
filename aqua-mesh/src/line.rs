//! Single line builder (`[[line]]`: moorings, bridles; docs/theory/cages.md#single-line).
//!
//! Nodes 0..N from anchor to fairlead, element unstretched length L0/N. Initial shape: straight
//! and uniformly stretched if L0 ≤ chord; otherwise the inextensible catenary of length L0
//! through both ends, z = a·cosh((x − x0)/a) + c in the vertical plane of the chord, with a from
//! √(L0² − h²) = 2a·sinh(l/2a) (l horizontal, h vertical span), nodes at arc lengths i·L0/N,
//! and nodes below the seabed projected onto it.

use crate::Mesh;
use crate::error::{MeshError, Result};
use crate::mesh::{MeshBuilder, Object, ObjectKind, Role, Section, SectionOverride};
use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

/// `fairlead` key: a point, or a reference `"<object>/<node group>[k]"` to an existing node.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum Fairlead {
    /// Coordinates [m].
    Point([f64; 3]),
    /// Reference to a node of another object, resolved by the caller (scene wiring).
    Node(String),
}

/// `shape` key.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LineShape {
    /// Inextensible catenary through both ends (default).
    #[default]
    Catenary,
    /// Straight chord.
    Straight,
}

/// One `[[line]]` table. Section keys (docs/theory/fem.md#sections) sit directly in the table.
#[derive(Debug, Clone, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LineParams {
    /// `name` (default `line0`).
    pub name: Option<String>,
    /// `anchor` [m].
    pub anchor: [f64; 3],
    /// `fairlead` [m] or node reference.
    pub fairlead: Option<Fairlead>,
    /// `length` L0 unstretched [m], > 0.
    pub length: f64,
    /// `segments` N ≥ 1 (or `element_length`).
    pub segments: Option<u32>,
    /// `element_length` [m]: N = max(1, round(L0/el)).
    pub element_length: Option<f64>,
    /// `group`: element group name (default = object name).
    pub group: Option<String>,
    /// `shape`: `catenary` (default) or `straight`.
    #[serde(default)]
    pub shape: LineShape,
    /// `fixed`: node groups fixed, default `["anchor"]`.
    pub fixed: Option<Vec<String>>,
    /// `diameter` d [m] (required).
    pub diameter: Option<f64>,
    /// `wall_thickness` [m].
    pub wall_thickness: Option<f64>,
    /// `ea` [N] (or `youngs_modulus`).
    pub ea: Option<f64>,
    /// `youngs_modulus` [Pa].
    pub youngs_modulus: Option<f64>,
    /// `density` [kg/m³] (or `mass_per_length`).
    pub density: Option<f64>,
    /// `mass_per_length` [kg/m].
    pub mass_per_length: Option<f64>,
    /// `hydro_diameter` [m].
    pub hydro_diameter: Option<f64>,
    /// `volume_diameter` [m].
    pub volume_diameter: Option<f64>,
    /// `elastic_diameter` [m].
    pub elastic_diameter: Option<f64>,
    /// `compression_ratio`.
    pub compression_ratio: Option<f64>,
    /// `axial_damping` [N·s].
    pub axial_damping: Option<f64>,
    /// `axial_damping_ratio`.
    pub axial_damping_ratio: Option<f64>,
    /// `initial_tension` [N].
    pub initial_tension: Option<f64>,
    /// `seabed` contact.
    pub seabed: Option<bool>,
    /// `contact_diameter` [m].
    pub contact_diameter: Option<f64>,
    /// `material` label.
    pub material: Option<String>,
    /// `ei` bending stiffness EI [N·m²] (docs/theory/fem.md#bending-of-sections).
    pub ei: Option<f64>,
    /// `bending` on/off (default: on for a pipe or when `ei` is given).
    pub bending: Option<bool>,
}

fn finite3(obj: &str, key: &str, v: [f64; 3]) -> Result<Point3<f64>> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(Point3::from(v))
    } else {
        Err(MeshError::param(
            obj,
            key,
            format!("{v:?}"),
            "must be finite",
        ))
    }
}

/// Positions of N+1 nodes of an inextensible line of length `l0` hanging between `a` and `b`
/// (catenary in the vertical plane through both ends; straight when slack is impossible or the
/// chord is vertical). Returns `None` if `a == b`.
pub fn catenary_nodes(
    a: Point3<f64>,
    b: Point3<f64>,
    l0: f64,
    n: usize,
) -> Option<Vec<Point3<f64>>> {
    let d = b - a;
    let chord = d.norm();
    if chord == 0.0 || n == 0 {
        return None;
    }
    let horiz = Vector3::new(d.x, d.y, 0.0);
    let l = horiz.norm();
    let h = d.z;
    let straight = || {
        (0..=n)
            .map(|i| a + d * (i as f64 / n as f64))
            .collect::<Vec<_>>()
    };
    if l0 <= chord || l <= 1e-9 * chord {
        return Some(straight());
    }
    // Solve sinh(u)/u = r with u = l/(2a), r = √(L0² − h²)/l > 1.
    let r = (l0 * l0 - h * h).sqrt() / l;
    let f = |u: f64| u.sinh() / u - r;
    let (mut lo, mut hi) = (1e-12_f64, 1.0_f64);
    while f(hi) < 0.0 && hi < 700.0 {
        lo = hi;
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    let u = 0.5 * (lo + hi);
    let ca = l / (2.0 * u); // catenary parameter a [m]
    let x0 = l / 2.0 - ca * (h / (2.0 * ca * u.sinh())).asinh();
    let ex = horiz / l;
    let s0 = (-x0 / ca).sinh();
    let c0 = (-x0 / ca).cosh();
    Some(
        (0..=n)
            .map(|i| {
                if i == n {
                    return b;
                }
                let s = l0 * i as f64 / n as f64;
                let x = x0 + ca * (s / ca + s0).asinh();
                let z = ca * ((x - x0) / ca).cosh() - ca * c0;
                a + ex * x + Vector3::new(0.0, 0.0, z)
            })
            .collect(),
    )
}

impl LineParams {
    /// Build with the fairlead given as a point and no seabed.
    pub fn build(&self) -> Result<Mesh> {
        self.build_with(None, None)
    }

    /// Build. `fairlead_position` resolves a node-reference fairlead (the scene looks the node
    /// up); `seabed_z` [m] (z of the flat seabed, e.g. −water depth) projects nodes below it
    /// onto it and rejects an anchor below it.
    pub fn build_with(
        &self,
        fairlead_position: Option<[f64; 3]>,
        seabed_z: Option<f64>,
    ) -> Result<Mesh> {
        let name = self.name.clone().unwrap_or_else(|| "line0".into());
        let obj = name.as_str();
        let anchor = finite3(obj, "anchor", self.anchor)?;
        let fair = match (&self.fairlead, fairlead_position) {
            (_, Some(p)) => finite3(obj, "fairlead", p)?,
            (Some(Fairlead::Point(p)), None) => finite3(obj, "fairlead", *p)?,
            (Some(Fairlead::Node(r)), None) => {
                return Err(MeshError::param(
                    obj,
                    "fairlead",
                    r,
                    "node references are resolved by the scene; give coordinates [x, y, z] here",
                ));
            }
            (None, None) => {
                return Err(MeshError::param(
                    obj,
                    "fairlead",
                    "(missing)",
                    "required: [x, y, z] or \"<object>/<node group>[k]\"",
                ));
            }
        };
        let l0 = self.length;
        if !(l0.is_finite() && l0 > 0.0) {
            return Err(MeshError::param(
                obj,
                "length",
                l0,
                "must be a finite number > 0",
            ));
        }
        let n = match (self.segments, self.element_length) {
            (Some(_), Some(_)) => {
                return Err(MeshError::inconsistent(
                    obj,
                    "both `segments` and `element_length` given; give only one",
                ));
            }
            (Some(s), None) if s >= 1 => s as usize,
            (Some(s), None) => {
                return Err(MeshError::param(obj, "segments", s, "must be >= 1"));
            }
            (None, Some(el)) if el.is_finite() && el > 0.0 => (l0 / el).round().max(1.0) as usize,
            (None, Some(el)) => {
                return Err(MeshError::param(
                    obj,
                    "element_length",
                    el,
                    "must be a finite number > 0",
                ));
            }
            (None, None) => {
                return Err(MeshError::param(
                    obj,
                    "segments",
                    "(missing)",
                    "give `segments` (>= 1) or `element_length` (> 0)",
                ));
            }
        };
        if n > crate::cage::MAX_NODES {
            return Err(MeshError::param(obj, "segments", n, "must be <= 2000000"));
        }
        if let Some(zb) = seabed_z
            && anchor.z < zb - 1e-9
        {
            return Err(MeshError::param(
                obj,
                "anchor",
                format!("{:?}", self.anchor),
                format!("is below the seabed z = {zb} m; put the anchor on or above it"),
            ));
        }
        let chord = (fair - anchor).norm();
        if chord == 0.0 {
            return Err(MeshError::inconsistent(
                obj,
                "anchor and fairlead coincide; a line needs two distinct ends",
            ));
        }
        let mut notices = Vec::new();
        if l0 < chord && (chord - l0) / l0 > 0.01 {
            notices.push(format!(
                "warning: {obj}: length {l0} m is shorter than the chord {chord:.4} m; the line \
                 starts stretched by {:.2} %",
                100.0 * (chord - l0) / l0
            ));
        }
        // Section.
        let d = match self.diameter {
            Some(d) if d.is_finite() && d > 0.0 => d,
            Some(d) => {
                return Err(MeshError::param(
                    obj,
                    "diameter",
                    d,
                    "must be a finite number > 0",
                ));
            }
            None => {
                return Err(MeshError::param(
                    obj,
                    "diameter",
                    "(missing)",
                    "required: the line's nominal diameter [m]",
                ));
            }
        };
        if self.ea.is_none() && self.youngs_modulus.is_none() {
            return Err(MeshError::param(
                obj,
                "ea",
                "(missing)",
                "give `ea` [N] or `youngs_modulus` [Pa]",
            ));
        }
        if self.mass_per_length.is_none() && self.density.is_none() {
            return Err(MeshError::param(
                obj,
                "mass_per_length",
                "(missing)",
                "give `mass_per_length` [kg/m] or `density` [kg/m³]",
            ));
        }
        let mut section = Section::cable(
            self.material.as_deref().unwrap_or("line"),
            d,
            self.youngs_modulus.unwrap_or(0.0),
            self.density.unwrap_or(0.0),
        );
        SectionOverride {
            diameter: None,
            wall_thickness: self.wall_thickness,
            ea: self.ea,
            youngs_modulus: self.youngs_modulus,
            density: self.density,
            mass_per_length: self.mass_per_length,
            hydro_diameter: self.hydro_diameter,
            volume_diameter: self.volume_diameter,
            elastic_diameter: self.elastic_diameter,
            compression_ratio: self.compression_ratio,
            axial_damping: self.axial_damping,
            axial_damping_ratio: self.axial_damping_ratio,
            initial_tension: self.initial_tension,
            seabed: self.seabed,
            contact_diameter: self.contact_diameter,
            material: None,
            ei: self.ei,
            bending: self.bending,
        }
        .apply(obj, "", &mut section)?;

        let mut pts = match self.shape {
            LineShape::Straight => (0..=n)
                .map(|i| anchor + (fair - anchor) * (i as f64 / n as f64))
                .collect(),
            LineShape::Catenary => catenary_nodes(anchor, fair, l0, n).unwrap_or_default(),
        };
        if let Some(zb) = seabed_z {
            for p in pts.iter_mut() {
                p.z = p.z.max(zb);
            }
        }
        let mut b = MeshBuilder::default();
        for p in pts {
            b.add_node(p);
        }
        let gname = self.group.clone().unwrap_or_else(|| name.clone());
        let g = b.group(&gname, Role::MooringLine, Some(section));
        for i in 0..n {
            b.add_line(g, i, i + 1, Some(l0 / n as f64));
        }
        b.finish_element_nodes();
        let ga = b.group("anchor", Role::Anchor, None);
        b.set_nodes(ga, [0]);
        let gf = b.group("fairlead", Role::Fairlead, None);
        b.set_nodes(gf, [n]);
        let gl = b.group("line_nodes", Role::LineNodes, None);
        b.set_nodes(gl, 0..=n);
        let fixed_names = self.fixed.clone().unwrap_or_else(|| vec!["anchor".into()]);
        let mut fixed = Vec::new();
        for f in &fixed_names {
            match b.mesh.groups.iter().find(|g| &g.name == f) {
                Some(g) => fixed.extend(g.nodes.iter().copied()),
                None => {
                    return Err(MeshError::UnknownGroup {
                        object: name.clone(),
                        key: "fixed".into(),
                        name: f.clone(),
                        valid: format!("anchor, fairlead, line_nodes, {gname}"),
                    });
                }
            }
        }
        let gx = b.group("fixed", Role::Fixed, None);
        b.set_nodes(gx, fixed);
        b.mesh.objects.push(Object {
            name,
            kind: ObjectKind::Line,
            origins: vec![self.anchor],
            net: None,
            counts: None,
            source_node_tags: Vec::new(),
        });
        b.mesh.notices = notices;
        Ok(b.mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain() -> LineParams {
        LineParams {
            anchor: [-100.0, 0.0, -50.0],
            fairlead: Some(Fairlead::Point([0.0, 0.0, 0.0])),
            length: 150.0,
            segments: Some(30),
            diameter: Some(0.1),
            ea: Some(1e8),
            mass_per_length: Some(100.0),
            ..Default::default()
        }
    }

    #[test]
    fn catenary_has_length_and_ends() {
        let m = chain().build().unwrap();
        assert_eq!(m.nodes.len(), 31);
        assert!((m.nodes[0] - Point3::new(-100.0, 0.0, -50.0)).norm() < 1e-12);
        assert!((m.nodes[30] - Point3::origin()).norm() < 1e-12);
        // Arc-length spacing: chords slightly shorter than L0/N, total close to L0.
        let total: f64 = (0..30).map(|e| m.line_length(e)).sum();
        assert!(total < 150.0 && total > 149.5, "{total}");
        for e in 0..30 {
            assert!(m.line_length(e) <= 5.0 + 1e-9);
            assert_eq!(m.lines[e].rest_length, Some(5.0));
        }
        // Sags below the chord; analytic catenary check z'' = (1 + z'^2)/a > 0 via convexity.
        for i in 1..30 {
            let p = m.nodes[i];
            let zc = -50.0 + 50.0 * (p.x + 100.0) / 100.0;
            assert!(p.z < zc);
        }
        assert_eq!(m.fixed_nodes(), vec![0]);
    }

    #[test]
    fn catenary_symmetric_level_ends() {
        // Level ends: the sag at mid-span follows from a: sag = a(cosh(l/2a) − 1), with
        // 2a·sinh(l/2a) = L0. For l = 100, L0 = 120 solve independently by Newton.
        let pts =
            catenary_nodes(Point3::origin(), Point3::new(100.0, 0.0, 0.0), 120.0, 40).unwrap();
        let mut a: f64 = 30.0;
        for _ in 0..100 {
            let g = 2.0 * a * (50.0 / a).sinh() - 120.0;
            let dg = 2.0 * (50.0 / a).sinh() - 100.0 / a * (50.0 / a).cosh();
            a -= g / dg;
        }
        let sag = a * ((50.0 / a).cosh() - 1.0);
        assert!((pts[20].z + sag).abs() < 1e-8, "{} vs {}", pts[20].z, -sag);
        assert!((pts[20].x - 50.0).abs() < 1e-9);
    }

    #[test]
    fn seabed_projection_and_errors() {
        let m = chain().build_with(None, Some(-50.0)).unwrap();
        assert!(m.nodes.iter().all(|p| p.z >= -50.0));
        assert!(chain().build_with(None, Some(-40.0)).is_err());
        let mut p = chain();
        p.length = -1.0;
        assert!(p.build().unwrap_err().to_string().contains("length"));
        let mut p = chain();
        p.diameter = None;
        assert!(p.build().unwrap_err().to_string().contains("diameter"));
        let mut p = chain();
        p.length = 100.0;
        let m = p.build().unwrap();
        assert_eq!(m.notices.len(), 1);
    }
}
