//! [`ModelBuilder`]: builds a [`Model`] node by node and element by element, validating every
//! input, then lumps the masses and weights and numbers the auxiliary nodes at
//! [`ModelBuilder::build`] (docs/theory/fem.md#sections, #rod, #net-triangle).

use crate::bending::Hinge;
use crate::error::{FemError, Result, invalid};
use crate::model::*;
use crate::motion::{Motion, check_finite3};
use crate::net_triangle::{NetGroupId, NetTriangle, NetTriangleGroup, NetTriangleSection};
use crate::rigid_body::{self, LINK_STIFFNESS_FACTOR, Link, RigidBody, RigidBodySpec};
use crate::rod::{self, EdgeFrame, RodEdge, RodVertex};
use std::collections::HashMap;

/// Builds a [`Model`], validating every input.
#[derive(Debug, Clone, Default)]
pub struct ModelBuilder {
    env: Environment,
    nodes: Vec<[f64; 3]>,
    elements: Vec<Cable>,
    groups: Vec<Group>,
    group_index: HashMap<String, usize>,
    points: Vec<PointBody>,
    supports: Vec<Support>,
    motions: Vec<Motion>,
    hinges: Vec<Hinge>,
    rods: Rods,
    net_triangles: Vec<NetTriangle>,
    net_groups: Vec<NetTriangleGroup>,
    bodies: Vec<RigidBody>,
}

impl ModelBuilder {
    /// New builder with the given environment (g, ρ_w, seabed).
    pub fn new(env: Environment) -> Self {
        Self {
            env,
            ..Default::default()
        }
    }

    /// Adds a node at its as-built position [m]; returns its index.
    pub fn add_node(&mut self, position: [f64; 3]) -> Result<usize> {
        check_finite3(&format!("node {} position [m]", self.nodes.len()), position)?;
        self.nodes.push(position);
        self.supports.push(Support::Free);
        Ok(self.nodes.len() - 1)
    }

    /// Adds (or looks up) a named element group with its section.
    pub fn add_group(&mut self, name: &str, section: CableSection) -> Result<GroupId> {
        section.validate(name)?;
        if self.group_index.contains_key(name) {
            return Err(FemError::InvalidModel(format!(
                "group '{name}' defined twice"
            )));
        }
        self.groups.push(Group {
            name: name.to_string(),
            section,
            elements: Vec::new(),
        });
        self.group_index
            .insert(name.to_string(), self.groups.len() - 1);
        Ok(GroupId(self.groups.len() - 1))
    }

    fn check_node(&self, what: &str, node: usize) -> Result<()> {
        if node >= self.nodes.len() {
            return Err(FemError::UnknownNode {
                what: what.to_string(),
                node,
                n_nodes: self.nodes.len(),
            });
        }
        Ok(())
    }

    /// Adds a cable element between nodes `a` and `b` in `group`; returns its index.
    pub fn add_cable(
        &mut self,
        a: usize,
        b: usize,
        group: GroupId,
        length: UnstretchedLength,
    ) -> Result<usize> {
        self.add_scaled_cable(a, b, group, length, 1.0)
    }

