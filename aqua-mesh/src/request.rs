//! One builder call described by flat keys: the cage, net, panel, line and gmsh keys of one
//! table side by side (what `aqua mesh` takes as flags), which of them each builder uses, and
//! their mapping into [`CageParams`], [`PanelParams`], [`LineParams`] or [`GmshParams`].
//!
//! Absent keys take the builders' defaults (docs/theory/cages.md#cage-parameters,
//! #flat-net-panel, #single-line, #gmsh-import). A key given to a builder that does not use it is
//! an error ([`RequestError::KeyNotUsed`]), never silently ignored.

use crate::cage::CageParams;
use crate::error::MeshError;
use crate::io::gmsh::{GmshParams, import_gmsh};
use crate::line::{Fairlead, LineParams, LineShape};
use crate::model::{CageType, Mesh};
use crate::net::NetParams;
use crate::panel::{PanelFixed, PanelParams};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The builder a [`MeshRequest`] runs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Builder {
    /// A parametric cage of this type.
    Cage(CageType),
    /// A flat net panel.
    Panel,
    /// A single line.
    Line,
    /// A gmsh import of this `.msh` file.
    Gmsh(PathBuf),
}

impl Builder {
    /// The name messages use: the cage code (`SSM`), `panel`, `line` or `gmsh`.
    pub fn label(&self) -> &'static str {
        match self {
            Builder::Cage(t) => t.code(),
            Builder::Panel => "panel",
            Builder::Line => "line",
            Builder::Gmsh(_) => "gmsh",
        }
    }

    /// The key groups this builder uses (see [`MeshRequest::given`]).
    fn groups(&self) -> &'static [KeyGroup] {
        use KeyGroup::*;
        match self {
            Builder::Cage(_) => &[Cage, Net, Size, Origin, Fixed],
            Builder::Panel => &[Panel, Net, Size, Fixed],
            Builder::Line => &[Line, Size, Fixed],
            Builder::Gmsh(_) => &[Gmsh, Net, Origin],
        }
    }
}

/// The groups of keys of a [`MeshRequest`], each used by some builders only.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum KeyGroup {
    Cage,
    Net,
    Panel,
    Line,
    Gmsh,
    Size,
    Origin,
    Fixed,
}

