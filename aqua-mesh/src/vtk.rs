//! VTK export: XML `.vtu` unstructured grids (through `vtkio`) and `.pvd` time collections.
//!
//! Cells: every line element as `VTK_LINE` (3), then every panel as `VTK_TRIANGLE` (5) or
//! `VTK_QUAD` (9), nodes in the mesh's cyclic order. Cell index c < `mesh.lines.len()` is line c,
//! otherwise panel c − `mesh.lines.len()`.
//!
//! Built-in arrays — point: `object_id`, `copy_id`, `fixed` (1 = fixed), `point_weight` [N];
//! cell: `group_id` (index in `mesh.groups`), `role_id` ([`crate::Role::id`]), `object_id`,
//! `copy_id`, `diameter`, `elastic_diameter`, `hydro_diameter` [m] (line groups: their section;
//! panels: the physical twine diameter dw0), `solidity` (panels; 0 for lines). Callers add their
//! own arrays (displacement, tension, wake factor, …) with [`VtkArrays`].
//!
//! Files are written to a temporary file in the same directory and renamed into place, so an
//! interrupted run never leaves a half-written file under the final name.

use crate::error::{MeshError, Result};
use crate::mesh::{Mesh, PanelNodes};
use nalgebra::{Point3, Vector3};
use std::io::Write;
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, IOBuffer,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

/// A named point or cell array with `components` values per point/cell.
#[derive(Debug, Clone, PartialEq)]
pub struct VtkArray {
    /// Array name as shown in ParaView.
    pub name: String,
    /// Values per entry (1 scalar, 3 vector, …).
    pub components: usize,
    /// `components × count` values, entry-major.
    pub values: Vec<f64>,
}

impl VtkArray {
    /// Scalar array.
    pub fn scalar(name: impl Into<String>, values: Vec<f64>) -> Self {
        VtkArray {
            name: name.into(),
            components: 1,
            values,
        }
    }

    /// 3-component vector array.
    pub fn vectors(name: impl Into<String>, values: &[Vector3<f64>]) -> Self {
        VtkArray {
            name: name.into(),
            components: 3,
            values: values.iter().flat_map(|v| [v.x, v.y, v.z]).collect(),
        }
    }
}

/// Extra point and cell arrays for [`write_vtu`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VtkArrays {
    /// Per node (mesh node order).
    pub point: Vec<VtkArray>,
    /// Per cell (lines, then panels).
    pub cell: Vec<VtkArray>,
}

const POINT_BUILTIN: [&str; 4] = ["object_id", "copy_id", "fixed", "point_weight"];
const CELL_BUILTIN: [&str; 8] = [
    "group_id",
    "role_id",
    "object_id",
    "copy_id",
    "diameter",
    "elastic_diameter",
    "hydro_diameter",
    "solidity",
];

fn check(arrays: &[VtkArray], n: usize, location: &'static str, builtin: &[&str]) -> Result<()> {
    let err = |a: &VtkArray, m: String| MeshError::VtkArray {
        location,
        name: a.name.clone(),
        message: m,
    };
    for (k, a) in arrays.iter().enumerate() {
        if a.name.is_empty() || a.name.contains(['"', '<', '>', '&']) {
            return Err(err(a, "name must be non-empty without \" < > &".into()));
        }
        if builtin.contains(&a.name.as_str()) || arrays[..k].iter().any(|b| b.name == a.name) {
            return Err(err(
                a,
                format!("name is already used (built-in: {})", builtin.join(", ")),
            ));
        }
        if a.components == 0 || a.values.len() != a.components * n {
            return Err(err(
                a,
                format!(
                    "has {} values; expected {} components × {n} = {}",
                    a.values.len(),
                    a.components,
                    a.components * n
                ),
            ));
        }
        if let Some(i) = a.values.iter().position(|v| !v.is_finite()) {
            return Err(err(
                a,
                format!(
                    "value {} (entry {}) is not finite",
                    a.values[i],
                    i / a.components
                ),
            ));
        }
    }
    Ok(())
}

fn f64_attr(name: &str, components: usize, values: Vec<f64>) -> Attribute {
    Attribute::DataArray(DataArray {
        name: name.to_string(),
        elem: if components == 1 {
            ElementType::Scalars {
                num_comp: 1,
                lookup_table: None,
            }
        } else {
            ElementType::Generic(components as u32)
        },
        data: IOBuffer::F64(values),
    })
}

fn i32_attr(name: &str, values: Vec<i32>) -> Attribute {
    Attribute::DataArray(DataArray {
        name: name.to_string(),
        elem: ElementType::Scalars {
            num_comp: 1,
            lookup_table: None,
        },
        data: IOBuffer::I32(values),
    })
}