    /// Adds a cable element that stands for `scale` (> 0) of its group's section: EA, μ and the
    /// axial damping are `scale` times the group's (a net twine carrying λ_e/λ̄ of the mean
    /// numerical twine, docs/theory/cages.md#mesh-grouping). Returns its index.
    pub fn add_scaled_cable(
        &mut self,
        a: usize,
        b: usize,
        group: GroupId,
        length: UnstretchedLength,
        scale: f64,
    ) -> Result<usize> {
        let id = self.elements.len();
        if !(scale.is_finite() && scale > 0.0) {
            return Err(invalid(format!("element {id} section scale"), scale, "> 0"));
        }
        self.check_node(&format!("element {id}"), a)?;
        self.check_node(&format!("element {id}"), b)?;
        if a == b {
            return Err(FemError::InvalidModel(format!(
                "element {id} connects node {a} to itself"
            )));
        }
        let g = self.groups.get(group.0).ok_or_else(|| {
            FemError::InvalidModel(format!("element {id}: group id {} does not exist", group.0))
        })?;
        let mut s = g.section;
        s.ea *= scale;
        s.mass_per_length *= scale;
        if let AxialDamping::Coefficient(c) = &mut s.axial_damping {
            *c *= scale;
        }
        let l = dist(self.nodes[a], self.nodes[b]);
        let l0 = match length {
            UnstretchedLength::Given(l0) => l0,
            UnstretchedLength::AsBuilt { initial_tension } => {
                if !(initial_tension.is_finite() && initial_tension > -s.ea) {
                    return Err(invalid(
                        format!("element {id} initial_tension [N]"),
                        initial_tension,
                        format!("> -EA = {}", -s.ea),
                    ));
                }
                l / (1.0 + initial_tension / s.ea)
            }
        };
        if !(l0.is_finite() && l0 > 0.0) {
            return Err(invalid(
                format!("element {id} (nodes {a}-{b}) unstretched_length [m]"),
                l0,
                "> 0 (coincident as-built nodes need an explicit length)",
            ));
        }
        let ca = match s.axial_damping {
            AxialDamping::None => 0.0,
            AxialDamping::Coefficient(c) => c,
            AxialDamping::Ratio(z) => z * l0 * (s.ea * s.mass_per_length).sqrt(),
        };
        self.elements.push(Cable {
            a,
            b,
            l0,
            ea: s.ea,
            rc: s.compression_ratio,
            ca,
            mu: s.mass_per_length,
            group: group.0,
            contact_diameter: s.contact_diameter.unwrap_or(0.0),
        });
        self.groups[group.0].elements.push(id);
        Ok(id)
    }

    /// Adds a named group of net triangles with its section (one twine's EA and μ, the bar
    /// length l_p, docs/theory/fem.md#net-triangle).
    pub fn add_net_triangle_group(
        &mut self,
        name: &str,
        section: NetTriangleSection,
    ) -> Result<NetGroupId> {
        section.validate(name)?;
        if self.net_groups.iter().any(|g| g.name == name) {
            return Err(FemError::InvalidModel(format!(
                "net triangle group '{name}' defined twice"
            )));
        }
        self.net_groups.push(NetTriangleGroup {
            name: name.to_string(),
            section,
            triangles: Vec::new(),
        });
        Ok(NetGroupId(self.net_groups.len() - 1))
    }

    /// Adds a net triangle (Priour's element, docs/theory/fem.md#net-triangle) on three
    /// distinct nodes with the mesh coordinates (U, V) of each: how many mesh bars along the
    /// two twine directions separate the node from an origin. Either orientation of the
    /// (U, V) triangle is accepted; it must span an area. Returns the triangle's index.
    pub fn add_net_triangle(
        &mut self,
        group: NetGroupId,
        nodes: [usize; 3],
        uv: [[f64; 2]; 3],
    ) -> Result<usize> {
        let id = self.net_triangles.len();
        let what = format!("net triangle {id}");
        for nd in nodes {
            self.check_node(&what, nd)?;
        }
        if nodes[0] == nodes[1] || nodes[1] == nodes[2] || nodes[0] == nodes[2] {
            return Err(FemError::InvalidModel(format!(
                "{what} needs three distinct nodes, got {}, {}, {}",
                nodes[0], nodes[1], nodes[2]
            )));
        }
        for (k, p) in uv.iter().enumerate() {
            for (c, &val) in ["U", "V"].iter().zip(p) {
                if !val.is_finite() {
                    return Err(invalid(
                        format!("{what} mesh coordinate {c} of node {}", nodes[k]),
                        val,
                        "finite",
                    ));
                }
            }
        }
        let g = self.net_groups.get(group.0).ok_or_else(|| {
            FemError::InvalidModel(format!(
                "{what}: net triangle group id {} does not exist",
                group.0
            ))
        })?;
        let t = NetTriangle::new(nodes, uv, group.0, &g.section).ok_or(
            FemError::DegenerateNetTriangle {
                triangle: id,
                nodes,
                uv,
                area: NetTriangle::signed_uv_area(uv),
            },
        )?;
        self.net_triangles.push(t);
        self.net_groups[group.0].triangles.push(id);
        Ok(id)
    }

