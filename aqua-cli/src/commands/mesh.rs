//! `aqua mesh`: build a cage, panel or line (or import a gmsh mesh), report it, write VTK.
//!
//! ```text
//! aqua mesh ssm --circumference 120 --depth 15 --cone-depth 3 --element-length 2.5 --out cage.vtm
//! aqua mesh --from net.msh --out net.vtm [--json]
//! ```
//!
//! `--out` writes the multiblock geometry of a run's `<scene>_reference.vtm`
//! ([`aqua_mesh::write_geometry`]): `cage.vtm` and its blocks in `cage/`.
//!
//! Prints counts per group, λ and the structural, elastic and hydrodynamic diameters
//! (docs/theory/cages.md#mesh-grouping); `--json` prints the same as JSON.

use crate::InputError;
use anyhow::Context;
use aqua_mesh::{
    CageParams, CageType, Fairlead, GmshParams, LineParams, LineShape, Mesh, MeshError, PanelFixed,
    PanelParams,
};
use std::path::{Path, PathBuf};

/// What to build.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Circular, conical wall, sinker tube.
    Cct,
    /// Circular, conical wall, central sinker.
    Ccs,
    /// Circular, straight wall, sinker masses.
    Csm,
    /// Square, straight wall, sinker masses.
    Ssm,
    /// Alias of CCT.
    Cst,
    /// Flat net panel.
    Panel,
    /// Single line (mooring, bridle).
    Line,
}