/// A request that cannot be built: a key the builder does not use, a missing or invalid key,
/// or the builder's own error.
#[derive(Debug, thiserror::Error)]
pub enum RequestError {
    /// `key` is given but `builder` does not use it.
    #[error("key `{key}` is not used by the {builder} builder")]
    KeyNotUsed {
        /// The key (scene spelling, e.g. `cone_depth`).
        key: &'static str,
        /// [`Builder::label`].
        builder: &'static str,
    },
    /// `diameter` given to a panel (a panel's size keys are `element_length` and `divisions`).
    #[error("key `diameter` is not used by the panel builder")]
    PanelDiameter,
    /// A key the builder needs is missing.
    #[error("{builder} needs `{key}` {what}")]
    MissingKey {
        /// [`Builder::label`].
        builder: &'static str,
        /// The key.
        key: &'static str,
        /// What it holds, e.g. `[m]` or `x,y,z [m]`.
        what: &'static str,
    },
    /// A panel's `fixed` value is not a panel mode.
    #[error("`fixed` = `{value}` for a panel: valid values all, top, top_bottom, edges, none")]
    PanelFixed {
        /// The value given.
        value: String,
    },
    /// More than one `fixed` value for a panel.
    #[error("`fixed` takes one value for a panel (all, top, top_bottom, edges, none)")]
    PanelFixedCount,
    /// A `rename` entry that is not `GmshName=role`.
    #[error("`rename` = `{value}`: expected GmshName=role")]
    Rename {
        /// The value given.
        value: String,
    },
    /// The builder rejected the parameters.
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// The keys of one builder call, all optional (`None`/empty = the builder's default). Each
/// field is the scene key of the same name; `origin` holds `origins`, `rename` holds
/// `GmshName=role` entries.
#[derive(Debug, Clone, Default, PartialEq)]
#[allow(missing_docs)]
pub struct MeshRequest {
    /// Object name (default `cage0` / `panel0` / `line0` / `mesh0`).
    pub name: Option<String>,
    // Cage keys (docs/theory/cages.md#cage-parameters); `diameter` is also a line's.
    pub circumference: Option<f64>,
    pub diameter: Option<f64>,
    pub side: Option<f64>,
    pub bottom_ratio: Option<f64>,
    pub depth: Option<f64>,
    pub cone_depth: Option<f64>,
    pub element_length: Option<f64>,
    pub frame_offset: Option<f64>,
    pub rope_depth: Option<f64>,
    pub tube_depth: Option<f64>,
    pub weight_depth: Option<f64>,
    pub sinker_weight_per_metre: Option<f64>,
    pub centre_weight: Option<f64>,
    pub tip_weight: Option<f64>,
    /// Origins of the copies [m] (cages, gmsh imports).
    pub origin: Vec<[f64; 3]>,
    /// Fixed groups (cages, lines; `none` dropped for a cage) or the panel mode (one value).
    pub fixed: Vec<String>,
    // Net keys (`net.*`).
    pub twine_diameter: Option<f64>,
    pub half_mesh: Option<f64>,
    pub solidity: Option<f64>,
    pub grouping_ratio: Option<f64>,
    // Panel keys.
    pub width: Option<f64>,
    pub height: Option<f64>,
    pub divisions: Option<[u32; 2]>,
    pub centre: Option<[f64; 3]>,
    pub normal: Option<[f64; 3]>,
    pub up: Option<[f64; 3]>,
    pub bottom_weight: Option<f64>,
    // Line keys; `seabed_z` [m] projects nodes below it onto it.
    pub anchor: Option<[f64; 3]>,
    pub fairlead: Option<[f64; 3]>,
    pub length: Option<f64>,
    pub segments: Option<u32>,
    pub shape: Option<LineShape>,
    pub ea: Option<f64>,
    pub mass_per_length: Option<f64>,
    pub seabed_z: Option<f64>,
    // gmsh keys.
    pub scale: Option<f64>,
    pub rotate_deg: Option<[f64; 3]>,
    pub translate: Option<[f64; 3]>,
    /// `GmshName=role` entries.
    pub rename: Vec<String>,
}

impl MeshRequest {
    /// The keys given, with their group, in a fixed order (the first one a builder does not
    /// use is the one reported).
    fn given(&self) -> Vec<(KeyGroup, &'static str)> {
        use KeyGroup as G;
        let mut v = Vec::new();
        macro_rules! g {
            ($grp:expr, $($f:ident),*) => {$(
                if self.$f.is_some() { v.push(($grp, stringify!($f))); }
            )*};
        }
        g!(
            G::Cage,
            circumference,
            side,
            bottom_ratio,
            depth,
            cone_depth,
            frame_offset,
            rope_depth,
            tube_depth,
            weight_depth,
            sinker_weight_per_metre,
            centre_weight,
            tip_weight
        );
        g!(G::Net, twine_diameter, half_mesh, solidity, grouping_ratio);
        g!(
            G::Panel,
            width,
            height,
            divisions,
            centre,
            normal,
            up,
            bottom_weight
        );
        g!(
            G::Line,
            anchor,
            fairlead,
            length,
            segments,
            shape,
            ea,
            mass_per_length,
            seabed_z
        );
        g!(G::Gmsh, scale, rotate_deg, translate);
        g!(G::Size, element_length, diameter);
        for (grp, key, empty) in [
            (G::Gmsh, "rename", self.rename.is_empty()),
            (G::Origin, "origin", self.origin.is_empty()),
            (G::Fixed, "fixed", self.fixed.is_empty()),
        ] {
            if !empty {
                v.push((grp, key));
            }
        }
        v
    }

    /// The `net.*` keys.
    fn net(&self) -> NetParams {
        NetParams {
            twine_diameter: self.twine_diameter,
            half_mesh: self.half_mesh,
            solidity: self.solidity,
            grouping_ratio: self.grouping_ratio,
            ..Default::default()
        }
    }

    fn origins(&self) -> Option<Vec<[f64; 3]>> {
        (!self.origin.is_empty()).then(|| self.origin.clone())
    }

    /// Check that `builder` uses every key given, then build.
    pub fn build(&self, builder: &Builder) -> Result<Mesh, RequestError> {
        let allowed = builder.groups();
        if let Some((_, key)) = self.given().into_iter().find(|(g, _)| !allowed.contains(g)) {
            return Err(RequestError::KeyNotUsed {
                key,
                builder: builder.label(),
            });
        }
        Ok(match builder {
            Builder::Cage(kind) => self.cage(*kind).build()?,
            Builder::Panel => self.panel()?.build()?,
            Builder::Line => self.line(builder)?.build_with(None, self.seabed_z)?,
            Builder::Gmsh(file) => import_gmsh(&self.gmsh(file)?)?,
        })
    }

    /// The cage's parameters.
    pub fn cage(&self, kind: CageType) -> CageParams {
        let mut p = CageParams::new(kind);
        p.name = self.name.clone();
        p.circumference = self.circumference;
        p.diameter = self.diameter;
        p.side = self.side;
        p.bottom_ratio = self.bottom_ratio;
        p.depth = self.depth;
        p.cone_depth = self.cone_depth;
        p.element_length = self.element_length;
        p.frame_offset = self.frame_offset;
        p.rope_depth = self.rope_depth;
        p.tube_depth = self.tube_depth;
        p.weight_depth = self.weight_depth;
        p.sinker_weight_per_metre = self.sinker_weight_per_metre;
        p.centre_weight = self.centre_weight;
        p.tip_weight = self.tip_weight;
        p.origins = self.origins();
        if !self.fixed.is_empty() {
            p.fixed = Some(
                self.fixed
                    .iter()
                    .filter(|f| *f != "none")
                    .cloned()
                    .collect(),
            );
        }
        p.net = self.net();
        p
    }