    /// Adds a bending hinge on the consecutive nodes a, b, c (b the hinge node) with bending
    /// stiffness EI [N·m²] (> 0); its rest curvature and length are those of the as-built
    /// positions, so the as-built shape is force free (docs/theory/fem.md#bending). The nodes
    /// should be joined by elements (a–b, b–c) that carry the axial stiffness and the mass.
    /// Returns the hinge index.
    pub fn add_bending(&mut self, a: usize, b: usize, c: usize, ei: f64) -> Result<usize> {
        let id = self.hinges.len();
        for nd in [a, b, c] {
            self.check_node(&format!("bending hinge {id}"), nd)?;
        }
        if a == b || b == c || a == c {
            return Err(FemError::InvalidModel(format!(
                "bending hinge {id} needs three distinct nodes, got {a}, {b}, {c}"
            )));
        }
        if !(ei.is_finite() && ei > 0.0) {
            return Err(invalid(
                format!("bending hinge {id} (nodes {a}-{b}-{c}) bending_stiffness EI [N m^2]"),
                ei,
                "> 0 and finite",
            ));
        }
        let x = [self.nodes[a], self.nodes[b], self.nodes[c]];
        let hinge = Hinge::as_built([a, b, c], ei, x).ok_or_else(|| {
            FemError::InvalidModel(format!(
                "bending hinge {id} (nodes {a}-{b}-{c}): an as-built edge has zero length or \
                 the edges fold back onto each other"
            ))
        })?;
        self.hinges.push(hinge);
        Ok(id)
    }

    /// Adds bending hinges with stiffness EI [N·m²] at every interior node of the node chain
    /// `nodes` (and, if `closed`, at the first and last nodes too, for a ring whose last node
    /// joins the first). Returns the index range of the hinges added.
    pub fn add_bending_line(
        &mut self,
        nodes: &[usize],
        ei: f64,
        closed: bool,
    ) -> Result<std::ops::Range<usize>> {
        let start = self.hinges.len();
        let n = nodes.len();
        if closed && n >= 3 {
            for i in 0..n {
                self.add_bending(nodes[(i + n - 1) % n], nodes[i], nodes[(i + 1) % n], ei)?;
            }
        } else {
            for w in nodes.windows(3) {
                self.add_bending(w[0], w[1], w[2], ei)?;
            }
        }
        Ok(start..self.hinges.len())
    }

