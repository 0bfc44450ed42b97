//! Sections and materials of line groups (docs/theory/fem.md#sections): diameters, stiffness,
//! mass and bending properties.

use serde::Serialize;

/// Compression ratio of tension-only members (twines, ropes, chains): a slack member carries
/// no force at all, so slack costs nothing in the answer (docs/theory/fem.md#slack-members).
/// A ratio of 1e-4, the earlier default, let slack twines push and raised the reference
/// cage's drag by 2.5 %.
pub const TENSION_ONLY: f64 = 0.0;

/// Section and material of a line group (keys of docs/theory/fem.md#sections).
///
/// Diameters in m, modulus in Pa, density in kg/m³. For net twines the three diameters come from
/// mesh grouping (docs/theory/cages.md#mesh-grouping): `diameter` = dws, `elastic_diameter` = dwe,
/// `hydro_diameter` = dwh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Section {
    /// Material label (informative), e.g. `nylon`, `rope`, `HDPE pipe`.
    pub material: String,
    /// Structural (outer) diameter d [m]: mass, buoyancy volume, contact width.
    pub diameter: f64,
    /// Pipe wall thickness [m]; `None` for a solid section.
    pub wall_thickness: Option<f64>,
    /// Diameter giving the axial stiffness, EA = E·π/4·d_e² (solid) [m].
    pub elastic_diameter: f64,
    /// Diameter for Morison drag [m].
    pub hydro_diameter: f64,
    /// Diameter of the displaced volume [m] (sealed pipe: outer diameter).
    pub volume_diameter: f64,
    /// Young's modulus E [Pa].
    pub youngs_modulus: f64,
    /// Material density ρ_s [kg/m³].
    pub density: f64,
    /// Compression ratio r_c (docs/theory/fem.md#slack-members): 0 for tension-only cables
    /// (default, [`TENSION_ONLY`]), 1 for bars/pipes.
    pub compression_ratio: f64,
    /// Explicit EA [N] overriding E·A.
    pub ea: Option<f64>,
    /// Explicit mass per length μ [kg/m] overriding ρ_s·A.
    pub mass_per_length: Option<f64>,
    /// Axial damping c_a [N·s] (docs/theory/fem.md#cable-element); `None` = no damping unless a
    /// ratio is given.
    pub axial_damping: Option<f64>,
    /// Axial damping ratio ζ (docs/theory/fem.md#cable-element).
    pub axial_damping_ratio: Option<f64>,
    /// Initial tension T0 [N] (docs/theory/fem.md#cable-element), default 0.
    pub initial_tension: f64,
    /// Seabed contact on/off (default on).
    pub seabed: bool,
    /// Seabed contact width [m]; `None` = `volume_diameter`.
    pub contact_diameter: Option<f64>,
    /// Bending on/off (docs/theory/fem.md#bending-of-sections); `None` = automatic: on for a
    /// pipe (`wall_thickness` set) or when `ei` is given, off for a solid section.
    pub bending: Option<bool>,
    /// Explicit bending stiffness EI [N·m²] overriding E·I.
    pub ei: Option<f64>,
    /// The element that carries the bending (docs/theory/fem.md#bending-of-sections).
    pub bending_element: BendingElement,
    /// Poisson's ratio ν for the shear modulus G = E/(2(1 + ν)) of the torsional stiffness.
    pub poisson_ratio: f64,
}

/// Poisson's ratio of the pipes' polyethylene (HDPE ≈ 0.4–0.46), the default ν of a section.
pub const DEFAULT_POISSON_RATIO: f64 = 0.4;

/// The element that carries a section's bending (docs/theory/fem.md#bending-of-sections).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BendingElement {
    /// Discrete elastic rod: bending about both axes in a material frame, and torsion
    /// (docs/theory/fem.md#rod). The default.
    #[default]
    Rod,
    /// Rotation-free hinge on three nodes: bending magnitude only, no torsion
    /// (docs/theory/fem.md#bending); cheaper, safe for members built straight.
    Hinge,
}

impl BendingElement {
    /// The key value.
    pub fn as_str(self) -> &'static str {
        match self {
            BendingElement::Rod => "rod",
            BendingElement::Hinge => "hinge",
        }
    }
}

