//! The net of an object as the model keeps it: the net model, twine orientation and the
//! mesh-grouping numbers (docs/theory/cages.md#mesh-grouping), filled by the net builder.

use crate::section::{BendingElement, DEFAULT_POISSON_RATIO, Section, TENSION_ONLY};
use serde::{Deserialize, Serialize};

/// How a net is modelled (`net.element`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NetElement {
    /// Numerical twines: tension-only cables along the mesh lines, λ physical twines each
    /// (docs/theory/cages.md#mesh-grouping).
    #[default]
    Cable,
    /// Priour's net triangles: each triangle carries the twines its mesh-coordinate area holds
    /// (docs/theory/fem.md#net-triangle).
    Triangle,
}

impl std::fmt::Display for NetElement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NetElement::Cable => "cable",
            NetElement::Triangle => "triangle",
        })
    }
}

/// How the twines lie on the surface (`net.orientation`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MeshOrientation {
    /// Square mesh: U twines along the reference direction, V twines across it.
    #[default]
    Square,
    /// Diamond mesh: the twines at +45° and −45° to the reference direction, meshes open at 90°.
    Diamond,
}

impl std::fmt::Display for MeshOrientation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            MeshOrientation::Square => "square",
            MeshOrientation::Diamond => "diamond",
        })
    }
}

/// The net of one object: inputs and the mesh-grouping numbers
/// (docs/theory/cages.md#mesh-grouping).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NetGrouping {
    /// Physical twine diameter dw0 [m] (screen panels, Reynolds numbers).
    pub twine_diameter: f64,
    /// Half mesh l_p [m].
    pub half_mesh: f64,
    /// Solidity Sn of the screen panels.
    pub solidity: f64,
    /// Mean as-built length of the object's `net_twines` elements [m].
    pub mean_twine_length: f64,
    /// Area of the object's net panels (copy 0) [m²]; 0 when the net has no panels.
    pub net_area: f64,
    /// Grouping ratio λ̄: physical twines per numerical twine, length-weighted mean over the
    /// elements (the given `net.grouping_ratio`, else 2·A/(l_p·ΣL_e) when every twine borders a
    /// panel).
    pub lambda: f64,
    /// Smallest and largest λ_e of the elements.
    pub lambda_range: [f64; 2],
    /// True when λ came from `net.grouping_ratio`.
    pub lambda_given: bool,
    /// Structural diameter dws = √λ·dw0 [m].
    pub structural_diameter: f64,
    /// Elastic diameter dwe = √λ·dw0 [m].
    pub elastic_diameter: f64,
    /// Hydrodynamic diameter dwh = λ·dw0 [m].
    pub hydro_diameter: f64,
    /// Twine Young's modulus [Pa].
    pub youngs_modulus: f64,
    /// Twine density [kg/m³].
    pub density: f64,
    /// Net model (`net.element`).
    pub element: NetElement,
    /// Twine orientation (`net.orientation`).
    pub orientation: MeshOrientation,
}

impl NetGrouping {
    /// The section of the `net_twines` group (cable, tension-only).
    pub fn twine_section(&self) -> Section {
        Section {
            material: "net twine".to_string(),
            diameter: self.structural_diameter,
            wall_thickness: None,
            elastic_diameter: self.elastic_diameter,
            hydro_diameter: self.hydro_diameter,
            volume_diameter: self.structural_diameter,
            youngs_modulus: self.youngs_modulus,
            density: self.density,
            compression_ratio: TENSION_ONLY,
            ea: None,
            mass_per_length: None,
            axial_damping: None,
            axial_damping_ratio: None,
            initial_tension: 0.0,
            seabed: true,
            contact_diameter: None,
            bending: None,
            ei: None,
            bending_element: BendingElement::Rod,
            poisson_ratio: DEFAULT_POISSON_RATIO,
        }
    }
}
