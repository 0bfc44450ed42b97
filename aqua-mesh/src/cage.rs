//! Parametric cage builders CCT, CCS, CSM, SSM (docs/theory/cages.md#cage-types to
//! #multiple-cages).
//!
//! Discretisation (round half away from zero): NT = round(C/el) (square: 4·round(a/el)),
//! NN = round(H/el), BN = round(R_b/(√2·el)) (square: round(a/(√2·el))). Net node (i, ℓ) =
//! origin + ρ_ℓ·u_i + z_ℓ·ẑ with id i·L + ℓ, L = NN + BN; tip id NT·L; then the rope columns.

use crate::collar::{
    Collar, CollarParams, DEFAULT_PIPE_DIAMETER, DEFAULT_SINKER_TUBE_DIAMETER,
    default_bracket_section, default_pipe_section, default_sinker_tube_section,
};
use crate::error::{MeshError, Result};
use crate::mesh_builder::{MeshBuilder, replicate};
use crate::model::{CageCounts, CageType, Mesh, NetElement, Object, ObjectKind, PanelNodes, Role};
use crate::net::{NetParams, NetResolved};
use crate::net_triangle::{TwineFrame, make_net_triangles};
use crate::section::Section;
use crate::section_override::SectionOverride;
use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::f64::consts::{PI, SQRT_2};

/// Default sinker weight per metre of circumference [N/m]: a submerged weight, specified in
/// newtons (docs/theory/cages.md#cage-parameters); its mass is W/g with the sea's g.
pub const DEFAULT_SINKER_WEIGHT_PER_METRE: f64 = 392.4;
/// Default tip weight [N].
pub const DEFAULT_TIP_WEIGHT: f64 = 981.0;
/// Default spacing of the vertical ropes of CCT and CCS cages along the circumference [m]
/// (`ropes` = round(C / 2.5 m), at least 3).
pub const DEFAULT_ROPE_SPACING: f64 = 2.5;
/// Most nodes a builder accepts (more is likely a unit mistake).
pub const MAX_NODES: usize = 2_000_000;

/// Keys of the `[[cage]]` table of each cage type (the cage builder's schema).
impl CageType {
    /// Keys of the `[[cage]]` table this type accepts.
    pub fn valid_keys(self) -> Vec<&'static str> {
        let t = self.canonical();
        let mut k = vec![
            "type",
            "name",
            "origins",
            "circumference",
            "depth",
            "cone_depth",
            "element_length",
            "frame_offset",
            "tip_weight",
            "fixed",
            "net",
            "groups",
            "collar",
        ];
        match t {
            CageType::Ssm => k.push("side"),
            _ => k.push("diameter"),
        }
        if matches!(t, CageType::Cct | CageType::Ccs) {
            k.push("bottom_ratio");
            k.push("ropes");
        }
        if matches!(t, CageType::Csm | CageType::Ssm) {
            k.push("rope_depth");
        }
        if t == CageType::Cct {
            k.push("tube_depth");
        }
        if t == CageType::Ccs {
            k.push("weight_depth");
            k.push("centre_weight");
        } else {
            k.push("sinker_weight_per_metre");
        }
        k
    }
}

