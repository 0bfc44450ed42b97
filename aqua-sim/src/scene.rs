//! Scene files (TOML): the schema, and reading with errors that name the file, the line, the
//! key and what would be valid.
//!
//! Every key is listed in docs/guide/scene.md (checked by `tests/guide.rs` against
//! [`scene_keys`]). Layout (`x.md#anchor` is a section of `docs/theory/x.md`, `scene.md#anchor`
//! one of docs/guide/scene.md):
//!
//! ```toml
//! name = "reference-cage" # optional; default: the file stem
//! [sea]                   # aqua-env (scene.md#sea), plus [sea.seabed] kbot, cbot, friction
//! [[cage]]                # aqua-mesh CageParams (cages.md#cage-parameters) + net.* hydro keys
//! [[panel]]               # aqua-mesh PanelParams (cages.md#flat-net-panel) + net.* hydro keys
//! [[line]]                # aqua-mesh LineParams (cages.md#single-line) + Morison keys
//! [[mesh]]                # aqua-mesh GmshParams (cages.md#gmsh-import) + net.* hydro keys
//! [[farm]]                # aqua-mesh FarmParams (cages.md#farm-grid); [farm.cage] as [[cage]],
//!                         # [[farm.slot]] per cell (crate::scene::slots)
//! [wake]                  # cage_to_cage (hydrodynamics.md#cage-to-cage-wake)
//! [[group]]               # per element group: section overrides + Morison keys
//! [[point]]               # point bodies on node groups (fem.md#loads)
//! [[buoy]]                # buoys and coupling plates (crate::buoy, farm.md#buoys)
//! [[fix]]                 # extra fixed DOFs (fem.md#boundary-conditions)
//! [[prescribed]]          # prescribed motions (fem.md#boundary-conditions)
//! [analysis]              # static / dynamic settings (scene.md#analysis)
//! ```

use crate::buoy::BuoySpec;
use crate::error::{Result, SimError};
use crate::overrides::Override;
use aqua_env::SeaSpec;
use aqua_fem::{DynamicSettings, ExplicitScheme, ExplicitSettings, MassMatrix, StaticSettings};
use aqua_hydro::MorisonModelId;
use aqua_hydro::screen::ScreenModelId;
use aqua_hydro::wake::WakeSpec;
use aqua_mesh::{CageParams, FarmParams, GmshParams, LineParams, PanelParams, SectionOverride};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use toml::{Spanned, Table, Value};

mod slots;
pub use slots::SlotSpec;

/// Reads a file to a string, with an input error naming it.
pub fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path)
        .map_err(|e| SimError::input(format!("{}: cannot read: {e}", path.display())))
}

/// Reads the `[sea]` table of a scene file (a file holding only sea keys at top level is
/// accepted too, so a bare sea description can be shared between scenes).
pub fn read_sea(path: &Path) -> Result<SeaSpec> {
    /// A scene seen only for its `[sea]` table; the other sections are checked elsewhere.
    #[derive(serde::Deserialize)]
    struct SeaOnly {
        sea: SeaSpec,
        #[serde(flatten)]
        _rest: toml::Table,
    }
    let text = read_text(path)?;
    let table: toml::Table =
        toml::from_str(&text).map_err(|e| SimError::input(format!("{}: {e}", path.display())))?;
    let err = |e: toml::de::Error| SimError::input(format!("{}: {e}", path.display()));
    if table.contains_key("sea") {
        toml::from_str::<SeaOnly>(&text).map(|s| s.sea).map_err(err)
    } else {
        toml::from_str::<SeaSpec>(&text).map_err(err)
    }
}

/// How a net's drag is carried.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NetDrag {
    /// Screen panels carry drag and lift (twines only mass, buoyancy, inertia).
    #[default]
    Screen,
    /// Twines carry Morison drag (no panels loaded).
    Morison,
}

/// The hydrodynamic `net.*` keys of a cage, panel or gmsh mesh
/// (docs/theory/hydrodynamics.md#screen-models).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NetHydro {
    /// "screen" or "morison".
    #[serde(default)]
    pub drag: NetDrag,
    /// Screen model id.
    #[serde(default = "default_screen")]
    pub screen_model: ScreenModelId,
    /// C_D for screen_model = "const".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cd: Option<f64>,
    /// C_L for screen_model = "const".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cl: Option<f64>,
    /// Override of C_cyl(Re) in S3/S6.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cyl_cd: Option<f64>,
    /// Twine Morison model when drag = "morison".
    #[serde(default = "default_twine_morison")]
    pub morison: MorisonModelId,
    /// Wake model (default: loland for cages, none for panels and meshes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wake: Option<WakeSpec>,
}