impl Section {
    /// Tension-only cable section of solid diameter `d` [m].
    pub fn cable(material: &str, d: f64, youngs_modulus: f64, density: f64) -> Self {
        Section {
            material: material.to_string(),
            diameter: d,
            wall_thickness: None,
            elastic_diameter: d,
            hydro_diameter: d,
            volume_diameter: d,
            youngs_modulus,
            density,
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

    /// Sealed pipe (bar carrying compression) of outer diameter `d` and wall `t` [m].
    pub fn pipe(material: &str, d: f64, t: f64, youngs_modulus: f64, density: f64) -> Self {
        Section {
            material: material.to_string(),
            diameter: d,
            wall_thickness: Some(t),
            elastic_diameter: d,
            hydro_diameter: d,
            volume_diameter: d,
            youngs_modulus,
            density,
            compression_ratio: 1.0,
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

    /// Material cross-section area for the stiffness [m²]: π/4·d_e² for a solid section,
    /// π/4·(D² − (D − 2t)²) for a pipe.
    pub fn stiffness_area(&self) -> f64 {
        let d = self.elastic_diameter;
        match self.wall_thickness {
            Some(t) => std::f64::consts::FRAC_PI_4 * (d * d - (d - 2.0 * t).powi(2)),
            None => std::f64::consts::FRAC_PI_4 * d * d,
        }
    }

    /// Material cross-section area for the mass [m²] (uses `diameter`).
    pub fn mass_area(&self) -> f64 {
        let d = self.diameter;
        match self.wall_thickness {
            Some(t) => std::f64::consts::FRAC_PI_4 * (d * d - (d - 2.0 * t).powi(2)),
            None => std::f64::consts::FRAC_PI_4 * d * d,
        }
    }

    /// Axial stiffness EA [N].
    pub fn axial_stiffness(&self) -> f64 {
        self.ea
            .unwrap_or(self.youngs_modulus * self.stiffness_area())
    }

    /// Mass per unit length μ [kg/m].
    pub fn linear_mass(&self) -> f64 {
        self.mass_per_length
            .unwrap_or(self.density * self.mass_area())
    }

    /// Second moment of area of the stiffness section [m⁴]: π/64·d_e⁴ (solid) or
    /// π/64·(D⁴ − (D − 2t)⁴) (pipe), with d_e = `elastic_diameter`.
    pub fn second_moment(&self) -> f64 {
        let d = self.elastic_diameter;
        let c = std::f64::consts::PI / 64.0;
        match self.wall_thickness {
            Some(t) => c * (d.powi(4) - (d - 2.0 * t).max(0.0).powi(4)),
            None => c * d.powi(4),
        }
    }

    /// True if the group bends: `bending` if set, otherwise on for pipes and when `ei` is
    /// given (docs/theory/fem.md#bending-of-sections).
    pub fn bends(&self) -> bool {
        self.bending
            .unwrap_or(self.wall_thickness.is_some() || self.ei.is_some())
    }

    /// Bending stiffness EI [N·m²]: 0 if the section does not bend, else `ei` or E·I.
    pub fn bending_stiffness(&self) -> f64 {
        if !self.bends() {
            return 0.0;
        }
        self.ei
            .unwrap_or(self.youngs_modulus * self.second_moment())
    }

    /// Torsional stiffness GJ [N·m²] of a round section, J = 2I: GJ = EI/(1 + ν), with the
    /// bending stiffness as given (`ei` or E·I).
    pub fn torsional_stiffness(&self) -> f64 {
        self.bending_stiffness() / (1.0 + self.poisson_ratio)
    }

    /// Spin inertia per unit length μ·r_g² [kg·m], r_g² = (D² + d_i²)/8 for a pipe of inner
    /// diameter d_i = D − 2t, D²/8 for a solid section.
    pub fn spin_inertia(&self) -> f64 {
        let d = self.diameter;
        let di = self.wall_thickness.map_or(0.0, |t| (d - 2.0 * t).max(0.0));
        self.linear_mass() * (d * d + di * di) / 8.0
    }

    /// Largest fibre stress |N|/A + |M|·(d_e/2)/I [Pa] of the stiffness section under axial
    /// force N [N] and bending moment M [N·m] (docs/theory/fem.md#rod).
    pub fn fibre_stress(&self, axial: f64, moment: f64) -> f64 {
        let i = self.second_moment();
        let bend = if i > 0.0 {
            moment.abs() * 0.5 * self.elastic_diameter / i
        } else {
            0.0
        };
        axial.abs() / self.stiffness_area() + bend
    }
}
