//! The mesh of a resolved cage (docs/theory/cages.md#net-geometry, #frame-ropes-and-weights):
//! net nodes and frame columns, net twines and panels, frame lines, node groups, weights,
//! mesh grouping and the copies at every origin.

use super::{ResolvedCage, default_frame_section};
use crate::collar::default_bracket_section;
use crate::error::{MeshError, Result};
use crate::mesh_builder::{MeshBuilder, replicate};
use crate::model::{CageCounts, CageType, Mesh, NetElement, Object, ObjectKind, PanelNodes, Role};
use crate::net_triangle::{TwineFrame, make_net_triangles};
use crate::section::Section;
use nalgebra::{Point3, Vector3};
use std::f64::consts::PI;

impl ResolvedCage {
    /// Unit shape vector u_i (docs/theory/cages.md#net-geometry).
    fn shape(&self, i: usize) -> Vector3<f64> {
        if self.square {
            const C: [[f64; 2]; 5] = [
                [1.0, -1.0],
                [1.0, 1.0],
                [-1.0, 1.0],
                [-1.0, -1.0],
                [1.0, -1.0],
            ];
            let s = i / self.ns;
            let t = (i % self.ns) as f64 / self.ns as f64;
            let (a, b) = (C[s], C[s + 1]);
            Vector3::new(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, 0.0)
        } else {
            let phi = 2.0 * PI * i as f64 / self.nt as f64;
            Vector3::new(phi.cos(), phi.sin(), 0.0)
        }
    }

    /// Radius ρ_ℓ and depth z_ℓ of net level ℓ.
    fn level(&self, l: usize) -> (f64, f64) {
        let (nn, bn) = (self.nn as f64, self.bn as f64);
        if l < self.nn {
            let rho = self.r_t - (self.r_t - self.r_b) * l as f64 / nn;
            (rho, -(l as f64) * self.depth / nn)
        } else {
            let k = (l - self.nn) as f64;
            (
                self.r_b * (bn - k) / bn,
                -self.depth - k * self.cone_depth / bn,
            )
        }
    }

    /// Levels L = NN + BN.
    pub fn levels(&self) -> usize {
        self.nn + self.bn
    }

    /// Nodes per rope column n_f.
    pub fn column_nodes(&self) -> usize {
        match self.kind {
            CageType::Ccs => self.nn + self.n_ext,
            _ => self.nn + 1 + self.n_ext,
        }
    }

