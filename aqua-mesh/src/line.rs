//! Single line builder (`[[line]]`: moorings, bridles; docs/theory/cages.md#single-line).
//!
//! Nodes 0..N from anchor to fairlead. A line is one section of unstretched length L0 in N
//! elements of L0/N, or a chain of segments (`[[line.segment]]`, e.g. chain then rope), segment
//! k of length L_k in N_k elements of L_k/N_k, each its own element group, L0 = Σ L_k.
//! Initial shape: straight and uniformly stretched if L0 ≤ chord; otherwise the inextensible
//! catenary of length L0 through both ends, z = a·cosh((x − x0)/a) + c in the vertical plane
//! of the chord, with a from √(L0² − h²) = 2a·sinh(l/2a) (l horizontal, h vertical span),
//! nodes at their arc lengths (i·L0/N for one section; the segments' own spacing otherwise),
//! and nodes below the seabed projected onto it. An anchor on the seabed with a line that
//! touches down starts as the catenary with touchdown ([`touchdown_points`]), and when statics
//! follow the length is stretched by [`INITIAL_STRETCH`] (docs/theory/cages.md#single-line).
//! The catenary is that of a uniform line: for segments of different weights it is a starting
//! shape only, statics finds the true one.

use crate::Mesh;
use crate::error::{MeshError, Result};
use crate::mesh_builder::MeshBuilder;
use crate::model::{Object, ObjectKind, Role};
use crate::section::Section;
use crate::section_override::{SectionOverride, section_table};
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

impl LineShape {
    /// Parse the scene/CLI spelling (`catenary`, `straight`).
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "catenary" => Some(LineShape::Catenary),
            "straight" => Some(LineShape::Straight),
            _ => None,
        }
    }
}

section_table! {
    /// One `[[line]]` table. Section keys (docs/theory/fem.md#sections) sit directly in the table.
    #[derive(Debug, Clone, PartialEq, Default, Deserialize, Serialize)]
    #[serde(deny_unknown_fields)]
    pub struct LineParams {
        /// Strain by which the initial catenary is stretched (not a scene key: the scene builder
        /// sets [`INITIAL_STRETCH`] when a static solve starts from the shape; 0 keeps the
        /// unstretched as-built line that dynamics-only runs start from at rest).
        #[serde(skip)]
        pub initial_stretch: f64,
        /// `name` (default `line0`).
        pub name: Option<String>,
        /// `anchor` [m].
        pub anchor: [f64; 3],
        /// `fairlead` [m] or node reference.
        pub fairlead: Option<Fairlead>,
        /// `length` L0 unstretched [m], > 0 (0 = not given; required without segments).
        #[serde(default)]
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
    }
    section: full;
    tail {
        /// `[[line.segment]]`: the line as segments from anchor to fairlead, instead of
        /// `length`, `segments`/`element_length`, `group` and the section keys.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        pub segment: Vec<LineSegment>,
    }
}

section_table! {
    /// One `[[line.segment]]`: a stretch of a line with its own section, listed from the anchor
    /// to the fairlead. Its elements form the group `name` of the line's object.
    #[derive(Debug, Clone, PartialEq, Default, Deserialize, Serialize)]
    #[serde(deny_unknown_fields)]
    pub struct LineSegment {
        /// `name`: the element group (default `segment<k>`, k from 0 at the anchor).
        pub name: Option<String>,
        /// `length` L_k unstretched [m], > 0.
        pub length: f64,
        /// `elements` N_k ≥ 1 (or `element_length`).
        pub elements: Option<u32>,
        /// `element_length` [m]: N_k = max(1, round(L_k/el)).
        pub element_length: Option<f64>,
    }
    section: axial;
    tail {}
}

/// The section keys of a line or a segment: diameter, material and the overrides.
struct SectionKeys {
    diameter: Option<f64>,
    material: Option<String>,
    over: SectionOverride,
}

impl LineParams {
    fn section_keys(&self) -> SectionKeys {
        SectionKeys::of(self.section_override())
    }
}

impl LineSegment {
    fn section_keys(&self) -> SectionKeys {
        SectionKeys::of(self.section_override())
    }
}

impl SectionKeys {
    /// The table's section keys with the diameter and the material apart.
    fn of(mut over: SectionOverride) -> Self {
        Self {
            diameter: over.diameter.take(),
            material: over.material.take(),
            over,
        }
    }

