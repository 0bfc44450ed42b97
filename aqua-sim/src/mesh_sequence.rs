//! Mesh sequencing of the static solve (`analysis.static.mesh_sequence`,
//! docs/theory/fem.md#mesh-sequencing): the scene with its nets' element length doubled is
//! solved first, its displacement is carried to the finer mesh (closest point on the coarse
//! as-built panels and lines of the same object copy, interpolated between their nodes), and
//! that shape starts the finer solve.

use crate::build::{Prescribed, build};
use crate::plan::Prepared;
use crate::run::water_loads;
use crate::scene::Scene;
use crate::solvers::static_equilibrium_from;
use aqua_env::Phase;
use aqua_fem::{StaticControl, StaticProgress};
use aqua_mesh::{CageParams, Mesh};
use std::collections::HashMap;

/// The start of a sequenced static solve and what the coarser solves did.
#[derive(Debug, Default)]
pub(crate) struct SequencedStart {
    /// Node positions of the scene's own model to start from [m]; `None`: as built.
    pub start: Option<Vec<[f64; 3]>>,
    /// Newton iterations of the coarser solves, coarsest first.
    pub iterations: Vec<usize>,
    /// Why the sequence was cut short, if it was.
    pub warnings: Vec<String>,
    /// A coarser solve was stopped on request.
    pub stopped: bool,
}

/// The scene with the element length of every net doubled: `[[cage]]`s, farm cages and
/// `[[panel]]`s meshed by `element_length`. Lines, frames and imported meshes keep theirs.
/// `None` when the scene has no such net.
pub(crate) fn coarser(scene: &Scene) -> Option<Scene> {
    let mut c = scene.clone();
    let mut changed = false;
    let mut double_cage = |p: &mut CageParams| {
        // The resolved length (the default where the key is absent).
        if let Ok(r) = p.resolve() {
            p.element_length = Some(2.0 * r.element_length);
            changed = true;
        }
    };
    for cage in &mut c.cage {
        double_cage(&mut cage.value.params);
    }
    for farm in &mut c.farm {
        double_cage(&mut farm.value.cage.params);
        for slot in &mut farm.value.slot {
            if let Some(cage) = slot.value.cage.as_mut() {
                double_cage(&mut cage.params);
            }
        }
    }
    for panel in &mut c.panel {
        if let Some(el) = panel.value.params.element_length.as_mut() {
            *el *= 2.0;
            changed = true;
        }
    }
    changed.then_some(c)
}

/// The start of `prep`'s static solve through `prep.plan.statics.mesh_sequence` coarser
/// meshes: the coarsest that builds is solved from its as-built shape, each finer one from the
/// coarser equilibrium carried to it ([`prolong`]), and the last equilibrium carried to
/// `prep`'s mesh is the start. A level that does not build ends the coarsening there; a
/// coarser solve that fails leaves the start as built (with a warning).
pub(crate) fn sequenced_start(
    prep: &Prepared,
    progress: &mut dyn FnMut(&StaticProgress) -> StaticControl,
) -> crate::Result<SequencedStart> {
    let mut out = SequencedStart::default();
    let levels = prep.plan.statics.mesh_sequence;
    // Coarser scenes, finest first, as far as they build.
    let mut coarse = Vec::new();
    let mut scene = prep.scene.clone();
    for _ in 0..levels {
        let Some(c) = coarser(&scene) else { break };
        let Ok(built) = build(&c, Prescribed::AsScene) else {
            out.warnings.push(format!(
                "mesh_sequence: the scene at {}× the nets' element length does not build; the \
                 sequence starts one level finer",
                1 << (coarse.len() + 1)
            ));
            break;
        };
        scene = c.clone();
        coarse.push(Prepared {
            scene: c,
            built,
            plan: prep.plan.clone(),
        });
    }
    let mut settings = prep.plan.statics.clone();
    settings.mesh_sequence = 0;
    let mut last: Option<(&Mesh, Vec<[f64; 3]>)> = None;
    for level in coarse.iter().rev() {
        let x0 = last
            .as_ref()
            .map(|(mesh, x)| carried(mesh, x, &level.built));
        let (mut loads, _) = water_loads(level, Phase::Static)?;
        let sol = match static_equilibrium_from(
            &level.built.model,
            &level.built.mesh,
            &mut loads,
            &settings,
            x0.as_deref(),
            progress,
        ) {
            Ok(sol) => sol,
            Err(e) => {
                out.warnings.push(format!(
                    "mesh_sequence: a coarser static solve failed ({}); the solve starts from \
                     the as-built shape",
                    e.chain()
                ));
                return Ok(SequencedStart { start: None, ..out });
            }
        };
        out.iterations.push(sol.report.iterations);
        if sol.report.interrupted {
            out.stopped = true;
            return Ok(out);
        }
        last = Some((&level.built.mesh, sol.state.x));
    }
    out.start = last.map(|(mesh, x)| carried(mesh, &x, &prep.built));
    Ok(out)
}

