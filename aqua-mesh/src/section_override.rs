//! The section keys of the scene: overrides of a line group's section, validated
//! (docs/theory/fem.md#sections key names).

use crate::section::Section;
use serde::Serialize;

/// Declares a scene table's struct whose fields are the given ones, then the section keys
/// (docs/theory/fem.md#sections key names) — every one, or with `axial` all but the bending
/// keys (`ei`, `bending`, `bending_element`, `poisson_ratio`) — then the given tail fields,
/// and its `section_override()`: the one declaration of the section keys, their types and
/// docs, shared by [`SectionOverride`], `[[line]]` and `[[line.segment]]`. (serde's `flatten`
/// cannot be used: it does not combine with `deny_unknown_fields`.)
macro_rules! section_table {
    (
        $(#[$attr:meta])*
        pub struct $name:ident { $($head:tt)* }
        section: $kind:ident;
        tail { $($tail:tt)* }
    ) => {
        section_table!(@struct [$(#[$attr])*] $name [$($head)*] [$($tail)*] $kind);
        section_table!(@convert $name $kind);
    };
    (@struct [$($attr:tt)*] $name:ident [$($head:tt)*] [$($tail:tt)*] full) => {
        section_table!(@emit [$($attr)*] $name [$($head)*] [$($tail)*] [
            /// `ei`: bending stiffness EI [N·m²] (≥ 0; switches bending on unless
            /// `bending = false`; docs/theory/fem.md#bending-of-sections).
            pub ei: Option<f64>,
            /// `bending`: bending on/off (default: on for pipes and when `ei` is given).
            pub bending: Option<bool>,
            /// `bending_element`: `rod` (default) or `hinge`.
            pub bending_element: Option<$crate::section::BendingElement>,
            /// `poisson_ratio` ν, 0 ≤ ν < 0.5 (default 0.4).
            pub poisson_ratio: Option<f64>,
        ]);
    };
    (@struct [$($attr:tt)*] $name:ident [$($head:tt)*] [$($tail:tt)*] axial) => {
        section_table!(@emit [$($attr)*] $name [$($head)*] [$($tail)*] []);
    };
    (@emit [$($attr:tt)*] $name:ident [$($head:tt)*] [$($tail:tt)*] [$($bend:tt)*]) => {
        $($attr)*
        pub struct $name {
            $($head)*
            /// `diameter` d [m] (also sets the elastic, hydro and volume diameters unless
            /// given; required for a line).
            pub diameter: Option<f64>,
            /// `wall_thickness` of a pipe [m].
            pub wall_thickness: Option<f64>,
            /// `sdr`: standard dimension ratio D/t of a pipe (> 2), instead of
            /// `wall_thickness`.
            pub sdr: Option<f64>,
            /// `ea` [N] (or `youngs_modulus`).
            pub ea: Option<f64>,
            /// `youngs_modulus` E [Pa].
            pub youngs_modulus: Option<f64>,
            /// `density` ρ_s [kg/m³] (or `mass_per_length`).
            pub density: Option<f64>,
            /// `mass_per_length` μ [kg/m].
            pub mass_per_length: Option<f64>,
            /// `hydro_diameter` [m].
            pub hydro_diameter: Option<f64>,
            /// `volume_diameter` [m].
            pub volume_diameter: Option<f64>,
            /// `elastic_diameter` [m].
            pub elastic_diameter: Option<f64>,
            /// `compression_ratio` r_c, 0 ≤ r_c ≤ 1.
            pub compression_ratio: Option<f64>,
            /// `axial_damping` c_a [N·s].
            pub axial_damping: Option<f64>,
            /// `axial_damping_ratio` ζ.
            pub axial_damping_ratio: Option<f64>,
            /// `initial_tension` T0 [N].
            pub initial_tension: Option<f64>,
            /// `seabed` contact on/off.
            pub seabed: Option<bool>,
            /// `contact_diameter` [m].
            pub contact_diameter: Option<f64>,
            /// `material` label.
            pub material: Option<String>,
            $($bend)*
            $($tail)*
        }
    };
    (@convert $name:ident full) => {
        impl $name {
            /// The section keys given in this table.
            pub fn section_override(&self) -> $crate::section_override::SectionOverride {
                section_table!(@fields self [
                    ei: self.ei,
                    bending: self.bending,
                    bending_element: self.bending_element,
                    poisson_ratio: self.poisson_ratio,
                ])
            }
        }
    };
    (@convert $name:ident axial) => {
        impl $name {
            /// The section keys given in this table (no bending keys).
            pub fn section_override(&self) -> $crate::section_override::SectionOverride {
                section_table!(@fields self [
                    ei: None,
                    bending: None,
                    bending_element: None,
                    poisson_ratio: None,
                ])
            }
        }
    };
    (@fields $s:ident [$($bend:tt)*]) => {
        $crate::section_override::SectionOverride {
            diameter: $s.diameter,
            wall_thickness: $s.wall_thickness,
            sdr: $s.sdr,
            ea: $s.ea,
            youngs_modulus: $s.youngs_modulus,
            density: $s.density,
            mass_per_length: $s.mass_per_length,
            hydro_diameter: $s.hydro_diameter,
            volume_diameter: $s.volume_diameter,
            elastic_diameter: $s.elastic_diameter,
            compression_ratio: $s.compression_ratio,
            axial_damping: $s.axial_damping,
            axial_damping_ratio: $s.axial_damping_ratio,
            initial_tension: $s.initial_tension,
            seabed: $s.seabed,
            contact_diameter: $s.contact_diameter,
            material: $s.material.clone(),
            $($bend)*
        }
    };
}
pub(crate) use section_table;

section_table! {
    /// Overrides of a line group's section: a `[cage.groups.<group>]` table or the section keys
    /// of a `[[line]]` table (docs/theory/fem.md#sections key names).
    #[derive(Debug, Clone, Default, PartialEq, serde::Deserialize, Serialize)]
    #[serde(deny_unknown_fields)]
    pub struct SectionOverride {}
    section: full;
    tail {}
}

impl SectionOverride {
    /// Apply to `s`, validating every value; `prefix` is the key path used in messages
    /// (e.g. `groups.ropes`).
    pub fn apply(&self, object: &str, prefix: &str, s: &mut Section) -> crate::Result<()> {
        use crate::MeshError;
        let key = |k: &str| {
            if prefix.is_empty() {
                k.to_string()
            } else {
                format!("{prefix}.{k}")
            }
        };
        let pos = |k: &str, v: Option<f64>| -> crate::Result<Option<f64>> {
            match v {
                Some(x) if !(x.is_finite() && x > 0.0) => Err(MeshError::param(
                    object,
                    &key(k),
                    x,
                    "must be a finite number > 0",
                )),
                _ => Ok(v),
            }
        };
        let nonneg = |k: &str, v: Option<f64>| -> crate::Result<Option<f64>> {
            match v {
                Some(x) if !(x.is_finite() && x >= 0.0) => Err(MeshError::param(
                    object,
                    &key(k),
                    x,
                    "must be a finite number >= 0",
                )),
                _ => Ok(v),
            }
        };
        if let (Some(t), Some(r)) = (self.wall_thickness, self.sdr) {
            return Err(MeshError::inconsistent(
                object,
                format!(
                    "both `{}` = {t} and `{}` = {r} given; give only one (sdr = diameter / \
                     wall_thickness)",
                    key("wall_thickness"),
                    key("sdr")
                ),
            ));
        }
        if let Some(d) = pos("diameter", self.diameter)? {
            // A pipe keeps its dimension ratio: a new diameter alone scales the wall with it
            // (docs/theory/fem.md#sections).
            if let Some(t) = s.wall_thickness {
                s.wall_thickness = Some(t * d / s.diameter);
            }
            s.diameter = d;
            s.elastic_diameter = d;
            s.hydro_diameter = d;
            s.volume_diameter = d;
        }
        if let Some(t) = pos("wall_thickness", self.wall_thickness)? {
            s.wall_thickness = Some(t);
        }
        if let Some(r) = self.sdr {
            if !(r.is_finite() && r > 2.0) {
                return Err(MeshError::param(
                    object,
                    &key("sdr"),
                    r,
                    "must be > 2 (SDR = diameter / wall_thickness; SDR <= 2 is a wall as thick \
                     as the radius); HDPE pipes are typically SDR 11 to 26",
                ));
            }
            s.wall_thickness = Some(s.diameter / r);
        }
        if let Some(v) = pos("ea", self.ea)? {
            s.ea = Some(v);
        }
        if let Some(v) = pos("youngs_modulus", self.youngs_modulus)? {
            s.youngs_modulus = v;
        }
        if let Some(v) = pos("density", self.density)? {
            s.density = v;
        }
        if let Some(v) = pos("mass_per_length", self.mass_per_length)? {
            s.mass_per_length = Some(v);
        }
        if let Some(v) = pos("hydro_diameter", self.hydro_diameter)? {
            s.hydro_diameter = v;
        }
        if let Some(v) = nonneg("volume_diameter", self.volume_diameter)? {
            s.volume_diameter = v;
        }
        if let Some(v) = pos("elastic_diameter", self.elastic_diameter)? {
            s.elastic_diameter = v;
        }
        if let Some(v) = self.compression_ratio {
            if !(0.0..=1.0).contains(&v) {
                return Err(MeshError::param(
                    object,
                    &key("compression_ratio"),
                    v,
                    "must be in [0, 1]",
                ));
            }
            s.compression_ratio = v;
        }
        if let Some(v) = nonneg("axial_damping", self.axial_damping)? {
            s.axial_damping = Some(v);
        }
        if let Some(v) = nonneg("axial_damping_ratio", self.axial_damping_ratio)? {
            s.axial_damping_ratio = Some(v);
        }
        if let Some(v) = nonneg("initial_tension", self.initial_tension)? {
            s.initial_tension = v;
        }
        if let Some(v) = self.seabed {
            s.seabed = v;
        }
        if let Some(v) = pos("contact_diameter", self.contact_diameter)? {
            s.contact_diameter = Some(v);
        }
        if let Some(m) = &self.material {
            s.material = m.clone();
        }
        if let Some(v) = nonneg("ei", self.ei)? {
            if self.bending == Some(false) {
                return Err(MeshError::param(
                    object,
                    &key("ei"),
                    v,
                    "is given together with `bending = false`; give `ei` to bend with that \
                     stiffness, or `bending = false` alone for no bending",
                ));
            }
            s.ei = Some(v);
        }
        if let Some(v) = self.bending {
            s.bending = Some(v);
        }
        if let Some(v) = self.bending_element {
            s.bending_element = v;
        }
        if let Some(v) = self.poisson_ratio {
            if !(0.0..0.5).contains(&v) {
                return Err(MeshError::param(
                    object,
                    &key("poisson_ratio"),
                    v,
                    "must be in [0, 0.5) (HDPE about 0.4, steel 0.3)",
                ));
            }
            s.poisson_ratio = v;
        }
        check_wall(s, object, &key("wall_thickness"), &key("sdr"))
    }
}

/// A pipe's wall must be thinner than its radius, for the mass (`diameter`) and, unless `ea`
/// is given, for the stiffness (`elastic_diameter`); the error names the wall and the fix.
fn check_wall(s: &Section, object: &str, wall_key: &str, sdr_key: &str) -> crate::Result<()> {
    let Some(t) = s.wall_thickness else {
        return Ok(());
    };
    let mut sizes = vec![("diameter", s.diameter)];
    if s.ea.is_none() {
        sizes.push(("elastic_diameter", s.elastic_diameter));
    }
    for (name, d) in sizes {
        if 2.0 * t >= d {
            return Err(crate::MeshError::param(
                object,
                wall_key,
                t,
                format!(
                    "a pipe wall must be thinner than the radius, {name}/2 = {} m: give a \
                     smaller `{wall_key}` [m], or `{sdr_key}` (wall = diameter/sdr, e.g. 17 for \
                     HDPE pipe)",
                    d / 2.0
                ),
            ));
        }
    }
    Ok(())
}