/// Flags of `aqua mesh`. Flags take the scene keys with dashes; absent flags use the
/// defaults of docs/theory/cages.md#cage-parameters, #flat-net-panel and #single-line.
#[derive(clap::Args, Debug, Default)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Builder: cct, ccs, csm, ssm (cst = cct), panel, line. Omit with --from.
    #[arg(value_enum)]
    pub kind: Option<Kind>,
    /// Import a gmsh .msh file (MSH 4.1 ASCII/binary or 2.2 ASCII) instead of building.
    #[arg(long, conflicts_with = "kind")]
    pub from: Option<PathBuf>,
    /// Build the whole structure of a scene file (its cages, panels, meshes and lines).
    #[arg(long, conflicts_with_all = ["kind", "from"])]
    pub scene: Option<PathBuf>,
    /// Write the mesh to this VTK multiblock .vtm file (its blocks go in the folder of the
    /// same name next to it), as a run's reference geometry.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Object name (default cage0 / panel0 / line0 / mesh0).
    #[arg(long)]
    pub name: Option<String>,

    // Cage keys.
    /// Cage circumference C [m] (SSM: 4 × side).
    #[arg(long)]
    pub circumference: Option<f64>,
    /// Cage diameter [m] (CCT, CCS, CSM) instead of --circumference; line: section diameter [m].
    #[arg(long)]
    pub diameter: Option<f64>,
    /// Square side [m] (SSM) instead of --circumference.
    #[arg(long)]
    pub side: Option<f64>,
    /// R_bottom / R_top, 0 < r ≤ 1 (CCT, CCS).
    #[arg(long)]
    pub bottom_ratio: Option<f64>,
    /// Side net depth H [m].
    #[arg(long)]
    pub depth: Option<f64>,
    /// Cone depth below the side net [m].
    #[arg(long)]
    pub cone_depth: Option<f64>,
    /// Target element length [m] (cages, panels, lines).
    #[arg(long)]
    pub element_length: Option<f64>,
    /// Frame offset from the net [m].
    #[arg(long)]
    pub frame_offset: Option<f64>,
    /// Rope extension below z = −H [m] (CSM, SSM).
    #[arg(long)]
    pub rope_depth: Option<f64>,
    /// Sinker tube depth below z = −H [m] (CCT).
    #[arg(long)]
    pub tube_depth: Option<f64>,
    /// Central weight depth below z = −H [m] (CCS).
    #[arg(long)]
    pub weight_depth: Option<f64>,
    /// Submerged sinker weight per metre of circumference [N/m] (CCT, CSM, SSM).
    #[arg(long)]
    pub sinker_weight_per_metre: Option<f64>,
    /// Submerged central sinker weight [N] (CCS).
    #[arg(long)]
    pub centre_weight: Option<f64>,
    /// Submerged tip weight [N].
    #[arg(long)]
    pub tip_weight: Option<f64>,
    /// Origin x,y,z [m]; repeat for several copies (cages, gmsh imports).
    #[arg(long, value_parser = parse_vec3)]
    pub origin: Vec<[f64; 3]>,
    /// Fixed groups (cages, lines; repeatable) or panel mode all|top|top_bottom|edges|none.
    #[arg(long)]
    pub fixed: Vec<String>,

    // Net keys.
    /// Physical twine diameter dw0 [m].
    #[arg(long)]
    pub twine_diameter: Option<f64>,
    /// Half mesh (bar length) l_p [m].
    #[arg(long)]
    pub half_mesh: Option<f64>,
    /// Net solidity Sn (default 2d/l − (d/l)²).
    #[arg(long)]
    pub solidity: Option<f64>,
    /// Grouping ratio λ (overrides the computed one).
    #[arg(long)]
    pub grouping_ratio: Option<f64>,

    // Panel keys.
    /// Panel width W [m].
    #[arg(long)]
    pub width: Option<f64>,
    /// Panel height H_p [m].
    #[arg(long)]
    pub height: Option<f64>,
    /// Panel divisions n_w,n_h.
    #[arg(long, value_parser = parse_divisions)]
    pub divisions: Option<[u32; 2]>,
    /// Panel centre x,y,z [m].
    #[arg(long, value_parser = parse_vec3)]
    pub centre: Option<[f64; 3]>,
    /// Panel normal x,y,z.
    #[arg(long, value_parser = parse_vec3)]
    pub normal: Option<[f64; 3]>,
    /// Panel up direction x,y,z.
    #[arg(long, value_parser = parse_vec3)]
    pub up: Option<[f64; 3]>,
    /// Panel bottom weight [N], shared over the bottom nodes.
    #[arg(long)]
    pub bottom_weight: Option<f64>,

    // Line keys.
    /// Line anchor x,y,z [m].
    #[arg(long, value_parser = parse_vec3)]
    pub anchor: Option<[f64; 3]>,
    /// Line fairlead x,y,z [m].
    #[arg(long, value_parser = parse_vec3)]
    pub fairlead: Option<[f64; 3]>,
    /// Unstretched line length L0 [m].
    #[arg(long)]
    pub length: Option<f64>,
    /// Line segments N.
    #[arg(long)]
    pub segments: Option<u32>,
    /// Line initial shape: catenary or straight.
    #[arg(long, value_parser = ["catenary", "straight"])]
    pub shape: Option<String>,
    /// Line axial stiffness EA [N].
    #[arg(long)]
    pub ea: Option<f64>,
    /// Line mass per length [kg/m].
    #[arg(long)]
    pub mass_per_length: Option<f64>,
    /// Seabed z [m] (line nodes below it are projected onto it).
    #[arg(long)]
    pub seabed_z: Option<f64>,

    // gmsh keys.
    /// Scale applied to the gmsh coordinates.
    #[arg(long)]
    pub scale: Option<f64>,
    /// Rotation rx,ry,rz [deg] applied about x, then y, then z.
    #[arg(long, value_parser = parse_vec3)]
    pub rotate_deg: Option<[f64; 3]>,
    /// Translation x,y,z [m] applied after the rotation.
    #[arg(long, value_parser = parse_vec3)]
    pub translate: Option<[f64; 3]>,
    /// Map a gmsh physical name to a role: GmshName=role (repeatable).
    #[arg(long)]
    pub rename: Vec<String>,
}

fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{s}` is not x,y,z (three numbers separated by commas)"))?;
    <[f64; 3]>::try_from(v).map_err(|_| format!("`{s}` is not x,y,z (three numbers)"))
}

fn parse_divisions(s: &str) -> Result<[u32; 2], String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|t| t.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{s}` is not n_w,n_h (two whole numbers)"))?;
    <[u32; 2]>::try_from(v).map_err(|_| format!("`{s}` is not n_w,n_h (two whole numbers)"))
}

/// Turn a library error into an input error (exit code 2) unless it is a write failure.
fn input(e: MeshError) -> anyhow::Error {
    InputError::new(e.to_string()).into()
}

