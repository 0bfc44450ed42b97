//! A multiblock time series: `<stem>.pvd` + `<stem>_NNNNNN.vtm` per step (+ block files).

use super::arrays::{StepArrays, check_arrays};
use super::block::{BlockTemplate, templates};
use super::layout::{BlockLayout, NameTables};
use super::multiblock::write_vtm;
use super::pvd::GrowingPvd;
use crate::error::MeshError;
use crate::error::Result;
use crate::model::Mesh;
use nalgebra::Point3;
use std::path::Path;
use std::path::PathBuf;

/// A multiblock time series `<stem>.pvd` + `<stem>_NNNNNN.vtm` (+ blocks in `<stem>_NNNNNN/`).
#[derive(Debug)]
pub struct MultiblockSeries {
    dir: PathBuf,
    stem: String,
    layout: BlockLayout,
    names: NameTables,
    /// The fixed part of every block's file, in layout order.
    templates: Vec<BlockTemplate>,
    pvd: GrowingPvd,
    step: usize,
}

impl MultiblockSeries {
    /// A new series of `mesh` in `dir` (created if needed). Nothing is written yet; files of an
    /// earlier series with the same stem (`<stem>_NNNNNN.vtm` and their directories) are
    /// removed so that the directory holds only what the new `.pvd` lists.
    pub fn new(dir: impl Into<PathBuf>, stem: &str, mesh: &Mesh) -> Result<Self> {
        let dir = dir.into();
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| MeshError::Io { path, source }
        };
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        let prefix = format!("{stem}_");
        if let Ok(entries) = std::fs::read_dir(&dir) {
            for e in entries.flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                let Some(rest) = name.strip_prefix(&prefix) else {
                    continue;
                };
                let digits = rest.strip_suffix(".vtm").or(rest.strip_suffix(".vtu"));
                let is_step = |s: &str| s.len() == 6 && s.bytes().all(|b| b.is_ascii_digit());
                if digits.is_some_and(is_step) {
                    let _ = std::fs::remove_file(e.path());
                } else if is_step(rest) && e.path().is_dir() {
                    let _ = std::fs::remove_dir_all(e.path());
                }
            }
        }
        let layout = BlockLayout::new(mesh);
        let names = NameTables::new(mesh, &layout);
        let templates = templates(mesh, &layout);
        let pvd_path = dir.join(format!("{stem}.pvd"));
        // A `.pvd` left by an earlier run lists files that were just removed.
        let _ = std::fs::remove_file(&pvd_path);
        Ok(MultiblockSeries {
            pvd: GrowingPvd {
                path: pvd_path,
                entries: Vec::new(),
                file: None,
            },
            dir,
            stem: stem.to_string(),
            layout,
            names,
            templates,
            step: 0,
        })
    }

    /// The block layout.
    pub fn layout(&self) -> &BlockLayout {
        &self.layout
    }

    /// The name tables.
    pub fn names(&self) -> &NameTables {
        &self.names
    }

    /// Path of the `.pvd`.
    pub fn pvd_path(&self) -> &Path {
        &self.pvd.path
    }

    /// `(time, .vtm file relative to the .pvd)` of the steps written.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.pvd.entries
    }

    fn check(&self, mesh: &Mesh, positions: &[Point3<f64>], arrays: &StepArrays) -> Result<()> {
        if positions.len() != mesh.nodes.len() {
            return Err(MeshError::VtkArray {
                location: "point",
                name: "positions".into(),
                message: format!(
                    "{} positions for {} nodes",
                    positions.len(),
                    mesh.nodes.len()
                ),
            });
        }
        if let Some(i) = positions
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            return Err(MeshError::VtkArray {
                location: "point",
                name: "positions".into(),
                message: format!("node {i} has a non-finite coordinate"),
            });
        }
        check_arrays(&arrays.point, mesh.nodes.len(), "point")?;
        check_arrays(&arrays.line, mesh.lines.len(), "line cell")?;
        check_arrays(&arrays.panel, mesh.panels.len(), "panel cell")
    }

    /// Writes the undeformed geometry once as `<stem>_reference.vtm` (+ `<stem>_reference/`),
    /// same blocks and points as every step, built-in arrays only. Returns the `.vtm` path.
    pub fn write_reference(&self, mesh: &Mesh) -> Result<PathBuf> {
        let empty = StepArrays::default();
        let name = format!("{}_reference", self.stem);
        write_vtm(
            &self.dir,
            &name,
            &self.layout,
            &self.templates,
            &mesh.nodes,
            None,
            &empty,
        )
    }

    /// Writes one step at `time` [s] (after the previous step) and lists it in the `.pvd`.
    /// `mesh` is the mesh the series was made for (its block files' fixed parts were rendered
    /// from it). Returns the `.vtm` path.
    pub fn write_step(
        &mut self,
        time: f64,
        mesh: &Mesh,
        positions: &[Point3<f64>],
        arrays: &StepArrays,
    ) -> Result<PathBuf> {
        let bad = |m: String| MeshError::VtkArray {
            location: "pvd",
            name: "time".into(),
            message: m,
        };
        if !time.is_finite() {
            return Err(bad(format!("time {time} is not finite")));
        }
        if let Some(&(last, _)) = self.pvd.entries.last()
            && time <= last
        {
            return Err(bad(format!(
                "time {time} s is not after the previous step {last} s"
            )));
        }
        self.check(mesh, positions, arrays)?;
        let name = format!("{}_{:06}", self.stem, self.step);
        let vtm = write_vtm(
            &self.dir,
            &name,
            &self.layout,
            &self.templates,
            positions,
            Some(time),
            arrays,
        )?;
        self.pvd.add(time, format!("{name}.vtm"))?;
        self.step += 1;
        Ok(vtm)
    }
}