fn default_screen() -> ScreenModelId {
    ScreenModelId::S1
}
fn default_twine_morison() -> MorisonModelId {
    MorisonModelId::M4
}

impl Default for NetHydro {
    fn default() -> Self {
        Self {
            drag: NetDrag::Screen,
            screen_model: default_screen(),
            cd: None,
            cl: None,
            cyl_cd: None,
            morison: default_twine_morison(),
            wake: None,
        }
    }
}

/// The net.* keys that belong to hydrodynamics (the rest go to aqua-mesh).
const NET_HYDRO_KEYS: &[&str] = &[
    "drag",
    "screen_model",
    "cd",
    "cl",
    "cyl_cd",
    "morison",
    "wake",
];

/// Morison and inertia keys of a cable group (docs/theory/hydrodynamics.md#morison-coefficients,
/// `[[group]]`, `[[line]]`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineHydro {
    /// Morison model id (default M4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub morison: Option<MorisonModelId>,
    /// C_n for morison = "const".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cn: Option<f64>,
    /// C_t for morison = "const".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ct: Option<f64>,
    /// Normal added-mass coefficient C_a (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub added_mass: Option<f64>,
    /// Axial added-mass coefficient C_at (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub added_mass_axial: Option<f64>,
    /// Froude–Krylov force (default true).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub froude_krylov: Option<bool>,
    /// Drag length L − d_h (default false).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub knot_correction: Option<bool>,
}

const LINE_HYDRO_KEYS: &[&str] = &[
    "morison",
    "cn",
    "ct",
    "added_mass",
    "added_mass_axial",
    "froude_krylov",
    "knot_correction",
];

impl LineHydro {
    /// These keys with those set in `over` replacing them (inline `[[line]]` keys override
    /// `[[group]]` keys).
    pub fn merged(mut self, over: &LineHydro) -> LineHydro {
        let LineHydro {
            morison,
            cn,
            ct,
            added_mass,
            added_mass_axial,
            froude_krylov,
            knot_correction,
        } = over;
        self.morison = morison.or(self.morison);
        self.cn = cn.or(self.cn);
        self.ct = ct.or(self.ct);
        self.added_mass = added_mass.or(self.added_mass);
        self.added_mass_axial = added_mass_axial.or(self.added_mass_axial);
        self.froude_krylov = froude_krylov.or(self.froude_krylov);
        self.knot_correction = knot_correction.or(self.knot_correction);
        self
    }
}

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

/// `analysis.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum AnalysisKind {
    /// Static equilibrium only.
    #[serde(rename = "static")]
    Static,
    /// Dynamics only (from the as-built state at rest).
    #[serde(rename = "dynamic")]
    Dynamic,
    /// Static equilibrium, then dynamics from it.
    #[default]
    #[serde(rename = "static+dynamic")]
    StaticDynamic,
}

/// `[analysis.static]` (docs/theory/fem.md#static-solver): the keys are fields of aqua-fem's
/// [`StaticSettings`], whose `Default` gives every default; this adapter only says which fields are
/// scene keys.
#[derive(Deserialize, Serialize)]
#[serde(
    remote = "StaticSettings",
    default = "StaticSettings::default",
    deny_unknown_fields
)]
struct StaticKeys {
    tol: f64,
    max_iter: usize,
    load_steps: usize,
    min_load_step: f64,
    stabilisation: f64,
    line_search: bool,
    watchdog: bool,
    #[serde(skip)]
    time: f64,
    #[serde(skip)]
    fd_position_jacobian: bool,
}

/// `analysis.dynamic.mass_matrix`: aqua-fem's [`MassMatrix`] with snake_case scene names.
#[derive(Deserialize, Serialize)]
#[serde(remote = "MassMatrix", rename_all = "snake_case")]
enum MassMatrixKey {
    Lumped,
    Consistent,
}

