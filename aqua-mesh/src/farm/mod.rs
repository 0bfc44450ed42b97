//! Farm builder (`[[farm]]`, docs/theory/cages.md#farm-grid): rows × columns of cages on a
//! square mooring grid.
//!
//! Layout (x east, y north, z up; the grid centred on `origin`):
//!
//! * **plates** at the grid intersections, (rows + 1) × (columns + 1) of them at
//!   z = −`grid_depth`; plate (i, j), i = 0..=columns along x and j = 0..=rows along y, is node
//!   `plates[j·(columns + 1) + i]` of the frame;
//! * **cages**: slot (r, c), r = 1..=rows along y and c = 1..=columns along x, is the cell
//!   between plates (c − 1, r − 1) and (c, r); its cage (the caller's cage for that slot, or
//!   none for an empty slot; `fixed = []`: the collar floats) is the object
//!   `<farm>/cage_r<r>c<c>` with its origin at the cell centre, z = 0;
//! * the **frame** object `<farm>/frame`: `frame_lines` along the grid lines between
//!   neighbouring plates, `bridles` from the four corner plates of each cell that holds a cage
//!   to the collar (`top_ring`) node of its cage nearest to that corner, `pendants` from every
//!   plate straight up to a surface **buoy** node (node groups `plates` and `buoys`);
//! * **anchor lines** `<farm>/anchor_<e|w|n|s><k>` from every outer plate outwards along the
//!   grid axes (one per edge plate, two at a corner): `e` runs along +x from the plates
//!   i = columns, `w` along −x from i = 0, `n` along +y from j = rows, `s` along −y from j = 0;
//!   k counts from 1 along the edge with increasing y (e, w) or x (n, s). The line is a chain
//!   (optional, at the anchor) then a rope to the plate; the anchor is fixed on the seabed.
//!
//! The buoy nodes are returned for the caller to put its buoy on (aqua-sim's `[farm.buoy]`,
//! typed as a `[[buoy]]`), and each part
//! is made by a small function ([`anchor_line`], the buoy list) so that the buoy and
//! segmented-line builders can replace them.

mod anchor_line;
mod grid;

pub use anchor_line::anchor_line;

use crate::Mesh;
use crate::cage::CageParams;
use crate::error::{MeshError, Result};
use crate::section::Section;
use crate::section_override::SectionOverride;
use grid::{Grid, frame_object};
use nalgebra::Point3;
use serde::{Deserialize, Serialize};

/// One `[[farm]]` table but its `cage` and `buoy` tables (which the caller types: the cage with
/// its net keys, the buoy as a `[[buoy]]`).
#[derive(Debug, Clone, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FarmParams {
    /// Strain by which the anchor lines' initial catenaries are stretched (not a scene key; see
    /// [`crate::line::INITIAL_STRETCH`]).
    #[serde(skip)]
    pub initial_stretch: f64,
    /// `name` (default `farm<index>`, set by the caller; `farm0` here).
    pub name: Option<String>,
    /// Cage rows (along y), ≥ 1.
    pub rows: u32,
    /// Cage columns (along x), ≥ 1.
    pub columns: u32,
    /// Grid spacing [m] (cell side), > 0.
    pub spacing: f64,
    /// Depth of the frame (plates) below the still water level [m], > 0.
    pub grid_depth: f64,
    /// Horizontal centre of the grid [x, y] [m], default [0, 0].
    pub origin: Option<[f64; 2]>,
    /// Element length of frame lines, bridles, pendants and anchor lines [m], default 5.
    pub element_length: Option<f64>,
    /// Unstretched length of each anchor line (chain + rope) [m], > 0.
    pub anchor_length: f64,
    /// Segments of each anchor line (chain + rope together), ≥ 1 (default: `anchor_length`
    /// over `element_length`). Sagging lines want about 40 or more
    /// (docs/theory/fem.md#mesh-resolution-warnings).
    pub anchor_segments: Option<u32>,
    /// Horizontal distance from the plate to its anchor [m] (default: the line's horizontal
    /// span when its chord is 97 % of `anchor_length`).
    pub anchor_distance: Option<f64>,
    /// Length of the chain part of each anchor line at the anchor [m] (default 0: rope only;
    /// needs `[farm.chain]`).
    pub chain_length: Option<f64>,
    /// The cage-to-cage wake among the farm's cages (default true).
    pub cage_wake: Option<bool>,
    /// `[farm.frame]`: section of the frame lines and pendants (diameter, ea or
    /// youngs_modulus, mass_per_length or density required).
    pub frame: Option<SectionOverride>,
    /// `[farm.bridle]`: section of the bridles.
    pub bridle: Option<SectionOverride>,
    /// `[farm.anchor]`: section of the anchor lines' rope part.
    pub anchor: Option<SectionOverride>,
    /// `[farm.chain]`: section of the anchor lines' chain part.
    pub chain: Option<SectionOverride>,
}

