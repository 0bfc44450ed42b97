//! The water loads (aqua-hydro) of a scene: screen panels of the nets, Morison lines (ropes,
//! chains and net twines with their volume and hydrodynamic diameters), point bodies, and one
//! wake group per net copy.
//!
//! The physics defaults that the scene leaves open are decided here, once:
//! a cage's net shadows with the Løland wake, a panel's or gmsh net's has none
//! ([`default_wake`]); ropes use Morison M4 with C_a = 1, C_at = 0 and the Froude–Krylov
//! force on ([`LineHydro`] resolved in [`line_props`]); twines carry Morison drag only when
//! `net.drag = "morison"`, then with the knot correction.

use super::NetCells;
use crate::error::{Result, SimError};
use crate::scene::{LineHydro, NetDrag, NetHydro, Scene};
use aqua_fem::GroupId;
use aqua_hydro::assembly::{
    LineElement as HydroLine, NetPanel, PanelNodes as HydroPanelNodes, PointElement, WakeGroup,
};
use aqua_hydro::{
    CageWake, LineProps, MorisonModel, MorisonModelId, NetProps, PointProps, PointShape,
    ScreenModel, TwineMap, WakeModelId, WakeSpec, WakeUpdate,
};
use aqua_mesh::{Mesh, NetGrouping, ObjectKind, PanelNodes, Role, Section};
use std::collections::{HashMap, HashSet};

/// The load elements with what the outputs need to map them back to mesh cells.
#[derive(Debug)]
pub(super) struct WaterLoadElements {
    /// Elements for the load assembly.
    pub elements: aqua_hydro::assembly::Elements,
    /// Per mesh line: true if it is a net twine.
    pub is_twine: Vec<bool>,
    /// Per mesh panel: true if it carries screen loads.
    pub panel_loaded: Vec<bool>,
    /// The panels of each net copy (one per wake group).
    pub nets: Vec<NetCells>,
    /// Per panel and line load element, in the assembly's order: its mesh cell.
    pub load_cells: Vec<LoadCell>,
    /// The cage-to-cage wake among the wake groups of the participating cages.
    pub cage_wake: CageWake,
}

/// The mesh cell of a panel or line load element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoadCell {
    /// VTK cell index: mesh lines first, then mesh panels.
    pub cell: usize,
    /// True for net panels and twines (counted in the net force).
    pub net: bool,
}

/// The wake model of a net when the scene names none: Løland behind a cage's net (its
/// downstream half is shadowed by the upstream one), none behind a panel or a gmsh net.
pub fn default_wake(is_cage: bool) -> WakeSpec {
    WakeSpec {
        model: if is_cage {
            WakeModelId::Loland
        } else {
            WakeModelId::None
        },
        factor: None,
        cd0: None,
        update: WakeUpdate::Step,
        margin: 0.0,
        apply_to_lines: false,
    }
}

/// Builds every water-load element of the mesh.
pub(super) fn build_water_loads(
    scene: &Scene,
    mesh: &Mesh,
    nets: &HashMap<String, NetHydro>,
    sections: &[Option<(GroupId, Section)>],
    points: Vec<PointElement>,
    wake_cages: &HashSet<String>,
) -> Result<WaterLoadElements> {
    let (wake_groups, wake_index, mut nets_out) = wake_groups(scene, mesh, nets)?;
    let mut points = points;
    points.extend(twine_volumes(mesh));
    // Every copy of a participating cage (docs/theory/hydrodynamics.md#cage-to-cage-wake).
    let mut members: Vec<usize> = wake_index
        .iter()
        .filter(|((o, _), _)| wake_cages.contains(&mesh.objects[*o as usize].name))
        .map(|(_, &g)| g)
        .collect();
    members.sort_unstable();
    let cage_wake = CageWake::among(&wake_groups, &members);
    let (panels, panel_loaded) = screen_panels(scene, mesh, nets, &wake_index, &mut nets_out)?;
    let (lines, is_twine) = morison_lines(scene, mesh, nets, sections, &wake_index)?;
    // The assembly numbers panels first, then lines (aqua-hydro `LoadAssembly`).
    let n_lines = mesh.lines.len();
    let load_cells = (0..mesh.panels.len())
        .filter(|&p| panel_loaded[p])
        .map(|p| LoadCell {
            cell: n_lines + p,
            net: true,
        })
        .chain(is_twine.iter().enumerate().map(|(e, &twine)| LoadCell {
            cell: e,
            net: twine,
        }))
        .collect();
    Ok(WaterLoadElements {
        load_cells,
        elements: aqua_hydro::assembly::Elements {
            panels,
            lines,
            points,
            wake_groups,
        },
        is_twine,
        panel_loaded,
        nets: nets_out,
        cage_wake,
    })
}

type WakeIndex = HashMap<(u32, u32), usize>;

fn hydro_err(file: &str, what: &str, e: aqua_hydro::HydroError) -> SimError {
    SimError::at(format!("{file}: {what}"), e)
}