/// `analysis.dynamic.scheme`: the implicit HHT-α integrator or one of aqua-fem's
/// [`ExplicitScheme`]s.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Scheme {
    /// Implicit HHT-α.
    #[default]
    Hht,
    /// Implicit midpoint with energy-consistent cable forces (aqua-fem's
    /// `DynamicSettings::midpoint`).
    Midpoint,
    /// Explicit lumped mass-spring, symplectic Euler.
    SemiImplicitEuler,
    /// Explicit lumped mass-spring, RK4.
    Rk4,
}

impl Scheme {
    /// The explicit scheme, or `None` for HHT-α.
    pub fn explicit(self) -> Option<ExplicitScheme> {
        match self {
            Scheme::Hht | Scheme::Midpoint => None,
            Scheme::SemiImplicitEuler => Some(ExplicitScheme::SemiImplicitEuler),
            Scheme::Rk4 => Some(ExplicitScheme::Rk4),
        }
    }
}

/// `[analysis.dynamic]` (docs/theory/fem.md#hht-alpha, #step-control, #explicit-schemes): the keys
/// of aqua-fem's [`DynamicSettings`] (HHT-α) and [`ExplicitSettings`]; defaults not given here are
/// theirs ([`DynamicSpec::default`]). Resolved into solver settings by [`crate::plan::Plan`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DynamicSpec {
    /// Integrator.
    pub scheme: Scheme,
    /// HHT α ∈ [0, 1/3] (default 0.3); exclusive with rho_inf.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    /// Spectral radius at infinity ρ∞ ∈ [0.5, 1]; exclusive with alpha.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rho_inf: Option<f64>,
    /// Midpoint rule only: weight θ ∈ [0.5, 1] of the end velocity (default 0.5, energy
    /// conserving; above, energy decaying at first order, docs/theory/fem.md#energy-decaying-midpoint).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub theta: Option<f64>,
    /// Time step [s] (HHT: nominal, default [`DEFAULT_DT`]; explicit: upper bound, default
    /// the stable estimate).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// End time [s].
    pub t_end: f64,
    /// Smallest step before the run stops [s] (default dt/1024).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt_min: Option<f64>,
    /// Explicit: error instead of reducing a user dt above the stable step.
    pub dt_fixed: bool,
    /// Newton tolerance (relative force residual).
    pub tol: f64,
    /// Newton iterations per step.
    pub max_iter: usize,
    /// Lumped or consistent mass.
    #[serde(with = "MassMatrixKey")]
    pub mass_matrix: MassMatrix,
    /// Rayleigh damping [a_M, a_K].
    pub rayleigh: [f64; 2],
    /// Explicit stability factor.
    pub cfl: f64,
    /// Output interval [s] (default max(dt, t_end/200); at least every step).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub output_interval: Option<f64>,
    /// Interval of the ParaView series [s] (default: the output interval): a whole multiple of
    /// the output interval, so that a large model writes its `.vtm`/`.vtu` files less often
    /// than its `summary.csv` rows.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paraview_interval: Option<f64>,
    /// Largest strain before a step is rejected.
    pub max_strain: f64,
    /// Modified Newton: reuse one LU factorisation for up to this many iterations while each
    /// halves the residual (1 = full Newton).
    pub reuse_factor: usize,
    /// Newton systems: `"symmetric"` (default: L·D·Lᵀ of the symmetric part, refined on the
    /// rest, LU fallback) or `"lu"` (docs/theory/fem.md#sparse-linear-algebra).
    pub linear_solver: aqua_fem::LinearSolverKind,
    /// Relax the free lines inside each Newton iteration (docs/theory/fem.md#line-relaxation).
    pub line_relaxation: bool,
}

/// The nominal HHT step when the scene gives none [s].
pub const DEFAULT_DT: f64 = 0.1;
/// The end time when the scene gives none [s].
pub const DEFAULT_T_END: f64 = 10.0;

impl Default for DynamicSpec {
    /// aqua-fem's defaults, with the scene's end time.
    fn default() -> Self {
        let hht = DynamicSettings::new(DEFAULT_DT, DEFAULT_T_END);
        let explicit = ExplicitSettings::new(DEFAULT_T_END);
        Self {
            scheme: Scheme::Hht,
            alpha: None,
            rho_inf: None,
            theta: None,
            dt: None,
            t_end: DEFAULT_T_END,
            dt_min: hht.dt_min,
            dt_fixed: explicit.dt_fixed,
            tol: hht.tol,
            max_iter: hht.max_iter,
            mass_matrix: hht.mass_matrix,
            rayleigh: hht.rayleigh,
            cfl: explicit.cfl,
            output_interval: None,
            paraview_interval: None,
            max_strain: hht.max_strain,
            reuse_factor: hht.reuse_factor,
            linear_solver: hht.linear_solver,
            line_relaxation: hht.line_relaxation,
        }
    }
}