/// Flags given that belong to a group of keys, for "flag not used by <kind>" errors.
fn given(args: &Args) -> Vec<(&'static str, &'static str)> {
    let mut v = Vec::new();
    macro_rules! g {
        ($cat:expr, $($f:ident => $flag:expr),*) => {$(
            if args.$f.is_some() { v.push(($cat, $flag)); }
        )*};
    }
    g!("cage", circumference => "--circumference", side => "--side",
       bottom_ratio => "--bottom-ratio", depth => "--depth", cone_depth => "--cone-depth",
       frame_offset => "--frame-offset", rope_depth => "--rope-depth",
       tube_depth => "--tube-depth", weight_depth => "--weight-depth",
       sinker_weight_per_metre => "--sinker-weight-per-metre",
       centre_weight => "--centre-weight", tip_weight => "--tip-weight");
    g!("net", twine_diameter => "--twine-diameter", half_mesh => "--half-mesh",
       solidity => "--solidity", grouping_ratio => "--grouping-ratio");
    g!("panel", width => "--width", height => "--height", divisions => "--divisions",
       centre => "--centre", normal => "--normal", up => "--up",
       bottom_weight => "--bottom-weight");
    g!("line", anchor => "--anchor", fairlead => "--fairlead", length => "--length",
       segments => "--segments", shape => "--shape", ea => "--ea",
       mass_per_length => "--mass-per-length", seabed_z => "--seabed-z");
    g!("gmsh", scale => "--scale", rotate_deg => "--rotate-deg", translate => "--translate");
    g!("size", element_length => "--element-length", diameter => "--diameter");
    if !args.rename.is_empty() {
        v.push(("gmsh", "--rename"));
    }
    if !args.origin.is_empty() {
        v.push(("origin", "--origin"));
    }
    if !args.fixed.is_empty() {
        v.push(("fixed", "--fixed"));
    }
    v
}

fn reject_others(args: &Args, what: &str, allowed: &[&str]) -> anyhow::Result<()> {
    for (cat, flag) in given(args) {
        if !allowed.contains(&cat) {
            return Err(InputError::new(format!(
                "flag {flag} is not used by `aqua mesh {what}`; see `aqua mesh --help`"
            ))
            .into());
        }
    }
    Ok(())
}

/// Cage parameters from the flags.
pub fn cage_params(args: &Args, kind: CageType) -> CageParams {
    let mut p = CageParams::new(kind);
    p.name = args.name.clone();
    p.circumference = args.circumference;
    p.diameter = args.diameter;
    p.side = args.side;
    p.bottom_ratio = args.bottom_ratio;
    p.depth = args.depth;
    p.cone_depth = args.cone_depth;
    p.element_length = args.element_length;
    p.frame_offset = args.frame_offset;
    p.rope_depth = args.rope_depth;
    p.tube_depth = args.tube_depth;
    p.weight_depth = args.weight_depth;
    p.sinker_weight_per_metre = args.sinker_weight_per_metre;
    p.centre_weight = args.centre_weight;
    p.tip_weight = args.tip_weight;
    if !args.origin.is_empty() {
        p.origins = Some(args.origin.clone());
    }
    if !args.fixed.is_empty() {
        p.fixed = Some(
            args.fixed
                .iter()
                .filter(|f| *f != "none")
                .cloned()
                .collect(),
        );
    }
    p.net.twine_diameter = args.twine_diameter;
    p.net.half_mesh = args.half_mesh;
    p.net.solidity = args.solidity;
    p.net.grouping_ratio = args.grouping_ratio;
    p
}

/// Build a cage from its parameter struct (e.g. a scene's `[[cage]]` table), print the report
/// and optionally write `out` (.vtm). This is what `aqua mesh <type>` runs.
pub fn run_cage(params: &CageParams, out: Option<&Path>, json: bool) -> anyhow::Result<()> {
    let mesh = params.build().map_err(input)?;
    report(&mesh, out, json)
}

/// Print the report of `mesh` (text or JSON) and write it to `out` if given.
pub fn report(mesh: &Mesh, out: Option<&Path>, json: bool) -> anyhow::Result<()> {
    report_with(mesh, out, json, true)
}

