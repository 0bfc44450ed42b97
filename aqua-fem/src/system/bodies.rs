//! The rigid bodies in the global system: evaluation of every rigid link at a state (with the
//! discrete gradient in the energy-consistent midpoint rule), their forces and tangents into
//! the residual and the Jacobian, each body's rotational inertia as a full 3×3 block on its
//! rotation carrier, the update of the bodies' reference frames when a state is accepted,
//! and the bodies' poses (docs/theory/fem.md#rigid-bodies).

use super::{NONE, System};
use crate::error::{FemError, Result};
use crate::model::Model;
use crate::rigid_body::{self, BodyFrame, BodyPose, Link, LinkVars};

fn vars(l: &Link, frame: &BodyFrame, x: &[[f64; 3]]) -> LinkVars {
    rigid_body::link_vars(x[l.node], x[l.centre], x[l.rotation], frame.psi)
}

impl System {
    /// Evaluates every rigid link at `x` (the midpoint in the energy-consistent midpoint
    /// rule, where the force is the discrete gradient between the step's ends).
    pub(super) fn evaluate_links(
        &mut self,
        model: &Model,
        x: &[[f64; 3]],
        tangent: bool,
    ) -> Result<()> {
        if model.links.is_empty() {
            return Ok(());
        }
        for (l, out) in model.links.iter().zip(self.link.iter_mut()) {
            let frame = &self.body_frames[l.body];
            let q = rigid_body::matvec(&frame.rotation, l.offset);
            match self.secant.as_ref() {
                Some((x0, x1)) => {
                    let (y0, y1) = (vars(l, frame, x0), vars(l, frame, x1));
                    let ym: LinkVars = std::array::from_fn(|i| 0.5 * (y0[i] + y1[i]));
                    rigid_body::evaluate_link(l.stiffness, q, &ym, Some((&y0, &y1)), tangent, out);
                }
                None => rigid_body::evaluate_link(
                    l.stiffness,
                    q,
                    &vars(l, frame, x),
                    None,
                    tangent,
                    out,
                ),
            }
        }
        if let Some(i) = self.link.iter().position(|r| r.bad) {
            let l = &model.links[i];
            return Err(FemError::NonFinite(format!(
                "rigid link of node {} to body '{}': the link force is non-finite",
                l.node, model.bodies[l.body].name
            )));
        }
        Ok(())
    }

    /// Adds the link forces of the last evaluation to f_int, each body's rotational
    /// inertia I_w = R_ref·I·R_refᵀ to the mass block of its rotation carrier and, in dynamics,
    /// its gyroscopic moment ω×(I_w·ω) at the carrier's velocity ω to f_int.
    pub(super) fn add_body_terms(&mut self, model: &Model, v: &[[f64; 3]], dynamic: bool) {
        for (l, ev) in model.links.iter().zip(&self.link) {
            for k in 0..3 {
                self.fint[l.node][k] += ev.force[k];
                self.fint[l.centre][k] += ev.force[3 + k];
                self.fint[l.rotation][k] += ev.force[6 + k];
            }
        }
        for ((b, frame), gc) in model
            .bodies
            .iter()
            .zip(&self.body_frames)
            .zip(self.gyro_c.iter_mut())
        {
            let iw = frame.world_inertia(&b.inertia);
            for (row, irow) in self.added[b.rotation_node].iter_mut().zip(iw) {
                for (m, i) in row.iter_mut().zip(irow) {
                    *m += i;
                }
            }
            *gc = [[0.0; 3]; 3];
            if dynamic {
                let w = v[b.rotation_node];
                let h = rigid_body::matvec(&iw, w);
                let g = cross(w, h);
                for k in 0..3 {
                    self.fint[b.rotation_node][k] += g[k];
                }
                // ∂(ω×h)/∂ω = [ω]×·I_w − [h]×.
                let (sw, sh) = (skew(w), skew(h));
                let swi = rigid_body::matmul(&sw, &iw);
                for i in 0..3 {
                    for j in 0..3 {
                        gc[i][j] = swi[i][j] - sh[i][j];
                    }
                }
            }
        }
    }

    /// Adds c·∂(ω×(I_w·ω))/∂ω of each body to its carrier's block of the Jacobian.
    pub(super) fn add_gyroscopic_damping(&mut self, model: &Model, c: f64) {
        for (b, gc) in model.bodies.iter().zip(&self.gyro_c) {
            let p = &self.node_pos[b.rotation_node];
            for i in 0..3 {
                for j in 0..3 {
                    if p[3 * i + j] != NONE {
                        self.values[p[3 * i + j]] += c * gc[i][j];
                    }
                }
            }
        }
    }

    /// Adds k·(link tangents) to the Jacobian's values.
    pub(super) fn add_link_tangents(&mut self, k: f64) {
        for (p, ev) in self.link_pos.iter().zip(&self.link) {
            for (r, row) in ev.k.iter().enumerate() {
                for (c, &kv) in row.iter().enumerate() {
                    let pp = p[9 * r + c];
                    if pp != NONE {
                        self.values[pp] += k * kv;
                    }
                }
            }
        }
    }

    /// Total energy of the rigid links at the last evaluation [J].
    pub fn link_energy(&self) -> f64 {
        self.link.iter().map(|l| l.energy).sum()
    }

    /// Moves each body's reference frame to its orientation in the accepted state `x`
    /// (R_ref ← R, ψ_ref ← ψ; the state is not touched, docs/theory/fem.md#rigid-bodies).
    pub(crate) fn accept_body_frames(&mut self, model: &Model, x: &[[f64; 3]]) {
        for (f, b) in self.body_frames.iter_mut().zip(&model.bodies) {
            f.accept(x[b.rotation_node]);
        }
    }

    /// The reference frames of the bodies.
    pub(crate) fn body_frames(&self) -> &[BodyFrame] {
        &self.body_frames
    }

    /// Puts back saved reference frames.
    pub(crate) fn set_body_frames(&mut self, frames: &[BodyFrame]) {
        self.body_frames.clone_from_slice(frames);
    }

    /// The pose of every body in the state (x, v) with the current reference frames.
    pub(crate) fn body_poses(
        &self,
        model: &Model,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
    ) -> Vec<BodyPose> {
        body_poses_with(model, &self.body_frames, x, v)
    }
}

/// The pose of every body in the state (x, v) with reference frames `frames`.
pub(crate) fn body_poses_with(
    model: &Model,
    frames: &[BodyFrame],
    x: &[[f64; 3]],
    v: &[[f64; 3]],
) -> Vec<BodyPose> {
    model
        .bodies
        .iter()
        .zip(frames)
        .map(|(b, f)| {
            let r = b.rotation_node;
            f.pose(x[b.node], x[r], v[b.node], v[r])
        })
        .collect()
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn skew(a: [f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]
}
