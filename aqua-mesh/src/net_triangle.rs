//! A net as Priour's net triangles (docs/theory/fem.md#net-triangle): the numerical twines of
//! an object are dropped and every net panel becomes triangles whose corners carry mesh
//! coordinates (U, V), counted in half meshes l_p along the two twine directions.
//!
//! The as-built net is the unstretched net with its meshes open at 90°: on each triangle the U
//! and V twines are the orthonormal directions d_U, d_V of its plane set by the reference
//! direction t (projected onto the plane) and the orientation (square: d_U = t̂; diamond: t̂
//! turned by ±45°), and corner k gets (U_k, V_k) = ((x_k − c)·d_U, (x_k − c)·d_V)/l_p with c the
//! centroid. Each triangle is developed on its own, so any triangulated surface is a net and the
//! twines follow the reference direction everywhere.

use crate::error::{MeshError, Result};
use crate::mesh_builder::MeshBuilder;
use crate::model::{MeshOrientation, PanelNodes};
use crate::net::NetResolved;
use nalgebra::Vector3;

type V3 = Vector3<f64>;

/// The reference direction of the twines on a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum TwineFrame {
    /// Along a given direction (projected onto each triangle).
    Along([f64; 3]),
    /// The horizontal tangent of the surface (ẑ × n); on a horizontal triangle the direction
    /// around the vertical axis through `axis`, or x̂ when the triangle sits on it.
    Horizontal {
        /// A point of the vertical axis [m].
        axis: [f64; 3],
    },
}

impl TwineFrame {
    /// The frame a net uses: `net.twine_direction` when given, else `default`.
    pub(crate) fn of(net: &NetResolved, default: TwineFrame) -> Self {
        net.twine_direction.map_or(default, TwineFrame::Along)
    }

    /// The unit reference direction in the plane of unit normal `n` at centroid `c`.
    fn direction(&self, n: &V3, c: &V3) -> Option<V3> {
        let project = |t: V3| {
            let p = t - t.dot(n) * n;
            (p.norm() > 1e-6 * t.norm()).then(|| p.normalize())
        };
        match *self {
            TwineFrame::Along(t) => project(V3::from(t)),
            TwineFrame::Horizontal { axis } => {
                let z = V3::z();
                let tangent = z.cross(n);
                if tangent.norm() > 0.1 {
                    return project(tangent);
                }
                let r = c - V3::from(axis);
                let around = z.cross(&r);
                project(around).or_else(|| project(V3::x()))
            }
        }
    }
}

/// Turns the net of the builder's object into net triangles: drops the lines of group
/// `twines` (the numerical twines) and splits the panels of group `panels` into triangles with
/// mesh coordinates (quads along their shorter diagonal).
pub(crate) fn make_net_triangles(
    b: &mut MeshBuilder,
    object: &str,
    net: &NetResolved,
    twines: usize,
    panels: usize,
    frame: TwineFrame,
) -> Result<()> {
    drop_lines(b, twines);
    split_quads(b, panels);
    let lp = net.half_mesh;
    let m = &mut b.mesh;
    for &p in &m.groups[panels].panels {
        let PanelNodes::Tri(n) = m.panels[p].nodes else {
            unreachable!("quads were split above");
        };
        let x = n.map(|i| m.nodes[i].coords);
        let c = (x[0] + x[1] + x[2]) / 3.0;
        let normal = (x[1] - x[0]).cross(&(x[2] - x[0]));
        if normal.norm() <= 0.0 {
            return Err(MeshError::param(
                object,
                "net",
                format!("triangle of nodes {n:?}"),
                "net triangles must have a non-zero area",
            ));
        }
        let normal = normal.normalize();
        let t = frame.direction(&normal, &c).ok_or_else(|| {
            MeshError::param(
                object,
                "net.twine_direction",
                format!("{frame:?}"),
                "must not be normal to the net: it is projected onto each triangle",
            )
        })?;
        let s = normal.cross(&t);
        let (du, dv) = match net.orientation {
            MeshOrientation::Square => (t, s),
            MeshOrientation::Diamond => (
                (t + s) * std::f64::consts::FRAC_1_SQRT_2,
                (s - t) * std::f64::consts::FRAC_1_SQRT_2,
            ),
        };
        m.panels[p].uv = Some(x.map(|xk| [(xk - c).dot(&du) / lp, (xk - c).dot(&dv) / lp]));
    }
    Ok(())
}

