//! Stress in the pipes modelled as rods (collars, sinker tubes, walkways): per element the
//! largest fibre stress σ = |N|/A + |M|·(d_e/2)/I from the axial force N and the bending
//! moment M at its ends, and its largest value per group (docs/theory/fem.md#rod).

use crate::build::Built;
use aqua_fem::{GroupId, Model, Outputs};
use aqua_mesh::{BendingElement, Section};

/// A group of pipes modelled as rods.
#[derive(Debug, Clone)]
pub struct PipeGroup {
    /// Structural group name (as in `Tmax_<name>`).
    pub name: String,
    /// Its structural group.
    pub group: GroupId,
    /// Its section (area, second moment, elastic diameter).
    pub section: Section,
}

/// The pipe groups of a model: every group whose section bends with `bending_element = "rod"`
/// and that has rod edges (a group of single links between other members has none).
pub fn pipe_groups(
    sections: &[Option<(GroupId, Section)>],
    group_names: &[String],
    model: &Model,
) -> Vec<PipeGroup> {
    let mut on_rod = vec![false; model.elements().len()];
    for e in model.rod_edges() {
        if let Some(el) = e.element {
            on_rod[el] = true;
        }
    }
    let mut out: Vec<PipeGroup> = Vec::new();
    for (id, s) in sections.iter().flatten() {
        if s.bending_stiffness() > 0.0
            && s.bending_element == BendingElement::Rod
            && model.groups()[id.0].elements.iter().any(|&e| on_rod[e])
            && !out.iter().any(|p| p.group == *id)
        {
            out.push(PipeGroup {
                name: group_names[id.0].clone(),
                group: *id,
                section: s.clone(),
            });
        }
    }
    out
}

/// Largest fibre stress per element of the pipe groups into `dst` (one per mesh line; 0 for
/// other elements) [Pa].
pub fn fibre_stresses(built: &Built, out: &Outputs, dst: &mut [f64]) {
    dst.iter_mut().for_each(|s| *s = 0.0);
    let groups = built.model.groups();
    for p in &built.pipes {
        for &e in &groups[p.group.0].elements {
            if e < dst.len() {
                dst[e] = p
                    .section
                    .fibre_stress(out.tension[e], out.bending_moment[e]);
            }
        }
    }
}

/// Largest fibre stress per pipe group into `dst` [Pa]; allocates nothing.
pub fn group_max_stresses(built: &Built, out: &Outputs, dst: &mut [f64]) {
    let groups = built.model.groups();
    for (d, p) in dst.iter_mut().zip(&built.pipes) {
        *d = groups[p.group.0]
            .elements
            .iter()
            .map(|&e| {
                p.section
                    .fibre_stress(out.tension[e], out.bending_moment[e])
            })
            .fold(0.0, f64::max);
    }
}