/// `[analysis]`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSpec {
    /// What to compute.
    #[serde(default)]
    pub kind: AnalysisKind,
    /// Statics settings (aqua-fem's, read directly).
    #[serde(default, rename = "static", with = "StaticKeys")]
    pub statics: StaticSettings,
    /// Dynamics settings.
    #[serde(default)]
    pub dynamic: DynamicSpec,
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
    /// Grid, frame, bridles, buoys and anchor lines (aqua-mesh).
    #[serde(flatten)]
    pub params: FarmParams,
    /// `[farm.cage]`: the cage of every slot without a `[[farm.slot]]`.
    pub cage: CageSpec,
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
    /// The sea.
    pub sea: SeaSpec,
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

/// The raw file: typed where the schema is ours, tables with spans where keys are split
/// between crates.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    sea: SeaSpec,
    #[serde(default)]
    cage: Vec<Spanned<Table>>,
    #[serde(default)]
    panel: Vec<Spanned<Table>>,
    #[serde(default)]
    line: Vec<Spanned<Table>>,
    #[serde(default)]
    mesh: Vec<Spanned<Table>>,
    #[serde(default)]
    farm: Vec<Spanned<Table>>,
    #[serde(default)]
    wake: SceneWake,
    #[serde(default)]
    group: Vec<Spanned<Table>>,
    #[serde(default)]
    point: Vec<Spanned<Table>>,
    #[serde(default)]
    buoy: Vec<Spanned<Table>>,
    #[serde(default)]
    fix: Vec<Spanned<Table>>,
    #[serde(default)]
    prescribed: Vec<Spanned<Table>>,
    #[serde(default)]
    analysis: AnalysisSpec,
}

/// 1-based line number of a byte offset.
fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// Moves the listed keys of `table` into a new table.
fn split_keys(table: &mut Table, keys: &[&str]) -> Table {
    let mut out = Table::new();
    for k in keys {
        if let Some(v) = table.remove(*k) {
            out.insert((*k).to_string(), v);
        }
    }
    out
}