/// Removes the lines of group `g` and renumbers every group's lines.
fn drop_lines(b: &mut MeshBuilder, g: usize) {
    let m = &mut b.mesh;
    let mut new_index = vec![usize::MAX; m.lines.len()];
    let mut kept = Vec::with_capacity(m.lines.len());
    for (e, l) in m.lines.iter().enumerate() {
        if l.group != g {
            new_index[e] = kept.len();
            kept.push(*l);
        }
    }
    m.lines = kept;
    m.groups[g].lines.clear();
    for grp in &mut m.groups {
        for e in &mut grp.lines {
            *e = new_index[*e];
        }
    }
}

/// Splits the quads of panel group `g` into two triangles along the shorter diagonal.
fn split_quads(b: &mut MeshBuilder, g: usize) {
    let quads: Vec<usize> = b.mesh.groups[g]
        .panels
        .iter()
        .copied()
        .filter(|&p| matches!(b.mesh.panels[p].nodes, PanelNodes::Quad(_)))
        .collect();
    for p in quads {
        let PanelNodes::Quad(q) = b.mesh.panels[p].nodes else {
            continue;
        };
        let d = |i: usize, j: usize| (b.mesh.nodes[q[i]] - b.mesh.nodes[q[j]]).norm();
        // Equal diagonals (a regular grid) are cut the same way everywhere, so every interior
        // node of the grid gets the same share of load and mass (alternating cuts give nodes
        // of 4 and 8 triangles and a chequered load: a hanging panel's bottom moved 4 % off
        // the cable net's). The cost is a slight hand: the reference cage's Fy_net is 0.17 %
        // of its drag.
        let (first, second) = if d(0, 2) <= d(1, 3) * (1.0 + 1e-9) {
            ([q[0], q[1], q[2]], [q[0], q[2], q[3]])
        } else {
            ([q[0], q[1], q[3]], [q[1], q[2], q[3]])
        };
        b.mesh.panels[p].nodes = PanelNodes::Tri(first);
        let mut other = b.mesh.panels[p];
        other.nodes = PanelNodes::Tri(second);
        b.mesh.panels.push(other);
        let idx = b.mesh.panels.len() - 1;
        b.mesh.groups[g].panels.push(idx);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::NetElement;
    use crate::net::NetParams;
    use crate::panel::PanelParams;

    fn triangle_panel(orientation: MeshOrientation) -> crate::Mesh {
        let mut p = PanelParams::new(1.0, 0.5);
        p.net.element = Some(NetElement::Triangle);
        p.net.orientation = Some(orientation);
        p.build().unwrap()
    }

    #[test]
    fn panel_becomes_triangles_that_hold_its_twines() {
        let m = triangle_panel(MeshOrientation::Square);
        let lp = NetParams::default()
            .resolve("t", &mut vec![])
            .unwrap()
            .half_mesh;
        assert!(m.lines.is_empty(), "the numerical twines are dropped");
        // Mesh-coordinate area = net area / l_p² for meshes open at 90°, for both orientations.
        for o in [MeshOrientation::Square, MeshOrientation::Diamond] {
            let m = triangle_panel(o);
            let mut a_uv = 0.0;
            for p in &m.panels {
                let uv = p.uv.expect("every panel is a net triangle");
                let e1 = [uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]];
                let e2 = [uv[2][0] - uv[0][0], uv[2][1] - uv[0][1]];
                a_uv += 0.5 * (e1[0] * e2[1] - e1[1] * e2[0]).abs();
            }
            assert!((a_uv * lp * lp / 0.5 - 1.0).abs() < 1e-12, "{o}: {a_uv}");
        }
    }

    #[test]
    fn diamond_twines_at_45_degrees() {
        // A horizontal edge of the panel (along its width) of length L spans L/(√2·l_p) half
        // meshes in U and in V on a diamond net, L/l_p in U alone on a square one.
        let lp = NetParams::default()
            .resolve("t", &mut vec![])
            .unwrap()
            .half_mesh;
        for (o, du, dv) in [
            (MeshOrientation::Square, 1.0, 0.0),
            (
                MeshOrientation::Diamond,
                std::f64::consts::FRAC_1_SQRT_2,
                0.0,
            ),
        ] {
            let m = triangle_panel(o);
            let p = &m.panels[0];
            let PanelNodes::Tri(n) = p.nodes else {
                panic!()
            };
            let uv = p.uv.unwrap();
            for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                let d = m.nodes[n[b]] - m.nodes[n[a]];
                if d.z.abs() < 1e-12 {
                    let l = d.norm();
                    let (u, v) = (uv[b][0] - uv[a][0], uv[b][1] - uv[a][1]);
                    assert!((u.abs() - du * l / lp).abs() < 1e-9, "{o}: U {u}");
                    if o == MeshOrientation::Square {
                        assert!((v - dv).abs() < 1e-9, "{o}: V {v}");
                    } else {
                        assert!((v.abs() - du * l / lp).abs() < 1e-9, "{o}: V {v}");
                    }
                }
            }
        }
    }
}