    /// The panel's parameters.
    fn panel(&self) -> Result<PanelParams, RequestError> {
        if self.diameter.is_some() {
            return Err(RequestError::PanelDiameter);
        }
        let fixed = match self.fixed.as_slice() {
            [] => PanelFixed::All,
            [f] => PanelFixed::from_name(f)
                .ok_or_else(|| RequestError::PanelFixed { value: f.clone() })?,
            _ => return Err(RequestError::PanelFixedCount),
        };
        let missing = |key, what| RequestError::MissingKey {
            builder: "panel",
            key,
            what,
        };
        let mut p = PanelParams::new(
            self.width.ok_or_else(|| missing("width", "[m]"))?,
            self.height.ok_or_else(|| missing("height", "[m]"))?,
        );
        p.name = self.name.clone();
        p.divisions = self.divisions;
        p.element_length = self.element_length;
        p.centre = self.centre;
        p.normal = self.normal;
        p.up = self.up;
        p.fixed = fixed;
        p.bottom_weight = self.bottom_weight;
        p.net = self.net();
        Ok(p)
    }

    /// The line's parameters.
    fn line(&self, builder: &Builder) -> Result<LineParams, RequestError> {
        let missing = |key, what| RequestError::MissingKey {
            builder: builder.label(),
            key,
            what,
        };
        Ok(LineParams {
            name: self.name.clone(),
            anchor: self.anchor.ok_or_else(|| missing("anchor", "x,y,z [m]"))?,
            fairlead: self.fairlead.map(Fairlead::Point),
            length: self
                .length
                .ok_or_else(|| missing("length", "(unstretched, m)"))?,
            segments: self.segments,
            element_length: self.element_length,
            shape: self.shape.unwrap_or_default(),
            fixed: (!self.fixed.is_empty()).then(|| self.fixed.clone()),
            diameter: self.diameter,
            ea: self.ea,
            mass_per_length: self.mass_per_length,
            ..Default::default()
        })
    }

    /// The gmsh import's parameters.
    fn gmsh(&self, file: &std::path::Path) -> Result<GmshParams, RequestError> {
        let mut rename = BTreeMap::new();
        for r in &self.rename {
            let (a, b) = r
                .split_once('=')
                .ok_or_else(|| RequestError::Rename { value: r.clone() })?;
            rename.insert(a.to_string(), b.to_string());
        }
        Ok(GmshParams {
            name: self.name.clone(),
            file: file.to_path_buf(),
            scale: self.scale,
            rotate_deg: self.rotate_deg,
            translate: self.translate,
            origins: self.origins(),
            rename,
            net: self.net(),
            ..Default::default()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_key_of_another_builder_is_named() {
        let r = MeshRequest {
            width: Some(3.0),
            depth: Some(10.0),
            ..Default::default()
        };
        // The cage keys come first: `width` is the one an SSM does not use.
        match r.build(&Builder::Cage(CageType::Ssm)) {
            Err(RequestError::KeyNotUsed { key, builder }) => {
                assert_eq!((key, builder), ("width", "SSM"));
            }
            other => panic!("expected KeyNotUsed, got {other:?}"),
        }
        // A panel does not take the cage's depth, and needs a height.
        let e = r.build(&Builder::Panel).unwrap_err();
        assert!(
            matches!(e, RequestError::KeyNotUsed { key: "depth", .. }),
            "{e:?}"
        );
        let panel = MeshRequest {
            width: Some(3.0),
            ..Default::default()
        };
        let e = panel.build(&Builder::Panel).unwrap_err();
        assert!(
            matches!(e, RequestError::MissingKey { key: "height", .. }),
            "{e:?}"
        );
    }

    #[test]
    fn keys_reach_the_builder() {
        let r = MeshRequest {
            width: Some(4.0),
            height: Some(2.0),
            divisions: Some([4, 2]),
            fixed: vec!["top".into()],
            ..Default::default()
        };
        let mesh = r.build(&Builder::Panel).unwrap();
        // (4 + 1)·(2 + 1) nodes of a 4 × 2 panel.
        assert_eq!(mesh.nodes.len(), 15);
        let cage = MeshRequest {
            fixed: vec!["none".into()],
            origin: vec![[1.0, 2.0, 3.0]],
            ..Default::default()
        }
        .cage(CageType::Cct);
        assert_eq!(cage.fixed, Some(vec![]));
        assert_eq!(cage.origins, Some(vec![[1.0, 2.0, 3.0]]));
    }
}