struct Ctx<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Ctx<'_> {
    fn err(
        &self,
        section: &str,
        index: usize,
        line: usize,
        msg: impl std::fmt::Display,
    ) -> SimError {
        SimError::input(format!(
            "{}: line {line}: [[{section}]] #{}: {msg}",
            self.path.display(),
            index + 1
        ))
    }

    fn typed<T: DeserializeOwned>(
        &self,
        section: &str,
        index: usize,
        line: usize,
        prefix: &str,
        table: Table,
    ) -> Result<T> {
        Value::Table(table).try_into::<T>().map_err(|e| {
            let msg = e.to_string();
            let msg = msg.trim();
            if prefix.is_empty() {
                self.err(section, index, line, msg)
            } else {
                self.err(section, index, line, format!("in {prefix}: {msg}"))
            }
        })
    }

    /// Every table of a section, typed by `f(index, line, table)`, with its line.
    fn each<T>(
        &self,
        list: &[Spanned<Table>],
        mut f: impl FnMut(usize, usize, Table) -> Result<T>,
    ) -> Result<Vec<Located<T>>> {
        list.iter()
            .enumerate()
            .map(|(i, s)| {
                let line = line_of(self.text, s.span().start);
                f(i, line, s.get_ref().clone()).map(|value| Located { line, value })
            })
            .collect()
    }

    /// A `[[mesh]]`: gmsh files are found relative to the scene file.
    fn gmsh(&self, i: usize, line: usize, mut t: Table) -> Result<MeshSpec> {
        let net_hydro = self.net_hydro("mesh", i, line, &mut t)?;
        let mut params: GmshParams = self.typed("mesh", i, line, "", t)?;
        if params.file.is_relative()
            && let Some(dir) = self.path.parent()
        {
            params.file = dir.join(&params.file);
        }
        Ok(MeshSpec { params, net_hydro })
    }

    /// A `[[farm]]`: its grid keys, its `[farm.cage]` (typed first, so that a mistake in
    /// it is reported as such), whose `net.*` keys are split as a `[[cage]]`'s, and its
    /// `[[farm.slot]]`s (crate::scene::slots).
    fn farm(&self, i: usize, line: usize, mut t: Table) -> Result<FarmSpec> {
        let slots = t.remove("slot");
        match t.remove("cage") {
            Some(Value::Table(mut c)) => {
                let raw = c.clone();
                let net_hydro = self.net_hydro("farm", i, line, &mut c)?;
                let cage = self.typed("farm", i, line, "cage", c)?;
                let params: FarmParams = self.typed("farm", i, line, "", t)?;
                params
                    .check_cage("cage", &cage)
                    .map_err(|e| self.err("farm", i, line, e))?;
                let slot = self.farm_slots(i, line, slots, &raw, &params)?;
                Ok(FarmSpec {
                    params,
                    cage: CageSpec {
                        params: cage,
                        net_hydro,
                    },
                    slot,
                })
            }
            Some(other) => Err(self.err(
                "farm",
                i,
                line,
                format!(
                    "cage = {other}: cage must be a table ([farm.cage] with type = \"CSM\", …)"
                ),
            )),
            None => {
                let _: FarmParams = self.typed("farm", i, line, "", t)?;
                Err(self.err(
                    "farm",
                    i,
                    line,
                    "cage is missing: add a [farm.cage] table (the cage of every slot: type = \
                     \"CCT\", \"CCS\", \"CSM\" or \"SSM\" and its [[cage]] keys)",
                ))
            }
        }
    }

    /// A `[[group]]`: its name, Morison keys and section overrides.
    fn group(&self, i: usize, line: usize, mut t: Table) -> Result<GroupSpec> {
        let name = match t.remove("name") {
            Some(Value::String(n)) => Some(n),
            Some(v) => {
                return Err(self.err("group", i, line, format!("name = {v}: a group name string")));
            }
            None => None,
        };
        // The other keys first: a misspelled `name` is reported as the unknown key it is.
        let hydro = self.typed("group", i, line, "", split_keys(&mut t, LINE_HYDRO_KEYS))?;
        let section = self.typed("group", i, line, "", t)?;
        let name = name.ok_or_else(|| {
            self.err(
                "group",
                i,
                line,
                "name is missing: the element group to set (e.g. \"ropes\")",
            )
        })?;
        Ok(GroupSpec {
            name,
            section,
            hydro,
        })
    }

    /// A `[[fix]]` with its DOFs checked.
    fn fix(&self, i: usize, line: usize, t: Table) -> Result<FixSpec> {
        let value: FixSpec = self.typed("fix", i, line, "", t)?;
        if let Some(d) = value
            .dofs
            .iter()
            .find(|d| !matches!(d.as_str(), "x" | "y" | "z"))
        {
            return Err(self.err(
                "fix",
                i,
                line,
                format!("dofs contains \"{d}\": valid are \"x\", \"y\", \"z\""),
            ));
        }
        Ok(value)
    }

    /// Splits the hydrodynamic `net.*` keys off an object table.
    fn net_hydro(
        &self,
        section: &str,
        index: usize,
        line: usize,
        table: &mut Table,
    ) -> Result<NetHydro> {
        let hydro = match table.get_mut("net") {
            Some(Value::Table(net)) => split_keys(net, NET_HYDRO_KEYS),
            Some(other) => {
                return Err(self.err(
                    section,
                    index,
                    line,
                    format!("net = {other}: net must be a table of net.* keys"),
                ));
            }
            None => Table::new(),
        };
        self.typed(section, index, line, "net", hydro)
    }
}

/// Reads and type-checks a scene file.
pub fn read_scene(path: &Path) -> Result<Scene> {
    parse_scene(&read_text(path)?, path)
}

/// Type-checks the text of a scene; `path` names it in messages, gives the default scene
/// name and the folder that relative gmsh files are found in.
pub fn parse_scene(text: &str, path: &Path) -> Result<Scene> {
    parse_scene_with(text, path, &[])
}

/// Reads and type-checks a scene file changed by `overrides` (crate::overrides).
pub fn read_scene_with(path: &Path, overrides: &[Override]) -> Result<Scene> {
    parse_scene_with(&read_text(path)?, path, overrides)
}