    /// The cable section; `prefix` names the table in messages (`""` or `segment[k].`).
    fn section(&self, obj: &str, prefix: &str) -> Result<Section> {
        let key = |k: &str| format!("{prefix}{k}");
        let d = match self.diameter {
            Some(d) if d.is_finite() && d > 0.0 => d,
            Some(d) => {
                return Err(MeshError::param(
                    obj,
                    &key("diameter"),
                    d,
                    "must be a finite number > 0",
                ));
            }
            None => {
                return Err(MeshError::param(
                    obj,
                    &key("diameter"),
                    "(missing)",
                    "required: the line's nominal diameter [m]",
                ));
            }
        };
        if self.over.ea.is_none() && self.over.youngs_modulus.is_none() {
            return Err(MeshError::param(
                obj,
                &key("ea"),
                "(missing)",
                "give `ea` [N] or `youngs_modulus` [Pa]",
            ));
        }
        if self.over.mass_per_length.is_none() && self.over.density.is_none() {
            return Err(MeshError::param(
                obj,
                &key("mass_per_length"),
                "(missing)",
                "give `mass_per_length` [kg/m] or `density` [kg/m³]",
            ));
        }
        let mut section = Section::cable(
            self.material.as_deref().unwrap_or("line"),
            d,
            self.over.youngs_modulus.unwrap_or(0.0),
            self.over.density.unwrap_or(0.0),
        );
        let trimmed = prefix.trim_end_matches('.');
        self.over.apply(obj, trimmed, &mut section)?;
        Ok(section)
    }
}

/// A stretch of uniform section: its element group, unstretched length [m], element count
/// and section.
struct Stretch {
    group: String,
    length: f64,
    elements: usize,
    section: Section,
}