/// What a farm builds: the mesh (cages, frame, anchor lines as objects) and its buoys.
#[derive(Debug, Clone)]
pub struct FarmMesh {
    /// All objects of the farm.
    pub mesh: Mesh,
    /// The buoy nodes, one on top of every plate's pendant (node ids of `mesh`); the caller
    /// puts its `[farm.buoy]` on each.
    pub buoys: Vec<usize>,
    /// Object names of the cages, slot order (r, then c).
    pub cages: Vec<String>,
    /// Object names of the anchor lines.
    pub anchors: Vec<String>,
}

/// Counts of a built farm (for `aqua check`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FarmCounts {
    /// Cages.
    pub cages: usize,
    /// Plates.
    pub plates: usize,
    /// Buoys.
    pub buoys: usize,
    /// Anchor lines.
    pub anchor_lines: usize,
    /// Frame line elements.
    pub frame_elements: usize,
    /// Bridles (lines, not elements).
    pub bridles: usize,
}

const DEFAULT_ELEMENT_LENGTH: f64 = 5.0;
/// Default anchor chord as a fraction of the anchor line length.
const ANCHOR_CHORD_FRACTION: f64 = 0.97;

impl FarmParams {
    fn name(&self) -> String {
        self.name.clone().unwrap_or_else(|| "farm0".into())
    }

    /// A slot's cage may not set what the farm sets: `name`, `origins`, a non-empty `fixed`
    /// (`what` names the table in the message, e.g. `cage` or `slot r1c2: cage`).
    pub fn check_cage(&self, what: &str, cage: &CageParams) -> Result<()> {
        for key in ["origins", "fixed", "name"] {
            let set = match key {
                "origins" => cage.origins.is_some(),
                "fixed" => cage.fixed.as_ref().is_some_and(|f| !f.is_empty()),
                _ => cage.name.is_some(),
            };
            if set {
                return Err(MeshError::param(
                    &self.name(),
                    &format!("{what}.{key}"),
                    "(set)",
                    "is set by the farm (slot names and positions; collars float, so fixed = [])",
                ));
            }
        }
        Ok(())
    }