/// [`parse_scene`] of the text changed by `overrides`, applied in order. The file itself must
/// be valid; each change is then checked exactly like the file, and the first one that makes
/// the scene invalid is named in the error. Messages keep the file's line numbers.
pub fn parse_scene_with(text: &str, path: &Path, overrides: &[Override]) -> Result<Scene> {
    let raw: RawScene = toml::from_str(text)
        .map_err(|e| sweep_file_error(path, text).unwrap_or_else(|| file_error(path, e)))?;
    let ctx = Ctx { path, text };
    if overrides.is_empty() {
        return ctx.scene(raw, Vec::new());
    }
    // The file must stand on its own first, so that its own mistakes are reported as such.
    ctx.scene(raw, Vec::new())?;
    let mut table: Table = toml::from_str(text).map_err(|e| file_error(path, e))?;
    let mut scene = None;
    for (k, o) in overrides.iter().enumerate() {
        let named = |msg: String| SimError::input(format!("{}: --set {o}: {msg}", path.display()));
        o.apply(&mut table).map_err(named)?;
        let edited = toml::to_string(&table).map_err(|e| named(e.to_string()))?;
        let raw: RawScene = toml::from_str(&edited).map_err(|e| named(e.to_string()))?;
        // Keep the file's spans so that messages and diagnostics give its line numbers.
        let base: RawScene = toml::from_str(text).map_err(|e| file_error(path, e))?;
        let raw = raw.with_spans_of(base);
        let done = overrides[..=k].iter().map(|o| o.to_string()).collect();
        let prefix = format!("{}: ", path.display());
        scene = Some(ctx.scene(raw, done).map_err(|e| {
            let msg = e.to_string();
            named(msg.strip_prefix(&prefix).unwrap_or(&msg).to_string())
        })?);
    }
    Ok(scene.expect("at least one override"))
}

fn file_error(path: &Path, e: toml::de::Error) -> SimError {
    SimError::input(format!("{}: {e}", path.display()))
}

/// A sweep file (it names the `scene` it varies) given where a scene is expected: say so.
fn sweep_file_error(path: &Path, text: &str) -> Option<SimError> {
    let table: Table = toml::from_str(text).ok()?;
    table.get("scene")?.as_str()?;
    Some(SimError::input(format!(
        "{}: this is a sweep file (it names the `scene` it varies), not a scene; run its cases \
         with `aqua sweep {}`",
        path.display(),
        path.display()
    )))
}

impl RawScene {
    /// The same tables with the spans of `base` (the unchanged file; overrides never add or
    /// remove array entries).
    fn with_spans_of(mut self, base: RawScene) -> RawScene {
        fn respan(list: &mut [Spanned<Table>], base: Vec<Spanned<Table>>) {
            for (t, b) in list.iter_mut().zip(base) {
                *t = Spanned::new(b.span(), std::mem::take(t.get_mut()));
            }
        }
        respan(&mut self.cage, base.cage);
        respan(&mut self.panel, base.panel);
        respan(&mut self.line, base.line);
        respan(&mut self.mesh, base.mesh);
        respan(&mut self.farm, base.farm);
        respan(&mut self.group, base.group);
        respan(&mut self.point, base.point);
        respan(&mut self.buoy, base.buoy);
        respan(&mut self.fix, base.fix);
        respan(&mut self.prescribed, base.prescribed);
        self
    }
}

