//! One value per physical default, whatever route a scene takes
//! (docs/README.md#conventions, "Physical constants"; docs/theory/farm.md#buoys;
//! docs/theory/cages.md#default-sections).

mod common;
use common::*;
use std::f64::consts::PI;
use std::path::Path;

/// The crates whose library code must take g, ρ_w and ν from `aqua-constants`.
const CRATES: [&str; 7] = [
    "aqua-env",
    "aqua-fem",
    "aqua-hydro",
    "aqua-mesh",
    "aqua-sim",
    "aqua-cli",
    "aqua-py",
];

/// The code of a source file before its test module, without comments and string literals.
fn code_of(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        if line.trim_start().starts_with("#[cfg(test)]") {
            break;
        }
        let line = line.split("//").next().unwrap_or("");
        // drop string literals (text between pairs of quotes)
        for (k, part) in line.split('"').enumerate() {
            if k % 2 == 0 {
                out.push_str(part);
            }
        }
        out.push('\n');
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// A second copy of a physical constant (gravity 9.81 or 9.80665, sea-water density 1025,
/// viscosity 1.19e-6) in any crate's library code is a default that depends on the route; the
/// values live in `aqua-constants` only.
#[test]
fn no_crate_spells_a_physical_constant_of_its_own() {
    let values = ["9.81", "9.80665", "1025.0", "1.19e-6"];
    let mut found = Vec::new();
    for c in CRATES {
        let mut files = Vec::new();
        rust_files(&root().join(c).join("src"), &mut files);
        for f in files {
            let code = code_of(&std::fs::read_to_string(&f).unwrap());
            for (i, line) in code.lines().enumerate() {
                for v in values {
                    let hit = line.match_indices(v).any(|(at, _)| {
                        // a whole number token: not part of 19.81 or 9.812
                        let before = line[..at].chars().next_back();
                        let after = line[at + v.len()..].chars().next();
                        !before.is_some_and(|ch| ch.is_ascii_digit() || ch == '.')
                            && !after.is_some_and(|ch| ch.is_ascii_digit())
                    });
                    if hit {
                        found.push(format!("{}:{}: {v}", f.display(), i + 1));
                    }
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "physical constants spelt outside aqua-constants: {found:?}"
    );
}

fn prepare_text(dir: &Path, name: &str, text: &str) -> aqua_sim::Prepared {
    let p = dir.join(format!("{name}.toml"));
    std::fs::write(&p, text).unwrap();
    aqua_sim::prepare(aqua_sim::PrepareOptions::file(&p))
        .unwrap_or_else(|e| panic!("{name}: {}", e.chain()))
}

/// The effective gravity of every path is the sea's: the structure's g, the cage builder's
/// sinker weights (kept in newtons: mass W/g, so they weigh W), and the defaults of a structure
/// built without a scene.
#[test]
fn gravity_is_the_sea_s_on_every_path() {
    assert_eq!(
        aqua_fem::DEFAULT_GRAVITY,
        aqua_env::constants::STANDARD_GRAVITY
    );
    assert_eq!(
        aqua_fem::DEFAULT_WATER_DENSITY,
        aqua_env::constants::SEA_WATER_DENSITY
    );
    assert_eq!(
        aqua_fem::Environment::default().gravity,
        aqua_env::Constants::default().gravity
    );
    let dir = scratch("defaults-gravity");
    for g in [None, Some(9.5)] {
        let key = g.map(|g| format!("gravity = {g}\n")).unwrap_or_default();
        let text = format!(
            "[sea]\ndepth = 60.0\n{key}\n[[cage]]\ntype = \"CSM\"\ncircumference = 60.0\n\
             depth = 6.0\ncone_depth = 2.0\nelement_length = 3.0\n"
        );
        let prep = prepare_text(&dir, "csm", &text);
        let sea_g = prep.built.sea.constants().gravity;
        assert_eq!(sea_g, g.unwrap_or(9.80665));
        let model = &prep.built.model;
        assert_eq!(model.environment().gravity, sea_g);
        // every builder weight weighs what the builder said, whatever g
        let weights = &prep.built.mesh.weights;
        assert!(!weights.is_empty());
        for w in weights {
            let m: f64 = model
                .point_bodies()
                .iter()
                .filter(|p| p.node == w.node)
                .map(|p| p.mass)
                .sum();
            assert!(
                (m * sea_g / w.weight - 1.0).abs() < 1e-12,
                "node {}: {m} kg at g = {sea_g} for {} N",
                w.node,
                w.weight
            );
        }
    }
}

/// A farm's buoys are vertical cylinders: their added-mass coefficient defaults to that of a
/// `[[buoy]]` cylinder (one default per body kind).
#[test]
fn farm_buoys_and_buoy_cylinders_share_the_added_mass_default() {
    let dir = scratch("defaults-buoy");
    let farm = example("farm.toml").replace("added_mass_coefficient = 0.5\n", "");
    assert!(!farm.contains("added_mass_coefficient"));
    let prep = prepare_text(&dir, "farm", &farm);
    let node = prep.built.farms[0].buoys[0];
    let ca_farm = prep
        .built
        .elements
        .points
        .iter()
        .find(|p| p.node == node)
        .unwrap()
        .props
        .added_mass;
    let text = "[sea]\ndepth = 30.0\n\n[[buoy]]\nposition = [0.0, 0.0, 0.0]\n\
                shape = \"cylinder\"\nvolume = 2.0\nheight = 1.2\nmass = 150.0\n";
    let prep = prepare_text(&dir, "cylinder", text);
    let ca_buoy = prep.built.elements.points[0].props.added_mass;
    assert_eq!(
        ca_farm, ca_buoy,
        "farm buoy C_a {ca_farm}, [[buoy]] C_a {ca_buoy}"
    );
    // the 2-D potential-flow value of a circle (docs/theory/farm.md#buoys)
    assert_eq!(ca_buoy, 1.0);
}

/// Mass per metre of a sealed pipe of outer diameter d and wall t, density 958 kg/m³.
fn pipe_mass(d: f64, t: f64) -> f64 {
    958.0 * PI / 4.0 * (d * d - (d - 2.0 * t).powi(2))
}

fn group_mass(prep: &aqua_sim::Prepared, suffix: &str) -> f64 {
    let g = prep
        .built
        .model
        .groups()
        .iter()
        .find(|g| g.name.ends_with(suffix))
        .unwrap_or_else(|| panic!("no group {suffix}"));
    g.section.mass_per_length
}

/// Pipe walls default to D/SDR with SDR 17 (13.6 for the sinker tube), the net–collar links are pieces of the collar
/// pipe, a pipe given a new diameter keeps its SDR, and a wall of half the diameter or more is
/// an error naming the wall and the fix.
#[test]
fn pipe_walls_follow_the_standard_dimension_ratio() {
    let dir = scratch("defaults-sdr");
    // The moored cage's 0.5 m collar: SDR 17, 41.66 kg/m, and so are its links.
    let prep = prepare_text(&dir, "moored", &example("moored-cage.toml"));
    let want = pipe_mass(0.5, 0.5 / 17.0);
    for g in ["/top_ring", "/top_links"] {
        let m = group_mass(&prep, g);
        assert!(
            (m / want - 1.0).abs() < 1e-12,
            "{g}: {m} kg/m, SDR 17: {want}"
        );
    }
    // A CCT cage's sinker tube (0.25 m) and a gmsh-free default collar (0.35 m).
    let cct = "[[cage]]\ntype = \"CCT\"\ncircumference = 60.0\ndepth = 6.0\n\
               cone_depth = 2.0\nelement_length = 3.0\n";
    let prep = prepare_text(&dir, "cct", cct);
    // The sinker tube is of the heavier class SDR 13.6.
    for (g, d, sdr) in [
        ("/top_ring", 0.35, 17.0),
        ("/top_links", 0.35, 17.0),
        ("/bottom_ring", 0.25, 13.6),
    ] {
        let m = group_mass(&prep, g);
        let want = pipe_mass(d, d / sdr);
        assert!(
            (m / want - 1.0).abs() < 1e-12,
            "{g}: {m} kg/m, SDR {sdr}: {want}"
        );
    }
    // Only a small diameter for a pipe group: the wall follows it.
    let small = format!("{cct}\n[cage.groups.top_links]\ndiameter = 0.01\n");
    let prep = prepare_text(&dir, "small", &small);
    let m = group_mass(&prep, "/top_links");
    let want = pipe_mass(0.01, 0.01 / 17.0);
    assert!((m / want - 1.0).abs() < 1e-12, "{m} kg/m, SDR 17: {want}");
    // `sdr` sets the wall.
    let sdr = format!("{cct}\n[cage.groups.bottom_ring]\nsdr = 11.0\n");
    let prep = prepare_text(&dir, "sdr", &sdr);
    let m = group_mass(&prep, "/bottom_ring");
    let want = pipe_mass(0.25, 0.25 / 11.0);
    assert!((m / want - 1.0).abs() < 1e-12, "{m} kg/m, SDR 11: {want}");
    // A stiffness diameter thinner than two walls: the error names the wall and the fix.
    let bad = format!("{cct}\n[cage.groups.top_links]\nelastic_diameter = 0.03\n");
    let p = dir.join("bad.toml");
    std::fs::write(&p, bad).unwrap();
    let Err(err) = aqua_sim::prepare(aqua_sim::PrepareOptions::file(&p)) else {
        panic!("a wall thicker than the radius must fail")
    };
    let err = err.chain();
    for part in [
        "groups.top_links.wall_thickness",
        "groups.top_links.sdr",
        "0.015",
    ] {
        assert!(err.contains(part), "{err}");
    }
}

/// The number in the default column of `key`'s row in the table under `heading` of the user
/// guide (docs/guide/scene.md): the documented default, written independently of the code.
fn guide_default(heading: &str, key: &str) -> f64 {
    let guide = std::fs::read_to_string(root().join("docs/guide/scene.md")).unwrap();
    let start = guide
        .lines()
        .position(|l| l.starts_with('#') && l.contains(heading))
        .unwrap_or_else(|| panic!("no heading {heading} in the guide"));
    let row = guide
        .lines()
        .skip(start + 1)
        .take_while(|l| !l.starts_with('#'))
        .find(|l| l.starts_with(&format!("| `{key}` |")))
        .unwrap_or_else(|| panic!("no row for {key} under {heading}"));
    let default = row.split('|').nth(3).unwrap().trim();
    let number = default.split_whitespace().next().unwrap();
    number
        .parse()
        .unwrap_or_else(|_| panic!("{heading} {key}: default {default:?} is not a number"))
}

/// A cage scene with the given extra `[sea]` keys and tables.
fn cage_scene(sea: &str, tail: &str) -> String {
    format!(
        "[sea]\ndepth = 40.0\n{sea}\n[[cage]]\ntype = \"CSM\"\ncircumference = 60.0\n\
         depth = 6.0\ncone_depth = 2.0\nelement_length = 3.0\n{tail}"
    )
}

/// The seabed's constants have one definition, aqua-fem's `SeabedSettings`: a scene without
/// `[sea.seabed]`, an empty `[sea.seabed]`, a structure built without a scene (`Seabed::new`),
/// the friction's and the contact law's own defaults all give the same seabed, and it is the
/// one the guide documents.
#[test]
fn the_seabed_defaults_have_one_definition() {
    use aqua_fem::{Seabed, SeabedFriction, SeabedSettings};
    let d = SeabedSettings::default();
    let h = 40.0;
    // the documented values (docs/guide/scene.md, `[sea.seabed]`)
    let doc = |k| guide_default("`[sea.seabed]`", k);
    assert_eq!(d.kbot, doc("kbot"));
    assert_eq!(d.cbot, doc("cbot"));
    assert_eq!(d.damping_depth, doc("damping_depth"));
    assert_eq!(d.friction_axial, doc("friction_axial"));
    assert_eq!(d.slip_velocity, doc("slip_velocity"));
    assert_eq!(d.transverse_friction(), d.friction_axial);
    // the structure's own routes
    assert_eq!(Seabed::new(h), d.seabed(h));
    assert_eq!(SeabedFriction::default(), d.seabed(h).friction);
    let partial: Seabed = serde_json::from_str(&format!(
        "{{\"depth\": {h}, \"stiffness\": {}, \"damping\": {}}}",
        d.kbot, d.cbot
    ))
    .unwrap();
    assert_eq!(partial, d.seabed(h));
    let empty: SeabedSettings = serde_json::from_str("{}").unwrap();
    assert_eq!(empty, d);
    // the scene's routes: no table, an empty table
    let dir = scratch("defaults-seabed");
    for (name, sea) in [("none", ""), ("empty", "[sea.seabed]\n")] {
        let prep = prepare_text(&dir, name, &cage_scene(sea, ""));
        assert_eq!(prep.scene.seabed, d, "{name}");
        assert_eq!(
            prep.built.model.environment().seabed,
            Some(Seabed::new(h)),
            "{name}"
        );
    }
    // a key given changes that key only
    let prep = prepare_text(
        &dir,
        "kbot",
        &cage_scene("[sea.seabed]\nkbot = 1e5\nfriction_axial = 0.7\n", ""),
    );
    let want = SeabedSettings {
        kbot: 1e5,
        friction_axial: 0.7,
        ..d
    };
    assert_eq!(prep.built.model.environment().seabed, Some(want.seabed(h)));
    assert_eq!(want.seabed(h).friction.transverse, 0.7);
}

/// g and ρ_w have one value per scene on every path: the sea the hydrodynamic loads read, the
/// structure's environment, and, without `[sea]` keys, the documented defaults.
#[test]
fn the_fluid_constants_have_one_value_on_every_path() {
    let dir = scratch("defaults-fluid");
    let doc_g = guide_default("`[sea]`", "gravity");
    let doc_rho = guide_default("`[sea.water]`", "density");
    for (name, sea, g, rho) in [
        ("default", "", doc_g, doc_rho),
        (
            "fresh",
            "gravity = 9.78\n[sea.water]\ndensity = 1000.0\n",
            9.78,
            1000.0,
        ),
    ] {
        let prep = prepare_text(&dir, name, &cage_scene(sea, ""));
        let sea = prep.built.sea.constants();
        let env = prep.built.model.environment();
        assert_eq!((sea.gravity, sea.density), (g, rho), "{name}: the sea");
        assert_eq!(
            (env.gravity, env.water_density),
            (g, rho),
            "{name}: the structure"
        );
    }
    assert_eq!(aqua_fem::Environment::default().gravity, doc_g);
    assert_eq!(aqua_fem::Environment::default().water_density, doc_rho);
    assert_eq!(aqua_env::Constants::default().gravity, doc_g);
    assert_eq!(aqua_env::Constants::default().density, doc_rho);
}

/// The integrators' defaults have one definition, aqua-fem's `DynamicSettings`: the HHT α and
/// the midpoint rule's θ a scene gets without the keys are the solver's own defaults and the
/// guide's.
#[test]
fn the_scheme_defaults_have_one_definition() {
    use aqua_fem::DynamicSettings;
    use aqua_sim::plan::Integrator;
    let fem = DynamicSettings::new(0.1, 1.0);
    let doc = |k| guide_default("`[analysis.dynamic]`", k);
    assert_eq!(fem.alpha, doc("alpha"));
    assert_eq!(fem.theta, doc("theta"));
    let dir = scratch("defaults-scheme");
    let dynamic = |scheme: &str| {
        format!(
            "\n[analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\nscheme = \"{scheme}\"\nt_end = 1.0\n"
        )
    };
    let prep = prepare_text(&dir, "hht", &cage_scene("", &dynamic("hht")));
    assert_eq!(prep.plan.alpha, fem.alpha);
    let Some(Integrator::Hht(s)) = &prep.plan.dynamics else {
        panic!("hht: an implicit integrator")
    };
    assert_eq!((s.alpha, s.theta), (fem.alpha, fem.theta));
    let prep = prepare_text(&dir, "midpoint", &cage_scene("", &dynamic("midpoint")));
    let Some(Integrator::Hht(s)) = &prep.plan.dynamics else {
        panic!("midpoint: an implicit integrator")
    };
    assert!(s.midpoint);
    assert_eq!(s.theta, fem.theta);
    // a settings record without θ (aqua-fem's serde default) has the same θ
    let mut json = serde_json::to_value(&fem).unwrap();
    json.as_object_mut().unwrap().remove("theta");
    let back: DynamicSettings = serde_json::from_value(json).unwrap();
    assert_eq!(back.theta, fem.theta);
}