    /// Adds a rod (a pipe with bending about both axes and torsion, docs/theory/fem.md#rod)
    /// along the node chain `nodes` (a ring whose last node joins the first if `closed`), with
    /// a twist carrier node per edge. `clamped[0]` / `clamped[1]` clamp the first / last node
    /// of an open chain: its position, its tangent and its twist are held (a held ghost edge
    /// continues the rod beyond it). Consecutive nodes should be joined by cable elements that
    /// carry the axial stiffness and the mass. Returns the twist carrier of each edge of
    /// `nodes` in order (a torque about an edge is a force on its carrier's first coordinate).
    pub fn add_rod(
        &mut self,
        nodes: &[usize],
        section: RodSection,
        closed: bool,
        clamped: [bool; 2],
    ) -> Result<Vec<usize>> {
        let id = self.rods.n_rods;
        let what = format!("rod {id}");
        section.validate(&what)?;
        for &nd in nodes {
            self.check_node(&what, nd)?;
        }
        let need = if closed { 3 } else { 2 };
        if nodes.len() < need || (closed && clamped.iter().any(|&c| c)) {
            return Err(FemError::InvalidModel(format!(
                "{what} needs at least {need} nodes (got {}); a ring cannot be clamped",
                nodes.len()
            )));
        }
        let mut chain: Vec<usize> = nodes.to_vec();
        // Ghost nodes one edge beyond a clamped end, held in place.
        let ghost = |b: &mut Self, end: usize, next: usize| -> Result<usize> {
            let (p, q) = (b.nodes[end], b.nodes[next]);
            let g = b.add_node([2.0 * p[0] - q[0], 2.0 * p[1] - q[1], 2.0 * p[2] - q[2]])?;
            b.rods.holders.push(g);
            b.fix(g, Dofs::ALL)?;
            Ok(g)
        };
        if clamped[0] {
            let g = ghost(self, nodes[0], nodes[1])?;
            chain.insert(0, g);
        }
        if clamped[1] {
            let n = nodes.len();
            let g = ghost(self, nodes[n - 1], nodes[n - 2])?;
            chain.push(g);
        }
        let m = chain.len();
        let n_edges = if closed { m } else { m - 1 };
        let first_edge = self.rods.edges.len();
        let mut frame: Option<EdgeFrame> = None;
        for j in 0..n_edges {
            let (a, b) = (chain[j], chain[(j + 1) % m]);
            let e = sub3(self.nodes[b], self.nodes[a]);
            let f = match frame {
                None => EdgeFrame::for_edge(e),
                Some(prev) => prev.transported(e),
            }
            .ok_or_else(|| {
                FemError::InvalidModel(format!(
                    "{what}: the as-built edge {a}-{b} has zero length or folds back onto the \
                     one before it"
                ))
            })?;
            frame = Some(f);
            let carrier = self.add_node([0.0; 3])?;
            let held = Dofs {
                x: (clamped[0] && j == 0) || (clamped[1] && j + 1 == n_edges),
                y: true,
                z: true,
            };
            self.fix(carrier, held)?;
            self.rods
                .carrier_inertia
                .push((carrier, section.spin_inertia * norm3(e)));
            self.rods.edges.push(RodEdge {
                nodes: [a, b],
                carrier,
                element: None,
                frame: f,
            });
        }
        let n_vertices = if closed { m } else { m - 2 };
        let mut curved = false;
        for k in 0..n_vertices {
            let (ia, ib) = if closed {
                ((k + n_edges - 1) % n_edges, k)
            } else {
                (k, k + 1)
            };
            let (ea, eb) = (
                &self.rods.edges[first_edge + ia],
                &self.rods.edges[first_edge + ib],
            );
            let va = sub3(self.nodes[ea.nodes[1]], self.nodes[ea.nodes[0]]);
            let vb = sub3(self.nodes[eb.nodes[1]], self.nodes[eb.nodes[0]]);
            let (rest_curvature, rest_twist) = rod::rest_state(&ea.frame, &eb.frame, va, vb);
            curved |= rest_curvature.iter().flatten().any(|c| c.abs() > 1e-8);
            self.rods.vertices.push(RodVertex {
                nodes: [ea.nodes[0], ea.nodes[1], eb.nodes[1]],
                carriers: [ea.carrier, eb.carrier],
                edges: [first_edge + ia, first_edge + ib],
                ei: section.ei,
                gj: section.gj,
                // At a clamped end the ghost edge adds nothing to the vertex's length: the
                // pipe starts at the clamp, whose Voronoi length is half an edge.
                length: if clamped[0] && k == 0 && !closed {
                    norm3(vb)
                } else if clamped[1] && !closed && k + 1 == n_vertices {
                    norm3(va)
                } else {
                    norm3(va) + norm3(vb)
                },
                rest_curvature,
                rest_twist,
            });
        }
        // A straight, unclamped rod of round section turns about its own axis at no cost: its
        // first twist is held (docs/theory/fem.md#rod).
        if !curved && !clamped.iter().any(|&c| c) {
            let c = self.rods.edges[first_edge].carrier;
            self.fix(c, Dofs::ALL)?;
        }
        self.rods.n_rods += 1;
        let skip = usize::from(clamped[0]);
        let n_own = if closed { nodes.len() } else { nodes.len() - 1 };
        Ok(
            self.rods.edges[first_edge + skip..first_edge + skip + n_own]
                .iter()
                .map(|e| e.carrier)
                .collect(),
        )
    }