impl Ctx<'_> {
    /// The typed scene of a raw file.
    fn scene(&self, raw: RawScene, overrides: Vec<String>) -> Result<Scene> {
        let (ctx, path) = (self, self.path);
        let name = raw.name.clone().unwrap_or_else(|| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scene".into())
        });
        if name.is_empty() || name.contains(['/', '\\']) {
            return Err(SimError::input(format!(
                "{}: name = \"{name}\": a non-empty scene name without path separators",
                path.display()
            )));
        }
        Ok(Scene {
            name,
            path: path.to_path_buf(),
            sea: raw.sea,
            cage: ctx.each(&raw.cage, |i, line, mut t| {
                let net_hydro = ctx.net_hydro("cage", i, line, &mut t)?;
                let params = ctx.typed("cage", i, line, "", t)?;
                Ok(CageSpec { params, net_hydro })
            })?,
            panel: ctx.each(&raw.panel, |i, line, mut t| {
                let net_hydro = ctx.net_hydro("panel", i, line, &mut t)?;
                let params = ctx.typed("panel", i, line, "", t)?;
                Ok(PanelSpec { params, net_hydro })
            })?,
            line: ctx.each(&raw.line, |i, line, mut t| {
                let hydro = ctx.typed("line", i, line, "", split_keys(&mut t, LINE_HYDRO_KEYS))?;
                let params = ctx.typed("line", i, line, "", t)?;
                Ok(LineSpec { params, hydro })
            })?,
            mesh: ctx.each(&raw.mesh, |i, line, t| ctx.gmsh(i, line, t))?,
            farm: ctx.each(&raw.farm, |i, line, t| ctx.farm(i, line, t))?,
            wake: raw.wake,
            group: ctx.each(&raw.group, |i, line, t| ctx.group(i, line, t))?,
            point: ctx.each(&raw.point, |i, line, t| ctx.typed("point", i, line, "", t))?,
            buoy: ctx.each(&raw.buoy, |i, line, t| {
                let spec: BuoySpec = ctx.typed("buoy", i, line, "", t)?;
                spec.resolve().map_err(|m| ctx.err("buoy", i, line, m))?;
                Ok(spec)
            })?,
            fix: ctx.each(&raw.fix, |i, line, t| ctx.fix(i, line, t))?,
            prescribed: ctx.each(&raw.prescribed, |i, line, t| {
                ctx.typed("prescribed", i, line, "", t)
            })?,
            analysis: raw.analysis,
            overrides,
        })
    }
}

/// The probe key of [`scene_keys`]: no schema type has it.
const PROBE: &str = "__aqua_probe__";

/// The field names a parse error of an unknown `PROBE` key lists (serde's "expected one of").
fn probed_fields(msg: &str) -> Option<Vec<String>> {
    let at = msg.find(&format!("unknown field `{PROBE}`"))?;
    let rest = &msg[at..];
    let rest = rest.lines().next().unwrap_or(rest);
    if rest.contains("there are no fields") {
        return Some(Vec::new());
    }
    let list = &rest[rest.find("expected")?..];
    Some(
        list.split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect(),
    )
}

/// The fields of a schema type, from its own unknown-field message.
fn fields_of<T: DeserializeOwned>() -> Vec<String> {
    let mut t = Table::new();
    t.insert(PROBE.into(), Value::Integer(1));
    match Value::Table(t).try_into::<T>() {
        Ok(_) => Vec::new(),
        Err(e) => probed_fields(&e.to_string()).unwrap_or_default(),
    }
}

/// Parses a probe scene whose table at `path` holds `leaf`; the error text, if any.
fn probe_scene(path: &[String], leaf: Value) -> Option<String> {
    // Array sections are entered as an array of one table; `<name>` stands for a map key.
    let mut value = leaf;
    for seg in path.iter().rev() {
        let mut t = Table::new();
        match seg.strip_suffix("[]") {
            Some(key) => t.insert(key.to_string(), Value::Array(vec![value])),
            None => t.insert(seg.clone(), value),
        };
        value = Value::Table(t);
    }
    let text = toml::to_string(&value).ok()?;
    parse_scene(&text, Path::new("probe.toml"))
        .err()
        .map(|e| e.to_string())
}