    /// Build all copies.
    pub fn build(&self) -> Result<Mesh> {
        let obj = self.name.as_str();
        let mut b = MeshBuilder::default();
        let origin = Vector3::from(self.origins[0]);
        let (nt, l) = (self.nt, self.levels());
        let net_id = |i: usize, lv: usize| (i % nt) * l + lv;

        // Net nodes, id = i·L + ℓ, then the tip.
        for i in 0..nt {
            let u = self.shape(i);
            for lv in 0..l {
                let (rho, z) = self.level(lv);
                b.add_node(Point3::from(origin + rho * u + Vector3::new(0.0, 0.0, z)));
            }
        }
        let tip = b.add_node(Point3::from(
            origin + Vector3::new(0.0, 0.0, -self.depth - self.cone_depth),
        ));

        // Frame columns.
        let n_net = nt * l + 1;
        let n_f = self.column_nodes();
        let hz = self.depth / self.nn as f64;
        for i in 0..nt {
            let u = self.shape(i);
            for j in 0..n_f {
                let p = match self.kind {
                    CageType::Csm | CageType::Ssm | CageType::Cct | CageType::Cst => {
                        let z = if j <= self.nn {
                            -(j as f64) * hz
                        } else {
                            -self.depth - (j - self.nn) as f64 * self.ext_depth / self.n_ext as f64
                        };
                        (self.r_t + self.frame_offset) * u + Vector3::new(0.0, 0.0, z)
                    }
                    CageType::Ccs => {
                        if j <= self.nn {
                            let rho = self.r_t - (self.r_t - self.r_b) * j as f64 / self.nn as f64;
                            (rho + self.frame_offset) * u + Vector3::new(0.0, 0.0, -(j as f64) * hz)
                        } else {
                            let m = (j - self.nn) as f64 / self.n_ext as f64;
                            (self.r_b + self.frame_offset) * (1.0 - m) * u
                                + Vector3::new(0.0, 0.0, -self.depth - self.ext_depth * m)
                        }
                    }
                };
                b.add_node(Point3::from(origin + p));
            }
        }
        let col = |i: usize, j: usize| n_net + (i % nt) * n_f + j;
        let centre = (self.kind == CageType::Ccs).then(|| {
            b.add_node(Point3::from(
                origin + Vector3::new(0.0, 0.0, -self.depth - self.ext_depth),
            ))
        });
        // Outer collar pipe (two-pipe collars): one node per column, further out.
        let r_in = self.r_t + self.frame_offset;
        let outer: Vec<usize> = (0..nt * (self.collar.pipes - 1))
            .map(|i| b.add_node(self.collar.outer_point(origin, self.shape(i), r_in)))
            .collect();

        // Net twines: rings, meridians, tip lines.
        let g_tw = b.group("net_twines", Role::NetTwines, None);
        for lv in 0..l {
            for i in 0..nt {
                b.add_line(g_tw, net_id(i, lv), net_id(i + 1, lv), None);
            }
        }
        for lv in 0..l - 1 {
            for i in 0..nt {
                b.add_line(g_tw, net_id(i, lv), net_id(i, lv + 1), None);
            }
        }
        for i in 0..nt {
            b.add_line(g_tw, net_id(i, l - 1), tip, None);
        }
        // Net panels: quads, then tip triangles.
        let g_pa = b.group("net_panels", Role::NetPanels, None);
        for lv in 0..l - 1 {
            for i in 0..nt {
                b.add_panel(
                    g_pa,
                    PanelNodes::Quad([
                        net_id(i, lv),
                        net_id(i, lv + 1),
                        net_id(i + 1, lv + 1),
                        net_id(i + 1, lv),
                    ]),
                );
            }
        }
        for i in 0..nt {
            b.add_panel(
                g_pa,
                PanelNodes::Tri([net_id(i, l - 1), tip, net_id(i + 1, l - 1)]),
            );
        }

        // Frame lines.
        let section = |name: &str| -> Result<Section> {
            let mut s = match name {
                "top_ring" | "outer_ring" | "top_links" => self.collar.section.clone(),
                "brackets" => default_bracket_section(),
                _ => default_frame_section(name).expect("frame group has a default section"),
            };
            if let Some(o) = self.groups.get(name) {
                o.apply(obj, &format!("groups.{name}"), &mut s)?;
            }
            Ok(s)
        };
        let g_ring = b.group("top_ring", Role::TopRing, Some(section("top_ring")?));
        for i in 0..nt {
            b.add_line(g_ring, col(i, 0), col(i + 1, 0), None);
        }
        let inner: Vec<usize> = (0..nt).map(|i| col(i, 0)).collect();
        let inner_length = (0..nt)
            .map(|i| (b.mesh.nodes[col(i + 1, 0)] - b.mesh.nodes[col(i, 0)]).norm())
            .sum();
        self.collar
            .add_outer_pipe(&mut b, &inner, &outer, inner_length, section)?;
        let g_links = b.group("top_links", Role::TopLinks, Some(section("top_links")?));
        for i in 0..nt {
            b.add_line(g_links, net_id(i, 0), col(i, 0), None);
        }
        let g_ropes = b.group("ropes", Role::Ropes, Some(section("ropes")?));
        for i in 0..nt {
            for j in 0..n_f - 1 {
                b.add_line(g_ropes, col(i, j), col(i, j + 1), None);
            }
            if let Some(c) = centre {
                b.add_line(g_ropes, col(i, n_f - 1), c, None);
            }
        }
        // The rope columns follow the mesh; together they carry the design's ropes
        // (docs/theory/cages.md#frame-ropes-and-weights).
        let per_column = self.ropes as f64 / nt as f64;
        for k in 0..b.mesh.groups[g_ropes].lines.len() {
            let e = b.mesh.groups[g_ropes].lines[k];
            b.mesh.lines[e].section_scale = per_column;
        }
        let g_ties = b.group("tie_lines", Role::TieLines, Some(section("tie_lines")?));
        match self.kind {
            CageType::Cct | CageType::Cst => {
                for i in 0..nt {
                    b.add_line(g_ties, net_id(i, self.nn), col(i, n_f - 1), None);
                }
            }
            _ => {
                for i in 0..nt {
                    for m in 0..self.nn / 2 {
                        let lv = self.nn - 2 * m;
                        b.add_line(g_ties, net_id(i, lv), col(i, lv), None);
                    }
                }
            }
        }
        if matches!(self.kind, CageType::Cct | CageType::Cst) {
            let g = b.group(
                "bottom_ring",
                Role::BottomRing,
                Some(section("bottom_ring")?),
            );
            for i in 0..nt {
                b.add_line(g, col(i, n_f - 1), col(i + 1, n_f - 1), None);
            }
        }
        b.finish_element_nodes();

        // Node groups.
        let g = b.group("net_nodes", Role::NetNodes, None);
        b.set_nodes(g, 0..n_net);
        let g = b.group("net_top", Role::NetTop, None);
        b.set_nodes(g, (0..nt).map(|i| net_id(i, 0)));
        let g = b.group("net_bottom", Role::NetBottom, None);
        b.set_nodes(g, (0..nt).map(|i| net_id(i, self.nn)));
        let g_tip = b.group("tip", Role::Tip, None);
        b.set_nodes(g_tip, [tip]);
        let g_sink = b.group("sinkers", Role::Sinkers, None);
        match centre {
            Some(c) => b.set_nodes(g_sink, [c]),
            None => b.set_nodes(g_sink, (0..nt).map(|i| col(i, n_f - 1))),
        }
        let g_centre = centre.map(|c| {
            let g = b.group("centre_weight", Role::CentreWeight, None);
            b.set_nodes(g, [c]);
            g
        });
        let g = b.group("frame_nodes", Role::FrameNodes, None);
        b.set_nodes(g, n_net..n_net + nt * n_f + usize::from(centre.is_some()));

        // Section overrides must name existing line groups.
        for key in self.groups.keys() {
            let ok = b
                .mesh
                .groups
                .iter()
                .any(|g| &g.name == key && g.section.is_some());
            if !ok && key != "net_twines" {
                let valid: Vec<&str> = b
                    .mesh
                    .groups
                    .iter()
                    .filter(|g| g.role.is_line_role())
                    .map(|g| g.name.as_str())
                    .collect();
                return Err(MeshError::UnknownGroup {
                    object: obj.to_string(),
                    key: format!("groups.{key}"),
                    name: key.clone(),
                    valid: valid.join(", "),
                });
            }
        }

        // Fixed nodes.
        let mut fixed = Vec::new();
        for name in &self.fixed {
            match b.mesh.groups.iter().find(|g| &g.name == name) {
                Some(g) => fixed.extend(g.nodes.iter().copied()),
                None => {
                    let valid: Vec<&str> = b.mesh.groups.iter().map(|g| g.name.as_str()).collect();
                    return Err(MeshError::UnknownGroup {
                        object: obj.to_string(),
                        key: "fixed".into(),
                        name: name.clone(),
                        valid: valid.join(", "),
                    });
                }
            }
        }
        let g = b.group("fixed", Role::Fixed, None);
        b.set_nodes(g, fixed);

        // Weights.
        match (centre, g_centre) {
            (Some(c), Some(gc)) => b.weight(gc, c, self.centre_weight),
            _ => {
                let w = self.sinker_weight_per_metre * self.circumference / nt as f64;
                for i in 0..nt {
                    b.weight(g_sink, col(i, n_f - 1), w);
                }
            }
        }
        b.weight(g_tip, tip, self.tip_weight);

        // Mesh grouping (docs/theory/cages.md#mesh-grouping) from copy 0.
        let mut notices = self.notices.clone();
        let size = format!(
            "`circumference` = {} m, `depth` = {} m and `cone_depth` = {} m",
            self.circumference, self.depth, self.cone_depth
        );
        let grouping = self
            .net
            .group_net(&mut b, obj, g_tw, Some(g_pa), &size, &mut notices)?;
        let mut tw = grouping.twine_section();
        if let Some(o) = self.groups.get("net_twines") {
            o.apply(obj, "groups.net_twines", &mut tw)?;
        }
        b.mesh.groups[g_tw].section = Some(tw);
        if self.net.element == NetElement::Triangle {
            let frame = TwineFrame::of(
                &self.net,
                TwineFrame::Horizontal {
                    axis: self.origins[0],
                },
            );
            make_net_triangles(&mut b, obj, &self.net, g_tw, g_pa, frame)?;
        }

        let x = |n: usize| b.mesh.nodes[n];
        let counts = CageCounts {
            nt,
            nn: self.nn,
            bn: self.bn,
            n_ext: self.n_ext,
            ropes: self.ropes,
            top_radius: self.r_t,
            bottom_radius: self.r_b,
            ring_element_length: (x(net_id(1, 0)) - x(net_id(0, 0))).norm(),
            side_element_length: (x(net_id(0, 1)) - x(net_id(0, 0))).norm(),
            cone_element_length: if self.bn > 1 {
                (x(net_id(0, self.nn + 1)) - x(net_id(0, self.nn))).norm()
            } else {
                (x(tip) - x(net_id(0, self.nn))).norm()
            },
        };
        b.mesh.objects.push(Object {
            name: self.name.clone(),
            kind: ObjectKind::Cage(self.kind),
            origins: self.origins.clone(),
            net: Some(grouping),
            detail: crate::model::ObjectDetail::Cage(counts),
        });
        b.mesh.notices = notices;
        let mut mesh = b.mesh;
        replicate(&mut mesh, &self.origins);
        Ok(mesh)
    }
}