    /// Adds a point body (mass [kg], constant force [N], seabed stiffness [N/m]) on a node.
    pub fn add_point_body(&mut self, body: PointBody) -> Result<usize> {
        let id = self.points.len();
        self.check_node(&format!("point body {id}"), body.node)?;
        if !(body.mass.is_finite() && body.mass >= 0.0) {
            return Err(invalid(
                format!("point body {id} mass [kg]"),
                body.mass,
                ">= 0",
            ));
        }
        check_finite3(&format!("point body {id} force [N]"), body.force)?;
        if !(body.seabed_stiffness.is_finite() && body.seabed_stiffness >= 0.0) {
            return Err(invalid(
                format!("point body {id} seabed_stiffness [N/m]"),
                body.seabed_stiffness,
                ">= 0",
            ));
        }
        self.points.push(body);
        Ok(id)
    }

    /// Adds a free rigid body (docs/theory/fem.md#rigid-bodies): creates its centre-of-gravity
    /// node at `spec.centre`, which carries the mass M (and its weight), and its rotation
    /// carrier, whose three coordinates are the body's rotation vector [rad]; holds each node
    /// of `spec.points` to the body by a rigid link at its as-built offset from the centre.
    /// A held point may be free, fixed or prescribed (a body hung from a pinned point); it
    /// must be a node of the structure (not a rod's twist carrier or ghost node, not another
    /// body's centre or carrier) held by no other body, and a free one needs mass of its own
    /// (an element or a point body) like any free node. Returns the body's index.
    pub fn add_rigid_body(&mut self, spec: RigidBodySpec) -> Result<usize> {
        rigid_body::validate(&spec)?;
        let bad = |key: &str, value: String, valid: String| FemError::RigidBody {
            body: spec.name.clone(),
            key: key.to_string(),
            value,
            valid,
        };
        if self.bodies.iter().any(|b| b.name == spec.name) {
            return Err(bad(
                "name",
                format!("{:?}", spec.name),
                "a name no other rigid body has".into(),
            ));
        }
        let n = self.nodes.len();
        let mut points = Vec::with_capacity(spec.points.len());
        for (j, &p) in spec.points.iter().enumerate() {
            let key = format!("points[{j}]");
            if p >= n {
                return Err(bad(
                    &key,
                    format!("node {p}"),
                    format!("an existing node (0 to {})", n.saturating_sub(1)),
                ));
            }
            if spec.points[..j].contains(&p) {
                return Err(bad(
                    &key,
                    format!("node {p}"),
                    "each node listed once".into(),
                ));
            }
            let auxiliary = self.rods.edges.iter().any(|e| e.carrier == p)
                || self.rods.holders.contains(&p)
                || self
                    .bodies
                    .iter()
                    .any(|b| b.node == p || b.rotation_node == p);
            if auxiliary {
                return Err(bad(
                    &key,
                    format!("node {p}"),
                    "a node of the structure, not a rod's twist carrier or ghost node nor a \
                     body's centre or rotation carrier"
                        .into(),
                ));
            }
            if let Some(other) = self
                .bodies
                .iter()
                .find(|b| b.points.iter().any(|&(q, _)| q == p))
            {
                return Err(bad(
                    &key,
                    format!("node {p}"),
                    format!(
                        "a node no other body holds (rigid body '{}' holds it)",
                        other.name
                    ),
                ));
            }
            points.push((p, sub3(self.nodes[p], spec.centre)));
        }
        let node = self.add_node(spec.centre)?;
        let rotation_node = self.add_node([0.0; 3])?;
        self.bodies.push(RigidBody {
            name: spec.name,
            node,
            rotation_node,
            mass: spec.mass,
            inertia: spec.inertia,
            points,
        });
        Ok(self.bodies.len() - 1)
    }

    /// The rigid bodies added so far (their centre and rotation carrier nodes, e.g. to put a
    /// point force or a load element on them before building).
    pub fn rigid_bodies(&self) -> &[RigidBody] {
        &self.bodies
    }

