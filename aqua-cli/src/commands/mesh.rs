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
use aqua_mesh::{Builder, CageType, LineShape, Mesh, MeshRequest, RequestError};
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

/// The library's error as an input error (exit code 2), its keys spelt as flags.
fn input(e: RequestError) -> anyhow::Error {
    let flag = |key: &str| format!("--{}", key.replace('_', "-"));
    let msg = match e {
        RequestError::KeyNotUsed { key, builder } => format!(
            "flag {} is not used by `aqua mesh {}`; see `aqua mesh --help`",
            flag(key),
            if builder == "gmsh" { "--from" } else { builder }
        ),
        RequestError::PanelDiameter => "flag --diameter is not used by `aqua mesh panel`".into(),
        RequestError::MissingKey { builder, key, what } => {
            format!("{builder} needs {} {what}", flag(key))
        }
        RequestError::PanelFixed { value } => {
            format!("--fixed `{value}` for a panel: valid values all, top, top_bottom, edges, none")
        }
        RequestError::PanelFixedCount => {
            "--fixed takes one value for a panel (all, top, top_bottom, edges, none)".into()
        }
        RequestError::Rename { value } => format!("--rename `{value}`: expected GmshName=role"),
        RequestError::Mesh(e) => e.to_string(),
    };
    InputError::new(msg).into()
}

/// The builder keys of the flags.
fn request(a: &Args) -> MeshRequest {
    MeshRequest {
        name: a.name.clone(),
        circumference: a.circumference,
        diameter: a.diameter,
        side: a.side,
        bottom_ratio: a.bottom_ratio,
        depth: a.depth,
        cone_depth: a.cone_depth,
        element_length: a.element_length,
        frame_offset: a.frame_offset,
        rope_depth: a.rope_depth,
        tube_depth: a.tube_depth,
        weight_depth: a.weight_depth,
        sinker_weight_per_metre: a.sinker_weight_per_metre,
        centre_weight: a.centre_weight,
        tip_weight: a.tip_weight,
        origin: a.origin.clone(),
        fixed: a.fixed.clone(),
        twine_diameter: a.twine_diameter,
        half_mesh: a.half_mesh,
        solidity: a.solidity,
        grouping_ratio: a.grouping_ratio,
        width: a.width,
        height: a.height,
        divisions: a.divisions,
        centre: a.centre,
        normal: a.normal,
        up: a.up,
        bottom_weight: a.bottom_weight,
        anchor: a.anchor,
        fairlead: a.fairlead,
        length: a.length,
        segments: a.segments,
        shape: a.shape.as_deref().and_then(LineShape::from_name),
        ea: a.ea,
        mass_per_length: a.mass_per_length,
        seabed_z: a.seabed_z,
        scale: a.scale,
        rotate_deg: a.rotate_deg,
        translate: a.translate,
        rename: a.rename.clone(),
    }
}

/// Print the report of `mesh` (text or JSON) and write it to `out` if given.
pub fn report(mesh: &Mesh, out: Option<&Path>, json: bool) -> anyhow::Result<()> {
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
    print!("{}", summary.to_text(true));
    if let Some(path) = out {
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Run `aqua mesh`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let out = args.out.as_deref();
    if let Some(path) = &args.scene {
        let scene = aqua_sim::scene::read_scene(aqua_sim::SceneInput::File(path), &[])?;
        let (mesh, _) = aqua_sim::build_mesh(&scene)?;
        return report(&mesh, out, args.json);
    }
    let builder = match (&args.from, args.kind) {
        (Some(file), _) => Builder::Gmsh(file.clone()),
        (None, Some(kind)) => match kind {
            Kind::Cct => Builder::Cage(CageType::Cct),
            Kind::Ccs => Builder::Cage(CageType::Ccs),
            Kind::Csm => Builder::Cage(CageType::Csm),
            Kind::Ssm => Builder::Cage(CageType::Ssm),
            Kind::Cst => Builder::Cage(CageType::Cst),
            Kind::Panel => Builder::Panel,
            Kind::Line => Builder::Line,
        },
        (None, None) => {
            return Err(InputError::new(
                "give a builder (cct, ccs, csm, ssm, panel, line) or --from <file.msh>",
            )
            .into());
        }
    };
    let mesh = request(&args).build(&builder).map_err(input)?;
    report(&mesh, out, args.json)
}
