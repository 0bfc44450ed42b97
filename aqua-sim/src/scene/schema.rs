//! The schema of a scene's object and boundary sections: `[[group]]`, `[[point]]`, `[[fix]]`,
//! `[[prescribed]]`, `[wake]`, the object tables with their hydrodynamic keys, and the typed
//! [`Scene`] they make.

use super::analysis::AnalysisSpec;
use super::hydro::{LineHydro, NetHydro};
use super::slots::SlotSpec;
use crate::body::BodySpec;
use crate::buoy::BuoySpec;
use aqua_env::SeaSpec;
use aqua_fem::SeabedSettings;
use aqua_mesh::{CageParams, FarmParams, GmshParams, LineParams, PanelParams, SectionOverride};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// `[[group]]`: settings of an element group by name, across objects.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroupSpec {
    /// Group name (e.g. "ropes", "net_twines", or a line's group).
    pub name: String,
    /// Section overrides (docs/theory/fem.md#sections).
    pub section: SectionOverride,
    /// Morison and inertia keys.
    pub hydro: LineHydro,
}

/// `[[point]]`: point bodies on every node of a node group (docs/theory/fem.md#loads).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSpec {
    /// Node group reference ("group", "object/group" or "object/group[k]").
    pub nodes: String,
    /// Mass m [kg] per node.
    #[serde(default)]
    pub mass: f64,
    /// Displaced volume V [m³] per node (buoyancy ρ g V when submerged).
    #[serde(default)]
    pub volume: f64,
    /// Vertical extent for partial submergence [m].
    #[serde(default)]
    pub height: f64,
    /// Added-mass coefficient (added mass C_a ρ V).
    #[serde(default)]
    pub added_mass_coefficient: f64,
    /// Constant force [N].
    #[serde(default)]
    pub force: [f64; 3],
    /// C_D·A [m²] for isotropic quadratic drag.
    #[serde(default)]
    pub drag_area: f64,
    /// Seabed stiffness of the body [N/m].
    #[serde(default)]
    pub seabed_stiffness: f64,
}

/// `[[fix]]`: extra fixed DOFs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixSpec {
    /// Node group reference.
    pub nodes: String,
    /// DOFs held ("x", "y", "z"; default all).
    #[serde(default = "all_dofs")]
    pub dofs: Vec<String>,
    /// Hold the rotation too: the tangent and the twist of the pipes (rods) through the nodes
    /// (docs/theory/fem.md#rod).
    #[serde(default)]
    pub clamp: bool,
}

fn all_dofs() -> Vec<String> {
    vec!["x".into(), "y".into(), "z".into()]
}

/// The kind of a prescribed motion (docs/theory/fem.md#boundary-conditions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MotionKind {
    /// Constant offset.
    Constant,
    /// Linear ramp to an offset.
    Ramp,
    /// A·(1 − cos 2πt/T) with a smooth start (or A sin(2πt/T + φ) about `mean`).
    Sine,
    /// Table of t, dx, dy, dz (natural cubic spline).
    Table,
    /// Driven from outside, step by step, by a coupling (`aqua.Coupling`); no other key.
    /// `aqua run` refuses it; `aqua check` holds the nodes at their as-built place.
    Coupled,
}

/// `[[prescribed]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrescribedSpec {
    /// Node group reference.
    pub nodes: String,
    /// Motion kind.
    pub motion: MotionKind,
    /// Offset [m] for constant and ramp.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<[f64; 3]>,
    /// Amplitude vector [m] for sine.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<[f64; 3]>,
    /// Mean offset [m] for sine (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean: Option<[f64; 3]>,
    /// Period [s] for sine.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub period: Option<f64>,
    /// Phase [deg] for sine.
    #[serde(default)]
    pub phase: f64,
    /// Ramp / smooth-start duration [s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ramp_time: Option<f64>,
    /// Rows [t, dx, dy, dz] for table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<Vec<[f64; 4]>>,
}

/// An object table with the line where it starts (for messages).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Located<T> {
    /// 1-based line of the table header in the scene file.
    pub line: usize,
    /// The table's contents.
    #[serde(flatten)]
    pub value: T,
}

/// A cage with its hydrodynamic net keys.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CageSpec {
    /// Geometry, frame, weights and materials (aqua-mesh).
    #[serde(flatten)]
    pub params: CageParams,
    /// Net hydrodynamics.
    pub net_hydro: NetHydro,
}