    /// The grid checks: counts, lengths and the section tables that must be there.
    fn check(&self) -> Result<()> {
        let obj = self.name();
        let obj = obj.as_str();
        for (key, v) in [("rows", self.rows), ("columns", self.columns)] {
            if v < 1 {
                return Err(MeshError::param(
                    obj,
                    key,
                    v,
                    "must be >= 1 (a farm has at least one cage)",
                ));
            }
        }
        if self.rows as usize * self.columns as usize > 400 {
            return Err(MeshError::param(
                obj,
                "rows",
                self.rows,
                "rows × columns must be <= 400 cages",
            ));
        }
        for (key, v) in [
            ("spacing", self.spacing),
            ("grid_depth", self.grid_depth),
            ("anchor_length", self.anchor_length),
        ] {
            length(obj, key, v)?;
        }
        if let Some(e) = self.element_length {
            length(obj, "element_length", e)?;
        }
        if self.anchor_segments == Some(0) {
            return Err(MeshError::param(
                obj,
                "anchor_segments",
                "0".to_string(),
                "must be at least 1",
            ));
        }
        self.check_nodes(obj)?;
        if let Some(o) = self.origin
            && !o.iter().all(|c| c.is_finite())
        {
            return Err(MeshError::param(
                obj,
                "origin",
                format!("{o:?}"),
                "must be finite [x, y] in m",
            ));
        }
        if let Some(c) = self.chain_length {
            if !(c.is_finite() && c >= 0.0 && c < self.anchor_length) {
                return Err(MeshError::param(
                    obj,
                    "chain_length",
                    c,
                    format!(
                        "must be >= 0 and < anchor_length = {} m (the rope takes the rest)",
                        self.anchor_length
                    ),
                ));
            }
            if c > 0.0 && self.chain.is_none() {
                return Err(missing_table(obj, "chain", "chain_length > 0"));
            }
        }
        Ok(())
    }

    /// The frame lines, pendants, bridles and anchor lines must stay within
    /// [`MAX_NODES`](crate::limits::MAX_NODES) (an upper estimate from the lengths given).
    fn check_nodes(&self, obj: &str) -> Result<()> {
        let el = self.element_length.unwrap_or(DEFAULT_ELEMENT_LENGTH);
        let (nc, nr) = (f64::from(self.columns), f64::from(self.rows));
        let frame = (nc * (nr + 1.0) + nr * (nc + 1.0) + 4.0 * nc * nr) * self.spacing;
        let pendants = (nc + 1.0) * (nr + 1.0) * self.grid_depth;
        let lines = 2.0 * (nc + nr + 2.0);
        if let Some(n) = self.anchor_segments
            && lines * f64::from(n) > crate::limits::MAX_NODES as f64
        {
            return Err(MeshError::param(
                obj,
                "anchor_segments",
                n,
                format!(
                    "gives {} anchor-line nodes (> {}); sagging lines need about 40 segments",
                    lines * f64::from(n),
                    crate::limits::MAX_NODES
                ),
            ));
        }
        let anchors = if self.anchor_segments.is_some() {
            0.0
        } else {
            lines * self.anchor_length
        };
        let nodes = (frame + pendants + anchors) / el;
        if nodes > crate::limits::MAX_NODES as f64 {
            return Err(MeshError::param(
                obj,
                "element_length",
                el,
                format!(
                    "gives about {nodes:.3e} frame, pendant, bridle and anchor-line nodes (> {}) \
                     for spacing = {} m, grid_depth = {} m and anchor_length = {} m; likely a \
                     unit mistake (lengths are in metres)",
                    crate::limits::MAX_NODES,
                    self.spacing,
                    self.grid_depth,
                    self.anchor_length
                ),
            ));
        }
        Ok(())
    }

    /// Builds the farm with `cage` in every slot; `seabed_z` [m] is the seabed level (−depth),
    /// required for the anchors.
    pub fn build(&self, cage: &CageParams, seabed_z: Option<f64>) -> Result<FarmMesh> {
        self.check_cage("cage", cage)?;
        self.build_slots(|_, _| Some(cage.clone()), seabed_z)
    }

