//! Flat net panel builder (`[[panel]]`, docs/theory/cages.md#flat-net-panel).
//!
//! Axes: e_n = normal, e_u = up projected onto the panel plane, e_w = e_u × e_n.
//! Node (i, j) = centre + (i/n_w − ½)·W·e_w + (½ − j/n_h)·H_p·e_u, id = j·(n_w+1) + i.

use crate::error::{MeshError, Result};
use crate::mesh_builder::MeshBuilder;
use crate::model::{Mesh, NetElement, Object, ObjectKind, PanelNodes, Role};
use crate::net::NetParams;
use crate::net_triangle::{TwineFrame, make_net_triangles};
use crate::section_override::SectionOverride;
use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

/// `fixed` key of a panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PanelFixed {
    /// Every node (rigid panel, default).
    #[default]
    All,
    /// Top row.
    Top,
    /// Top and bottom rows.
    TopBottom,
    /// All four edges.
    Edges,
    /// Nothing fixed.
    None,
}

impl PanelFixed {
    /// Parse the scene/CLI spelling (`all`, `top`, `top_bottom`, `edges`, `none`).
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "all" => Some(PanelFixed::All),
            "top" => Some(PanelFixed::Top),
            "top_bottom" => Some(PanelFixed::TopBottom),
            "edges" => Some(PanelFixed::Edges),
            "none" => Some(PanelFixed::None),
            _ => None,
        }
    }
}

/// One `[[panel]]` table.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PanelParams {
    /// `name` (default `panel0`).
    pub name: Option<String>,
    /// `width` W [m], > 0.
    pub width: f64,
    /// `height` H_p [m], > 0.
    pub height: f64,
    /// `divisions` [n_w, n_h], ≥ 1 each; default [10, 10] unless `element_length` is given.
    pub divisions: Option<[u32; 2]>,
    /// `element_length` [m]: n = max(1, round(size/el)) per direction.
    pub element_length: Option<f64>,
    /// `centre` [m], default [0, 0, −1].
    pub centre: Option<[f64; 3]>,
    /// `normal`, default [1, 0, 0].
    pub normal: Option<[f64; 3]>,
    /// `up`, default [0, 0, 1]; must not be parallel to `normal`.
    pub up: Option<[f64; 3]>,
    /// `fixed`, default `all`.
    #[serde(default)]
    pub fixed: PanelFixed,
    /// `bottom_weight` [N] shared over the bottom nodes, default 0.
    pub bottom_weight: Option<f64>,
    /// `net.*`.
    #[serde(default)]
    pub net: NetParams,
    /// `groups.net_twines` section override.
    #[serde(default)]
    pub groups: std::collections::BTreeMap<String, SectionOverride>,
}

impl PanelParams {
    /// A W × H panel with all other keys at their defaults.
    pub fn new(width: f64, height: f64) -> Self {
        PanelParams {
            name: None,
            width,
            height,
            divisions: None,
            element_length: None,
            centre: None,
            normal: None,
            up: None,
            fixed: PanelFixed::All,
            bottom_weight: None,
            net: NetParams::default(),
            groups: Default::default(),
        }
    }