/// Element count from `count` or `element_length` (keys named as in the table).
fn element_count(
    obj: &str,
    keys: (&str, &str),
    length: f64,
    count: Option<u32>,
    element_length: Option<f64>,
) -> Result<usize> {
    let (count_key, el_key) = keys;
    match (count, element_length) {
        (Some(_), Some(_)) => Err(MeshError::inconsistent(
            obj,
            format!("both `{count_key}` and `{el_key}` given; give only one"),
        )),
        (Some(s), None) if s >= 1 => Ok(s as usize),
        (Some(s), None) => Err(MeshError::param(obj, count_key, s, "must be >= 1")),
        (None, Some(el)) if el.is_finite() && el > 0.0 => {
            Ok((length / el).round().max(1.0) as usize)
        }
        (None, Some(el)) => Err(MeshError::param(
            obj,
            el_key,
            el,
            "must be a finite number > 0",
        )),
        (None, None) => Err(MeshError::param(
            obj,
            count_key,
            "(missing)",
            format!("give `{count_key}` (>= 1) or `{el_key}` (> 0)"),
        )),
    }
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

/// Strain by which a hanging line's initial shape is stretched when a static solve starts from
/// it (the scene builder sets it; dynamics-only runs keep the unstretched shape): its
/// elements then start taut (where their chord deficit on the curve is below it), with their
/// axial stiffness in the first tangent. From the unstretched shape the slack elements were
/// invisible to the tangent and each Newton step over-stretched them
/// (docs/theory/cages.md#single-line).
pub const INITIAL_STRETCH: f64 = 1e-4;

/// The initial shape of a hanging line of unstretched length `l0` from `a` to `b` at arc lengths
/// `arc`: the touchdown catenary when the anchor lies on the seabed z = `zb` and the line touches
/// down, else the free catenary (straight if it cannot sag), for the length stretched by the
/// strain `stretch` (e.g. [`INITIAL_STRETCH`]). Empty if `a == b`.
pub fn hanging_points(
    a: Point3<f64>,
    b: Point3<f64>,
    l0: f64,
    arc: &[f64],
    seabed_z: Option<f64>,
    stretch: f64,
) -> Vec<Point3<f64>> {
    let stretch = 1.0 + stretch;
    let arc: Vec<f64> = arc.iter().map(|s| s * stretch).collect();
    seabed_z
        .and_then(|zb| touchdown_points(a, b, l0 * stretch, &arc, zb))
        .or_else(|| catenary_points(a, b, l0 * stretch, &arc))
        .unwrap_or_default()
}

/// Positions at arc lengths `arc` from `a` of an inextensible line of length `l0` from an anchor
/// `a` on the seabed z = `zb` to a fairlead `b` above it, lying on the seabed from `a` and
/// rising from the touchdown point as the catenary whose vertex is there:
///
/// ```text
/// s_s = √(h² + 2·h·c),  x_s = c·asinh(s_s/c),  l = (l0 − s_s) + x_s
/// ```
///
/// (c = H/w the catenary parameter, h the fairlead's height above the seabed, l the horizontal
/// span, s_s and x_s the suspended arc and span), solved for c by bisection. `None` when the
/// anchor is not on the seabed, the line cannot reach (l0 ≥ l + h: it would pile up) or the line
/// does not touch down (s_s > l0): then the free catenary applies
/// (docs/theory/cages.md#single-line).
pub fn touchdown_points(
    a: Point3<f64>,
    b: Point3<f64>,
    l0: f64,
    arc: &[f64],
    zb: f64,
) -> Option<Vec<Point3<f64>>> {
    let d = b - a;
    let horiz = Vector3::new(d.x, d.y, 0.0);
    let l = horiz.norm();
    let h = b.z - zb;
    if (a.z - zb).abs() > 1e-6 * (1.0 + l0) || h <= 0.0 || l <= 0.0 || l0 >= l + h {
        return None;
    }
    let suspended = |c: f64| (h * h + 2.0 * h * c).sqrt();
    let span = |c: f64| l0 - suspended(c) + c * (suspended(c) / c).asinh() - l;
    let (mut lo, mut hi) = (1e-9 * (l + h), 1e3 * (l + h));
    if !(span(lo) < 0.0 && span(hi) > 0.0) {
        return None;
    }
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if span(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-14 * hi {
            break;
        }
    }
    let c = 0.5 * (lo + hi);
    let laid = l0 - suspended(c);
    if laid < 0.0 {
        return None;
    }
    let ex = horiz / l;
    let ground = Point3::new(a.x, a.y, zb);
    Some(
        arc.iter()
            .map(|&s| {
                if s >= l0 {
                    b
                } else if s <= laid {
                    ground + ex * s
                } else {
                    let sigma = (s - laid) / c;
                    let x = laid + c * sigma.asinh();
                    let z = c * ((1.0 + sigma * sigma).sqrt() - 1.0);
                    ground + ex * x + Vector3::new(0.0, 0.0, z)
                }
            })
            .collect(),
    )
}

/// Positions of N+1 nodes of an inextensible line of length `l0` hanging between `a` and `b`
/// (catenary in the vertical plane through both ends; straight when slack is impossible or the
/// chord is vertical), at arc lengths i·l0/N. Returns `None` if `a == b`.
pub fn catenary_nodes(
    a: Point3<f64>,
    b: Point3<f64>,
    l0: f64,
    n: usize,
) -> Option<Vec<Point3<f64>>> {
    if n == 0 {
        return None;
    }
    let arc: Vec<f64> = (0..=n).map(|i| l0 * i as f64 / n as f64).collect();
    catenary_points(a, b, l0, &arc)
}

/// As [`catenary_nodes`], at the given arc lengths s ∈ [0, l0] from `a` [m] (s ≥ l0 gives `b`
/// exactly); on the straight chord the point at s is at the fraction s/l0 of it.
pub fn catenary_points(
    a: Point3<f64>,
    b: Point3<f64>,
    l0: f64,
    arc: &[f64],
) -> Option<Vec<Point3<f64>>> {
    let d = b - a;
    let chord = d.norm();
    if chord == 0.0 || arc.is_empty() || !(l0 > 0.0) {
        return None;
    }
    let horiz = Vector3::new(d.x, d.y, 0.0);
    let l = horiz.norm();
    let h = d.z;
    let straight = || {
        arc.iter()
            .map(|&s| if s >= l0 { b } else { a + d * (s / l0) })
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
        arc.iter()
            .map(|&s| {
                if s >= l0 {
                    return b;
                }
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
        let stretches = self.stretches(obj, &name)?;
        let l0: f64 = stretches.iter().map(|st| st.length).sum();
        let n = stretches
            .iter()
            .map(|st| st.elements)
            .fold(0usize, usize::saturating_add);
        if n > crate::limits::MAX_NODES {
            let key = if self.segment.is_empty() {
                "segments"
            } else {
                "segment[*].elements"
            };
            return Err(MeshError::param(
                obj,
                key,
                n,
                format!(
                    "gives {n} elements in all; at most {} (from the elements or \
                     element_length of each part)",
                    crate::limits::MAX_NODES
                ),
            ));
        }
        if let Some(zb) = seabed_z
            && anchor.z < zb - 1e-9
        {
            return Err(MeshError::param(
                obj,
                "anchor",
                format!("{:?}", self.anchor),
                format!(
                    "is below the seabed z = {zb} m ([sea] depth = {} m); put the anchor on or \
                     above it",
                    -zb
                ),
            ));
        }
        if (fair - anchor).norm() == 0.0 {
            return Err(MeshError::inconsistent(
                obj,
                "anchor and fairlead coincide; a line needs two distinct ends",
            ));
        }
        // Arc length of every node from the anchor, each stretch evenly divided.
        let mut arc = vec![0.0];
        for st in &stretches {
            let s0 = *arc.last().unwrap_or(&0.0);
            arc.extend((1..=st.elements).map(|i| s0 + st.length * i as f64 / st.elements as f64));
        }
        let mut pts = match self.shape {
            LineShape::Straight => arc
                .iter()
                .map(|&s| anchor + (fair - anchor) * (s / l0))
                .collect(),
            LineShape::Catenary => {
                hanging_points(anchor, fair, l0, &arc, seabed_z, self.initial_stretch)
            }
        };
        if let Some(p) = pts.last_mut() {
            *p = fair;
        }
        if let Some(zb) = seabed_z {
            for p in pts.iter_mut() {
                p.z = p.z.max(zb);
            }
        }
        let mut b = MeshBuilder::default();
        for p in pts {
            b.add_node(p);
        }
        let mut first = 0;
        let mut joints = Vec::new();
        for st in &stretches {
            let g = b.group(&st.group, Role::MooringLine, Some(st.section.clone()));
            let le = st.length / st.elements as f64;
            for i in first..first + st.elements {
                b.add_line(g, i, i + 1, Some(le));
            }
            first += st.elements;
            if first < n {
                joints.push(first);
            }
        }
        b.finish_element_nodes();
        let ga = b.group("anchor", Role::Anchor, None);
        b.set_nodes(ga, [0]);
        let gf = b.group("fairlead", Role::Fairlead, None);
        b.set_nodes(gf, [n]);
        let gl = b.group("line_nodes", Role::LineNodes, None);
        b.set_nodes(gl, 0..=n);
        if !joints.is_empty() {
            let gj = b.group("joints", Role::UserNodes, None);
            b.set_nodes(gj, joints);
        }
        let gname = stretches
            .iter()
            .map(|st| st.group.as_str())
            .collect::<Vec<_>>()
            .join(", ");
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
                        valid: format!(
                            "anchor, fairlead, line_nodes, {}{gname}",
                            if stretches.len() > 1 { "joints, " } else { "" }
                        ),
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
            detail: crate::model::ObjectDetail::None,
        });
        Ok(b.mesh)
    }

    /// The stretches of uniform section: the one section of the line, or its segments.
    fn stretches(&self, obj: &str, name: &str) -> Result<Vec<Stretch>> {
        if self.segment.is_empty() {
            let l0 = crate::limits::length(
                obj,
                "length",
                self.length,
                " (the unstretched length; or give [[line.segment]] tables)",
            )?;
            let elements = element_count(
                obj,
                ("segments", "element_length"),
                l0,
                self.segments,
                self.element_length,
            )?;
            return Ok(vec![Stretch {
                group: self.group.clone().unwrap_or_else(|| name.to_string()),
                length: l0,
                elements,
                section: self.section_keys().section(obj, "")?,
            }]);
        }
        self.single_section_keys_absent(obj)?;
        let mut out: Vec<Stretch> = Vec::with_capacity(self.segment.len());
        for (k, seg) in self.segment.iter().enumerate() {
            let prefix = format!("segment[{k}].");
            let key = |x: &str| format!("{prefix}{x}");
            crate::limits::length(
                obj,
                &key("length"),
                seg.length,
                " (the segment's unstretched length)",
            )?;
            let elements = element_count(
                obj,
                (&key("elements"), &key("element_length")),
                seg.length,
                seg.elements,
                seg.element_length,
            )?;
            let group = seg.name.clone().unwrap_or_else(|| format!("segment{k}"));
            if RESERVED.contains(&group.as_str()) || out.iter().any(|o| o.group == group) {
                return Err(MeshError::param(
                    obj,
                    &key("name"),
                    &group,
                    format!(
                        "must differ from the other segments' names and from {}",
                        RESERVED.join(", ")
                    ),
                ));
            }
            out.push(Stretch {
                group,
                length: seg.length,
                elements,
                section: seg.section_keys().section(obj, &prefix)?,
            });
        }
        Ok(out)
    }

    /// With `[[line.segment]]`, the keys of a one-section line must be absent.
    fn single_section_keys_absent(&self, obj: &str) -> Result<()> {
        let given = [
            ("length", self.length != 0.0),
            ("segments", self.segments.is_some()),
            ("element_length", self.element_length.is_some()),
            ("group", self.group.is_some()),
            ("diameter", self.diameter.is_some()),
            ("wall_thickness", self.wall_thickness.is_some()),
            ("sdr", self.sdr.is_some()),
            ("ea", self.ea.is_some()),
            ("youngs_modulus", self.youngs_modulus.is_some()),
            ("density", self.density.is_some()),
            ("mass_per_length", self.mass_per_length.is_some()),
            ("hydro_diameter", self.hydro_diameter.is_some()),
            ("volume_diameter", self.volume_diameter.is_some()),
            ("elastic_diameter", self.elastic_diameter.is_some()),
            ("compression_ratio", self.compression_ratio.is_some()),
            ("axial_damping", self.axial_damping.is_some()),
            ("axial_damping_ratio", self.axial_damping_ratio.is_some()),
            ("initial_tension", self.initial_tension.is_some()),
            ("seabed", self.seabed.is_some()),
            ("contact_diameter", self.contact_diameter.is_some()),
            ("material", self.material.is_some()),
            ("ei", self.ei.is_some()),
            ("bending", self.bending.is_some()),
            ("bending_element", self.bending_element.is_some()),
            ("poisson_ratio", self.poisson_ratio.is_some()),
        ];
        match given.iter().find(|(_, g)| *g) {
            Some((k, _)) => Err(MeshError::inconsistent(
                obj,
                format!(
                    "`{k}` is given with [[line.segment]] tables; a segmented line takes its \
                     length (the sum), element counts, groups (the segment names) and sections \
                     from its segments: move `{k}` into the segments or remove it"
                ),
            )),
            None => Ok(()),
        }
    }
}

/// Node group names of a line; a segment may not use them.
const RESERVED: [&str; 5] = ["anchor", "fairlead", "line_nodes", "joints", "fixed"];

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
    fn touchdown_catenary_lies_on_the_bed_has_its_length_and_meets_the_bed_tangentially() {
        let (a, b, zb) = (
            Point3::new(0.0, 0.0, -50.0),
            Point3::new(100.0, 0.0, -5.0),
            -50.0,
        );
        let n = 4000;
        let arc: Vec<f64> = (0..=n).map(|i| 120.0 * i as f64 / n as f64).collect();
        let p = touchdown_points(a, b, 120.0, &arc, zb).expect("it touches down");
        assert_eq!(p[0], a);
        assert_eq!(p[n], b);
        // Consecutive points are one arc step apart (to the chord's second-order deficit).
        let step = 120.0 / n as f64;
        for w in p.windows(2) {
            let d = (w[1] - w[0]).norm();
            assert!(d <= step * (1.0 + 1e-12) && d > step * (1.0 - 1e-4), "{d}");
            assert!(w[1].z >= zb - 1e-12);
        }
        // A laid part, then a rise whose first slope is zero (tangent at touchdown).
        let laid = p.iter().filter(|q| q.z == zb).count();
        assert!(laid > 100 && laid < n);
        let rise = (p[laid + 1].z - p[laid].z) / (p[laid + 1].x - p[laid].x);
        assert!(rise.abs() < 0.01, "{rise}");
        // A short line hangs free of the bed; a line longer than span + height piles up.
        assert!(touchdown_points(a, b, 110.0, &arc, zb).is_none());
        assert!(touchdown_points(a, b, 146.0, &arc, zb).is_none());
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
        // A line shorter than its chord builds (straight, stretched); the scene warns.
        let mut p = chain();
        p.length = 100.0;
        let m = p.build().unwrap();
        assert!((m.nodes[15] - Point3::new(-50.0, 0.0, -25.0)).norm() < 1e-9);
    }

    fn chain_then_rope() -> LineParams {
        let seg = |name: &str, length, elements, d, mu, ea| LineSegment {
            name: Some(name.into()),
            length,
            elements: Some(elements),
            diameter: Some(d),
            mass_per_length: Some(mu),
            ea: Some(ea),
            ..Default::default()
        };
        LineParams {
            name: Some("m1".into()),
            anchor: [-100.0, 0.0, -50.0],
            fairlead: Some(Fairlead::Point([0.0, 0.0, 0.0])),
            segment: vec![
                seg("chain", 60.0, 12, 0.08, 130.0, 6e8),
                seg("rope", 90.0, 30, 0.06, 3.0, 5e7),
            ],
            ..Default::default()
        }
    }

    #[test]
    fn segments_have_their_groups_spacing_and_joint() {
        let m = chain_then_rope().build().unwrap();
        assert_eq!(m.nodes.len(), 43);
        assert_eq!(m.lines.len(), 42);
        let gc = m.group(0, "chain").unwrap();
        let gr = m.group(0, "rope").unwrap();
        assert_eq!(gc.lines, (0..12).collect::<Vec<_>>());
        assert_eq!(gr.lines, (12..42).collect::<Vec<_>>());
        assert_eq!(gc.section.as_ref().unwrap().linear_mass(), 130.0);
        assert_eq!(gr.section.as_ref().unwrap().linear_mass(), 3.0);
        for e in 0..12 {
            assert_eq!(m.lines[e].rest_length, Some(5.0));
        }
        for e in 12..42 {
            assert_eq!(m.lines[e].rest_length, Some(3.0));
        }
        assert_eq!(m.group(0, "joints").unwrap().nodes, vec![12]);
        // The joint sits on the same catenary of length 150 m at arc length 60 m as a
        // one-section line of 30 elements has its node 12 (also at 60 m).
        let one = chain().build().unwrap();
        assert!((m.nodes[12] - one.nodes[12]).norm() < 1e-9);
        assert!((m.nodes[42] - Point3::origin()).norm() < 1e-12);
        // Straight shape: the joint at 60/150 of the chord.
        let mut p = chain_then_rope();
        p.shape = LineShape::Straight;
        let m = p.build().unwrap();
        assert!((m.nodes[12] - Point3::new(-60.0, 0.0, -30.0)).norm() < 1e-9);
    }

    #[test]
    fn segment_errors_name_the_key() {
        let mut p = chain_then_rope();
        p.segment[1].length = -5.0;
        let e = p.build().unwrap_err().to_string();
        assert!(e.contains("segment[1].length") && e.contains("-5"), "{e}");
        let mut p = chain_then_rope();
        p.length = 150.0;
        let e = p.build().unwrap_err().to_string();
        assert!(
            e.contains("`length`") && e.contains("[[line.segment]]"),
            "{e}"
        );
        let mut p = chain_then_rope();
        p.segment[1].name = Some("chain".into());
        let e = p.build().unwrap_err().to_string();
        assert!(e.contains("segment[1].name"), "{e}");
        let mut p = chain_then_rope();
        p.segment[0].diameter = None;
        let e = p.build().unwrap_err().to_string();
        assert!(e.contains("segment[0].diameter"), "{e}");
        let mut p = chain_then_rope();
        p.segment[0].elements = None;
        let e = p.build().unwrap_err().to_string();
        assert!(e.contains("segment[0].elements"), "{e}");
        let t = "anchor = [0, 0, -10]\nfairlead = [5, 0, 0]\n[[segment]]\nlength = 5\nlenght = 2\n";
        let e = toml::from_str::<LineParams>(t).unwrap_err().to_string();
        assert!(e.contains("lenght") && e.contains("elements"), "{e}");
    }
}