    /// Builds the farm with `slot(r, c)` in slot (r, c) (1-based row along y, column along
    /// x): its cage, or `None` for an empty cell (no cage and none of its four bridles). At
    /// least one slot must hold a cage. `seabed_z` [m] is the seabed level (−depth).
    pub fn build_slots(
        &self,
        slot: impl Fn(usize, usize) -> Option<CageParams>,
        seabed_z: Option<f64>,
    ) -> Result<FarmMesh> {
        self.check()?;
        let name = self.name();
        let obj = name.as_str();
        let zb = seabed_z.ok_or_else(|| {
            MeshError::param(
                obj,
                "anchor_length",
                self.anchor_length,
                "a farm needs a finite sea depth ([sea] depth) for its anchors",
            )
        })?;
        if -self.grid_depth <= zb {
            return Err(MeshError::param(
                obj,
                "grid_depth",
                self.grid_depth,
                format!("must be less than the water depth {} m", -zb),
            ));
        }
        let frame = line_section(obj, "frame", self.frame.as_ref(), "rope")?;
        let bridle = line_section(obj, "bridle", self.bridle.as_ref(), "rope")?;
        let rope = line_section(obj, "anchor", self.anchor.as_ref(), "rope")?;
        let chain_len = self.chain_length.unwrap_or(0.0);
        let chain = match (&self.chain, chain_len > 0.0) {
            (Some(c), true) => Some(line_section(obj, "chain", Some(c), "chain")?),
            (Some(_), false) => {
                return Err(MeshError::param(
                    obj,
                    "chain",
                    "(set)",
                    "needs chain_length > 0 (the length of chain at the anchor)",
                ));
            }
            _ => None,
        };
        let el = self.element_length.unwrap_or(DEFAULT_ELEMENT_LENGTH);

        let grid = Grid::new(self);
        let mut mesh = Mesh::default();
        let mut cages = Vec::new();
        let mut collars = Vec::new();
        for r in 1..=self.rows as usize {
            for c in 1..=self.columns as usize {
                let Some(mut p) = slot(r, c) else { continue };
                self.check_cage(&format!("slot r{r}c{c}: cage"), &p)?;
                let cname = format!("{name}/cage_r{r}c{c}");
                let centre = grid.cell_centre(c, r);
                p.name = Some(cname.clone());
                p.origins = Some(vec![[centre.x, centre.y, 0.0]]);
                p.fixed = Some(Vec::new());
                mesh.append(p.build()?);
                let oi = mesh.objects.len() as u32 - 1;
                let ring = mesh
                    .group(oi, "top_ring")
                    .map(|g| g.nodes.clone())
                    .unwrap_or_default();
                collars.push(((c, r), centre, ring));
                cages.push(cname);
            }
        }
        if cages.is_empty() {
            return Err(MeshError::param(
                obj,
                "slot",
                "(every slot empty)",
                "at least one slot must hold a cage",
            ));
        }
        let (frame_mesh, buoys_local, welds) = frame_object(
            &format!("{name}/frame"),
            &grid,
            &frame,
            &bridle,
            el,
            &mesh,
            &collars,
        )?;
        let off = mesh.append(frame_mesh);
        mesh.weld_tail(&welds);
        let buoys = buoys_local.into_iter().map(|n| n + off).collect();
        let plate_node = |i: usize, j: usize| off + grid.plate(i, j);
        let mut anchors = Vec::new();
        let span = -self.grid_depth - zb;
        let distance = match self.anchor_distance {
            Some(d) => length(obj, "anchor_distance", d)?,
            None => {
                let chord = ANCHOR_CHORD_FRACTION * self.anchor_length;
                if chord <= span {
                    return Err(MeshError::param(
                        obj,
                        "anchor_length",
                        self.anchor_length,
                        format!(
                            "must exceed the height of the grid above the seabed ([sea] depth \
                             {} m − grid_depth {} m = {span} m) by more than 3 % (or give \
                             anchor_distance)",
                            -zb, self.grid_depth
                        ),
                    ));
                }
                (chord * chord - span * span).sqrt()
            }
        };
        let anchor_el = self
            .anchor_segments
            .map_or(el, |n| self.anchor_length / f64::from(n));
        let mut parts = Vec::new();
        if let Some(ch) = &chain {
            parts.push(("chain", ch.clone(), chain_len));
        }
        parts.push(("rope", rope, self.anchor_length - chain_len));
        for (tag, i, j, dir) in grid.outer_plates() {
            let k = if matches!(tag, 'e' | 'w') {
                j + 1
            } else {
                i + 1
            };
            let aname = format!("{name}/anchor_{tag}{k}");
            let plate = grid.plate_position(i, j);
            let a = plate + dir * distance;
            let line = anchor_line(
                &aname,
                Point3::new(a.x, a.y, zb),
                plate,
                &parts,
                anchor_el,
                zb,
                self.initial_stretch,
            )?;
            mesh.append(line);
            mesh.weld_tail(&[plate_node(i, j)]);
            anchors.push(aname);
        }
        Ok(FarmMesh {
            mesh,
            buoys,
            cages,
            anchors,
        })
    }
}