/// [`report`]; `notices` false leaves the mesh notices out of the text (a caller that prints
/// them as diagnostics, like `aqua check`, says each once).
pub fn report_with(
    mesh: &Mesh,
    out: Option<&Path>,
    json: bool,
    notices: bool,
) -> anyhow::Result<()> {
    if let Some(path) = out {
        if path.extension().and_then(|e| e.to_str()) != Some("vtm") {
            return Err(InputError::new(format!(
                "--out {}: the mesh is written as a VTK multiblock (a .vtm file and a folder of \
                 .vtu blocks, as a run's reference geometry); use a .vtm file name",
                path.display()
            ))
            .into());
        }
        aqua_mesh::write_geometry(path, mesh)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    let summary = mesh.summary();
    if json {
        let mut v = serde_json::to_value(&summary)?;
        if let Some(path) = out {
            v["out"] = serde_json::Value::String(path.display().to_string());
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    print!("{}", summary.to_text(notices));
    if let Some(path) = out {
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Run `aqua mesh`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let out = args.out.clone();
    let out = out.as_deref();
    if let Some(path) = &args.scene {
        let scene = aqua_sim::scene::read_scene(aqua_sim::SceneInput::File(path), &[])?;
        let (mesh, _) = aqua_sim::build_mesh(&scene)?;
        return report(&mesh, out, args.json);
    }
    if let Some(file) = &args.from {
        reject_others(&args, "--from", &["gmsh", "net", "origin"])?;
        let mut rename = std::collections::BTreeMap::new();
        for r in &args.rename {
            let (a, b) = r.split_once('=').ok_or_else(|| {
                InputError::new(format!("--rename `{r}`: expected GmshName=role"))
            })?;
            rename.insert(a.to_string(), b.to_string());
        }
        let mut p = GmshParams {
            name: args.name.clone(),
            file: file.clone(),
            scale: args.scale,
            rotate_deg: args.rotate_deg,
            translate: args.translate,
            origins: (!args.origin.is_empty()).then(|| args.origin.clone()),
            rename,
            ..Default::default()
        };
        p.net.twine_diameter = args.twine_diameter;
        p.net.half_mesh = args.half_mesh;
        p.net.solidity = args.solidity;
        p.net.grouping_ratio = args.grouping_ratio;
        let mesh = aqua_mesh::import_gmsh(&p).map_err(input)?;
        return report(&mesh, out, args.json);
    }
    let Some(kind) = args.kind else {
        return Err(InputError::new(
            "give a builder (cct, ccs, csm, ssm, panel, line) or --from <file.msh>",
        )
        .into());
    };
    match kind {
        Kind::Cct | Kind::Ccs | Kind::Csm | Kind::Ssm | Kind::Cst => {
            let t = match kind {
                Kind::Cct => CageType::Cct,
                Kind::Ccs => CageType::Ccs,
                Kind::Csm => CageType::Csm,
                Kind::Ssm => CageType::Ssm,
                _ => CageType::Cst,
            };
            reject_others(&args, t.code(), &["cage", "net", "size", "origin", "fixed"])?;
            run_cage(&cage_params(&args, t), out, args.json)
        }
        Kind::Panel => {
            reject_others(&args, "panel", &["panel", "net", "size", "fixed"])?;
            if args.diameter.is_some() {
                return Err(
                    InputError::new("flag --diameter is not used by `aqua mesh panel`").into(),
                );
            }
            let fixed = match args.fixed.as_slice() {
                [] => PanelFixed::All,
                [f] => PanelFixed::from_name(f).ok_or_else(|| {
                    InputError::new(format!(
                        "--fixed `{f}` for a panel: valid values all, top, top_bottom, edges, none"
                    ))
                })?,
                _ => {
                    return Err(InputError::new(
                        "--fixed takes one value for a panel (all, top, top_bottom, edges, none)",
                    )
                    .into());
                }
            };
            let mut p = PanelParams::new(
                args.width
                    .ok_or_else(|| InputError::new("panel needs --width [m]"))?,
                args.height
                    .ok_or_else(|| InputError::new("panel needs --height [m]"))?,
            );
            p.name = args.name.clone();
            p.divisions = args.divisions;
            p.element_length = args.element_length;
            p.centre = args.centre;
            p.normal = args.normal;
            p.up = args.up;
            p.fixed = fixed;
            p.bottom_weight = args.bottom_weight;
            p.net.twine_diameter = args.twine_diameter;
            p.net.half_mesh = args.half_mesh;
            p.net.solidity = args.solidity;
            p.net.grouping_ratio = args.grouping_ratio;
            let mesh = p.build().map_err(input)?;
            report(&mesh, out, args.json)
        }
        Kind::Line => {
            reject_others(&args, "line", &["line", "size", "fixed"])?;
            let p = LineParams {
                name: args.name.clone(),
                anchor: args
                    .anchor
                    .ok_or_else(|| InputError::new("line needs --anchor x,y,z [m]"))?,
                fairlead: args.fairlead.map(Fairlead::Point),
                length: args
                    .length
                    .ok_or_else(|| InputError::new("line needs --length (unstretched, m)"))?,
                segments: args.segments,
                element_length: args.element_length,
                shape: match args.shape.as_deref() {
                    Some("straight") => LineShape::Straight,
                    _ => LineShape::Catenary,
                },
                fixed: (!args.fixed.is_empty()).then(|| args.fixed.clone()),
                diameter: args.diameter,
                ea: args.ea,
                mass_per_length: args.mass_per_length,
                ..Default::default()
            };
            let mesh = p.build_with(None, args.seabed_z).map_err(input)?;
            report(&mesh, out, args.json)
        }
    }
}