    /// Validate and build.
    pub fn build(&self) -> Result<Mesh> {
        let name = self.name.clone().unwrap_or_else(|| "panel0".into());
        let obj = name.as_str();
        for (k, v) in [("width", self.width), ("height", self.height)] {
            crate::limits::length(obj, k, v, "")?;
        }
        let (nw, nh) = match (self.divisions, self.element_length) {
            (Some(_), Some(_)) => {
                return Err(MeshError::inconsistent(
                    obj,
                    "both `divisions` and `element_length` given; give only one",
                ));
            }
            (Some([a, b]), None) => {
                if a < 1 || b < 1 {
                    return Err(MeshError::param(
                        obj,
                        "divisions",
                        format!("[{a}, {b}]"),
                        "both entries must be >= 1",
                    ));
                }
                (a as usize, b as usize)
            }
            (None, Some(el)) => {
                if !(el.is_finite() && el > 0.0) {
                    return Err(MeshError::param(
                        obj,
                        "element_length",
                        el,
                        "must be a finite number > 0",
                    ));
                }
                let n = |s: f64| (s / el).round().max(1.0) as usize;
                (n(self.width), n(self.height))
            }
            (None, None) => (10, 10),
        };
        if (nw.saturating_add(1)).saturating_mul(nh.saturating_add(1)) > crate::limits::MAX_NODES {
            return Err(MeshError::param(
                obj,
                "divisions",
                format!("[{nw}, {nh}]"),
                "gives more than 2000000 nodes",
            ));
        }
        let vec = |key: &str, v: [f64; 3]| -> Result<Vector3<f64>> {
            let x = Vector3::from(v);
            if x.iter().all(|c| c.is_finite()) && x.norm() > 0.0 {
                Ok(x)
            } else {
                Err(MeshError::param(
                    obj,
                    key,
                    format!("{v:?}"),
                    "must be a finite non-zero vector",
                ))
            }
        };
        let centre = self.centre.unwrap_or([0.0, 0.0, -1.0]);
        if centre.iter().any(|c| !c.is_finite()) {
            return Err(MeshError::param(
                obj,
                "centre",
                format!("{centre:?}"),
                "must be finite",
            ));
        }
        let e_n = vec("normal", self.normal.unwrap_or([1.0, 0.0, 0.0]))?.normalize();
        let up = vec("up", self.up.unwrap_or([0.0, 0.0, 1.0]))?;
        let up_perp = up - e_n * up.dot(&e_n);
        if up_perp.norm() < 1e-9 * up.norm() {
            return Err(MeshError::inconsistent(
                obj,
                format!(
                    "`up` = {:?} is parallel to `normal` = {:?}; give an `up` direction in the \
                     panel plane",
                    self.up.unwrap_or([0.0, 0.0, 1.0]),
                    self.normal.unwrap_or([1.0, 0.0, 0.0])
                ),
            ));
        }
        let e_u = up_perp.normalize();
        let e_w = e_u.cross(&e_n);
        let bottom_weight = self.bottom_weight.unwrap_or(0.0);
        if !(bottom_weight.is_finite() && bottom_weight >= 0.0) {
            return Err(MeshError::param(
                obj,
                "bottom_weight",
                bottom_weight,
                "must be >= 0 (use buoys for upward forces)",
            ));
        }
        let mut notices = Vec::new();
        let net = self.net.resolve(obj, &mut notices)?;

        let mut b = MeshBuilder::default();
        let c = Point3::from(centre);
        for j in 0..=nh {
            for i in 0..=nw {
                let s = (i as f64 / nw as f64 - 0.5) * self.width;
                let t = (0.5 - j as f64 / nh as f64) * self.height;
                b.add_node(c + s * e_w + t * e_u);
            }
        }
        let id = |i: usize, j: usize| j * (nw + 1) + i;
        let g_tw = b.group("net_twines", Role::NetTwines, None);
        for j in 0..=nh {
            for i in 0..nw {
                b.add_line(g_tw, id(i, j), id(i + 1, j), None);
            }
        }
        for j in 0..nh {
            for i in 0..=nw {
                b.add_line(g_tw, id(i, j), id(i, j + 1), None);
            }
        }
        let g_pa = b.group("net_panels", Role::NetPanels, None);
        for j in 0..nh {
            for i in 0..nw {
                b.add_panel(
                    g_pa,
                    PanelNodes::Quad([id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)]),
                );
            }
        }
        b.finish_element_nodes();
        let top: Vec<usize> = (0..=nw).map(|i| id(i, 0)).collect();
        let bottom: Vec<usize> = (0..=nw).map(|i| id(i, nh)).collect();
        let left: Vec<usize> = (0..=nh).map(|j| id(0, j)).collect();
        let right: Vec<usize> = (0..=nh).map(|j| id(nw, j)).collect();
        for (n, r, v) in [
            ("panel_top", Role::PanelTop, &top),
            ("panel_bottom", Role::PanelBottom, &bottom),
            ("panel_left", Role::PanelLeft, &left),
            ("panel_right", Role::PanelRight, &right),
        ] {
            let g = b.group(n, r, None);
            b.set_nodes(g, v.iter().copied());
        }
        let fixed: Vec<usize> = match self.fixed {
            PanelFixed::All => (0..b.mesh.nodes.len()).collect(),
            PanelFixed::Top => top.clone(),
            PanelFixed::TopBottom => top.iter().chain(&bottom).copied().collect(),
            PanelFixed::Edges => top
                .iter()
                .chain(&bottom)
                .chain(&left)
                .chain(&right)
                .copied()
                .collect(),
            PanelFixed::None => Vec::new(),
        };
        let g = b.group("fixed", Role::Fixed, None);
        b.set_nodes(g, fixed);
        if bottom_weight > 0.0 {
            let g = b.group_index_of("panel_bottom");
            for &n in &bottom {
                b.weight(g, n, bottom_weight / bottom.len() as f64);
            }
        }
        for key in self.groups.keys() {
            if key != "net_twines" {
                return Err(MeshError::UnknownGroup {
                    object: obj.to_string(),
                    key: format!("groups.{key}"),
                    name: key.clone(),
                    valid: "net_twines".into(),
                });
            }
        }
        let size = format!(
            "`width` = {} m and `height` = {} m",
            self.width, self.height
        );
        let grouping = net.group_net(&mut b, obj, g_tw, Some(g_pa), &size, &mut notices)?;
        let mut tw = grouping.twine_section();
        if let Some(o) = self.groups.get("net_twines") {
            o.apply(obj, "groups.net_twines", &mut tw)?;
        }
        b.mesh.groups[g_tw].section = Some(tw);
        if net.element == NetElement::Triangle {
            let frame = TwineFrame::of(&net, TwineFrame::Along(e_w.into()));
            make_net_triangles(&mut b, obj, &net, g_tw, g_pa, frame)?;
        }
        b.mesh.objects.push(Object {
            name,
            kind: ObjectKind::Panel,
            origins: vec![centre],
            net: Some(grouping),
            detail: crate::model::ObjectDetail::None,
        });
        b.mesh.notices = notices;
        Ok(b.mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_counts_and_normal() {
        // docs/theory/cages.md#flat-net-panel: 1 m × 1 m, 10 × 10 → 121 nodes, 220 lines, 100
        // quads.
        let m = PanelParams::new(1.0, 1.0).build().unwrap();
        assert_eq!(
            (m.nodes.len(), m.lines.len(), m.panels.len()),
            (121, 220, 100)
        );
        for p in 0..m.panels.len() {
            let a = m.panel_area_vector(p);
            assert!((a - Vector3::new(0.01, 0.0, 0.0)).norm() < 1e-12);
        }
        // Yawed 30°: normal follows.
        let th = 30f64.to_radians();
        let mut p = PanelParams::new(2.0, 1.0);
        p.normal = Some([th.cos(), th.sin(), 0.0]);
        p.divisions = Some([4, 2]);
        let m = p.build().unwrap();
        let total: Vector3<f64> = (0..m.panels.len()).map(|i| m.panel_area_vector(i)).sum();
        assert!((total - 2.0 * Vector3::new(th.cos(), th.sin(), 0.0)).norm() < 1e-12);
        assert_eq!(m.fixed_nodes().len(), 15);
    }

    #[test]
    fn bad_panel_inputs() {
        let mut p = PanelParams::new(1.0, 1.0);
        p.up = Some([2.0, 0.0, 0.0]);
        assert!(p.build().unwrap_err().to_string().contains("parallel"));
        let p = PanelParams::new(0.0, 1.0);
        assert!(p.build().unwrap_err().to_string().contains("width"));
        let mut p = PanelParams::new(1.0, 1.0);
        p.divisions = Some([0, 3]);
        assert!(p.build().unwrap_err().to_string().contains("divisions"));
    }

    #[test]
    fn bottom_weight_shared() {
        let mut p = PanelParams::new(1.0, 1.0);
        p.bottom_weight = Some(110.0);
        p.fixed = PanelFixed::Top;
        let m = p.build().unwrap();
        assert_eq!(m.weights.len(), 11);
        assert!((m.weights.iter().map(|w| w.weight).sum::<f64>() - 110.0).abs() < 1e-9);
        assert_eq!(m.fixed_nodes(), (0..11).collect::<Vec<_>>());
    }
}