impl FarmMesh {
    /// Counts per part.
    pub fn counts(&self, farm: &str) -> FarmCounts {
        let frame = self
            .mesh
            .objects
            .iter()
            .position(|o| o.name == format!("{farm}/frame"))
            .map(|o| o as u32);
        let group = |g: &str| frame.and_then(|o| self.mesh.group(o, g));
        FarmCounts {
            cages: self.cages.len(),
            plates: group("plates").map_or(0, |g| g.nodes.len()),
            buoys: self.buoys.len(),
            anchor_lines: self.anchors.len(),
            frame_elements: group("frame_lines").map_or(0, |g| g.lines.len()),
            bridles: 4 * self.cages.len(),
        }
    }
}

/// A length of the farm [m]: > 0 and within [`crate::limits::MAX_LENGTH`].
fn length(obj: &str, key: &str, v: f64) -> Result<f64> {
    crate::limits::length(obj, key, v, "")
}

fn missing_table(obj: &str, key: &str, who: &str) -> MeshError {
    MeshError::param(
        obj,
        key,
        "(missing)",
        format!(
            "[farm.{key}] is required for {who}: a section table with diameter, ea or \
             youngs_modulus, mass_per_length or density"
        ),
    )
}

/// The section of a farm line part from its table: diameter, EA (or E) and mass (or density)
/// are required, as for `[[line]]`.
fn line_section(
    obj: &str,
    key: &str,
    table: Option<&SectionOverride>,
    material: &str,
) -> Result<Section> {
    let t = table.ok_or_else(|| missing_table(obj, key, "every farm"))?;
    let need = |k: &str, ok: bool, what: &str| {
        if ok {
            Ok(())
        } else {
            Err(MeshError::param(
                obj,
                &format!("{key}.{k}"),
                "(missing)",
                what.to_string(),
            ))
        }
    };
    need(
        "diameter",
        t.diameter.is_some(),
        "required: the nominal diameter [m]",
    )?;
    need(
        "ea",
        t.ea.is_some() || t.youngs_modulus.is_some(),
        "give `ea` [N] or `youngs_modulus` [Pa]",
    )?;
    need(
        "mass_per_length",
        t.mass_per_length.is_some() || t.density.is_some(),
        "give `mass_per_length` [kg/m] or `density` [kg/m³]",
    )?;
    let mut s = Section::cable(material, 1.0, 0.0, 0.0);
    t.apply(obj, key, &mut s)?;
    Ok(s)
}

