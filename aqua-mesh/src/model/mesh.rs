//! The mesh: nodes, 2-node line elements, net panels, named groups by role, point weights.
//!
//! Ids are dense indices into the vectors of [`Mesh`] and follow the normative ordering of
//! docs/theory/cages.md#net-geometry and #frame-ropes-and-weights. Several objects (cages, panels,
//! lines, imported meshes) can live in one mesh ([`Mesh::append`]); every group belongs to one
//! object, and every entity records its `(object, copy)` (copy = index of the origin of a
//! multi-origin cage).

use crate::model::{Group, LineElement, Object, Panel, PanelNodes, PointWeight, Role};
use nalgebra::{Point3, Vector3};
use std::collections::BTreeSet;

/// Nodes, elements, panels, groups and weights of one or several objects.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Node positions [m].
    pub nodes: Vec<Point3<f64>>,
    /// `(object, copy)` of every node.
    pub node_owner: Vec<(u32, u32)>,
    /// Line elements.
    pub lines: Vec<LineElement>,
    /// Net panels.
    pub panels: Vec<Panel>,
    /// Groups of all objects.
    pub groups: Vec<Group>,
    /// Objects.
    pub objects: Vec<Object>,
    /// Point weights.
    pub weights: Vec<PointWeight>,
    /// Warnings and notices produced while building (λ > 500, CST alias, …).
    pub notices: Vec<String>,
}

impl Mesh {
    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Iterate over line elements with their index.
    pub fn iter_lines(&self) -> impl Iterator<Item = (usize, &LineElement)> {
        self.lines.iter().enumerate()
    }

    /// Iterate over panels with their index.
    pub fn iter_panels(&self) -> impl Iterator<Item = (usize, &Panel)> {
        self.panels.iter().enumerate()
    }