/// A flat net panel with its hydrodynamic net keys.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PanelSpec {
    /// Geometry (aqua-mesh).
    #[serde(flatten)]
    pub params: PanelParams,
    /// Net hydrodynamics.
    pub net_hydro: NetHydro,
}

/// A single line with its Morison keys.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LineSpec {
    /// Geometry and section (aqua-mesh).
    #[serde(flatten)]
    pub params: LineParams,
    /// Morison and inertia keys.
    pub hydro: LineHydro,
}

/// A gmsh mesh with its hydrodynamic net keys.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshSpec {
    /// File and transform (aqua-mesh).
    #[serde(flatten)]
    pub params: GmshParams,
    /// Net hydrodynamics.
    pub net_hydro: NetHydro,
}

/// A farm: the grid keys (aqua-mesh), the cage of every slot with its net keys, and the
/// slots that differ.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FarmSpec {
    /// Grid, frame, bridles and anchor lines (aqua-mesh).
    #[serde(flatten)]
    pub params: FarmParams,
    /// `[farm.cage]`: the cage of every slot without a `[[farm.slot]]`.
    pub cage: CageSpec,
    /// `[farm.buoy]`: the buoy on every plate, a `[[buoy]]` of [`crate::buoy::FARM_BUOY_KEYS`]
    /// (shape `cylinder`; checked with the farm, [`BuoySpec::resolve_farm`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub buoy: Option<BuoySpec>,
    /// `[[farm.slot]]`: cells with their own cage or none (at most one per cell).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub slot: Vec<Located<SlotSpec>>,
}

impl FarmSpec {
    /// The cage of slot (r, c) (1-based): its `[[farm.slot]]`'s, else `[farm.cage]`; `None`
    /// for an empty slot.
    pub fn slot_cage(&self, r: usize, c: usize) -> Option<&CageSpec> {
        match self
            .slot
            .iter()
            .find(|s| s.value.row as usize == r && s.value.column as usize == c)
        {
            Some(s) => s.value.cage.as_ref(),
            None => Some(&self.cage),
        }
    }
}

/// `[wake]`: scene-wide wake switches (docs/theory/hydrodynamics.md#cage-to-cage-wake).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneWake {
    /// Cage-to-cage wake among the `[[cage]]` cages and their copies (default false; a
    /// `[[farm]]` sets its own with `cage_wake`, default true).
    #[serde(default)]
    pub cage_to_cage: bool,
}

/// A parsed, type-checked scene (cross-references are resolved when the model is built).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scene {
    /// Scene name (file stem unless given).
    pub name: String,
    /// The file it came from.
    #[serde(skip)]
    pub path: PathBuf,
    /// The sea: every `[sea]` key but `seabed`.
    pub sea: SeaSpec,
    /// `[sea.seabed]`: the structure's contact with the bed (split off `[sea]` by the reader,
    /// crate::scene::sea).
    pub seabed: SeabedSettings,
    /// Cages.
    pub cage: Vec<Located<CageSpec>>,
    /// Flat panels.
    pub panel: Vec<Located<PanelSpec>>,
    /// Lines.
    pub line: Vec<Located<LineSpec>>,
    /// gmsh meshes.
    pub mesh: Vec<Located<MeshSpec>>,
    /// Farms.
    pub farm: Vec<Located<FarmSpec>>,
    /// Scene-wide wake switches.
    pub wake: SceneWake,
    /// Group settings.
    pub group: Vec<Located<GroupSpec>>,
    /// Point bodies.
    pub point: Vec<Located<PointSpec>>,
    /// Buoys and coupling plates.
    pub buoy: Vec<Located<BuoySpec>>,
    /// `[[body]]`: free rigid bodies (crate::body).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub body: Vec<Located<BodySpec>>,
    /// Extra fixed DOFs.
    pub fix: Vec<Located<FixSpec>>,
    /// Prescribed motions.
    pub prescribed: Vec<Located<PrescribedSpec>>,
    /// Analysis settings.
    pub analysis: AnalysisSpec,
    /// The `--set` changes applied to the file, as `PATH=VALUE` (crate::overrides).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub overrides: Vec<String>,
}