/// Number of elements of about `el` along `length` (at least one).
pub(super) fn segments(length: f64, el: f64) -> usize {
    (length / el).round().max(1.0) as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::CageType;
    use nalgebra::Vector3;

    fn section(d: f64) -> Option<SectionOverride> {
        Some(SectionOverride {
            diameter: Some(d),
            ea: Some(1e7),
            mass_per_length: Some(2.0),
            ..Default::default()
        })
    }

    fn farm(rows: u32, columns: u32) -> FarmParams {
        FarmParams {
            name: Some("f".into()),
            rows,
            columns,
            spacing: 40.0,
            grid_depth: 5.0,
            anchor_length: 120.0,
            anchor_segments: None,
            chain_length: Some(30.0),
            frame: section(0.05),
            bridle: section(0.04),
            anchor: section(0.05),
            chain: section(0.06),
            ..Default::default()
        }
    }

    fn cage() -> CageParams {
        let mut c = CageParams::new(CageType::Csm);
        c.diameter = Some(20.0);
        c.depth = Some(6.0);
        c.element_length = Some(4.0);
        c
    }

    #[test]
    fn counts_names_positions_and_joints() {
        let (r, c) = (2usize, 3usize);
        let f = farm(r as u32, c as u32)
            .build(&cage(), Some(-40.0))
            .unwrap();
        let n = f.counts("f");
        assert_eq!(n.cages, r * c);
        assert_eq!(n.plates, (r + 1) * (c + 1));
        assert_eq!(n.buoys, (r + 1) * (c + 1));
        assert_eq!(n.anchor_lines, 2 * (r + c + 2));
        // 40 m frame segments of 5 m elements.
        assert_eq!(n.frame_elements, (r * (c + 1) + c * (r + 1)) * 8);
        let m = &f.mesh;
        let names: Vec<&str> = m.objects.iter().map(|o| o.name.as_str()).collect();
        for want in [
            "f/cage_r1c1",
            "f/cage_r2c3",
            "f/frame",
            "f/anchor_n3",
            "f/anchor_w1",
        ] {
            assert!(names.contains(&want), "{want} not in {names:?}");
        }
        // Plates on the grid, centred on the origin.
        let plates = m.resolve_nodes("f/frame/plates").unwrap();
        assert_eq!(plates.len(), 12);
        let p0 = m.nodes[plates[0]];
        assert!((p0 - Point3::new(-60.0, -40.0, -5.0)).norm() < 1e-12);
        // Cage r1c2 centred in its cell, collar at z = 0 and free.
        let ring = m.resolve_nodes("f/cage_r1c2/top_ring").unwrap();
        let mean = ring
            .iter()
            .fold(Vector3::zeros(), |a, &i| a + m.nodes[i].coords)
            / ring.len() as f64;
        assert!((mean - Vector3::new(0.0, -20.0, 0.0)).norm() < 1e-9);
        let fixed = m.fixed_nodes();
        assert!(ring.iter().all(|i| !fixed.contains(i)));
        // Only the anchors are fixed, all on the seabed.
        assert_eq!(fixed.len(), n.anchor_lines);
        assert!(fixed.iter().all(|&i| (m.nodes[i].z + 40.0).abs() < 1e-12));
        // Every bridle runs from a plate to a collar node (welded: no free duplicate nodes).
        let fi = m.objects.iter().position(|o| o.name == "f/frame").unwrap() as u32;
        let bridles = m.group(fi, "bridles").unwrap();
        let ends: Vec<usize> = bridles
            .nodes
            .iter()
            .copied()
            .filter(|nd| ring.contains(nd) || plates.contains(nd))
            .collect();
        assert!(ends.iter().filter(|nd| ring.contains(nd)).count() == 4);
        // Anchor lines: chain then rope, the fairlead is the plate.
        let ai = m
            .objects
            .iter()
            .position(|o| o.name == "f/anchor_e1")
            .unwrap() as u32;
        let fair = m.group(ai, "fairlead").unwrap().nodes[0];
        assert!(plates.contains(&fair));
        let chain = m.group(ai, "chain").unwrap();
        let l: f64 = chain
            .lines
            .iter()
            .map(|&e| m.lines[e].rest_length.unwrap())
            .sum();
        assert!((l - 30.0).abs() < 1e-9);
        let rope = m.group(ai, "rope").unwrap();
        let l: f64 = rope
            .lines
            .iter()
            .map(|&e| m.lines[e].rest_length.unwrap())
            .sum();
        assert!((l - 90.0).abs() < 1e-9);
        // Nothing dangles: every node is used by an element.
        let mut used = vec![false; m.nodes.len()];
        for e in &m.lines {
            used[e.nodes[0]] = true;
            used[e.nodes[1]] = true;
        }
        assert!(used.iter().all(|u| *u));
    }

    #[test]
    fn slots_hold_their_own_cage_or_none() {
        // Slot (1, 2) an SSM of side 14 m, slot (1, 3) empty, the rest the CSM of `cage()`.
        let mut square = CageParams::new(CageType::Ssm);
        square.side = Some(14.0);
        square.depth = Some(6.0);
        square.element_length = Some(3.5);
        let slot = |_r: usize, c: usize| match c {
            2 => Some(square.clone()),
            3 => None,
            _ => Some(cage()),
        };
        let f = farm(2, 3).build_slots(slot, Some(-40.0)).unwrap();
        let names: Vec<&str> = f.cages.iter().map(String::as_str).collect();
        assert_eq!(
            names,
            ["f/cage_r1c1", "f/cage_r1c2", "f/cage_r2c1", "f/cage_r2c2"]
        );
        let n = f.counts("f");
        assert_eq!((n.cages, n.bridles), (4, 16));
        assert_eq!(n.plates, 12);
        let m = &f.mesh;
        assert!(!m.objects.iter().any(|o| o.name.ends_with("c3")));
        // The square collar (cages.md: half-width side/2 + frame_offset = 7 + 1 m): corner
        // nodes at (±8, ±8) from the cell centre (0, −20).
        let ring = m.resolve_nodes("f/cage_r1c2/top_ring").unwrap();
        let far = ring
            .iter()
            .map(|&i| (m.nodes[i] - Point3::new(0.0, -20.0, 0.0)).norm())
            .fold(0.0, f64::max);
        assert!((far - 8.0 * 2f64.sqrt()).abs() < 1e-9, "{far}");
        // 4 cages × 4 bridles, each ending on a collar node.
        let fi = m.objects.iter().position(|o| o.name == "f/frame").unwrap() as u32;
        let bridles = m.group(fi, "bridles").unwrap();
        let mut collar_ends = 0;
        for cage in &f.cages {
            let ring = m.resolve_nodes(&format!("{cage}/top_ring")).unwrap();
            collar_ends += bridles.nodes.iter().filter(|n| ring.contains(n)).count();
        }
        assert_eq!(collar_ends, 16);
        // Plates of the column-3 edge (i = 3) carry no bridle.
        let plates = m.resolve_nodes("f/frame/plates").unwrap();
        for j in 0..=2 {
            assert!(!bridles.nodes.contains(&plates[j * 4 + 3]));
        }
        let e = farm(1, 1)
            .build_slots(|_, _| None, Some(-40.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("at least one slot"), "{e}");
        let e = farm(1, 2)
            .build_slots(
                |_, c| {
                    let mut p = cage();
                    if c == 2 {
                        p.origins = Some(vec![[0.0; 3]]);
                    }
                    Some(p)
                },
                Some(-40.0),
            )
            .unwrap_err()
            .to_string();
        assert!(e.contains("slot r1c2: cage.origins"), "{e}");
    }

    #[test]
    fn bad_grids_and_missing_parts_are_named() {
        let err = |f: FarmParams| f.build(&cage(), Some(-40.0)).unwrap_err().to_string();
        let e = err(FarmParams {
            rows: 0,
            ..farm(1, 1)
        });
        assert!(e.contains("rows") && e.contains(">= 1"), "{e}");
        let e = err(FarmParams {
            frame: None,
            ..farm(1, 1)
        });
        assert!(e.contains("frame") && e.contains("[farm.frame]"), "{e}");
        let e = err(FarmParams {
            grid_depth: 50.0,
            ..farm(1, 1)
        });
        assert!(e.contains("grid_depth"), "{e}");
        let e = err(FarmParams {
            anchor_length: 20.0,
            anchor_segments: None,
            chain_length: None,
            chain: None,
            ..farm(1, 1)
        });
        assert!(e.contains("anchor_length"), "{e}");
        let mut c = cage();
        c.fixed = Some(vec!["top_ring".into()]);
        let e = farm(1, 1).build(&c, Some(-40.0)).unwrap_err().to_string();
        assert!(e.contains("cage.fixed"), "{e}");
        let e = farm(1, 1).build(&cage(), None).unwrap_err().to_string();
        assert!(e.contains("depth"), "{e}");
    }
}
