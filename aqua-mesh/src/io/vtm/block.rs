//! The `.vtu` file of one block: the parts that are the same every step rendered once
//! ([`BlockTemplate`]), a step's time, arrays and points put between them.

use super::arrays::StepArrays;
use super::layout::{BlockKind, BlockLayout, BlockSpec};
use super::xml::{array_subset, b64_into, data_array, f64_bytes, i32_bytes, i64_bytes};
use crate::model::Mesh;
use crate::model::PanelNodes;
use nalgebra::Point3;
use std::fmt::Write as _;

/// Per-mesh data computed once: fixed flags and point weights per node.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct NodeData {
    fixed: Vec<i32>,
    weight: Vec<f64>,
}

/// The parts of a block's `.vtu` that are the same every step (ids, names, sections,
/// connectivity), rendered once; [`BlockTemplate::render`] puts a step's time, arrays and
/// points between them.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct BlockTemplate {
    /// Up to the field data's first array; the field data after `TimeValue` up to the
    /// built-in point arrays; the built-in cell arrays; the opening of `<Points>`; the cells
    /// and closing tags.
    parts: [String; 5],
}

impl BlockTemplate {
    pub(super) fn new(mesh: &Mesh, spec: &BlockSpec, nd: &NodeData) -> Self {
        let mut local = std::collections::HashMap::with_capacity(spec.nodes.len());
        for (k, &n) in spec.nodes.iter().enumerate() {
            local.insert(n, k as i64);
        }
        let mut conn: Vec<i64> = Vec::new();
        let mut offsets: Vec<i64> = Vec::new();
        let mut types: Vec<u8> = Vec::new();
        match spec.kind {
            BlockKind::Lines => {
                for &e in &spec.cells {
                    conn.extend(mesh.lines[e].nodes.iter().map(|n| local[n]));
                    offsets.push(conn.len() as i64);
                    types.push(3);
                }
            }
            BlockKind::Panels => {
                for &p in &spec.cells {
                    let pn = &mesh.panels[p].nodes;
                    conn.extend(pn.as_slice().iter().map(|n| local[n]));
                    offsets.push(conn.len() as i64);
                    types.push(match pn {
                        PanelNodes::Tri(_) => 5,
                        PanelNodes::Quad(_) => 9,
                    });
                }
            }
            BlockKind::Points => {
                for k in 0..spec.nodes.len() {
                    conn.push(k as i64);
                    offsets.push(k as i64 + 1);
                    types.push(1);
                }
            }
        }
        let mut parts: [String; 5] = Default::default();
        let mut s = String::new();
        s.push_str(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n    \
         <FieldData>\n",
        );
        parts[0] = std::mem::take(&mut s);
        let _ = writeln!(
            s,
            "    </FieldData>\n    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
            spec.nodes.len(),
            types.len()
        );
        // Point data.
        s.push_str("      <PointData>\n");
        let nodes = &spec.nodes;
        let ids: Vec<i32> = nodes.iter().map(|&n| n as i32).collect();
        data_array(&mut s, "Int32", "node_id", 1, &i32_bytes(&ids));
        let own: Vec<i32> = nodes.iter().map(|&n| mesh.node_owner[n].0 as i32).collect();
        data_array(&mut s, "Int32", "object_id", 1, &i32_bytes(&own));
        let cp: Vec<i32> = nodes.iter().map(|&n| mesh.node_owner[n].1 as i32).collect();
        data_array(&mut s, "Int32", "copy_id", 1, &i32_bytes(&cp));
        let fx: Vec<i32> = nodes.iter().map(|&n| nd.fixed[n]).collect();
        data_array(&mut s, "Int32", "fixed", 1, &i32_bytes(&fx));
        let w: Vec<f64> = nodes.iter().map(|&n| nd.weight[n]).collect();
        data_array(&mut s, "Float64", "point_weight", 1, &f64_bytes(&w));
        parts[1] = std::mem::take(&mut s);
        s.push_str("      </PointData>\n      <CellData>\n");
        // Cell data.
        match spec.kind {
            BlockKind::Lines => {
                let c = &spec.cells;
                let ids: Vec<i32> = c.iter().map(|&e| e as i32).collect();
                data_array(&mut s, "Int32", "element_id", 1, &i32_bytes(&ids));
                let lines = || c.iter().map(|&e| &mesh.lines[e]);
                let g: Vec<i32> = lines().map(|l| l.group as i32).collect();
                data_array(&mut s, "Int32", "group_id", 1, &i32_bytes(&g));
                let r: Vec<i32> = lines()
                    .map(|l| mesh.groups[l.group].role.id() as i32)
                    .collect();
                data_array(&mut s, "Int32", "role_id", 1, &i32_bytes(&r));
                let o: Vec<i32> = lines().map(|l| l.object as i32).collect();
                data_array(&mut s, "Int32", "object_id", 1, &i32_bytes(&o));
                let cp: Vec<i32> = lines().map(|l| l.copy as i32).collect();
                data_array(&mut s, "Int32", "copy_id", 1, &i32_bytes(&cp));
                // The element's own diameters: its section scale k multiplies areas.
                type Diam = fn(&crate::Section, f64) -> f64;
                let diam: [(&str, Diam); 3] = [
                    ("diameter", |s, k| s.diameter * k.sqrt()),
                    ("elastic_diameter", |s, k| s.elastic_diameter * k.sqrt()),
                    ("hydro_diameter", |s, k| s.hydro_diameter * k),
                ];
                for (name, f) in diam {
                    let d: Vec<f64> = lines()
                        .map(|l| {
                            mesh.groups[l.group]
                                .section
                                .as_ref()
                                .map_or(0.0, |s| f(s, l.section_scale))
                        })
                        .collect();
                    data_array(&mut s, "Float64", name, 1, &f64_bytes(&d));
                }
            }
            BlockKind::Panels => {
                let c = &spec.cells;
                let ids: Vec<i32> = c.iter().map(|&e| e as i32).collect();
                data_array(&mut s, "Int32", "panel_id", 1, &i32_bytes(&ids));
                let panels = || c.iter().map(|&e| &mesh.panels[e]);
                let g: Vec<i32> = panels().map(|p| p.group as i32).collect();
                data_array(&mut s, "Int32", "group_id", 1, &i32_bytes(&g));
                let r: Vec<i32> = panels()
                    .map(|p| mesh.groups[p.group].role.id() as i32)
                    .collect();
                data_array(&mut s, "Int32", "role_id", 1, &i32_bytes(&r));
                let o: Vec<i32> = panels().map(|p| p.object as i32).collect();
                data_array(&mut s, "Int32", "object_id", 1, &i32_bytes(&o));
                let cp: Vec<i32> = panels().map(|p| p.copy as i32).collect();
                data_array(&mut s, "Int32", "copy_id", 1, &i32_bytes(&cp));
                let net = |p: &crate::Panel| {
                    mesh.objects
                        .get(p.object as usize)
                        .and_then(|o| o.net.as_ref())
                };
                let dw: Vec<f64> = panels()
                    .map(|p| net(p).map_or(0.0, |n| n.twine_diameter))
                    .collect();
                data_array(&mut s, "Float64", "twine_diameter", 1, &f64_bytes(&dw));
                let sn: Vec<f64> = panels()
                    .map(|p| net(p).map_or(0.0, |n| n.solidity))
                    .collect();
                data_array(&mut s, "Float64", "solidity", 1, &f64_bytes(&sn));
            }
            BlockKind::Points => {}
        }
        parts[2] = std::mem::take(&mut s);
        s.push_str("      </CellData>\n      <Points>\n");
        parts[3] = std::mem::take(&mut s);
        s.push_str("      </Points>\n      <Cells>\n");
        data_array(&mut s, "Int64", "connectivity", 1, &i64_bytes(&conn));
        data_array(&mut s, "Int64", "offsets", 1, &i64_bytes(&offsets));
        data_array(&mut s, "UInt8", "types", 1, &types);
        s.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
        parts[4] = s;
        BlockTemplate { parts }
    }

