//! Assembly of a mesh by the parametric builders: nodes, groups, elements and weights added one
//! by one ([`MeshBuilder`]), and copies of an object at several origins ([`replicate`]).

use crate::model::{Group, LineElement, Mesh, Panel, PanelNodes, PointWeight, Role};
use crate::section::Section;
use nalgebra::{Point3, Vector3};
use std::collections::BTreeSet;

/// Incremental builder used by the parametric builders.
#[derive(Debug, Default)]
pub(crate) struct MeshBuilder {
    pub mesh: Mesh,
}

impl MeshBuilder {
    pub fn add_node(&mut self, p: Point3<f64>) -> usize {
        self.mesh.nodes.push(p);
        self.mesh.node_owner.push((0, 0));
        self.mesh.nodes.len() - 1
    }

    /// New empty group of object 0; returns its index.
    pub fn group(&mut self, name: &str, role: Role, section: Option<Section>) -> usize {
        self.mesh.groups.push(Group {
            name: name.to_string(),
            role,
            object: 0,
            lines: Vec::new(),
            panels: Vec::new(),
            nodes: Vec::new(),
            section,
        });
        self.mesh.groups.len() - 1
    }

    /// Index of the (first) group named `name`; the builders only ask for groups they made.
    pub fn group_index_of(&self, name: &str) -> usize {
        self.mesh
            .groups
            .iter()
            .position(|g| g.name == name)
            .unwrap_or(0)
    }

    pub fn add_line(&mut self, group: usize, a: usize, b: usize, rest_length: Option<f64>) {
        self.mesh.lines.push(LineElement {
            nodes: [a, b],
            group,
            object: 0,
            copy: 0,
            rest_length,
            section_scale: 1.0,
        });
        self.mesh.groups[group]
            .lines
            .push(self.mesh.lines.len() - 1);
    }

    pub fn add_panel(&mut self, group: usize, nodes: PanelNodes) {
        self.mesh.panels.push(Panel {
            nodes,
            group,
            object: 0,
            copy: 0,
            uv: None,
        });
        self.mesh.groups[group]
            .panels
            .push(self.mesh.panels.len() - 1);
    }

    pub fn set_nodes(&mut self, group: usize, nodes: impl IntoIterator<Item = usize>) {
        let set: BTreeSet<usize> = nodes.into_iter().collect();
        self.mesh.groups[group].nodes = set.into_iter().collect();
    }

    /// Fill `nodes` of every line/panel group from its elements.
    pub fn finish_element_nodes(&mut self) {
        let m = &mut self.mesh;
        for g in m.groups.iter_mut() {
            if g.lines.is_empty() && g.panels.is_empty() {
                continue;
            }
            let mut set = BTreeSet::new();
            for &e in &g.lines {
                set.extend(m.lines[e].nodes);
            }
            for &p in &g.panels {
                set.extend(m.panels[p].nodes.as_slice().iter().copied());
            }
            g.nodes = set.into_iter().collect();
        }
    }

    pub fn weight(&mut self, group: usize, node: usize, weight: f64) {
        self.mesh.weights.push(PointWeight {
            node,
            weight,
            group,
        });
    }
}

/// Replicate copy 0 of a single-object mesh at several origins
/// (docs/theory/cages.md#multiple-cages): copy k is copy 0 translated by `origins[k] − origins[0]`;
/// its entities follow copy k−1's; groups are shared.
pub(crate) fn replicate(mesh: &mut Mesh, origins: &[[f64; 3]]) {
    let n0 = mesh.nodes.len();
    let l0 = mesh.lines.len();
    let p0 = mesh.panels.len();
    let w0 = mesh.weights.len();
    let base = Vector3::from(origins[0]);
    for (k, o) in origins.iter().enumerate().skip(1) {
        let shift = Vector3::from(*o) - base;
        let off = k * n0;
        for i in 0..n0 {
            let p = mesh.nodes[i] + shift;
            mesh.nodes.push(p);
            mesh.node_owner.push((mesh.node_owner[i].0, k as u32));
        }
        for e in 0..l0 {
            let mut l = mesh.lines[e];
            l.nodes = l.nodes.map(|n| n + off);
            l.copy = k as u32;
            mesh.lines.push(l);
            let idx = mesh.lines.len() - 1;
            mesh.groups[l.group].lines.push(idx);
        }
        for p in 0..p0 {
            let mut q = mesh.panels[p];
            q.nodes = match q.nodes {
                PanelNodes::Tri(n) => PanelNodes::Tri(n.map(|i| i + off)),
                PanelNodes::Quad(n) => PanelNodes::Quad(n.map(|i| i + off)),
            };
            q.copy = k as u32;
            mesh.panels.push(q);
            let idx = mesh.panels.len() - 1;
            mesh.groups[q.group].panels.push(idx);
        }
        for w in 0..w0 {
            let mut pw = mesh.weights[w];
            pw.node += off;
            mesh.weights.push(pw);
        }
    }
    let copies = origins.len();
    for g in mesh.groups.iter_mut() {
        let base_nodes = g.nodes.clone();
        for k in 1..copies {
            g.nodes.extend(base_nodes.iter().map(|n| n + k * n0));
        }
    }
}
