//! The floating collar of a cage: one or two concentric HDPE pipes, joined by brackets
//! (docs/theory/cages.md#collar).
//!
//! The inner pipe is the `top_ring` group (the net and the rope columns hang from it). With
//! `collar.pipes = 2` a second ring `outer_ring` lies `collar.pipe_spacing` further out at the
//! same height, joined to the inner one by radial `brackets` about every
//! `collar.bracket_spacing` metres of the inner pipe.

use crate::error::{MeshError, Result};
use crate::mesh_builder::MeshBuilder;
use crate::model::Role;
use crate::section::Section;
use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

/// Default pipe outer diameter D [m].
pub const DEFAULT_PIPE_DIAMETER: f64 = 0.35;
/// Default standard dimension ratio SDR = D/t of HDPE pipes: every default pipe wall is
/// t = D/SDR (when neither `wall_thickness` nor `sdr` is given). SDR 17 (PN 10 for PE100) is
/// the usual class of fish-farm collar pipe (docs/theory/cages.md#default-sections).
pub const DEFAULT_SDR: f64 = 17.0;
/// Default outer diameter of a CCT cage's sinker tube (`bottom_ring`) [m].
pub const DEFAULT_SINKER_TUBE_DIAMETER: f64 = 0.25;
/// Default SDR of a CCT cage's sinker tube: 13.6 (PN 12.5 in PE100), the heavier standard
/// class a sinker tube is made of; at 0.25 m the wall is 18.4 mm and the sealed tube lifts
/// 368 N/m, 94 % of the default sinkers (docs/theory/cages.md#default-sections). With the
/// collar's SDR 17 it would lift more than its sinkers weigh.
pub const DEFAULT_SINKER_TUBE_SDR: f64 = 13.6;
/// Default HDPE density [kg/m³].
pub const DEFAULT_PIPE_DENSITY: f64 = 958.0;
/// Default HDPE Young's modulus [Pa] (short-term modulus of PE pipe grades, 0.8–1.1 GPa).
pub const DEFAULT_PIPE_MODULUS: f64 = 1.0e9;
/// Default bracket spacing along the inner pipe [m].
pub const DEFAULT_BRACKET_SPACING: f64 = 2.5;

/// `collar.*` keys of a `[[cage]]` table; `None` = default.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CollarParams {
    /// `collar.pipe_diameter` D [m], default 0.35.
    pub pipe_diameter: Option<f64>,
    /// `collar.wall_thickness` t [m], 0 < t < D/2 (or `sdr`), default D/17.
    pub wall_thickness: Option<f64>,
    /// `collar.sdr` standard dimension ratio D/t (> 2), instead of `wall_thickness`;
    /// default [`DEFAULT_SDR`].
    pub sdr: Option<f64>,
    /// `collar.density` of the pipe material [kg/m³], default 958.
    pub density: Option<f64>,
    /// `collar.youngs_modulus` E of the pipe material [Pa], default 1.0e9.
    pub youngs_modulus: Option<f64>,
    /// `collar.pipes`: 1 or 2 concentric pipes, default 1.
    pub pipes: Option<u32>,
    /// `collar.pipe_spacing`: radial centre-to-centre distance of the two pipes [m] (> D),
    /// default 2·D (2 pipes only).
    pub pipe_spacing: Option<f64>,
    /// `collar.bracket_spacing` along the inner pipe [m], default 2.5 (2 pipes only).
    pub bracket_spacing: Option<f64>,
}

/// A validated collar.
#[derive(Debug, Clone, PartialEq)]
pub struct Collar {
    /// Section of each pipe (before `groups.*` overrides).
    pub section: Section,
    /// 1 or 2.
    pub pipes: usize,
    /// Radial centre distance of the pipes [m] (0 for one pipe).
    pub pipe_spacing: f64,
    /// Requested bracket spacing [m].
    pub bracket_spacing: f64,
}