/// One `[[cage]]` table (docs/theory/cages.md#cage-parameters). Every key is optional except
/// `type`; `None` = default.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CageParams {
    /// `type`: CCT, CCS, CSM, SSM (CST = CCT).
    #[serde(rename = "type")]
    pub kind: CageType,
    /// `name` (default `cage<index>`, set by the caller; `cage0` here).
    pub name: Option<String>,
    /// `origins` [m], default `[[0, 0, 0]]`.
    pub origins: Option<Vec<[f64; 3]>>,
    /// `circumference` C [m], default 120.
    pub circumference: Option<f64>,
    /// `diameter` D [m] instead of C (circular types).
    pub diameter: Option<f64>,
    /// `side` a [m] instead of C (SSM).
    pub side: Option<f64>,
    /// `bottom_ratio` R_b/R_t (CCT, CCS), default 1.
    pub bottom_ratio: Option<f64>,
    /// `depth` H of the side net [m], default 15.
    pub depth: Option<f64>,
    /// `cone_depth` h_c [m], default 3.
    pub cone_depth: Option<f64>,
    /// `element_length` el [m], default 2.5.
    pub element_length: Option<f64>,
    /// `frame_offset` f [m], default 1.
    pub frame_offset: Option<f64>,
    /// `rope_depth` [m] below z = −H (CSM, SSM), default 2.5.
    pub rope_depth: Option<f64>,
    /// `tube_depth` [m] below z = −H (CCT), default 2.5.
    pub tube_depth: Option<f64>,
    /// `weight_depth` d_w [m] below z = −H (CCS), default 2·depth.
    pub weight_depth: Option<f64>,
    /// `sinker_weight_per_metre` [N/m] (CCT, CSM, SSM), default 392.4.
    pub sinker_weight_per_metre: Option<f64>,
    /// `centre_weight` [N] (CCS), default 392.4·C.
    pub centre_weight: Option<f64>,
    /// `tip_weight` [N], default 981.
    pub tip_weight: Option<f64>,
    /// `ropes`: number of vertical ropes of the design (CCT, CCS), ≥ 3; default
    /// round(C / [`DEFAULT_ROPE_SPACING`]). The rope columns follow the mesh and carry
    /// `ropes`/NT ropes each (docs/theory/cages.md#frame-ropes-and-weights).
    pub ropes: Option<usize>,
    /// `fixed`: groups whose nodes are fixed, default `["top_ring"]`.
    pub fixed: Option<Vec<String>>,
    /// `net.*`.
    #[serde(default)]
    pub net: NetParams,
    /// `collar.*`: the floating collar's pipes (docs/theory/cages.md#collar).
    #[serde(default)]
    pub collar: CollarParams,
    /// `groups.<group>`: section overrides of line groups.
    #[serde(default)]
    pub groups: BTreeMap<String, SectionOverride>,
}

impl CageParams {
    /// All keys unset (defaults) for the given type.
    pub fn new(kind: CageType) -> Self {
        CageParams {
            kind,
            name: None,
            origins: None,
            circumference: None,
            diameter: None,
            side: None,
            bottom_ratio: None,
            depth: None,
            cone_depth: None,
            element_length: None,
            frame_offset: None,
            rope_depth: None,
            tube_depth: None,
            weight_depth: None,
            sinker_weight_per_metre: None,
            centre_weight: None,
            tip_weight: None,
            ropes: None,
            fixed: None,
            net: NetParams::default(),
            collar: CollarParams::default(),
            groups: BTreeMap::new(),
        }
    }

