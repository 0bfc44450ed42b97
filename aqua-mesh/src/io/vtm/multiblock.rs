//! The `.vtm` multiblock index and its block files: written with a temporary name and renamed,
//! removed again on an error; the geometry of a mesh as one multiblock file.

use super::arrays::StepArrays;
use super::block::{BlockTemplate, templates};
use super::layout::BlockLayout;
use super::xml::xml_escape;
use crate::error::MeshError;
use crate::error::Result;
use crate::model::Mesh;
use nalgebra::Point3;
use std::fmt::Write as _;
use std::path::Path;
use std::path::PathBuf;

/// Write `path` by filling a temporary file next to it and renaming it into place (no fsync:
/// atomic against the process stopping, not against a power cut).
pub(super) fn write_replace(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let fname = path
        .file_name()
        .map_or_else(String::new, |f| f.to_string_lossy().into_owned());
    let tmp = dir.join(format!(".{fname}.tmp{}", std::process::id()));
    let result = std::fs::write(&tmp, bytes).and_then(|_| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)
}

pub(super) fn vtm_text(layout: &BlockLayout, subdir: &str) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <vtkMultiBlockDataSet>\n",
    );
    let mut i = 0;
    let mut top = 0;
    while i < layout.blocks.len() {
        let label = &layout.blocks[i].object_label;
        let (o, c) = (layout.blocks[i].object, layout.blocks[i].copy);
        let _ = writeln!(
            s,
            "    <Block index=\"{top}\" name=\"{}\">",
            xml_escape(label)
        );
        let mut k = 0;
        while i < layout.blocks.len() && (layout.blocks[i].object, layout.blocks[i].copy) == (o, c)
        {
            let b = &layout.blocks[i];
            let _ = writeln!(
                s,
                "      <DataSet index=\"{k}\" name=\"{}\" file=\"{}/{}\"/>",
                b.kind.as_str(),
                xml_escape(subdir),
                xml_escape(&b.file)
            );
            i += 1;
            k += 1;
        }
        s.push_str("    </Block>\n");
        top += 1;
    }
    s.push_str("  </vtkMultiBlockDataSet>\n</VTKFile>\n");
    s
}

/// Writes the blocks into `<dir>/<name>/`, then `<dir>/<name>.vtm` (temporary name + rename: a
/// `.vtm` under its final name is always complete). On an error, what was written is removed
/// again. Returns the `.vtm` path.
pub(super) fn write_vtm(
    dir: &Path,
    name: &str,
    layout: &BlockLayout,
    templates: &[BlockTemplate],
    positions: &[Point3<f64>],
    time: Option<f64>,
    arrays: &StepArrays,
) -> Result<PathBuf> {
    let sub = dir.join(name);
    let vtm = dir.join(format!("{name}.vtm"));
    let result = (|| {
        std::fs::create_dir_all(&sub).map_err(|source| MeshError::Io {
            path: sub.clone(),
            source,
        })?;
        for (b, tpl) in layout.blocks.iter().zip(templates) {
            // Written in place: the block is reachable only through the `.vtm`, which is
            // written after it.
            let path = sub.join(&b.file);
            let text = tpl.render(b, positions, time, arrays);
            std::fs::write(&path, text).map_err(|source| MeshError::Io { path, source })?;
        }
        write_replace(&vtm, vtm_text(layout, name).as_bytes())
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&vtm);
        let _ = std::fs::remove_dir_all(&sub);
        return Err(e);
    }
    Ok(vtm)
}

/// Writes the undeformed geometry of `mesh` as the multiblock file `path` (`<stem>.vtm`) with
/// its block files in `<stem>/` next to it: the blocks, points and built-in arrays of a run's
/// `<stem>_reference.vtm` ([`MultiblockSeries::write_reference`](super::MultiblockSeries::write_reference)), without a time. The
/// directory `<stem>/` is replaced. Returns the `.vtm` path.
pub fn write_geometry(path: &Path, mesh: &Mesh) -> Result<PathBuf> {
    let bad = |path: &Path, m: &str| MeshError::VtkPath {
        path: path.to_path_buf(),
        message: m.to_string(),
    };
    if path.extension().and_then(|e| e.to_str()) != Some("vtm") {
        return Err(bad(path, "a multiblock file name must end in .vtm"));
    }
    let name = path
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty())
        .ok_or_else(|| bad(path, "the file name needs a UTF-8 stem before .vtm"))?;
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|source| MeshError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    // The block directory is cleared, which is only safe if it holds nothing but block files.
    let sub = dir.join(name);
    if sub.exists() {
        let foreign = std::fs::read_dir(&sub)
            .map_err(|source| MeshError::Io {
                path: sub.clone(),
                source,
            })?
            .flatten()
            .any(|e| {
                !(e.path().is_file()
                    && e.path().extension().and_then(|x| x.to_str()) == Some("vtu"))
            });
        if foreign {
            return Err(bad(
                &sub,
                "the block directory exists and holds files other than .vtu; \
                 choose another .vtm name or remove the directory",
            ));
        }
        std::fs::remove_dir_all(&sub).map_err(|source| MeshError::Io {
            path: sub.clone(),
            source,
        })?;
    }
    let layout = BlockLayout::new(mesh);
    let templates = templates(mesh, &layout);
    write_vtm(
        dir,
        name,
        &layout,
        &templates,
        &mesh.nodes,
        None,
        &StepArrays::default(),
    )
}
