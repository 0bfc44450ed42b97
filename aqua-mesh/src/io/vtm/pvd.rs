//! The `.pvd` collection of a time series, grown by one `<DataSet>` line per step in place.

use super::multiblock::write_replace;
use super::xml::xml_escape;
use crate::error::MeshError;
use crate::error::Result;
use std::io::Write;
use std::io::{Seek, SeekFrom};
use std::path::PathBuf;

/// A `.pvd` collection that grows by one `<DataSet>` line per step, written in place.
#[derive(Debug)]
pub(super) struct GrowingPvd {
    pub(super) path: PathBuf,
    pub(super) entries: Vec<(f64, String)>,
    /// Open file and the byte offset of its closing tags.
    pub(super) file: Option<(std::fs::File, u64)>,
}

pub(super) const PVD_HEAD: &str = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
                        byte_order=\"LittleEndian\">\n  <Collection>\n";
pub(super) const PVD_TAIL: &str = "  </Collection>\n</VTKFile>\n";

pub(super) fn pvd_line(t: f64, f: &str) -> String {
    format!(
        "    <DataSet timestep=\"{t:e}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
        xml_escape(f)
    )
}

impl GrowingPvd {
    pub(super) fn rewrite(&mut self) -> Result<()> {
        let mut s = String::from(PVD_HEAD);
        for (t, f) in &self.entries {
            s.push_str(&pvd_line(*t, f));
        }
        let body = s.len() as u64;
        s.push_str(PVD_TAIL);
        write_replace(&self.path, s.as_bytes())?;
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(&self.path)
            .map_err(|source| MeshError::Io {
                path: self.path.clone(),
                source,
            })?;
        self.file = Some((f, body));
        Ok(())
    }

    pub(super) fn add(&mut self, t: f64, file: String) -> Result<()> {
        let line = pvd_line(t, &file);
        self.entries.push((t, file));
        let Some((f, body)) = self.file.as_mut() else {
            return self.rewrite();
        };
        // One write of the new line and the closing tags over the old closing tags.
        let text = format!("{line}{PVD_TAIL}");
        let r = f
            .seek(SeekFrom::Start(*body))
            .and_then(|_| f.write_all(text.as_bytes()));
        match r {
            Ok(()) => {
                *body += line.len() as u64;
                Ok(())
            }
            Err(_) => self.rewrite(),
        }
    }
}
