//! The `[[cage]]` table (docs/theory/cages.md#cage-parameters) and its resolution: defaults
//! applied, values validated, discretisation counts (NT, NN, BN, …) and the default frame
//! sections.

use super::{DEFAULT_ROPE_SPACING, DEFAULT_SINKER_WEIGHT_PER_METRE, DEFAULT_TIP_WEIGHT};
use crate::collar::{
    Collar, CollarParams, DEFAULT_PIPE_DIAMETER, DEFAULT_SINKER_TUBE_DIAMETER,
    default_pipe_section, default_sinker_tube_section,
};
use crate::error::{MeshError, Result};
use crate::limits::MAX_NODES;
use crate::model::{CageType, Mesh};
use crate::net::{NetParams, NetResolved};
use crate::section::Section;
use crate::section_override::SectionOverride;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::f64::consts::{PI, SQRT_2};

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