    /// All groups with this name (one per object that has it).
    pub fn groups_named<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Group> + 'a {
        self.groups.iter().filter(move |g| g.name == name)
    }

    /// All groups with this role.
    pub fn groups_with_role(&self, role: Role) -> impl Iterator<Item = &Group> + '_ {
        self.groups.iter().filter(move |g| g.role == role)
    }

    /// The group `name` of object `object`.
    pub fn group(&self, object: u32, name: &str) -> Option<&Group> {
        self.groups
            .iter()
            .find(|g| g.object == object && g.name == name)
    }

    /// Index of the group `name` of object `object`.
    pub fn group_index(&self, object: u32, name: &str) -> Option<usize> {
        self.groups
            .iter()
            .position(|g| g.object == object && g.name == name)
    }

    /// Resolve a scene group reference: `<group>` (all objects), `<name>/<group>` (one object)
    /// or `<name>#<k>/<group>` (copy k). The group name is what follows the last `/`, so object
    /// names may hold `/` (a farm's `farm/cage_r1c2`). Returns the node ids, sorted and unique;
    /// `None` if no group matches.
    pub fn resolve_nodes(&self, reference: &str) -> Option<Vec<usize>> {
        let (obj, copy, group) = match reference.rsplit_once('/') {
            None => (None, None, reference),
            Some((o, g)) => match o.split_once('#') {
                Some((name, k)) => (Some(name), Some(k.parse::<u32>().ok()?), g),
                None => (Some(o), None, g),
            },
        };
        let mut found = false;
        let mut set = BTreeSet::new();
        for g in &self.groups {
            if g.name != group {
                continue;
            }
            if let Some(o) = obj
                && self.objects[g.object as usize].name != o
            {
                continue;
            }
            found = true;
            set.extend(
                g.nodes
                    .iter()
                    .copied()
                    .filter(|&n| copy.is_none_or(|c| self.node_owner[n].1 == c)),
            );
        }
        found.then(|| set.into_iter().collect())
    }

    /// Nodes held fixed: union of all `fixed` groups.
    pub fn fixed_nodes(&self) -> Vec<usize> {
        let mut set = BTreeSet::new();
        for g in self.groups_with_role(Role::Fixed) {
            set.extend(g.nodes.iter().copied());
        }
        set.into_iter().collect()
    }

    /// Current length of line element `e` [m].
    pub fn line_length(&self, e: usize) -> f64 {
        let [a, b] = self.lines[e].nodes;
        (self.nodes[b] - self.nodes[a]).norm()
    }

    /// Area of panel `p` [m²] (quads: half the norm of the cross product of the diagonals, exact
    /// for planar quads).
    pub fn panel_area(&self, p: usize) -> f64 {
        self.panel_area_vector(p).norm()
    }

    /// Area vector of panel `p` (area × unit normal, right-hand rule over the node order) [m²].
    pub fn panel_area_vector(&self, p: usize) -> Vector3<f64> {
        let x = |i: usize| self.nodes[i];
        match self.panels[p].nodes {
            PanelNodes::Tri([a, b, c]) => 0.5 * (x(b) - x(a)).cross(&(x(c) - x(a))),
            PanelNodes::Quad([a, b, c, d]) => 0.5 * (x(c) - x(a)).cross(&(x(d) - x(b))),
        }
    }

    /// Total number of VTK cells: lines first, then panels.
    pub fn cell_count(&self) -> usize {
        self.lines.len() + self.panels.len()
    }

    /// Append another mesh (ids of `other` are offset; its objects get new indices).
    /// Returns the node offset applied to `other`'s node ids.
    pub fn append(&mut self, other: Mesh) -> usize {
        let node_off = self.nodes.len();
        let line_off = self.lines.len();
        let panel_off = self.panels.len();
        let group_off = self.groups.len();
        let obj_off = self.objects.len() as u32;
        self.nodes.extend(other.nodes);
        self.node_owner
            .extend(other.node_owner.into_iter().map(|(o, c)| (o + obj_off, c)));
        self.lines.extend(other.lines.into_iter().map(|mut l| {
            l.nodes = l.nodes.map(|n| n + node_off);
            l.group += group_off;
            l.object += obj_off;
            l
        }));
        self.panels.extend(other.panels.into_iter().map(|mut p| {
            p.nodes = match p.nodes {
                PanelNodes::Tri(n) => PanelNodes::Tri(n.map(|i| i + node_off)),
                PanelNodes::Quad(n) => PanelNodes::Quad(n.map(|i| i + node_off)),
            };
            p.group += group_off;
            p.object += obj_off;
            p
        }));
        self.groups.extend(other.groups.into_iter().map(|mut g| {
            g.object += obj_off;
            g.lines.iter_mut().for_each(|e| *e += line_off);
            g.panels.iter_mut().for_each(|e| *e += panel_off);
            g.nodes.iter_mut().for_each(|e| *e += node_off);
            g
        }));
        self.weights.extend(other.weights.into_iter().map(|mut w| {
            w.node += node_off;
            w.group += group_off;
            w
        }));
        self.objects.extend(other.objects);
        self.notices.extend(other.notices);
        node_off
    }

    /// Merges the last `targets.len()` nodes, in order, into the existing nodes `targets` (a
    /// part's end joined to a node of another part: a line's fairlead, a farm's bridle ends):
    /// the trailing nodes are removed and the elements, panels, groups and weights that used
    /// them use their targets instead (group node lists stay sorted and unique).
    pub fn weld_tail(&mut self, targets: &[usize]) {
        let first = self.nodes.len() - targets.len();
        self.nodes.truncate(first);
        self.node_owner.truncate(first);
        let map = |n: &mut usize| {
            if *n >= first {
                *n = targets[*n - first];
            }
        };
        for l in &mut self.lines {
            l.nodes.iter_mut().for_each(map);
        }
        for p in &mut self.panels {
            match &mut p.nodes {
                PanelNodes::Tri(n) => n.iter_mut().for_each(map),
                PanelNodes::Quad(n) => n.iter_mut().for_each(map),
            }
        }
        for g in &mut self.groups {
            g.nodes.iter_mut().for_each(map);
            g.nodes.sort_unstable();
            g.nodes.dedup();
        }
        for w in &mut self.weights {
            map(&mut w.node);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nodes 0..5 on the x axis, lines 0-1, 1-2 and 3-4, a triangle 2-3-4, group `g` on 1, 3
    /// and 4, a weight on 4; welding the tail [3, 4] onto [1, 0] leaves three nodes and
    /// the lines 0-1, 1-2, 1-0, the triangle 2-1-0, the group on 0 and 1, the weight on 0.
    #[test]
    fn weld_tail_moves_every_reference_to_the_targets() {
        let line = |a, b| LineElement {
            nodes: [a, b],
            group: 0,
            object: 0,
            copy: 0,
            rest_length: None,
            section_scale: 1.0,
        };
        let mut m = Mesh {
            nodes: (0..5).map(|i| Point3::new(i as f64, 0.0, 0.0)).collect(),
            node_owner: vec![(0, 0); 5],
            lines: vec![line(0, 1), line(1, 2), line(3, 4)],
            panels: vec![Panel {
                nodes: PanelNodes::Tri([2, 3, 4]),
                group: 0,
                object: 0,
                copy: 0,
                uv: None,
            }],
            groups: vec![Group {
                name: "g".into(),
                role: Role::LineNodes,
                object: 0,
                lines: vec![],
                panels: vec![],
                nodes: vec![1, 3, 4],
                section: None,
            }],
            weights: vec![PointWeight {
                node: 4,
                weight: 1.0,
                group: 0,
            }],
            ..Default::default()
        };
        m.weld_tail(&[1, 0]);
        assert_eq!(m.nodes.len(), 3);
        assert_eq!(m.node_owner.len(), 3);
        let lines: Vec<[usize; 2]> = m.lines.iter().map(|l| l.nodes).collect();
        assert_eq!(lines, vec![[0, 1], [1, 2], [1, 0]]);
        assert_eq!(m.panels[0].nodes, PanelNodes::Tri([2, 1, 0]));
        assert_eq!(m.groups[0].nodes, vec![0, 1]);
        assert_eq!(m.weights[0].node, 0);
    }
}