impl CollarParams {
    /// Defaults applied and every key checked; `obj` names the cage in messages.
    pub fn resolve(&self, obj: &str) -> Result<Collar> {
        let pos = |key: &str, v: f64| -> Result<f64> {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(MeshError::param(
                    obj,
                    &format!("collar.{key}"),
                    v,
                    "must be a finite number > 0",
                ))
            }
        };
        let len = |key: &str, v: f64| crate::limits::length(obj, &format!("collar.{key}"), v, "");
        let d = len(
            "pipe_diameter",
            self.pipe_diameter.unwrap_or(DEFAULT_PIPE_DIAMETER),
        )?;
        let t = match (self.wall_thickness, self.sdr) {
            (Some(t), Some(s)) => {
                return Err(MeshError::inconsistent(
                    obj,
                    format!(
                        "both `collar.wall_thickness` = {t} and `collar.sdr` = {s} given; give \
                         only one (sdr = pipe_diameter / wall_thickness)"
                    ),
                ));
            }
            (None, s) => {
                let s = s.unwrap_or(DEFAULT_SDR);
                if !(s.is_finite() && s > 2.0) {
                    return Err(MeshError::param(
                        obj,
                        "collar.sdr",
                        s,
                        "must be > 2 (SDR = D/t; SDR <= 2 is a wall as thick as the radius); \
                         HDPE collar pipes are typically SDR 11 to 26",
                    ));
                }
                d / s
            }
            (Some(t), None) => {
                let t = len("wall_thickness", t)?;
                if 2.0 * t >= d {
                    return Err(MeshError::param(
                        obj,
                        "collar.wall_thickness",
                        t,
                        format!(
                            "must be < the pipe radius collar.pipe_diameter/2 = {} m",
                            d / 2.0
                        ),
                    ));
                }
                t
            }
        };
        let rho = pos("density", self.density.unwrap_or(DEFAULT_PIPE_DENSITY))?;
        let e = pos(
            "youngs_modulus",
            self.youngs_modulus.unwrap_or(DEFAULT_PIPE_MODULUS),
        )?;
        let pipes = self.pipes.unwrap_or(1);
        if !(1..=2).contains(&pipes) {
            return Err(MeshError::param(
                obj,
                "collar.pipes",
                pipes,
                "must be 1 or 2",
            ));
        }
        let (spacing, brackets) = if pipes == 2 {
            let s = len("pipe_spacing", self.pipe_spacing.unwrap_or(2.0 * d))?;
            if s <= d {
                return Err(MeshError::param(
                    obj,
                    "collar.pipe_spacing",
                    s,
                    format!(
                        "must be > collar.pipe_diameter = {d} m (centre-to-centre; the pipes \
                         would overlap)"
                    ),
                ));
            }
            let b = len(
                "bracket_spacing",
                self.bracket_spacing.unwrap_or(DEFAULT_BRACKET_SPACING),
            )?;
            (s, b)
        } else {
            for (key, v) in [
                ("pipe_spacing", self.pipe_spacing),
                ("bracket_spacing", self.bracket_spacing),
            ] {
                if let Some(v) = v {
                    return Err(MeshError::param(
                        obj,
                        &format!("collar.{key}"),
                        v,
                        "is used only with collar.pipes = 2",
                    ));
                }
            }
            (0.0, DEFAULT_BRACKET_SPACING)
        };
        Ok(Collar {
            section: Section::pipe(PIPE_MATERIAL, d, t, e, rho),
            pipes: pipes as usize,
            pipe_spacing: spacing,
            bracket_spacing: brackets,
        })
    }
}

/// Material label of HDPE pipes.
const PIPE_MATERIAL: &str = "HDPE pipe";

/// Default HDPE pipe of outer diameter `d` [m]: wall d/[`DEFAULT_SDR`], E = 1.0e9 Pa,
/// ρ = 958 kg/m³ (the collar's defaults).
pub fn default_pipe_section(d: f64) -> Section {
    pipe_section_of_sdr(d, DEFAULT_SDR)
}

/// Default sinker tube of outer diameter `d` [m]: the collar's pipe with wall
/// d/[`DEFAULT_SINKER_TUBE_SDR`].
pub fn default_sinker_tube_section(d: f64) -> Section {
    pipe_section_of_sdr(d, DEFAULT_SINKER_TUBE_SDR)
}

/// HDPE pipe (E = 1.0e9 Pa, ρ = 958 kg/m³) of outer diameter `d` [m] and wall d/`sdr`.
fn pipe_section_of_sdr(d: f64, sdr: f64) -> Section {
    Section::pipe(
        PIPE_MATERIAL,
        d,
        d / sdr,
        DEFAULT_PIPE_MODULUS,
        DEFAULT_PIPE_DENSITY,
    )
}

/// Default section of the brackets of a two-pipe collar: a steel tube 0.1 m × 5 mm,
/// E = 2.1e11 Pa, ρ = 7850 kg/m³ (override with `groups.brackets.*`).
pub fn default_bracket_section() -> Section {
    Section::pipe("steel bracket", 0.1, 0.005, 2.1e11, 7850.0)
}

/// Indices (in 0..nt) of the inner-ring nodes that carry a bracket: m = max(3, round(C/b))
/// brackets (C the inner pipe's length, b the bracket spacing), at most nt, at nodes
/// round(k·nt/m), k = 0..m.
pub fn bracket_nodes(nt: usize, inner_length: f64, spacing: f64) -> Vec<usize> {
    let m = ((inner_length / spacing).round() as usize)
        .clamp(3, nt.max(3))
        .min(nt);
    let mut v: Vec<usize> = (0..m)
        .map(|k| ((k * nt) as f64 / m as f64).round() as usize % nt)
        .collect();
    v.dedup();
    v
}