/// Write `path` atomically: `write` fills a temporary file next to it, which is then synced and
/// renamed over `path`.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let io = |source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let fname = path.file_name().ok_or_else(|| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "path has no file name",
        ))
    })?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        fname.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let f = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(f);
        write(&mut w)?;
        w.flush()?;
        w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)
}

/// Write the mesh as an XML `.vtu` file (binary-base64 data arrays, little endian).
///
/// `positions` (one per node) replace the mesh's node positions, e.g. the deformed shape;
/// `extra` adds caller arrays. All values must be finite.
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    positions: Option<&[Point3<f64>]>,
    extra: &VtkArrays,
) -> Result<()> {
    let n = mesh.nodes.len();
    let nc = mesh.cell_count();
    let pts = positions.unwrap_or(&mesh.nodes);
    if pts.len() != n {
        return Err(MeshError::VtkArray {
            location: "point",
            name: "positions".into(),
            message: format!("{} positions for {n} nodes", pts.len()),
        });
    }
    if let Some(i) = pts.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(MeshError::VtkArray {
            location: "point",
            name: "positions".into(),
            message: format!("node {i} has a non-finite coordinate"),
        });
    }
    check(&extra.point, n, "point", &POINT_BUILTIN)?;
    check(&extra.cell, nc, "cell", &CELL_BUILTIN)?;

    let mut connectivity = Vec::with_capacity(2 * mesh.lines.len() + 4 * mesh.panels.len());
    let mut offsets = Vec::with_capacity(nc);
    let mut types = Vec::with_capacity(nc);
    for l in &mesh.lines {
        connectivity.extend(l.nodes.iter().map(|&i| i as u64));
        offsets.push(connectivity.len() as u64);
        types.push(CellType::Line);
    }
    for p in &mesh.panels {
        connectivity.extend(p.nodes.as_slice().iter().map(|&i| i as u64));
        offsets.push(connectivity.len() as u64);
        types.push(match p.nodes {
            PanelNodes::Tri(_) => CellType::Triangle,
            PanelNodes::Quad(_) => CellType::Quad,
        });
    }

    // Point arrays.
    let mut fixed = vec![0i32; n];
    for i in mesh.fixed_nodes() {
        fixed[i] = 1;
    }
    let mut weight = vec![0.0; n];
    for w in &mesh.weights {
        weight[w.node] += w.weight;
    }
    let mut point = vec![
        i32_attr(
            "object_id",
            mesh.node_owner.iter().map(|o| o.0 as i32).collect(),
        ),
        i32_attr(
            "copy_id",
            mesh.node_owner.iter().map(|o| o.1 as i32).collect(),
        ),
        i32_attr("fixed", fixed),
        f64_attr("point_weight", 1, weight),
    ];
    point.extend(
        extra
            .point
            .iter()
            .map(|a| f64_attr(&a.name, a.components, a.values.clone())),
    );

    // Cell arrays.
    let mut group_id = Vec::with_capacity(nc);
    let mut role_id = Vec::with_capacity(nc);
    let mut object_id = Vec::with_capacity(nc);
    let mut copy_id = Vec::with_capacity(nc);
    let mut d = Vec::with_capacity(nc);
    let mut de = Vec::with_capacity(nc);
    let mut dh = Vec::with_capacity(nc);
    let mut sn = Vec::with_capacity(nc);
    for l in &mesh.lines {
        let g = &mesh.groups[l.group];
        group_id.push(l.group as i32);
        role_id.push(g.role.id() as i32);
        object_id.push(l.object as i32);
        copy_id.push(l.copy as i32);
        // The element's own diameters: its section scale multiplies areas.
        let s = g.section.as_ref();
        let r = l.section_scale.sqrt();
        d.push(s.map_or(0.0, |s| s.diameter * r));
        de.push(s.map_or(0.0, |s| s.elastic_diameter * r));
        dh.push(s.map_or(0.0, |s| s.hydro_diameter * l.section_scale));
        sn.push(0.0);
    }
    for p in &mesh.panels {
        let g = &mesh.groups[p.group];
        group_id.push(p.group as i32);
        role_id.push(g.role.id() as i32);
        object_id.push(p.object as i32);
        copy_id.push(p.copy as i32);
        let net = mesh.objects[p.object as usize].net.as_ref();
        let dw0 = net.map_or(0.0, |n| n.twine_diameter);
        d.push(dw0);
        de.push(dw0);
        dh.push(dw0);
        sn.push(net.map_or(0.0, |n| n.solidity));
    }
    let mut cell = vec![
        i32_attr("group_id", group_id),
        i32_attr("role_id", role_id),
        i32_attr("object_id", object_id),
        i32_attr("copy_id", copy_id),
        f64_attr("diameter", 1, d),
        f64_attr("elastic_diameter", 1, de),
        f64_attr("hydro_diameter", 1, dh),
        f64_attr("solidity", 1, sn),
    ];
    cell.extend(
        extra
            .cell
            .iter()
            .map(|a| f64_attr(&a.name, a.components, a.values.clone())),
    );

    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: IOBuffer::F64(pts.iter().flat_map(|p| [p.x, p.y, p.z]).collect()),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types,
            },
            data: Attributes { point, cell },
        }),
    };
    let mut buf = Vec::new();
    vtk.write_xml(&mut buf).map_err(|e| MeshError::VtkWrite {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    write_atomic(path, |w| w.write_all(&buf))
}

/// A `.pvd` collection of time steps, rewritten (atomically) after every change so that it
/// always lists exactly the step files written so far.
#[derive(Debug, Clone, PartialEq)]
pub struct PvdWriter {
    path: PathBuf,
    entries: Vec<(f64, String)>,
}

impl PvdWriter {
    /// A collection to be written at `path` (nothing is written until [`PvdWriter::add`]).
    pub fn new(path: impl Into<PathBuf>) -> Self {
        PvdWriter {
            path: path.into(),
            entries: Vec::new(),
        }
    }

    /// Path of the `.pvd` file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// `(time [s], file relative to the .pvd)` entries.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    fn relative(&self, file: &Path) -> String {
        let dir = self.path.parent().unwrap_or(Path::new(""));
        file.strip_prefix(dir)
            .unwrap_or(file)
            .to_string_lossy()
            .replace('\\', "/")
    }

    /// Add an existing step file at `time` [s] (finite, strictly after the previous one) and
    /// rewrite the collection.
    pub fn add(&mut self, time: f64, file: &Path) -> Result<()> {
        let bad = |m: String| MeshError::VtkArray {
            location: "pvd",
            name: "time".into(),
            message: m,
        };
        if !time.is_finite() {
            return Err(bad(format!("time {time} is not finite")));
        }
        if let Some(&(last, _)) = self.entries.last()
            && time <= last
        {
            return Err(bad(format!(
                "time {time} s is not after the previous step {last} s"
            )));
        }
        if !file.exists() {
            return Err(MeshError::Io {
                path: file.to_path_buf(),
                source: std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "step file does not exist; write it before adding it to the collection",
                ),
            });
        }
        let rel = self.relative(file);
        self.entries.push((time, rel));
        self.write()
    }

    /// Drop entries whose files no longer exist, and rewrite.
    pub fn retain_existing(&mut self) -> Result<()> {
        let dir = self.path.parent().unwrap_or(Path::new("")).to_path_buf();
        self.entries.retain(|(_, f)| dir.join(f).exists());
        self.write()
    }

    /// Write the collection now.
    pub fn write(&self) -> Result<()> {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
             byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, f) in &self.entries {
            let f = f
                .replace('&', "&amp;")
                .replace('"', "&quot;")
                .replace('<', "&lt;");
            s.push_str(&format!(
                "    <DataSet timestep=\"{t:e}\" group=\"\" part=\"0\" file=\"{f}\"/>\n"
            ));
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        write_atomic(&self.path, |w| w.write_all(s.as_bytes()))
    }
}