    fn set_keys(&self) -> Vec<&'static str> {
        let mut k = Vec::new();
        macro_rules! chk {
            ($($f:ident),*) => {$( if self.$f.is_some() { k.push(stringify!($f)); } )*};
        }
        chk!(
            ropes,
            circumference,
            diameter,
            side,
            bottom_ratio,
            depth,
            cone_depth,
            element_length,
            frame_offset,
            rope_depth,
            tube_depth,
            weight_depth,
            sinker_weight_per_metre,
            centre_weight,
            tip_weight
        );
        k
    }

    /// Apply defaults and validate every key (docs/theory/cages.md#input-validation).
    pub fn resolve(&self) -> Result<ResolvedCage> {
        let name = self.name.clone().unwrap_or_else(|| "cage0".to_string());
        let obj = name.as_str();
        let mut notices = Vec::new();
        if self.kind == CageType::Cst {
            notices.push(format!(
                "notice: {obj}: type CST is treated exactly as CCT; prefer type = \"CCT\" (use \
                 bottom_ratio = 1 for straight walls)"
            ));
        }
        let kind = self.kind.canonical();
        let valid = self.kind.valid_keys();
        for key in self.set_keys() {
            if !valid.contains(&key) {
                return Err(MeshError::KeyNotForType {
                    object: name.clone(),
                    key: key.to_string(),
                    kind: self.kind.code().to_string(),
                    valid_keys: valid.join(", "),
                });
            }
        }
        let pos = |key: &str, v: f64| crate::limits::length(obj, key, v, "");
        let nonneg = |key: &str, v: f64, hint: &str| -> Result<f64> {
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(MeshError::param(
                    obj,
                    key,
                    v,
                    format!("must be a finite number >= 0{hint}"),
                ))
            }
        };
        let square = kind == CageType::Ssm;
        let alt = if square { "side" } else { "diameter" };
        let alt_val = if square { self.side } else { self.diameter };
        // The key the circumference comes from, for messages about what it limits.
        let c_key = match (self.circumference, alt_val) {
            (None, Some(a)) => format!("`{alt}` = {a} m"),
            (Some(c), _) => format!("`circumference` = {c} m"),
            (None, None) => "`circumference` = 120 m (default)".to_string(),
        };
        let c = match (self.circumference, alt_val) {
            (Some(c), Some(a)) => {
                return Err(MeshError::inconsistent(
                    obj,
                    format!("both `circumference` = {c} and `{alt}` = {a} given; give only one"),
                ));
            }
            (Some(c), None) => pos("circumference", c)?,
            (None, Some(a)) => {
                let a = pos(alt, a)?;
                if square { 4.0 * a } else { PI * a }
            }
            (None, None) => 120.0,
        };
        let depth = pos("depth", self.depth.unwrap_or(15.0))?;
        let cone_depth =
            crate::limits::length_or_zero(obj, "cone_depth", self.cone_depth.unwrap_or(3.0))?;
        let el = pos("element_length", self.element_length.unwrap_or(2.5))?;
        let bottom_ratio = self.bottom_ratio.unwrap_or(1.0);
        if !(bottom_ratio.is_finite() && bottom_ratio > 0.0 && bottom_ratio <= 1.0) {
            return Err(MeshError::param(
                obj,
                "bottom_ratio",
                bottom_ratio,
                "must be in (0, 1] (R_bottom / R_top)",
            ));
        }
        let (r_t, r_b) = if square {
            (c / 8.0, c / 8.0)
        } else {
            let r = c / (2.0 * PI);
            (r, r * bottom_ratio)
        };
        let f = self.frame_offset.unwrap_or(1.0);
        if !(f.is_finite() && f > 0.0 && f < r_t) {
            let lim = if square {
                format!("side/2 = {r_t}")
            } else {
                format!("the top radius C/(2π) = {r_t:.6}")
            };
            return Err(MeshError::param(
                obj,
                "frame_offset",
                f,
                format!("must be > 0 and < {lim} m (from {c_key})"),
            ));
        }

        // Counts (docs/theory/cages.md#discretisation-counts), with the limits of
        // #input-validation in the messages.
        let (nt, ns) = if square {
            let a = c / 4.0;
            let ns = (a / el).round() as usize;
            if ns < 1 {
                return Err(MeshError::param(
                    obj,
                    "element_length",
                    el,
                    format!(
                        "gives n_s = round({a}/{el}) = 0 nodes per side; side {a} m needs \
                         element_length <= {} m",
                        2.0 * a
                    ),
                ));
            }
            (ns.saturating_mul(4), ns)
        } else {
            let nt = (c / el).round() as usize;
            if nt < 3 {
                return Err(MeshError::param(
                    obj,
                    "element_length",
                    el,
                    format!(
                        "gives NT = round({c}/{el}) = {nt} < 3 nodes around; circumference {c} m \
                         needs element_length <= {} m",
                        c / 2.5
                    ),
                ));
            }
            (nt, 0)
        };
        let nn = (depth / el).round() as usize;
        if nn < 1 {
            return Err(MeshError::param(
                obj,
                "element_length",
                el,
                format!(
                    "gives NN = round({depth}/{el}) = 0; depth {depth} m needs element_length <= \
                     {} m",
                    2.0 * depth
                ),
            ));
        }
        let cone_ref = if square { c / 4.0 } else { r_b };
        let bn = (cone_ref / (SQRT_2 * el)).round() as usize;
        if bn < 1 {
            let what = if square {
                format!("side {cone_ref} m")
            } else {
                format!("bottom radius {cone_ref:.6} m")
            };
            return Err(MeshError::param(
                obj,
                "element_length",
                el,
                format!(
                    "gives BN = round({cone_ref:.6}/(√2·{el})) = 0 cone segments; {what} needs \
                     element_length <= {:.6} m",
                    SQRT_2 * cone_ref
                ),
            ));
        }

        let ext_depth = match kind {
            CageType::Csm | CageType::Ssm => pos("rope_depth", self.rope_depth.unwrap_or(2.5))?,
            CageType::Cct => pos("tube_depth", self.tube_depth.unwrap_or(2.5))?,
            _ => {
                let dw = pos("weight_depth", self.weight_depth.unwrap_or(2.0 * depth))?;
                if dw <= cone_depth {
                    return Err(MeshError::param(
                        obj,
                        "weight_depth",
                        dw,
                        format!(
                            "must be > cone_depth = {cone_depth} m (the bottom ropes would cross \
                             the net)"
                        ),
                    ));
                }
                dw
            }
        };
        let n_ext = match kind {
            CageType::Ccs => (((r_b + f).powi(2) + ext_depth * ext_depth).sqrt() / el)
                .round()
                .max(1.0) as usize,
            _ => (ext_depth / el).round().max(1.0) as usize,
        };
        let neg_hint = " (use buoys for upward forces)";
        let sinker_w = nonneg(
            "sinker_weight_per_metre",
            self.sinker_weight_per_metre
                .unwrap_or(DEFAULT_SINKER_WEIGHT_PER_METRE),
            neg_hint,
        )?;
        let centre_w = nonneg(
            "centre_weight",
            self.centre_weight
                .unwrap_or(DEFAULT_SINKER_WEIGHT_PER_METRE * c),
            neg_hint,
        )?;
        let tip_w = nonneg(
            "tip_weight",
            self.tip_weight.unwrap_or(DEFAULT_TIP_WEIGHT),
            neg_hint,
        )?;

        let ropes = match kind {
            CageType::Cct | CageType::Ccs => {
                let n = self
                    .ropes
                    .unwrap_or(((c / DEFAULT_ROPE_SPACING).round() as usize).max(3));
                if n < 3 {
                    return Err(MeshError::param(
                        obj,
                        "ropes",
                        n,
                        "must be >= 3 (the number of vertical ropes around the cage)",
                    ));
                }
                n
            }
            _ => nt,
        };
        let origins = self.origins.clone().unwrap_or_else(|| vec![[0.0; 3]]);
        if origins.is_empty() {
            return Err(MeshError::param(
                obj,
                "origins",
                "[]",
                "needs at least one point [x, y, z]",
            ));
        }
        if let Some(o) = origins.iter().find(|o| o.iter().any(|v| !v.is_finite())) {
            return Err(MeshError::param(
                obj,
                "origins",
                format!("{o:?}"),
                "coordinates must be finite numbers",
            ));
        }
        let collar = self.collar.resolve(obj)?;
        let reach = r_t + f + collar.pipe_spacing;
        for (a, oa) in origins.iter().enumerate() {
            for (b, ob) in origins.iter().enumerate().skip(a + 1) {
                let (dx, dy) = (ob[0] - oa[0], ob[1] - oa[1]);
                let overlap = if square {
                    dx.abs() < 2.0 * reach && dy.abs() < 2.0 * reach
                } else {
                    dx.hypot(dy) < 2.0 * reach
                };
                if overlap {
                    return Err(MeshError::inconsistent(
                        obj,
                        format!(
                            "origins {a} {oa:?} and {b} {ob:?} are too close: the frames \
                             (footprint {} {reach:.6} m) overlap; move them at least {:.6} m \
                             apart",
                            if square { "half-width" } else { "radius" },
                            2.0 * reach
                        ),
                    ));
                }
            }
        }

        let l = nn.saturating_add(bn);
        let n_f = match kind {
            CageType::Ccs => nn.saturating_add(n_ext),
            _ => nn.saturating_add(1).saturating_add(n_ext),
        };
        // Saturating: a tiny element_length must give an error, not an overflow.
        let per_copy = [
            nt.saturating_mul(l),
            1,
            nt.saturating_mul(n_f),
            usize::from(kind == CageType::Ccs),
            nt.saturating_mul(collar.pipes - 1),
        ]
        .into_iter()
        .fold(0usize, usize::saturating_add);
        let total = per_copy.saturating_mul(origins.len());
        if total > MAX_NODES {
            return Err(MeshError::param(
                obj,
                "element_length",
                el,
                format!(
                    "gives {total} nodes (> {MAX_NODES}) for {c_key}, `depth` = {depth} m and \
                     {} origin(s); likely a unit mistake (lengths are in metres)",
                    origins.len()
                ),
            ));
        }
        let net = self.net.resolve(obj, &mut notices)?;
        Ok(ResolvedCage {
            name,
            kind,
            square,
            circumference: c,
            r_t,
            r_b,
            depth,
            cone_depth,
            element_length: el,
            frame_offset: f,
            ext_depth,
            sinker_weight_per_metre: sinker_w,
            centre_weight: centre_w,
            tip_weight: tip_w,
            ropes,
            nt,
            ns,
            nn,
            bn,
            n_ext,
            origins,
            fixed: self
                .fixed
                .clone()
                .unwrap_or_else(|| vec!["top_ring".to_string()]),
            groups: self.groups.clone(),
            net,
            collar,
            notices,
        })
    }

    /// Validate and build the cage (all copies).
    pub fn build(&self) -> Result<Mesh> {
        self.resolve()?.build()
    }
}

