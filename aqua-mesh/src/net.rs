//! Net parameters and mesh grouping (docs/theory/cages.md#cage-parameters `net.*`, #mesh-grouping;
//! docs/theory/fem.md#sections).
//!
//! A physical square-mesh net of half mesh l_p holds 2/l_p metres of twine per square metre. Each
//! numerical twine e carries the twine of the net area A_e it represents (its share of the
//! panels it borders): λ_e = 2·A_e/(l_p·L_e) physical twines side by side. The group section is
//! that of the length-weighted mean λ̄ (dws = dwe = √λ̄·dw0, dwh = λ̄·dw0) and each element
//! scales it by λ_e/λ̄ ([`crate::LineElement::section_scale`]).

use crate::error::{MeshError, Result};
use crate::mesh_builder::MeshBuilder;
use crate::model::{Mesh, MeshOrientation, NetElement, NetGrouping, PanelNodes};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Default physical twine diameter dw0 [m].
pub const DEFAULT_TWINE_DIAMETER: f64 = 2.85e-3;
/// Default half mesh (bar length) l_p [m].
pub const DEFAULT_HALF_MESH: f64 = 25.87e-3;
/// Default net Young's modulus [Pa] (nylon).
pub const DEFAULT_NET_YOUNGS_MODULUS: f64 = 2.0e9;
/// Default net density [kg/m³] (nylon).
pub const DEFAULT_NET_DENSITY: f64 = 1140.0;
/// λ above which a warning is issued.
pub const LAMBDA_WARN: f64 = 500.0;

/// `net.*` keys of a `[[cage]]`, `[[panel]]` or `[[mesh]]` table.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct NetParams {
    /// `twine_diameter`: physical twine diameter dw0 [m], > 0. Default 2.85e-3.
    pub twine_diameter: Option<f64>,
    /// `half_mesh`: bar length l_p [m], > `twine_diameter`. Default 25.87e-3.
    pub half_mesh: Option<f64>,
    /// `solidity`: Sn, 0 < Sn < 1. Default 2d/l − (d/l)².
    pub solidity: Option<f64>,
    /// `grouping_ratio`: λ override, ≥ 1. Default computed from the mesh.
    pub grouping_ratio: Option<f64>,
    /// `youngs_modulus` of the twine material [Pa], > 0. Default 2.0e9.
    pub youngs_modulus: Option<f64>,
    /// `density` of the twine material [kg/m³], > 0. Default 1140.
    pub density: Option<f64>,
    /// `element`: how the net is modelled, `"cable"` (numerical twines along the mesh lines,
    /// the default) or `"triangle"` (Priour's net triangles, docs/theory/fem.md#net-triangle).
    pub element: Option<NetElement>,
    /// `orientation` of the twines on the surface (triangles only): `"square"` (twines along
    /// and across the reference direction, the default) or `"diamond"` (at ±45° to it).
    pub orientation: Option<MeshOrientation>,
    /// `twine_direction` (triangles only): the reference direction of the twines, projected
    /// onto each triangle. Default: the horizontal tangent of the surface (around the cage for
    /// flat bottoms; along the panel's width for `[[panel]]`).
    pub twine_direction: Option<[f64; 3]>,
}

/// Net parameters with defaults applied and validated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NetResolved {
    /// dw0 [m].
    pub twine_diameter: f64,
    /// l_p [m].
    pub half_mesh: f64,
    /// Sn.
    pub solidity: f64,
    /// λ override.
    pub grouping_ratio: Option<f64>,
    /// E [Pa].
    pub youngs_modulus: f64,
    /// ρ [kg/m³].
    pub density: f64,
    /// Net model.
    pub element: NetElement,
    /// Twine orientation (triangles).
    pub orientation: MeshOrientation,
    /// Reference twine direction (triangles), if given.
    pub twine_direction: Option<[f64; 3]>,
}

/// Solidity of a knotless square-mesh net from twine diameter and half mesh: 2d/l − (d/l)².
pub fn default_solidity(twine_diameter: f64, half_mesh: f64) -> f64 {
    let r = twine_diameter / half_mesh;
    2.0 * r - r * r
}

fn positive(object: &str, key: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(MeshError::param(
            object,
            key,
            v,
            "must be a finite number > 0",
        ))
    }
}