    /// The block's `.vtu` at `time` (none: the reference) with the caller's arrays.
    pub(super) fn render(
        &self,
        spec: &BlockSpec,
        positions: &[Point3<f64>],
        time: Option<f64>,
        arrays: &StepArrays,
    ) -> String {
        let p = &self.parts;
        let n = spec.nodes.len();
        let per_point: usize = arrays
            .point
            .iter()
            .map(|a| 8 * a.components())
            .sum::<usize>()
            + 24;
        let per_cell: usize = 8 * (arrays.line.len() + arrays.panel.len());
        let cap = p.iter().map(String::len).sum::<usize>()
            + (n * per_point + spec.cells.len() * per_cell) * 4 / 3
            + 512 * (arrays.point.len() + arrays.line.len() + arrays.panel.len() + 2);
        let mut s = String::with_capacity(cap);
        s.push_str(&p[0]);
        if let Some(t) = time {
            s.push_str(
                "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" \
                 format=\"binary\">\n        ",
            );
            b64_into(&mut s, &t.to_le_bytes());
            s.push_str("\n      </DataArray>\n");
        }
        s.push_str(&p[1]);
        for a in &arrays.point {
            array_subset(&mut s, a, &spec.nodes);
        }
        s.push_str(&p[2]);
        let cell_arrays = match spec.kind {
            BlockKind::Lines => arrays.line.as_slice(),
            BlockKind::Panels => arrays.panel.as_slice(),
            BlockKind::Points => &[],
        };
        for a in cell_arrays {
            array_subset(&mut s, a, &spec.cells);
        }
        s.push_str(&p[3]);
        let pts: Vec<f64> = spec
            .nodes
            .iter()
            .flat_map(|&n| {
                let p = positions[n];
                [p.x, p.y, p.z]
            })
            .collect();
        data_array(&mut s, "Float64", "Points", 3, &f64_bytes(&pts));
        s.push_str(&p[4]);
        s
    }
}

/// The fixed part of every block's file of `layout`, in layout order.
pub(super) fn templates(mesh: &Mesh, layout: &BlockLayout) -> Vec<BlockTemplate> {
    let mut fixed = vec![0i32; mesh.nodes.len()];
    for i in mesh.fixed_nodes() {
        fixed[i] = 1;
    }
    let mut weight = vec![0.0; mesh.nodes.len()];
    for w in &mesh.weights {
        weight[w.node] += w.weight;
    }
    let nodes = NodeData { fixed, weight };
    layout
        .blocks
        .iter()
        .map(|b| BlockTemplate::new(mesh, b, &nodes))
        .collect()
}