/// A cage with all defaults applied, validated, with its counts.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedCage {
    /// Object name.
    pub name: String,
    /// Canonical type (CST → CCT).
    pub kind: CageType,
    /// True for SSM.
    pub square: bool,
    /// Circumference C [m].
    pub circumference: f64,
    /// Top radius R_t (square: half-width h) [m].
    pub r_t: f64,
    /// Bottom radius R_b (square: h) [m].
    pub r_b: f64,
    /// Side depth H [m].
    pub depth: f64,
    /// Cone depth h_c [m].
    pub cone_depth: f64,
    /// Requested element length [m].
    pub element_length: f64,
    /// Frame offset f [m].
    pub frame_offset: f64,
    /// rope_depth (CSM/SSM), tube_depth (CCT) or weight_depth (CCS) [m].
    pub ext_depth: f64,
    /// [N/m].
    pub sinker_weight_per_metre: f64,
    /// [N].
    pub centre_weight: f64,
    /// [N].
    pub tip_weight: f64,
    /// Physical ropes of the design (CCT, CCS: `ropes`; CSM, SSM: NT).
    pub ropes: usize,
    /// Nodes around NT.
    pub nt: usize,
    /// Nodes per side n_s (square only).
    pub ns: usize,
    /// Side segments NN.
    pub nn: usize,
    /// Cone segments BN.
    pub bn: usize,
    /// n_x, n_t or n_b.
    pub n_ext: usize,
    /// Origins of the copies [m].
    pub origins: Vec<[f64; 3]>,
    /// Group names whose nodes are fixed.
    pub fixed: Vec<String>,
    /// Section overrides.
    pub groups: BTreeMap<String, SectionOverride>,
    /// Net parameters.
    pub net: NetResolved,
    /// The collar's pipes.
    pub collar: Collar,
    /// Notices so far.
    pub notices: Vec<String>,
}