/// One wake group (and one net for the volume output) per copy of every object with a net.
fn wake_groups(
    scene: &Scene,
    mesh: &Mesh,
    nets: &HashMap<String, NetHydro>,
) -> Result<(Vec<WakeGroup>, WakeIndex, Vec<NetCells>)> {
    let file = scene.path.display().to_string();
    let mut groups = Vec::new();
    let mut index = WakeIndex::new();
    let mut nets_out = Vec::new();
    for (oi, obj) in mesh.objects.iter().enumerate() {
        let Some(net) = &obj.net else { continue };
        let hydro = nets.get(&obj.name).cloned().unwrap_or_default();
        let is_cage = matches!(obj.kind, ObjectKind::Cage(_));
        let wake = hydro
            .wake
            .clone()
            .unwrap_or_else(|| default_wake(is_cage))
            .build()
            .map_err(|e| hydro_err(&file, &format!("{} net.wake", obj.name), e))?;
        for copy in 0..obj.origins.len().max(1) as u32 {
            index.insert((oi as u32, copy), groups.len());
            groups.push(WakeGroup {
                name: format!("{} copy {copy}", obj.name),
                wake,
                solidity: net.solidity,
            });
            nets_out.push(NetCells {
                name: if obj.origins.len() > 1 {
                    format!("{}#{copy}", obj.name)
                } else {
                    obj.name.clone()
                },
                panels: Vec::new(),
                closed: is_cage,
            });
        }
    }
    Ok((groups, index, nets_out))
}

/// Screen panels of the nets whose drag is carried by panels
/// (docs/theory/hydrodynamics.md#scope-and-principles).
fn screen_panels(
    scene: &Scene,
    mesh: &Mesh,
    nets: &HashMap<String, NetHydro>,
    wake_index: &WakeIndex,
    nets_out: &mut [NetCells],
) -> Result<(Vec<NetPanel>, Vec<bool>)> {
    let file = scene.path.display().to_string();
    let mut panels = Vec::new();
    let mut panel_loaded = vec![false; mesh.panels.len()];
    for (pi, p) in mesh.panels.iter().enumerate() {
        let obj = &mesh.objects[p.object as usize];
        let Some(net) = &obj.net else { continue };
        let hydro = nets.get(&obj.name).cloned().unwrap_or_default();
        let wg = wake_index.get(&(p.object, p.copy)).copied();
        if let Some(w) = wg {
            nets_out[w].panels.push(pi);
        }
        if hydro.drag != NetDrag::Screen {
            if p.uv.is_some() {
                return Err(SimError::input(format!(
                    "{file}: {}: net.drag = \"morison\" puts the drag on numerical twines, \
                     which net.element = \"triangle\" has none of; use net.drag = \"screen\" \
                     or net.element = \"cable\"",
                    obj.name
                )));
            }
            continue;
        }
        let model = ScreenModel::new(hydro.screen_model, hydro.cd, hydro.cl, hydro.cyl_cd)
            .map_err(|e| hydro_err(&file, &obj.name, e))?;
        panels.push(NetPanel {
            nodes: match p.nodes {
                PanelNodes::Tri(n) => HydroPanelNodes::Triangle(n),
                PanelNodes::Quad(n) => HydroPanelNodes::Quad(n),
            },
            net: NetProps {
                model,
                solidity: net.solidity,
                twine_diameter: net.twine_diameter,
            },
            wake_group: wg,
            twines: match p.uv {
                Some(uv) => Some(TwineMap::new(uv).ok_or_else(|| {
                    SimError::input(format!(
                        "{file}: {}: net triangle {pi} has no area in mesh coordinates",
                        obj.name
                    ))
                })?),
                None => None,
            },
        });
        panel_loaded[pi] = true;
    }
    Ok((panels, panel_loaded))
}