/// The start of `fine`'s model: its mesh nodes [`prolong`]ed from the coarse equilibrium, the
/// model's own nodes beyond the mesh (a rod's edge carriers at zero twist and held ghost nodes,
/// docs/theory/fem.md#rod) as built.
fn carried(coarse: &Mesh, coarse_x: &[[f64; 3]], fine: &crate::build::Built) -> Vec<[f64; 3]> {
    let mut x = prolong(coarse, coarse_x, &fine.mesh);
    x.extend_from_slice(&fine.model.nodes()[x.len()..]);
    x
}

/// What a fine node takes its displacement from: up to three coarse nodes and their weights.
type Stencil = ([usize; 3], [f64; 3]);

/// A coarse triangle, segment or lone node: its nodes (a segment repeats its end, a lone node
/// its index) and how many are distinct.
type Primitive = ([usize; 3], u8);

/// Positions of `fine`'s nodes displaced as `coarse` moved from its as-built nodes to
/// `coarse_x` [m]: each fine node takes the displacement at its closest point on the coarse
/// triangles (a quad as two), line elements and lone nodes of the same object copy,
/// interpolated linearly between their nodes (barycentric). A node whose object copy has no
/// coarse counterpart stays as built. Brute force per object copy: O(fine × coarse) per copy.
pub(crate) fn prolong(coarse: &Mesh, coarse_x: &[[f64; 3]], fine: &Mesh) -> Vec<[f64; 3]> {
    let p = |m: &Mesh, i: usize| [m.nodes[i].x, m.nodes[i].y, m.nodes[i].z];
    // Coarse primitives per (object, copy).
    let mut prims: HashMap<(u32, u32), Vec<Primitive>> = HashMap::new();
    let mut used = vec![false; coarse.nodes.len()];
    for panel in &coarse.panels {
        let n = panel.nodes.as_slice();
        let list = prims.entry((panel.object, panel.copy)).or_default();
        list.push(([n[0], n[1], n[2]], 3));
        if n.len() == 4 {
            list.push(([n[0], n[2], n[3]], 3));
        }
        n.iter().for_each(|&i| used[i] = true);
    }
    for line in &coarse.lines {
        let [a, b] = line.nodes;
        prims
            .entry((line.object, line.copy))
            .or_default()
            .push(([a, b, b], 2));
        used[a] = true;
        used[b] = true;
    }
    for (i, &(o, c)) in coarse.node_owner.iter().enumerate() {
        if !used[i] {
            prims.entry((o, c)).or_default().push(([i, i, i], 1));
        }
    }
    let mut out = Vec::with_capacity(fine.nodes.len());
    for (i, owner) in fine.node_owner.iter().enumerate() {
        let q = p(fine, i);
        let best = prims.get(owner).and_then(|list| {
            let mut best: Option<(f64, Stencil)> = None;
            for &(n, k) in list {
                let (a, b, c) = (p(coarse, n[0]), p(coarse, n[1]), p(coarse, n[2]));
                let w = match k {
                    3 => closest_on_triangle(q, a, b, c),
                    2 => {
                        let t = closest_on_segment(q, a, b);
                        [1.0 - t, t, 0.0]
                    }
                    _ => [1.0, 0.0, 0.0],
                };
                let mut y = [0.0; 3];
                for (pt, wk) in [a, b, c].iter().zip(w) {
                    for d in 0..3 {
                        y[d] += wk * pt[d];
                    }
                }
                let d2 = (0..3).map(|d| (y[d] - q[d]).powi(2)).sum::<f64>();
                if best.as_ref().is_none_or(|(bd, _)| d2 < *bd) {
                    best = Some((d2, (n, w)));
                }
            }
            best
        });
        let mut x = q;
        if let Some((_, (n, w))) = best {
            for (&j, wk) in n.iter().zip(w) {
                let x0 = p(coarse, j);
                for d in 0..3 {
                    x[d] += wk * (coarse_x[j][d] - x0[d]);
                }
            }
        }
        out.push(x);
    }
    out
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Parameter t ∈ [0, 1] of the point of segment ab closest to q.
fn closest_on_segment(q: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    if l2 <= 0.0 {
        return 0.0;
    }
    (dot(sub(q, a), ab) / l2).clamp(0.0, 1.0)
}

/// Barycentric weights of the point of triangle abc closest to q: the projection onto the
/// plane if it falls inside, else the closest point of the nearest edge or corner (the
/// Voronoi regions of the corners and edges, tested in turn; Ericson, *Real-Time Collision
/// Detection*, 2005, §5.1.5). A degenerate triangle gives its closest edge point.
fn closest_on_triangle(q: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let (ab, ac, aq) = (sub(b, a), sub(c, a), sub(q, a));
    let (d1, d2) = (dot(ab, aq), dot(ac, aq));
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bq = sub(q, b);
    let (d3, d4) = (dot(ab, bq), dot(ac, bq));
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let t = d1 / (d1 - d3);
        return [1.0 - t, t, 0.0];
    }
    let cq = sub(q, c);
    let (d5, d6) = (dot(ab, cq), dot(ac, cq));
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let t = d2 / (d2 - d6);
        return [1.0 - t, 0.0, t];
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0.0, 1.0 - t, t];
    }
    let sum = va + vb + vc;
    if !(sum > 0.0) {
        // Degenerate: the closest point on edge ab.
        let t = closest_on_segment(q, a, b);
        return [1.0 - t, t, 0.0];
    }
    let (v, w) = (vb / sum, vc / sum);
    [1.0 - v - w, v, w]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(w: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|d| w[0] * a[d] + w[1] * b[d] + w[2] * c[d])
    }

    /// The closest point agrees with a dense sampling of the triangle, for points above it,
    /// beyond each edge and beyond each corner.
    #[test]
    fn closest_point_on_a_triangle_matches_sampling() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 1.5, 0.3]);
        let queries = [
            [0.7, 0.4, 1.0],
            [1.0, -1.0, 0.2],
            [-1.0, -1.0, 0.0],
            [3.0, 0.5, -0.4],
            [0.4, 2.5, 0.0],
            [-0.6, 1.0, 0.5],
            [1.8, 1.2, 0.1],
        ];
        for q in queries {
            let w = closest_on_triangle(q, a, b, c);
            assert!(
                w.iter().all(|&x| (-1e-12..=1.0 + 1e-12).contains(&x)),
                "{w:?}"
            );
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            let d = |y: [f64; 3]| (0..3).map(|k| (y[k] - q[k]).powi(2)).sum::<f64>();
            let got = d(point(w, a, b, c));
            let n = 400;
            let mut best = f64::INFINITY;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    best = best.min(d(point([1.0 - u - v, u, v], a, b, c)));
                }
            }
            assert!(got <= best + 1e-9, "q {q:?}: {got} > sampled {best}");
            assert!(
                got >= best - 1e-2,
                "q {q:?}: {got} far below sampled {best}"
            );
        }
    }

    /// Barycentric interpolation is exact for an affine displacement: a 10 m × 6 m panel at
    /// 1 m elements started from the same panel at 2 m elements moved by u(x) = A·x + b gets
    /// exactly u at each of its nodes (every fine node lies on the coarse panel).
    #[test]
    fn an_affine_displacement_is_carried_exactly() {
        let mesh = |el: f64| {
            let mut p = aqua_mesh::PanelParams::new(10.0, 6.0);
            p.element_length = Some(el);
            p.build().unwrap()
        };
        let (coarse, fine) = (mesh(2.0), mesh(1.0));
        assert!(fine.nodes.len() > 2 * coarse.nodes.len());
        let u = |x: [f64; 3]| {
            [
                0.1 * x[0] - 0.3 * x[2] + 1.0,
                0.05 * x[1] + 0.2 * x[2] - 2.0,
                -0.4 * x[0] + 0.1 * x[1] + 0.5,
            ]
        };
        let moved: Vec<[f64; 3]> = coarse
            .nodes
            .iter()
            .map(|n| {
                let x = [n.x, n.y, n.z];
                let d = u(x);
                [x[0] + d[0], x[1] + d[1], x[2] + d[2]]
            })
            .collect();
        let got = prolong(&coarse, &moved, &fine);
        for (n, g) in fine.nodes.iter().zip(&got) {
            let x = [n.x, n.y, n.z];
            let d = u(x);
            for k in 0..3 {
                assert!((g[k] - x[k] - d[k]).abs() < 1e-12, "{x:?}: {g:?}");
            }
        }
    }

    #[test]
    fn closest_point_on_a_segment_is_clamped() {
        let (a, b) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        assert_eq!(closest_on_segment([1.0, 3.0, 0.0], a, b), 0.5);
        assert_eq!(closest_on_segment([-1.0, 0.0, 0.0], a, b), 0.0);
        assert_eq!(closest_on_segment([5.0, 1.0, 0.0], a, b), 1.0);
        assert_eq!(closest_on_segment([5.0, 1.0, 0.0], a, a), 0.0);
    }
}