impl Collar {
    /// Adds the outer ring (nodes at `outer` positions, one per inner node, same order) and the
    /// brackets joining inner node `inner[i]` to outer node i at the bracket nodes. Returns
    /// nothing for a one-pipe collar. `section` gives each group's section with overrides.
    pub(crate) fn add_outer_pipe(
        &self,
        b: &mut MeshBuilder,
        inner: &[usize],
        outer: &[usize],
        inner_length: f64,
        section: impl Fn(&str) -> Result<Section>,
    ) -> Result<()> {
        if self.pipes < 2 {
            return Ok(());
        }
        let nt = inner.len();
        let g = b.group("outer_ring", Role::OuterRing, Some(section("outer_ring")?));
        for i in 0..nt {
            b.add_line(g, outer[i], outer[(i + 1) % nt], None);
        }
        let g = b.group("brackets", Role::Brackets, Some(section("brackets")?));
        for i in bracket_nodes(nt, inner_length, self.bracket_spacing) {
            b.add_line(g, inner[i], outer[i], None);
        }
        Ok(())
    }

    /// Position of the outer pipe's node on the ray of the inner node at
    /// `origin` + `r_inner`·`u` (`u` the cage's horizontal shape vector).
    pub(crate) fn outer_point(
        &self,
        origin: Vector3<f64>,
        u: Vector3<f64>,
        r_inner: f64,
    ) -> Point3<f64> {
        Point3::from(origin + (r_inner + self.pipe_spacing) * u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn sdr_gives_wall_thickness_and_bad_values_name_the_key() {
        let p = CollarParams {
            pipe_diameter: Some(0.5),
            sdr: Some(17.0),
            ..Default::default()
        };
        let c = p.resolve("c").unwrap();
        assert!((c.section.wall_thickness.unwrap() - 0.5 / 17.0).abs() < 1e-15);
        for (p, key) in [
            (
                CollarParams {
                    sdr: Some(2.0),
                    ..Default::default()
                },
                "collar.sdr",
            ),
            (
                CollarParams {
                    wall_thickness: Some(0.175),
                    ..Default::default()
                },
                "collar.wall_thickness",
            ),
            (
                CollarParams {
                    pipes: Some(3),
                    ..Default::default()
                },
                "collar.pipes",
            ),
            (
                CollarParams {
                    pipe_spacing: Some(1.0),
                    ..Default::default()
                },
                "collar.pipe_spacing",
            ),
            (
                CollarParams {
                    pipes: Some(2),
                    pipe_spacing: Some(0.3),
                    ..Default::default()
                },
                "collar.pipe_spacing",
            ),
        ] {
            let e = p.resolve("cage0").unwrap_err().to_string();
            assert!(e.contains(key) && e.contains("cage0"), "{e}");
        }
    }

    #[test]
    fn two_pipe_collar_has_outer_ring_and_brackets() {
        let mut p = crate::CageParams::new(crate::CageType::Csm);
        p.diameter = Some(30.0);
        p.element_length = Some(4.0);
        p.collar.pipes = Some(2);
        p.collar.pipe_spacing = Some(1.0);
        p.collar.bracket_spacing = Some(6.0);
        let m = p.build().unwrap();
        let group = |n: &str| m.groups.iter().find(|g| g.name == n).unwrap();
        let (inner, outer, br) = (group("top_ring"), group("outer_ring"), group("brackets"));
        let nt = inner.lines.len();
        assert_eq!(nt, (PI * 30.0 / 4.0).round() as usize);
        assert_eq!(outer.lines.len(), nt);
        let radius = |n: usize| m.nodes[n].x.hypot(m.nodes[n].y);
        // Inner pipe at R + f = 16 m, outer 1 m further out, both at z = 0.
        for (g, r) in [(inner, 16.0), (outer, 17.0)] {
            for &n in &g.nodes {
                assert!((radius(n) - r).abs() < 1e-9 && m.nodes[n].z.abs() < 1e-12);
            }
        }
        // round(C_in / 6) brackets, C_in the inner polygon's perimeter; each 1 m long and radial.
        let c_in = nt as f64 * 2.0 * 16.0 * (PI / nt as f64).sin();
        assert_eq!(br.lines.len(), (c_in / 6.0).round() as usize);
        for &e in &br.lines {
            let [a, b] = m.lines[e].nodes;
            assert!(inner.nodes.contains(&a) && outer.nodes.contains(&b));
            assert!((m.line_length(e) - 1.0).abs() < 1e-9);
        }
        // One pipe (default): no outer ring, and the same nodes as before the collar keys.
        let mut q = p.clone();
        q.collar = CollarParams::default();
        let m1 = q.build().unwrap();
        assert!(m1.groups.iter().all(|g| g.name != "outer_ring"));
        assert_eq!(m1.nodes.len() + nt, m.nodes.len());
    }

    #[test]
    fn brackets_are_spread_evenly() {
        // 48 nodes, 120 m of pipe, every 10 m: 12 brackets, every 4th node.
        let v = bracket_nodes(48, 120.0, 10.0);
        assert_eq!(v, (0..12).map(|k| 4 * k).collect::<Vec<_>>());
        // Spacing below the element length: one per node.
        assert_eq!(bracket_nodes(8, 8.0, 0.1).len(), 8);
        // At least three.
        assert_eq!(bracket_nodes(8, 8.0, 100.0), vec![0, 3, 5]);
    }
}