/// Every key a scene file accepts, as dotted paths (`sea.current.velocity`,
/// `cage.net.solidity`, `cage.groups.<name>.diameter`), derived from the schema types
/// themselves: each table is given an unknown key and the parser's own "expected one of"
/// list is read back, recursing into every key that is a table, an array of tables or a map of
/// tables. The `net.*` and Morison keys that [`parse_scene`] splits off before the mesh types
/// see them come from their own types ([`NetHydro`], [`LineHydro`]), as do `[[group]]`'s
/// section keys ([`SectionOverride`]).
pub fn scene_keys() -> Vec<String> {
    fn walk(path: &mut Vec<String>, out: &mut Vec<String>) {
        let probe = || {
            let mut t = Table::new();
            t.insert(PROBE.into(), Value::Integer(1));
            Value::Table(t)
        };
        let fields = match probe_scene(path, probe())
            .as_deref()
            .and_then(probed_fields)
        {
            Some(f) => f,
            None => return,
        };
        for f in fields {
            let shown = |p: &[String], f: &str| {
                let mut v: Vec<String> = p.iter().map(|s| s.replace("[]", "")).collect();
                v.push(f.to_string());
                v.join(".")
            };
            let before = out.len();
            // A table?
            path.push(f.clone());
            if probe_scene(path, probe())
                .as_deref()
                .and_then(probed_fields)
                .is_some()
            {
                walk(path, out);
            }
            path.pop();
            // An array of tables?
            if out.len() == before {
                path.push(format!("{f}[]"));
                let hit = probe_scene(&path[..path.len() - 1], {
                    let mut t = Table::new();
                    t.insert(f.clone(), Value::Array(vec![probe()]));
                    Value::Table(t)
                })
                .as_deref()
                .and_then(probed_fields)
                .is_some();
                if hit {
                    walk(path, out);
                }
                path.pop();
            }
            // A map of tables?
            if out.len() == before {
                path.push(f.clone());
                path.push("<name>".into());
                if probe_scene(path, probe())
                    .as_deref()
                    .and_then(probed_fields)
                    .is_some()
                {
                    walk(path, out);
                }
                path.pop();
                path.pop();
            }
            if out.len() == before {
                out.push(shown(path, &f));
            }
        }
    }
    let mut out = Vec::new();
    walk(&mut Vec::new(), &mut out);
    // `[farm.cage]` and `[[farm.slot]]` are typed apart from the farm's own keys, as a
    // `[[cage]]` (a slot with its own row, column and empty).
    let cage_keys: Vec<String> = out
        .iter()
        .filter_map(|k| k.strip_prefix("cage."))
        .flat_map(|k| [format!("farm.cage.{k}"), format!("farm.slot.{k}")])
        .collect();
    out.extend(cage_keys);
    out.extend(
        fields_of::<slots::SlotKeys>()
            .into_iter()
            .map(|k| format!("farm.slot.{k}")),
    );
    // Keys split off before the mesh types see them.
    for section in ["cage", "panel", "mesh", "farm.cage", "farm.slot"] {
        out.extend(
            fields_of::<NetHydro>()
                .into_iter()
                .map(|k| format!("{section}.net.{k}")),
        );
    }
    for section in ["line", "group"] {
        out.extend(
            fields_of::<LineHydro>()
                .into_iter()
                .map(|k| format!("{section}.{k}")),
        );
    }
    // `[[group]]` takes its `name` out before its section keys are typed.
    out.retain(|k| k != "group");
    out.push("group.name".into());
    out.extend(
        fields_of::<SectionOverride>()
            .into_iter()
            .map(|k| format!("group.{k}")),
    );
    out.sort();
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("aqua-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn cage_net_keys_are_split_between_mesh_and_hydro() {
        let p = write(
            "a.toml",
            "[sea]\ndepth = 60\n\n[[cage]]\ntype = \"SSM\"\nnet.solidity = 0.2\nnet.screen_model = \"S2\"\n\
             net.wake = { model = \"cheng\" }\n",
        );
        let s = read_scene(&p).unwrap();
        assert_eq!(s.name, "a");
        assert_eq!(s.cage[0].line, 4);
        assert_eq!(s.cage[0].value.params.net.solidity, Some(0.2));
        assert_eq!(s.cage[0].value.net_hydro.screen_model, ScreenModelId::S2);
    }

    #[test]
    fn errors_name_file_line_section_and_key() {
        let p = write(
            "b.toml",
            "[sea]\ndepth = 60\n\n\n[[cage]]\ntype = \"SSM\"\ncircumferense = 100\n",
        );
        let e = read_scene(&p).unwrap_err().to_string();
        assert!(
            e.contains("b.toml") && e.contains("line 5") && e.contains("[[cage]] #1"),
            "{e}"
        );
        assert!(e.contains("circumferense"), "{e}");
        let p = write(
            "c.toml",
            "[[cage]]\ntype = \"SSM\"\nnet.screen_model = \"S9\"\n",
        );
        let e = read_scene(&p).unwrap_err().to_string();
        assert!(e.contains("S9") && e.contains("S1"), "{e}");
        let p = write("d.toml", "[analysis]\nkind = \"quasi\"\n");
        let e = read_scene(&p).unwrap_err().to_string();
        assert!(
            e.contains("line 2") && e.contains("quasi") && e.contains("static+dynamic"),
            "{e}"
        );
        let p = write(
            "e.toml",
            "[[line]]\nanchor = [0,0,-50]\nlength = 10\nmorison = \"M9\"\n",
        );
        let e = read_scene(&p).unwrap_err().to_string();
        assert!(e.contains("[[line]] #1") && e.contains("M9"), "{e}");
    }
}