/// Default section of the frame groups (docs/theory/cages.md#default-sections). The pipe modulus is
/// not given by the spec: 1.0e9 Pa (short-term modulus of PE pipe grades) is used; override with
/// `groups.<group>.youngs_modulus`.
pub fn default_frame_section(group: &str) -> Option<Section> {
    match group {
        "ropes" | "tie_lines" => Some(Section::cable("rope", 0.05, 1.0e9, 1100.0)),
        "top_ring" | "top_links" => Some(default_pipe_section(DEFAULT_PIPE_DIAMETER)),
        "bottom_ring" => Some(default_sinker_tube_section(DEFAULT_SINKER_TUBE_DIAMETER)),
        _ => None,
    }
}

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
            counts: Some(counts),
            source_node_tags: Vec::new(),
        });
        b.mesh.notices = notices;
        let mut mesh = b.mesh;
        replicate(&mut mesh, &self.origins);
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_not_for_type() {
        let mut p = CageParams::new(CageType::Ssm);
        p.tube_depth = Some(2.0);
        let e = p.resolve().unwrap_err().to_string();
        assert!(e.contains("tube_depth") && e.contains("SSM"), "{e}");
        let mut p = CageParams::new(CageType::Cct);
        p.side = Some(30.0);
        assert!(p.resolve().is_err());
    }

    #[test]
    fn cst_is_cct_with_notice() {
        let m = CageParams::new(CageType::Cst).build().unwrap();
        let c = CageParams::new(CageType::Cct).build().unwrap();
        assert_eq!(m.nodes, c.nodes);
        assert_eq!(m.lines.len(), c.lines.len());
        assert!(m.notices.iter().any(|n| n.contains("CST")));
    }
}