/// Morison line elements, one per mesh line (docs/theory/hydrodynamics.md#morison-line-model).
fn morison_lines(
    scene: &Scene,
    mesh: &Mesh,
    nets: &HashMap<String, NetHydro>,
    sections: &[Option<(GroupId, Section)>],
    wake_index: &WakeIndex,
) -> Result<(Vec<HydroLine>, Vec<bool>)> {
    let file = scene.path.display().to_string();
    let mut lines = Vec::new();
    let mut is_twine = vec![false; mesh.lines.len()];
    let line_hydro: HashMap<String, LineHydro> = scene
        .line
        .iter()
        .enumerate()
        .map(|(i, l)| {
            (
                super::mesh::default_name(&l.value.params.name, "line", i),
                l.value.hydro.clone(),
            )
        })
        .collect();
    for (e, l) in mesh.lines.iter().enumerate() {
        let g = &mesh.groups[l.group];
        let obj = &mesh.objects[l.object as usize];
        let (_, section) = sections[l.group].as_ref().ok_or_else(|| {
            SimError::input(format!(
                "{file}: element {e} belongs to a group without a section"
            ))
        })?;
        let twine = g.role == Role::NetTwines;
        is_twine[e] = twine;
        let mut h = super::structure::group_spec(scene, &obj.name, &g.name)
            .map(|(_, s)| s.value.hydro.clone())
            .unwrap_or_default();
        if let Some(inline) = line_hydro.get(&obj.name) {
            h = h.merged(inline);
        }
        if twine && h.morison.is_some() {
            return Err(SimError::input(format!(
                "{file}: [[group]] {}: a morison key on net twines is not allowed; set net.drag = \"morison\" and net.morison on the object",
                g.name
            )));
        }
        let net = twine.then(|| {
            (
                obj.net.as_ref(),
                nets.get(&obj.name).cloned().unwrap_or_default(),
            )
        });
        let props = line_props(&h, section, net)
            .map_err(|err| hydro_err(&file, &format!("{}/{}", obj.name, g.name), err))?;
        // An element standing for `section_scale` sections has that multiple of the drag
        // area and of the displaced volume (docs/theory/cages.md#mesh-grouping).
        lines.push(HydroLine {
            nodes: l.nodes,
            props: LineProps {
                rest_length: l.rest_length.unwrap_or_else(|| mesh.line_length(e)),
                hydro_diameter: props.hydro_diameter * l.section_scale,
                volume_diameter: props.volume_diameter * l.section_scale.sqrt(),
                ..props
            },
            net_twine: twine,
            wake_group: wake_index.get(&(l.object, l.copy)).copied(),
        });
    }
    Ok((lines, is_twine))
}

/// The Morison and inertia properties of a line element (rest length left at 0 for the
/// caller). A net twine (`twine` = its net grouping and the net's keys) takes its drag model
/// from the net (`net.drag`, `net.morison`) and its Reynolds diameter from the twine diameter.
fn line_props(
    h: &LineHydro,
    section: &Section,
    twine: Option<(Option<&NetGrouping>, NetHydro)>,
) -> std::result::Result<LineProps, aqua_hydro::HydroError> {
    let (model, knot_default, re_diameter) = if let Some((net, hydro)) = twine {
        let morison = hydro.drag == NetDrag::Morison;
        let id = if morison {
            hydro.morison
        } else {
            MorisonModelId::None
        };
        (
            MorisonModel::new(id, None, None, net.map(|n| n.solidity))?,
            morison,
            net.map(|n| n.twine_diameter)
                .unwrap_or(section.hydro_diameter),
        )
    } else {
        (
            MorisonModel::new(h.morison.unwrap_or(MorisonModelId::M4), h.cn, h.ct, None)?,
            false,
            section.hydro_diameter,
        )
    };
    Ok(LineProps {
        model,
        hydro_diameter: section.hydro_diameter,
        reynolds_diameter: re_diameter,
        volume_diameter: section.volume_diameter,
        rest_length: 0.0,
        added_mass: h.added_mass.unwrap_or(1.0),
        added_mass_axial: h.added_mass_axial.unwrap_or(0.0),
        froude_krylov: h.froude_krylov.unwrap_or(true),
        knot_correction: h.knot_correction.unwrap_or(knot_default),
    })
}

/// The twines of net triangles as point volumes on their nodes: each triangle holds A_uv U bars
/// and A_uv V bars of length l_p, volume 2·A_uv·l_p·πd²/4, a third to each corner, wetted over
/// half the mean length of the node's triangle edges, with C_a = 1
/// (docs/theory/hydrodynamics.md#net-triangle-screen).
fn twine_volumes(mesh: &Mesh) -> Vec<PointElement> {
    let n = mesh.nodes.len();
    let mut volume = vec![0.0; n];
    let mut edges = vec![(0.0, 0usize); n];
    for p in &mesh.panels {
        let (Some(uv), PanelNodes::Tri(nodes)) = (p.uv, p.nodes) else {
            continue;
        };
        let Some(net) = &mesh.objects[p.object as usize].net else {
            continue;
        };
        let a_uv = 0.5
            * ((uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1])
                - (uv[2][0] - uv[0][0]) * (uv[1][1] - uv[0][1]))
                .abs();
        let d = net.twine_diameter;
        let v = 2.0 * a_uv * net.half_mesh * std::f64::consts::FRAC_PI_4 * d * d;
        for k in 0..3 {
            let (i, j) = (nodes[k], nodes[(k + 1) % 3]);
            volume[i] += v / 3.0;
            let l = (mesh.nodes[j] - mesh.nodes[i]).norm();
            for m in [i, j] {
                edges[m].0 += l;
                edges[m].1 += 1;
            }
        }
    }
    (0..n)
        .filter(|&i| volume[i] > 0.0)
        .map(|i| PointElement {
            node: i,
            props: PointProps {
                volume: volume[i],
                shape: PointShape::Prism {
                    height: 0.5 * edges[i].0 / edges[i].1 as f64,
                },
                drag_area: 0.0,
                added_mass: 1.0,
            },
        })
        .collect()
}