    /// Holds a node at its as-built position in the given DOFs.
    pub fn fix(&mut self, node: usize, dofs: Dofs) -> Result<()> {
        self.check_node("fix", node)?;
        if let Support::Prescribed(_) = self.supports[node] {
            return Err(FemError::InvalidModel(format!(
                "node {node} is both fixed and prescribed"
            )));
        }
        let prev = match self.supports[node] {
            Support::Fixed(d) => d.as_array(),
            _ => [false; 3],
        };
        let d = dofs.as_array();
        self.supports[node] = Support::Fixed(Dofs {
            x: prev[0] || d[0],
            y: prev[1] || d[1],
            z: prev[2] || d[2],
        });
        Ok(())
    }

    /// Prescribes the motion x(t) = X + d(t) of a node (all DOFs).
    pub fn prescribe(&mut self, node: usize, motion: Motion) -> Result<()> {
        self.check_node("prescribe", node)?;
        motion.validate()?;
        if !matches!(self.supports[node], Support::Free) {
            return Err(FemError::InvalidModel(format!(
                "node {node} already has a support; a node is either fixed or prescribed"
            )));
        }
        self.motions.push(motion);
        self.supports[node] = Support::Prescribed(self.motions.len() - 1);
        Ok(())
    }

    /// Validates and freezes the model.
    pub fn build(self) -> Result<Model> {
        let env = self.env;
        if !(env.gravity.is_finite() && env.gravity >= 0.0) {
            return Err(invalid("gravity g [m/s^2]", env.gravity, ">= 0"));
        }
        if !(env.water_density.is_finite() && env.water_density > 0.0) {
            return Err(invalid("water density [kg/m^3]", env.water_density, "> 0"));
        }
        if let Some(s) = env.seabed {
            if !(s.depth.is_finite() && s.depth > 0.0) {
                return Err(invalid("water depth [m]", s.depth, "> 0"));
            }
            if !(s.stiffness.is_finite() && s.stiffness >= 0.0) {
                return Err(invalid("seabed kbot [Pa/m]", s.stiffness, ">= 0"));
            }
            if !(s.damping.is_finite() && s.damping >= 0.0) {
                return Err(invalid("seabed cbot [Pa s/m]", s.damping, ">= 0"));
            }
            if !(s.damping_depth.is_finite() && s.damping_depth > 0.0) {
                return Err(invalid("seabed damping_depth [m]", s.damping_depth, "> 0"));
            }
            s.friction.validate()?;
        }
        if self.nodes.is_empty() {
            return Err(FemError::InvalidModel("the model has no nodes".into()));
        }
        let n = self.nodes.len();
        let mut attached = vec![false; n];
        for e in &self.elements {
            attached[e.a] = true;
            attached[e.b] = true;
        }
        for p in &self.points {
            attached[p.node] = true;
        }
        for t in &self.net_triangles {
            for nd in t.nodes {
                attached[nd] = true;
            }
        }
        for e in &self.rods.edges {
            attached[e.carrier] = true;
        }
        for &g in &self.rods.holders {
            attached[g] = true;
        }
        for b in &self.bodies {
            attached[b.node] = true;
            attached[b.rotation_node] = true;
            for &(p, _) in &b.points {
                attached[p] = true;
            }
        }
        if let Some(i) = attached.iter().position(|a| !a) {
            return Err(FemError::InvalidModel(format!(
                "node {i} at {:?} belongs to no element and carries no point body",
                self.nodes[i]
            )));
        }
        let mut lumped_mass = vec![0.0; n];
        let mut weight = vec![[0.0; 3]; n];
        let mut bed_coef = vec![0.0; n];
        let mut bed_point = vec![0.0; n];
        let mut point_force = vec![[0.0; 3]; n];
        let mut point_mass = vec![0.0; n];
        for e in &self.elements {
            let m = 0.5 * e.mu * e.l0;
            lumped_mass[e.a] += m;
            lumped_mass[e.b] += m;
            if e.contact_diameter > 0.0 {
                bed_coef[e.a] += 0.5 * e.l0 * e.contact_diameter;
                bed_coef[e.b] += 0.5 * e.l0 * e.contact_diameter;
            }
        }
        for t in &self.net_triangles {
            let m = t.mass() / 3.0;
            for nd in t.nodes {
                lumped_mass[nd] += m;
            }
        }
        for p in &self.points {
            lumped_mass[p.node] += p.mass;
            point_mass[p.node] += p.mass;
            bed_point[p.node] += p.seabed_stiffness;
            for k in 0..3 {
                point_force[p.node][k] += p.force[k];
            }
        }
        // A rigid body's mass on its centre; its inertia is a full block on the rotation
        // carrier, formed at each evaluation (docs/theory/fem.md#rigid-bodies).
        for b in &self.bodies {
            lumped_mass[b.node] += b.mass;
            point_mass[b.node] += b.mass;
        }
        for i in 0..n {
            weight[i][2] = -lumped_mass[i] * env.gravity;
        }
        let mut rotation_of = vec![None; n];
        let mut links = Vec::new();
        if !self.bodies.is_empty() {
            let member = member_stiffness(&self.elements, &self.net_triangles, n);
            for (ib, b) in self.bodies.iter().enumerate() {
                rotation_of[b.rotation_node] = Some(ib);
                let floor = rigid_body::link_floor(b.mass, env.gravity, &b.points);
                for &(p, offset) in &b.points {
                    links.push(Link {
                        body: ib,
                        node: p,
                        centre: b.node,
                        rotation: b.rotation_node,
                        offset,
                        stiffness: (LINK_STIFFNESS_FACTOR * member[p]).max(floor),
                    });
                }
            }
        }
        // Spin inertia of the rods' twists, on their carriers (weightless).
        for &(c, j) in &self.rods.carrier_inertia {
            lumped_mass[c] += j;
            point_mass[c] += j;
        }
        let mut rods = self.rods;
        if !rods.edges.is_empty() {
            let mut by_nodes = HashMap::new();
            for (i, e) in self.elements.iter().enumerate() {
                by_nodes.entry((e.a.min(e.b), e.a.max(e.b))).or_insert(i);
            }
            for e in &mut rods.edges {
                let [a, b] = e.nodes;
                e.element = by_nodes.get(&(a.min(b), a.max(b))).copied();
            }
            rods.auxiliary = vec![false; n];
            for e in &rods.edges {
                rods.auxiliary[e.carrier] = true;
            }
            for &g in &rods.holders {
                rods.auxiliary[g] = true;
            }
        }
        let n_members = self.elements.len() + self.net_triangles.len();
        let mean_length = if n_members == 0 {
            1.0
        } else {
            (self.elements.iter().map(|e| e.l0).sum::<f64>()
                + self
                    .net_triangles
                    .iter()
                    .map(|t| t.bar_length())
                    .sum::<f64>())
                / n_members as f64
        };
        Ok(Model {
            env,
            nodes: self.nodes,
            elements: self.elements,
            groups: self.groups,
            group_index: self.group_index,
            points: self.points,
            supports: self.supports,
            motions: self.motions,
            hinges: self.hinges,
            rods,
            net_triangles: self.net_triangles,
            net_groups: self.net_groups,
            bodies: self.bodies,
            links,
            rotation_of,
            lumped_mass,
            weight,
            point_force,
            bed_coef,
            bed_point,
            point_mass,
            mean_length,
            partition: None,
        })
    }
}

/// The largest axial stiffness of the members at each node [N/m]: EA/L0 of its cables, the
/// taut diagonal A_uv·(a_k² + b_k²)·EA/l_p of its net triangles.
fn member_stiffness(elements: &[Cable], triangles: &[NetTriangle], n: usize) -> Vec<f64> {
    let mut d = vec![0.0f64; n];
    for e in elements {
        d[e.a] = d[e.a].max(e.ea / e.l0);
        d[e.b] = d[e.b].max(e.ea / e.l0);
    }
    for t in triangles {
        let (gu, gv) = t.shape_gradients();
        let k = t.uv_area() * t.twine.ea / t.twine.l0;
        for (j, &nd) in t.nodes.iter().enumerate() {
            d[nd] = d[nd].max(k * (gu[j] * gu[j] + gv[j] * gv[j]));
        }
    }
    d
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm3(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