impl NetParams {
    /// Apply defaults and validate (docs/theory/cages.md#input-validation). Warnings (solidity far
    /// from the formula) are pushed to `notices`.
    pub fn resolve(&self, object: &str, notices: &mut Vec<String>) -> Result<NetResolved> {
        let d = positive(
            object,
            "net.twine_diameter",
            self.twine_diameter.unwrap_or(DEFAULT_TWINE_DIAMETER),
        )?;
        let l = positive(
            object,
            "net.half_mesh",
            self.half_mesh.unwrap_or(DEFAULT_HALF_MESH),
        )?;
        if l <= d {
            return Err(MeshError::param(
                object,
                "net.half_mesh",
                l,
                format!("must be > net.twine_diameter = {d} m"),
            ));
        }
        let formula = default_solidity(d, l);
        let sn = match self.solidity {
            None => formula,
            Some(s) => {
                if !(s.is_finite() && s > 0.0 && s < 1.0) {
                    return Err(MeshError::param(
                        object,
                        "net.solidity",
                        s,
                        "must be in (0, 1)",
                    ));
                }
                if ((s - formula) / formula).abs() > 0.2 {
                    notices.push(format!(
                        "warning: {object}: net.solidity = {s} differs by more than 20 % from \
                         2d/l - (d/l)^2 = {formula:.4} for twine_diameter {d} m, half_mesh {l} m"
                    ));
                }
                s
            }
        };
        if self.element == Some(NetElement::Triangle) {
            for (key, given) in [
                ("solidity", self.solidity.is_some()),
                ("grouping_ratio", self.grouping_ratio.is_some()),
            ] {
                if given {
                    notices.push(format!(
                        "warning: {object}: net.{key} is not used by net.element = \"triangle\": \
                         the triangles hold the physical twines, and their solidity follows \
                         twine_diameter, half_mesh and the twines' stretch"
                    ));
                }
            }
        } else if self.orientation.is_some() || self.twine_direction.is_some() {
            notices.push(format!(
                "warning: {object}: net.orientation and net.twine_direction are used only by \
                 net.element = \"triangle\"; the cable net's twines follow the mesh lines"
            ));
        }
        if let Some(g) = self.grouping_ratio
            && !(g.is_finite() && g >= 1.0)
        {
            return Err(MeshError::param(
                object,
                "net.grouping_ratio",
                g,
                "must be >= 1 (a numerical twine stands for at least one physical twine)",
            ));
        }
        Ok(NetResolved {
            twine_diameter: d,
            half_mesh: l,
            solidity: sn,
            grouping_ratio: self.grouping_ratio,
            youngs_modulus: positive(
                object,
                "net.youngs_modulus",
                self.youngs_modulus.unwrap_or(DEFAULT_NET_YOUNGS_MODULUS),
            )?,
            density: positive(
                object,
                "net.density",
                self.density.unwrap_or(DEFAULT_NET_DENSITY),
            )?,
            element: self.element.unwrap_or_default(),
            orientation: self.orientation.unwrap_or_default(),
            twine_direction: match self.twine_direction {
                Some(t) if t.iter().all(|v| v.is_finite()) && t.iter().any(|v| *v != 0.0) => {
                    Some(t)
                }
                Some(t) => {
                    return Err(MeshError::param(
                        object,
                        "net.twine_direction",
                        format!("{t:?}"),
                        "must be a finite, non-zero vector [x, y, z]",
                    ));
                }
                None => None,
            },
        })
    }
}

/// The net area each twine of an object's net represents (docs/theory/cages.md#mesh-grouping).
#[derive(Debug, Clone, PartialEq)]
pub struct TwineAreas {
    /// As-built length L_e of each twine, in the group's order [m].
    pub lengths: Vec<f64>,
    /// Net area A_e each twine carries [m²]; `None` for a twine on no panel edge.
    pub areas: Vec<Option<f64>>,
    /// Total area of the panels [m²].
    pub net_area: f64,
}

impl TwineAreas {
    /// Lengths and net areas of the lines of group `twines` from the panels of group `panels`.
    /// Each panel is cut into triangles from its vertex centroid to its edges, scaled so that
    /// they add up to the panel's area ([`Mesh::panel_area`]); the triangle on an edge goes to
    /// the twine along that edge. The area of an edge that is no twine is shared by all twines
    /// that carry area, in proportion to their length.
    pub fn of(mesh: &Mesh, twines: usize, panels: Option<usize>) -> Self {
        let lines = &mesh.groups[twines].lines;
        let lengths: Vec<f64> = lines.iter().map(|&e| mesh.line_length(e)).collect();
        let mut areas = vec![None::<f64>; lines.len()];
        let key = |a: usize, b: usize| (a.min(b), a.max(b));
        let edge: HashMap<(usize, usize), usize> = lines
            .iter()
            .enumerate()
            .map(|(k, &e)| (key(mesh.lines[e].nodes[0], mesh.lines[e].nodes[1]), k))
            .collect();
        let mut net_area = 0.0;
        let mut orphan = 0.0;
        for &p in panels.map_or(&[][..], |g| &mesh.groups[g].panels) {
            let corners: &[usize] = match &mesh.panels[p].nodes {
                PanelNodes::Tri(n) => n,
                PanelNodes::Quad(n) => n,
            };
            let k = corners.len();
            let c = corners
                .iter()
                .fold(nalgebra::Vector3::zeros(), |a, &n| a + mesh.nodes[n].coords)
                / k as f64;
            let tri: Vec<f64> = (0..k)
                .map(|j| {
                    let (a, b) = (
                        mesh.nodes[corners[j]].coords,
                        mesh.nodes[corners[(j + 1) % k]].coords,
                    );
                    0.5 * (a - c).cross(&(b - c)).norm()
                })
                .collect();
            let area = mesh.panel_area(p);
            let sum: f64 = tri.iter().sum();
            if sum <= 0.0 {
                continue;
            }
            net_area += area;
            for (j, t) in tri.iter().enumerate() {
                let share = t * area / sum;
                match edge.get(&key(corners[j], corners[(j + 1) % k])) {
                    Some(&i) => *areas[i].get_or_insert(0.0) += share,
                    None => orphan += share,
                }
            }
        }
        if orphan > 0.0 {
            let carried: f64 = lengths
                .iter()
                .zip(&areas)
                .filter(|(_, a)| a.is_some())
                .map(|(l, _)| l)
                .sum();
            for (l, a) in lengths.iter().zip(areas.iter_mut()) {
                if let Some(a) = a {
                    *a += orphan * l / carried;
                }
            }
        }
        TwineAreas {
            lengths,
            areas,
            net_area,
        }
    }
}

