//! The list of every key a scene file accepts, written out once per schema table: the
//! [`Keys`] of each type, composed into the scene's tree by [`scene_keys`] (which the guide's
//! test, `tests/guide.rs`, checks docs/guide/scene.md against). A unit test checks every list
//! against what the parser itself accepts.

use super::analysis::{AnalysisSpec, DynamicSpec};
use super::hydro::{LINE_HYDRO_KEYS, LineHydro, NET_HYDRO_KEYS, NetHydro};
use super::schema::{
    CageSpec, FarmSpec, FixSpec, GroupSpec, LineSpec, MeshSpec, PanelSpec, PointSpec,
    PrescribedSpec, Scene, SceneWake,
};
use super::sea::SeaSection;
use super::slots::SLOT_KEYS;
use crate::body::BodySpec;
use crate::buoy::{BuoySpec, FARM_BUOY_KEYS};
use aqua_env::SeaSpec;
use aqua_env::config::{CurrentSpec, SpectrumSpec, WaterSpec, WavesSpec};
use aqua_fem::{SeabedSettings, StaticSettings};
use aqua_mesh::{
    CageParams, CollarParams, FarmParams, GmshParams, LineParams, LineSegment, NetParams,
    PanelParams, SectionOverride,
};

/// One key of a scene table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Key {
    /// A value (number, string, array of numbers, inline table read as one value).
    Value(&'static str),
    /// A table `[name]` with its keys.
    Table(&'static str, Vec<Key>),
    /// A table of named tables, `[name.<name>]`, each with these keys.
    Map(&'static str, Vec<Key>),
    /// An array of tables, `[[name]]`, each with these keys.
    Array(&'static str, Vec<Key>),
}

impl Key {
    /// The key's name in its table.
    pub fn name(&self) -> &'static str {
        match self {
            Key::Value(n) | Key::Table(n, _) | Key::Map(n, _) | Key::Array(n, _) => n,
        }
    }
}

/// The keys of one schema table.
pub trait Keys {
    /// Every key the table accepts, sub-tables with their own keys.
    fn keys() -> Vec<Key>;
}

fn values(names: &[&'static str]) -> Vec<Key> {
    names.iter().map(|n| Key::Value(n)).collect()
}

fn with(mut keys: Vec<Key>, more: Vec<Key>) -> Vec<Key> {
    keys.extend(more);
    keys
}

/// `keys` with the hydrodynamic `net.*` keys the scene splits off before aqua-mesh sees them.
fn with_net_hydro(mut keys: Vec<Key>) -> Vec<Key> {
    for k in &mut keys {
        if let Key::Table("net", net) = k {
            net.extend(NetHydro::keys());
        }
    }
    keys
}

impl Keys for SeaSpec {
    fn keys() -> Vec<Key> {
        with(
            values(&["gravity", "depth"]),
            vec![
                Key::Table("water", WaterSpec::keys()),
                Key::Table("current", CurrentSpec::keys()),
                Key::Table("waves", WavesSpec::keys()),
            ],
        )
    }
}

/// `[sea]`: the sea's keys and `[sea.seabed]` (crate::scene::sea).
impl Keys for SeaSection {
    fn keys() -> Vec<Key> {
        with(
            SeaSpec::keys(),
            vec![Key::Table("seabed", SeabedSettings::keys())],
        )
    }
}

impl Keys for WaterSpec {
    fn keys() -> Vec<Key> {
        values(&["density", "kinematic_viscosity"])
    }
}

impl Keys for CurrentSpec {
    fn keys() -> Vec<Key> {
        values(&[
            "kind",
            "velocity",
            "points",
            "surface_velocity",
            "exponent",
            "schedule",
            "in_static",
            "ramp_time",
        ])
    }
}

impl Keys for WavesSpec {
    fn keys() -> Vec<Key> {
        with(
            values(&[
                "kind",
                "height",
                "period",
                "direction",
                "phase",
                "stretching",
                "ramp_time",
                "components",
            ]),
            vec![Key::Table("spectrum", SpectrumSpec::keys())],
        )
    }
}

impl Keys for SpectrumSpec {
    fn keys() -> Vec<Key> {
        values(&[
            "shape",
            "hs",
            "tp",
            "gamma",
            "mean_direction",
            "spreading_s",
            "components",
            "spacing",
            "seed",
            "energy_cutoff",
            "normalise",
            "table",
        ])
    }
}

impl Keys for SeabedSettings {
    fn keys() -> Vec<Key> {
        values(&[
            "kbot",
            "cbot",
            "damping_depth",
            "friction_axial",
            "friction_transverse",
            "slip_velocity",
        ])
    }
}

impl Keys for SectionOverride {
    fn keys() -> Vec<Key> {
        values(&[
            "diameter",
            "wall_thickness",
            "sdr",
            "ea",
            "youngs_modulus",
            "density",
            "mass_per_length",
            "hydro_diameter",
            "volume_diameter",
            "elastic_diameter",
            "compression_ratio",
            "axial_damping",
            "axial_damping_ratio",
            "initial_tension",
            "seabed",
            "contact_diameter",
            "material",
            "ei",
            "bending",
            "bending_element",
            "poisson_ratio",
        ])
    }
}

impl Keys for NetParams {
    fn keys() -> Vec<Key> {
        values(&[
            "density",
            "element",
            "grouping_ratio",
            "half_mesh",
            "orientation",
            "solidity",
            "twine_diameter",
            "twine_direction",
            "youngs_modulus",
        ])
    }
}

impl Keys for CollarParams {
    fn keys() -> Vec<Key> {
        values(&[
            "pipes",
            "pipe_diameter",
            "pipe_spacing",
            "bracket_spacing",
            "wall_thickness",
            "sdr",
            "density",
            "youngs_modulus",
        ])
    }
}

impl Keys for CageParams {
    fn keys() -> Vec<Key> {
        with(
            values(&[
                "type",
                "name",
                "origins",
                "circumference",
                "diameter",
                "side",
                "bottom_ratio",
                "depth",
                "cone_depth",
                "element_length",
                "frame_offset",
                "rope_depth",
                "tube_depth",
                "weight_depth",
                "sinker_weight_per_metre",
                "centre_weight",
                "tip_weight",
                "ropes",
                "fixed",
            ]),
            vec![
                Key::Table("net", NetParams::keys()),
                Key::Table("collar", CollarParams::keys()),
                Key::Map("groups", SectionOverride::keys()),
            ],
        )
    }
}

impl Keys for PanelParams {
    fn keys() -> Vec<Key> {
        with(
            values(&[
                "name",
                "width",
                "height",
                "divisions",
                "element_length",
                "centre",
                "normal",
                "up",
                "fixed",
                "bottom_weight",
            ]),
            vec![
                Key::Table("net", NetParams::keys()),
                Key::Map("groups", SectionOverride::keys()),
            ],
        )
    }
}

impl Keys for LineSegment {
    fn keys() -> Vec<Key> {
        let section = SectionOverride::keys().into_iter().filter(|k| {
            // a segment is straight and has no bending of its own
            !matches!(
                k.name(),
                "ei" | "bending" | "bending_element" | "poisson_ratio"
            )
        });
        with(
            values(&["name", "length", "elements", "element_length"]),
            section.collect(),
        )
    }
}

impl Keys for LineParams {
    fn keys() -> Vec<Key> {
        with(
            with(
                values(&[
                    "name",
                    "anchor",
                    "fairlead",
                    "length",
                    "segments",
                    "element_length",
                    "group",
                    "shape",
                    "fixed",
                ]),
                SectionOverride::keys(),
            ),
            vec![Key::Array("segment", LineSegment::keys())],
        )
    }
}

impl Keys for GmshParams {
    fn keys() -> Vec<Key> {
        with(
            values(&[
                "file",
                "name",
                "origins",
                "rename",
                "rotate_deg",
                "scale",
                "translate",
            ]),
            vec![
                Key::Table("net", NetParams::keys()),
                Key::Map("groups", SectionOverride::keys()),
            ],
        )
    }
}

impl Keys for FarmParams {
    fn keys() -> Vec<Key> {
        with(
            values(&[
                "name",
                "rows",
                "columns",
                "spacing",
                "grid_depth",
                "origin",
                "element_length",
                "anchor_length",
                "anchor_segments",
                "anchor_distance",
                "chain_length",
                "cage_wake",
            ]),
            vec![
                Key::Table("frame", SectionOverride::keys()),
                Key::Table("bridle", SectionOverride::keys()),
                Key::Table("anchor", SectionOverride::keys()),
                Key::Table("chain", SectionOverride::keys()),
            ],
        )
    }
}

impl Keys for NetHydro {
    fn keys() -> Vec<Key> {
        values(NET_HYDRO_KEYS)
    }
}

impl Keys for LineHydro {
    fn keys() -> Vec<Key> {
        values(LINE_HYDRO_KEYS)
    }
}

impl Keys for CageSpec {
    fn keys() -> Vec<Key> {
        with_net_hydro(CageParams::keys())
    }
}

impl Keys for PanelSpec {
    fn keys() -> Vec<Key> {
        with_net_hydro(PanelParams::keys())
    }
}

impl Keys for MeshSpec {
    fn keys() -> Vec<Key> {
        with_net_hydro(GmshParams::keys())
    }
}

impl Keys for LineSpec {
    fn keys() -> Vec<Key> {
        with(LineParams::keys(), LineHydro::keys())
    }
}

impl Keys for FarmSpec {
    /// The grid keys, `[farm.cage]` as a `[[cage]]`, `[farm.buoy]` as a `[[buoy]]` of
    /// [`FARM_BUOY_KEYS`], and `[[farm.slot]]` as a `[[cage]]` with its cell
    /// (crate::scene::slots).
    fn keys() -> Vec<Key> {
        with(
            FarmParams::keys(),
            vec![
                Key::Table("cage", CageSpec::keys()),
                Key::Table("buoy", values(FARM_BUOY_KEYS)),
                Key::Array("slot", with(CageSpec::keys(), values(SLOT_KEYS))),
            ],
        )
    }
}

impl Keys for GroupSpec {
    fn keys() -> Vec<Key> {
        with(
            with(values(&["name"]), LineHydro::keys()),
            SectionOverride::keys(),
        )
    }
}

impl Keys for PointSpec {
    fn keys() -> Vec<Key> {
        values(&[
            "nodes",
            "mass",
            "volume",
            "height",
            "added_mass_coefficient",
            "force",
            "drag_area",
            "seabed_stiffness",
        ])
    }
}

impl Keys for BuoySpec {
    fn keys() -> Vec<Key> {
        values(&[
            "name",
            "position",
            "node",
            "shape",
            "diameter",
            "height",
            "volume",
            "mass",
            "drag_coefficient",
            "drag_area",
            "added_mass_coefficient",
            "seabed_stiffness",
            "submerged",
        ])
    }
}

impl Keys for BodySpec {
    fn keys() -> Vec<Key> {
        with(
            values(&["name", "centre", "mass", "inertia"]),
            vec![
                Key::Table(
                    "hull",
                    values(&[
                        "length",
                        "width",
                        "height",
                        "centre",
                        "columns",
                        "layers",
                        "drag_coefficient",
                        "added_mass_coefficient",
                    ]),
                ),
                Key::Array("point", values(&["name", "position"])),
            ],
        )
    }
}

impl Keys for FixSpec {
    fn keys() -> Vec<Key> {
        values(&["nodes", "dofs", "clamp"])
    }
}

impl Keys for PrescribedSpec {
    fn keys() -> Vec<Key> {
        values(&[
            "nodes",
            "motion",
            "offset",
            "amplitude",
            "mean",
            "period",
            "phase",
            "ramp_time",
            "table",
        ])
    }
}

impl Keys for SceneWake {
    fn keys() -> Vec<Key> {
        values(&["cage_to_cage"])
    }
}

impl Keys for StaticSettings {
    /// The fields of aqua-fem's settings that are scene keys (`[analysis.static]`).
    fn keys() -> Vec<Key> {
        values(&[
            "tol",
            "max_iter",
            "load_steps",
            "min_load_step",
            "stabilisation",
            "line_search",
            "watchdog",
            "stretch_damping",
            "mesh_sequence",
        ])
    }
}

impl Keys for DynamicSpec {
    fn keys() -> Vec<Key> {
        values(&[
            "scheme",
            "alpha",
            "rho_inf",
            "theta",
            "dt",
            "t_end",
            "dt_min",
            "dt_fixed",
            "tol",
            "max_iter",
            "mass_matrix",
            "rayleigh",
            "cfl",
            "output_interval",
            "paraview_interval",
            "max_strain",
            "reuse_factor",
            "linear_solver",
            "line_relaxation",
            "extreme_tolerance",
        ])
    }
}

impl Keys for AnalysisSpec {
    fn keys() -> Vec<Key> {
        vec![
            Key::Value("kind"),
            Key::Table("static", StaticSettings::keys()),
            Key::Table("dynamic", DynamicSpec::keys()),
        ]
    }
}

impl Keys for Scene {
    fn keys() -> Vec<Key> {
        vec![
            Key::Value("name"),
            Key::Table("sea", SeaSection::keys()),
            Key::Array("cage", CageSpec::keys()),
            Key::Array("panel", PanelSpec::keys()),
            Key::Array("line", LineSpec::keys()),
            Key::Array("mesh", MeshSpec::keys()),
            Key::Array("farm", FarmSpec::keys()),
            Key::Table("wake", SceneWake::keys()),
            Key::Array("group", GroupSpec::keys()),
            Key::Array("point", PointSpec::keys()),
            Key::Array("buoy", BuoySpec::keys()),
            Key::Array("body", BodySpec::keys()),
            Key::Array("fix", FixSpec::keys()),
            Key::Array("prescribed", PrescribedSpec::keys()),
            Key::Table("analysis", AnalysisSpec::keys()),
        ]
    }
}

/// Every key a scene file accepts, as sorted dotted paths (`sea.current.velocity`,
/// `cage.net.solidity`, `cage.groups.<name>.diameter`): the [`Keys`] of [`Scene`], flattened.
pub fn scene_keys() -> Vec<String> {
    fn flatten(prefix: &str, keys: &[Key], out: &mut Vec<String>) {
        for k in keys {
            let path = if prefix.is_empty() {
                k.name().to_string()
            } else {
                format!("{prefix}.{}", k.name())
            };
            match k {
                Key::Value(_) => out.push(path),
                Key::Table(_, sub) | Key::Array(_, sub) => flatten(&path, sub, out),
                Key::Map(_, sub) => flatten(&format!("{path}.<name>"), sub, out),
            }
        }
    }
    let mut out = Vec::new();
    flatten("", &Scene::keys(), &mut out);
    out.sort();
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneInput, read_scene};
    use serde::de::DeserializeOwned;
    use std::path::Path;
    use toml::{Table, Value};

    /// The probe key: no schema type has it.
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
        read_scene(
            SceneInput::Text {
                text: &text,
                path: Path::new("probe.toml"),
            },
            &[],
        )
        .err()
        .map(|e| e.to_string())
    }

    /// Every key a scene file accepts, as dotted paths (`sea.current.velocity`,
    /// `cage.net.solidity`, `cage.groups.<name>.diameter`), derived from the schema types
    /// themselves: each table is given an unknown key and the parser's own "expected one of"
    /// list is read back, recursing into every key that is a table, an array of tables or a map of
    /// tables. The `net.*` and Morison keys that [`read_scene`] splits off before the mesh types
    /// see them come from their own types ([`NetHydro`], [`LineHydro`]), as do `[[group]]`'s
    /// section keys ([`SectionOverride`]).
    fn probed_scene_keys() -> Vec<String> {
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
            fields_of::<super::super::slots::SlotKeys>()
                .into_iter()
                .map(|k| format!("farm.slot.{k}")),
        );
        // `[farm.buoy]` is typed apart from the farm's own keys, as a `[[buoy]]` of fewer keys:
        // its message in a farm that is otherwise whole.
        let farm = format!(
            "[[farm]]\nrows = 1\ncolumns = 1\nspacing = 40\ngrid_depth = 5\n\
             anchor_length = 100\n[farm.cage]\ntype = \"CSM\"\n[farm.buoy]\n{PROBE} = 1\n"
        );
        let text = Value::Table(toml::from_str(&farm).expect("probe farm"));
        let e = probe_scene(&[], text).expect("an unknown [farm.buoy] key is refused");
        out.extend(
            probed_fields(&e)
                .expect("[farm.buoy] lists its keys")
                .into_iter()
                .map(|k| format!("farm.buoy.{k}")),
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

    /// The explicit lists are exactly what the parser accepts: the whole tree, derived from the
    /// parser's own "expected one of" messages (each table given an unknown key).
    #[test]
    fn the_key_lists_are_the_keys_the_parser_accepts() {
        let listed = scene_keys();
        let probed = probed_scene_keys();
        let missing: Vec<_> = probed.iter().filter(|k| !listed.contains(k)).collect();
        let extra: Vec<_> = listed.iter().filter(|k| !probed.contains(k)).collect();
        assert!(
            missing.is_empty() && extra.is_empty(),
            "accepted but not listed: {missing:?}; listed but not accepted: {extra:?}"
        );
        assert!(listed.len() > 500, "{}", listed.len());
    }

    /// Each table's list has no key twice and holds the fields of its schema type.
    #[test]
    fn each_list_names_its_type_s_fields() {
        fn names<T: Keys>() -> Vec<String> {
            let mut v: Vec<String> = T::keys().iter().map(|k| k.name().to_string()).collect();
            let n = v.len();
            v.sort();
            v.dedup();
            assert_eq!(
                v.len(),
                n,
                "{} lists a key twice",
                std::any::type_name::<T>()
            );
            v
        }
        fn same<T: Keys + DeserializeOwned>() {
            let mut fields = fields_of::<T>();
            fields.sort();
            assert_eq!(names::<T>(), fields, "{}", std::any::type_name::<T>());
        }
        same::<SeaSpec>();
        same::<SeaSection>();
        same::<WaterSpec>();
        same::<CurrentSpec>();
        same::<WavesSpec>();
        same::<SpectrumSpec>();
        same::<SeabedSettings>();
        same::<SectionOverride>();
        same::<CollarParams>();
        same::<CageParams>();
        same::<PanelParams>();
        same::<LineParams>();
        same::<LineSegment>();
        same::<GmshParams>();
        same::<FarmParams>();
        same::<NetHydro>();
        same::<LineHydro>();
        same::<PointSpec>();
        same::<BuoySpec>();
        same::<FixSpec>();
        same::<PrescribedSpec>();
        same::<SceneWake>();
        same::<DynamicSpec>();
        same::<AnalysisSpec>();
    }
}
