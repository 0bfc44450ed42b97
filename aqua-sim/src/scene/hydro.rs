//! The hydrodynamic keys a scene adds to aqua-mesh's tables: the `net.*` keys of a net
//! (screen or Morison drag, wake) and the Morison and inertia keys of a cable group.

use aqua_hydro::MorisonModelId;
use aqua_hydro::screen::ScreenModelId;
use aqua_hydro::wake::WakeSpec;
use serde::{Deserialize, Serialize};

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
pub(super) const NET_HYDRO_KEYS: &[&str] = &[
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

pub(super) const LINE_HYDRO_KEYS: &[&str] = &[
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