impl NetResolved {
    /// Mesh grouping of a net (docs/theory/cages.md#mesh-grouping): the grouping numbers and
    /// each twine's λ_e/λ̄ ([`crate::LineElement::section_scale`]). With `net.grouping_ratio`
    /// every twine has the given λ; a twine on no panel edge (or a net without panels) has
    /// λ = L̄/l_p. λ̄ < 1 is an error; λ̄ > 500 a warning pushed to `notices`.
    pub fn grouping(
        &self,
        object: &str,
        twines: &TwineAreas,
        size: &str,
        notices: &mut Vec<String>,
    ) -> Result<(NetGrouping, Vec<f64>)> {
        let n = twines.lengths.len().max(1) as f64;
        let total: f64 = twines.lengths.iter().sum();
        let mean_twine_length = total / n;
        let lp = self.half_mesh;
        let lambdas: Vec<f64> = twines
            .lengths
            .iter()
            .zip(&twines.areas)
            .map(|(&l, a)| match (self.grouping_ratio, a) {
                (Some(g), _) => g,
                (None, Some(a)) if *a > 0.0 && l > 0.0 => 2.0 * a / (lp * l),
                (None, _) => mean_twine_length / lp,
            })
            .collect();
        let lambda = if total > 0.0 {
            lambdas
                .iter()
                .zip(&twines.lengths)
                .map(|(g, l)| g * l)
                .sum::<f64>()
                / total
        } else {
            f64::NAN
        };
        if !(lambda.is_finite() && lambda >= 1.0) {
            return Err(MeshError::param(
                object,
                "net.half_mesh",
                self.half_mesh,
                format!(
                    "gives grouping ratio λ = {lambda:.4} < 1 (a numerical twine, of mean length \
                     {mean_twine_length:.6} m, would carry less than one real twine{}); use a \
                     longer element_length or set net.grouping_ratio",
                    if twines.net_area > 0.0 {
                        format!(
                            ": the net's {:.6e} m² from {size} hold {:.6e} m of twine, the mesh \
                             {total:.6e} m",
                            twines.net_area,
                            2.0 * twines.net_area / lp
                        )
                    } else {
                        String::new()
                    }
                ),
            ));
        }
        if lambda > LAMBDA_WARN && self.element == NetElement::Cable {
            notices.push(format!(
                "warning: {object}: grouping ratio λ = {lambda:.2} > {LAMBDA_WARN}; consider a \
                 shorter element_length"
            ));
        }
        let unpaneled = twines.areas.iter().filter(|a| a.is_none()).count();
        if self.grouping_ratio.is_none() && twines.net_area > 0.0 && unpaneled > 0 {
            notices.push(format!(
                "notice: {object}: {unpaneled} net twine(s) lie on no net panel edge and carry \
                 λ = mean twine length / half_mesh"
            ));
        }
        let range = lambdas
            .iter()
            .fold([f64::INFINITY, 0.0_f64], |r, &g| [r[0].min(g), r[1].max(g)]);
        let s = lambda.sqrt() * self.twine_diameter;
        let grouping = NetGrouping {
            twine_diameter: self.twine_diameter,
            half_mesh: self.half_mesh,
            solidity: self.solidity,
            mean_twine_length,
            net_area: twines.net_area,
            lambda,
            lambda_range: range,
            lambda_given: self.grouping_ratio.is_some(),
            structural_diameter: s,
            elastic_diameter: s,
            hydro_diameter: lambda * self.twine_diameter,
            youngs_modulus: self.youngs_modulus,
            density: self.density,
            element: self.element,
            orientation: self.orientation,
        };
        Ok((grouping, lambdas.iter().map(|g| g / lambda).collect()))
    }