/// A time series of `.vtu` files `<stem>_<step:06>.vtu` in `dir` plus `<stem>.pvd`.
#[derive(Debug, Clone, PartialEq)]
pub struct VtuSeries {
    dir: PathBuf,
    stem: String,
    pvd: PvdWriter,
    step: usize,
}

impl VtuSeries {
    /// New series; creates `dir` if needed.
    pub fn new(dir: impl Into<PathBuf>, stem: &str) -> Result<Self> {
        let dir = dir.into();
        std::fs::create_dir_all(&dir).map_err(|source| MeshError::Io {
            path: dir.clone(),
            source,
        })?;
        Ok(VtuSeries {
            pvd: PvdWriter::new(dir.join(format!("{stem}.pvd"))),
            dir,
            stem: stem.to_string(),
            step: 0,
        })
    }

    /// Write one step at `time` [s] and update the `.pvd`; returns the step file's path.
    pub fn write_step(
        &mut self,
        time: f64,
        mesh: &Mesh,
        positions: Option<&[Point3<f64>]>,
        extra: &VtkArrays,
    ) -> Result<PathBuf> {
        if let Some(&(last, _)) = self.pvd.entries().last()
            && !(time > last)
        {
            return Err(MeshError::VtkArray {
                location: "pvd",
                name: "time".into(),
                message: format!("time {time} s is not after the previous step {last} s"),
            });
        }
        let file = self.dir.join(format!("{}_{:06}.vtu", self.stem, self.step));
        write_vtu(&file, mesh, positions, extra)?;
        self.pvd.add(time, &file)?;
        self.step += 1;
        Ok(file)
    }

    /// The collection.
    pub fn pvd(&self) -> &PvdWriter {
        &self.pvd
    }
}