    /// Groups the net of the builder's object (copy 0): the twines of group `twines` carry the
    /// net area of the panels of group `panels`; sets each twine's section scale and returns
    /// the grouping. `size` names the keys the net's size comes from (for messages). The
    /// caller sets the group's section.
    pub(crate) fn group_net(
        &self,
        b: &mut MeshBuilder,
        object: &str,
        twines: usize,
        panels: Option<usize>,
        size: &str,
        notices: &mut Vec<String>,
    ) -> Result<NetGrouping> {
        let areas = TwineAreas::of(&b.mesh, twines, panels);
        let (grouping, scales) = self.grouping(object, &areas, size, notices)?;
        for (k, s) in scales.into_iter().enumerate() {
            let e = b.mesh.groups[twines].lines[k];
            b.mesh.lines[e].section_scale = s;
        }
        Ok(grouping)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two twines of length `l` on no panel: λ = l / l_p.
    fn unpaneled(l: f64) -> TwineAreas {
        TwineAreas {
            lengths: vec![l, l],
            areas: vec![None, None],
            net_area: 0.0,
        }
    }

    #[test]
    fn twine_of_the_net_area() {
        // Twines of 2 m and 1 m carrying 3 m² and 1 m²: λ_e = 2·A_e/(l_p·L_e); the mean is
        // weighted by length and the scales are λ_e/λ̄.
        let net = NetParams::default().resolve("t", &mut vec![]).unwrap();
        let lp = DEFAULT_HALF_MESH;
        let t = TwineAreas {
            lengths: vec![2.0, 1.0],
            areas: vec![Some(3.0), Some(1.0)],
            net_area: 4.0,
        };
        let (g, s) = net.grouping("t", &t, "", &mut vec![]).unwrap();
        let (l0, l1) = (3.0 / lp, 2.0 / lp);
        let mean = (l0 * 2.0 + l1) / 3.0;
        assert!((g.lambda - mean).abs() < 1e-9 * mean);
        assert!((s[0] - l0 / mean).abs() < 1e-12 && (s[1] - l1 / mean).abs() < 1e-12);
        // Twine length carried: Σ λ_e·L_e = 2·A/l_p.
        assert!((g.lambda * 3.0 - 2.0 * 4.0 / lp).abs() < 1e-9);
    }

    #[test]
    fn worked_case_diameters() {
        // Twines on no panel, λ = L̄/l_p = 81.11 (the mean-length rule of
        // docs/theory/cages.md#mesh-grouping), dw0 = 2.85 mm -> dws = √λ·dw0 = 0.02567 m,
        // dwh = λ·dw0 = 0.2312 m.
        let net = NetParams::default().resolve("t", &mut vec![]).unwrap();
        let (g, _) = net
            .grouping("t", &unpaneled(81.11 * DEFAULT_HALF_MESH), "", &mut vec![])
            .unwrap();
        assert!((g.structural_diameter - 0.02567).abs() / 0.02567 < 1e-3);
        assert!((g.hydro_diameter - 0.2312).abs() / 0.2312 < 1e-3);
        // μ = 0.590 kg/m and EA = 1.035e6 N with ρ = 1140, E = 2e9.
        let s = g.twine_section();
        assert!((s.linear_mass() - 0.590).abs() < 1e-3);
        assert!((s.axial_stiffness() - 1.035e6).abs() / 1.035e6 < 1e-3);
    }

    #[test]
    fn bad_net_inputs() {
        let mut n = NetParams {
            half_mesh: Some(1e-3),
            ..Default::default()
        };
        let e = n.resolve("cage0", &mut vec![]).unwrap_err().to_string();
        assert!(
            e.contains("net.half_mesh") && e.contains("twine_diameter"),
            "{e}"
        );
        n.half_mesh = None;
        n.solidity = Some(1.2);
        let e = n.resolve("cage0", &mut vec![]).unwrap_err().to_string();
        assert!(e.contains("net.solidity") && e.contains("(0, 1)"), "{e}");
        n.solidity = Some(0.5);
        let mut notes = vec![];
        n.resolve("cage0", &mut notes).unwrap();
        assert_eq!(notes.len(), 1);
        let r = NetParams::default().resolve("c", &mut vec![]).unwrap();
        assert!(r.grouping("c", &unpaneled(0.01), "", &mut vec![]).is_err());
        let mut notes = vec![];
        r.grouping("c", &unpaneled(600.0 * DEFAULT_HALF_MESH), "", &mut notes)
            .unwrap();
        assert_eq!(notes.len(), 1);
    }
}
