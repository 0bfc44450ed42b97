//! Low-level MSH readers: format detection, `$PhysicalNames`, MSH 2.2 ASCII (ours) and
//! MSH 4.1 ASCII/binary (through `mshio`, which reads 4.1 only and skips `$PhysicalNames`).

use super::check41::{Layout, check_v41};
use crate::error::{FilePos, MeshError, Result};
use std::path::Path;

/// One node as stored in the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RawNode {
    /// gmsh node tag (may be sparse).
    pub tag: u64,
    /// Coordinates as written [file units].
    pub x: [f64; 3],
}

/// One element as stored in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct RawElement {
    /// gmsh element tag.
    pub tag: u64,
    /// gmsh element type (1 line, 2 triangle, 3 quad, 15 point, …).
    pub kind: i32,
    /// Dimension of its entity.
    pub dim: i32,
    /// Node tags.
    pub nodes: Vec<u64>,
    /// Physical tags (2.2: the first element tag if non-zero; 4.1: from `$Entities`).
    pub physical: Vec<i32>,
    /// Where it is in the file.
    pub pos: FilePos,
}

/// One `$PhysicalNames` entry.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalName {
    /// Dimension.
    pub dim: i32,
    /// Physical tag.
    pub tag: i32,
    /// Name (without quotes).
    pub name: String,
    /// Where it is in the file.
    pub pos: FilePos,
}

/// The content of an MSH file needed by aqua.
#[derive(Debug, Clone, PartialEq)]
pub struct RawMsh {
    /// `2.2` or `4.1`.
    pub version: String,
    /// True for binary files.
    pub binary: bool,
    /// Nodes in file order.
    pub nodes: Vec<RawNode>,
    /// Elements in file order.
    pub elements: Vec<RawElement>,
    /// `$PhysicalNames`.
    pub names: Vec<PhysicalName>,
}

/// Human name of a gmsh element type.
pub fn element_type_name(kind: i32) -> &'static str {
    match kind {
        1 => "2-node line",
        2 => "3-node triangle",
        3 => "4-node quadrangle",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        8 => "3-node second-order line",
        9 => "6-node second-order triangle",
        10 => "9-node second-order quadrangle",
        11 => "10-node second-order tetrahedron",
        15 => "1-node point",
        16 => "8-node second-order quadrangle",
        _ => "higher-order or unknown element",
    }
}

/// Gmsh element types of volume elements (tetrahedra, hexahedra, prisms, pyramids of any
/// order).
fn is_volume_type(kind: i32) -> bool {
    matches!(kind, 4..=7 | 11..=14 | 17..=19 | 29..=35 | 71..=79 | 92..=93)
}

const SUPPORTED_TYPES: &str =
    "1 (2-node line), 2 (3-node triangle), 3 (4-node quadrangle), 15 (1-node point)";

pub(crate) fn unsupported_type(file: &Path, pos: FilePos, tag: u64, kind: i32) -> MeshError {
    let advice = if is_volume_type(kind) {
        "volume elements are not supported: aqua models nets, ropes and nodes, so export only \
         the surfaces, curves and points (in gmsh, put only those in physical groups, or set \
         Mesh.SaveAll = 0)"
            .to_string()
    } else if matches!(kind, 1..=3 | 15) {
        "this type is supported here; the file is inconsistent".to_string()
    } else {
        "higher-order elements are not supported: re-mesh with first-order elements \
         (Mesh.ElementOrder = 1)"
            .to_string()
    };
    MeshError::Gmsh {
        file: file.to_path_buf(),
        position: pos,
        message: format!(
            "in $Elements: element {tag} has type {kind} ({}); {advice}. Supported types: \
             {SUPPORTED_TYPES}",
            element_type_name(kind)
        ),
    }
}

fn gerr(file: &Path, position: FilePos, message: impl Into<String>) -> MeshError {
    MeshError::Gmsh {
        file: file.to_path_buf(),
        position,
        message: message.into(),
    }
}

/// Line number (1-based) of a byte offset.
fn line_of(bytes: &[u8], offset: usize) -> usize {
    bytes[..offset.min(bytes.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// Read and parse an MSH file (2.2 ASCII, 4.1 ASCII, 4.1 binary).
pub fn read_msh(path: &Path) -> Result<RawMsh> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_msh(path, &bytes)
}

/// Parse MSH bytes; `path` is used in messages only.
pub fn parse_msh(path: &Path, bytes: &[u8]) -> Result<RawMsh> {
    // Header: "$MeshFormat\n<version> <file-type> <data-size>\n".
    let mut lines = bytes.split(|&b| b == b'\n');
    let first = lines.next().unwrap_or_default();
    if trim(first) != b"$MeshFormat" {
        return Err(gerr(
            path,
            FilePos::Line(1),
            "not a gmsh MSH file: the first line must be `$MeshFormat`",
        ));
    }
    let header = String::from_utf8_lossy(lines.next().unwrap_or_default()).to_string();
    let mut it = header.split_whitespace();
    let version = it.next().unwrap_or("").to_string();
    let file_type: i32 = it.next().and_then(|s| s.parse().ok()).ok_or_else(|| {
        gerr(
            path,
            FilePos::Line(2),
            format!("malformed $MeshFormat line `{}`", header.trim()),
        )
    })?;
    let binary = file_type == 1;
    match (version.as_str(), binary) {
        ("2.2", false) => parse_v2_ascii(path, bytes),
        ("2.2", true) => Err(gerr(
            path,
            FilePos::Line(2),
            "MSH 2.2 binary is not supported; re-export as MSH 2.2 ASCII or MSH 4.1 (ASCII or \
             binary), e.g. `gmsh net.geo -2 -format msh41`",
        )),
        ("4.1", _) => parse_v41(path, bytes, binary),
        (v, _) => Err(gerr(
            path,
            FilePos::Line(2),
            format!(
                "MSH version {v} is not supported; supported: 4.1 (ASCII, binary) and 2.2 \
                 (ASCII). Re-export with `-format msh41` or `-format msh22`"
            ),
        )),
    }
}

fn trim(b: &[u8]) -> &[u8] {
    let s = b
        .iter()
        .position(|c| !c.is_ascii_whitespace())
        .unwrap_or(b.len());
    let e = b
        .iter()
        .rposition(|c| !c.is_ascii_whitespace())
        .map_or(s, |e| e + 1);
    &b[s..e.max(s)]
}

/// ASCII line cursor with 1-based line numbers.
struct Lines<'a> {
    path: &'a Path,
    lines: Vec<&'a [u8]>,
    next: usize,
}

impl<'a> Lines<'a> {
    fn new(path: &'a Path, bytes: &'a [u8]) -> Self {
        let mut lines: Vec<&[u8]> = bytes.split(|&b| b == b'\n').collect();
        if lines.last().is_some_and(|l| l.is_empty()) {
            lines.pop();
        }
        Lines {
            path,
            lines,
            next: 0,
        }
    }

    /// Next line (trimmed) and its number; error naming `what` at end of file.
    fn take(&mut self, what: &str) -> Result<(usize, &'a str)> {
        match self.lines.get(self.next) {
            Some(l) => {
                self.next += 1;
                let s = std::str::from_utf8(trim(l)).map_err(|_| {
                    gerr(
                        self.path,
                        FilePos::Line(self.next),
                        "line is not valid UTF-8 text",
                    )
                })?;
                Ok((self.next, s))
            }
            None => Err(gerr(
                self.path,
                FilePos::Line(self.lines.len() + 1),
                format!("file ends early (truncated?): expected {what}"),
            )),
        }
    }

    fn at_end(&self) -> bool {
        self.next >= self.lines.len()
    }

    /// Lines not yet taken.
    fn remaining(&self) -> usize {
        self.lines.len().saturating_sub(self.next)
    }

    /// Check a count of one-line items read at line `ln` against the lines left (the section
    /// also needs its end line), so that nothing is reserved or looped over that the file
    /// cannot hold.
    fn check_count(&self, ln: usize, section: &str, n: usize, what: &str) -> Result<()> {
        let left = self.remaining().saturating_sub(1);
        if n > left {
            return Err(gerr(
                self.path,
                FilePos::Line(ln),
                format!(
                    "in {section}: the number of {what} = {n} is more than the rest of the \
                     file can hold ({left} lines remain before the end line, one per entry): a \
                     corrupt count, or a truncated file?"
                ),
            ));
        }
        Ok(())
    }
}

fn num<T: std::str::FromStr>(path: &Path, line: usize, tok: Option<&str>, what: &str) -> Result<T> {
    let t = tok.ok_or_else(|| gerr(path, FilePos::Line(line), format!("missing {what}")))?;
    t.parse::<T>().map_err(|_| {
        gerr(
            path,
            FilePos::Line(line),
            format!("cannot read {what} from `{t}`"),
        )
    })
}

/// Parse a `$PhysicalNames` body starting after its header line (shared by 2.2 and 4.1).
fn parse_names(cur: &mut Lines<'_>) -> Result<Vec<PhysicalName>> {
    let path = cur.path;
    let (ln, l) = cur.take("the number of physical names in $PhysicalNames")?;
    let n: usize = num(
        path,
        ln,
        l.split_whitespace().next(),
        "the number of physical names in $PhysicalNames",
    )?;
    cur.check_count(ln, "$PhysicalNames", n, "physical names")?;
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let (ln, l) = cur.take(&format!("physical name {} of {n} in $PhysicalNames", k + 1))?;
        let mut it = l.splitn(3, char::is_whitespace);
        let dim: i32 = num(
            path,
            ln,
            it.next(),
            "a physical dimension in $PhysicalNames",
        )?;
        let tag: i32 = num(path, ln, it.next(), "a physical tag in $PhysicalNames")?;
        let rest = it.next().unwrap_or("").trim();
        let name = rest
            .strip_prefix('"')
            .and_then(|r| r.strip_suffix('"'))
            .ok_or_else(|| {
                gerr(
                    path,
                    FilePos::Line(ln),
                    format!("in $PhysicalNames: a physical name must be quoted, found `{rest}`"),
                )
            })?;
        out.push(PhysicalName {
            dim,
            tag,
            name: name.to_string(),
            pos: FilePos::Line(ln),
        });
    }
    let (ln, l) = cur.take("$EndPhysicalNames")?;
    if l != "$EndPhysicalNames" {
        return Err(gerr(
            path,
            FilePos::Line(ln),
            format!("expected $EndPhysicalNames after {n} physical names, found `{l}`"),
        ));
    }
    Ok(out)
}

pub(crate) fn nodes_per_element(kind: i32) -> Option<usize> {
    match kind {
        1 => Some(2),
        2 => Some(3),
        3 => Some(4),
        15 => Some(1),
        _ => None,
    }
}

fn dim_of(kind: i32) -> i32 {
    match kind {
        15 => 0,
        1 => 1,
        _ => 2,
    }
}

fn parse_v2_ascii(path: &Path, bytes: &[u8]) -> Result<RawMsh> {
    let mut cur = Lines::new(path, bytes);
    cur.take("$MeshFormat")?;
    cur.take("the format line")?;
    let (ln, l) = cur.take("$EndMeshFormat")?;
    if l != "$EndMeshFormat" {
        return Err(gerr(
            path,
            FilePos::Line(ln),
            format!("expected $EndMeshFormat, found `{l}`"),
        ));
    }
    let mut nodes = Vec::new();
    let mut elements = Vec::new();
    let mut names = Vec::new();
    let (mut seen_nodes, mut seen_elements) = (false, false);
    while !cur.at_end() {
        let (ln, l) = cur.take("a section")?;
        match l {
            "" => continue,
            "$PhysicalNames" => names = parse_names(&mut cur)?,
            "$Nodes" => {
                seen_nodes = true;
                let (ln, l) = cur.take("the number of nodes in $Nodes")?;
                let what = "the number of nodes in $Nodes";
                let n: usize = num(path, ln, l.split_whitespace().next(), what)?;
                cur.check_count(ln, "$Nodes", n, "nodes")?;
                nodes.reserve(n);
                for k in 0..n {
                    let (ln, l) = cur.take(&format!("node {} of {n} in $Nodes", k + 1))?;
                    let mut it = l.split_whitespace();
                    let tag: u64 = num(path, ln, it.next(), "a node tag in $Nodes")?;
                    let x: f64 = num(path, ln, it.next(), "a node x in $Nodes")?;
                    let y: f64 = num(path, ln, it.next(), "a node y in $Nodes")?;
                    let z: f64 = num(path, ln, it.next(), "a node z in $Nodes")?;
                    nodes.push(RawNode { tag, x: [x, y, z] });
                }
                let (ln, l) = cur.take("$EndNodes")?;
                if l != "$EndNodes" {
                    return Err(gerr(
                        path,
                        FilePos::Line(ln),
                        format!("expected $EndNodes after {n} nodes, found `{l}`"),
                    ));
                }
            }
            "$Elements" => {
                seen_elements = true;
                let (ln, l) = cur.take("the number of elements in $Elements")?;
                let what = "the number of elements in $Elements";
                let n: usize = num(path, ln, l.split_whitespace().next(), what)?;
                cur.check_count(ln, "$Elements", n, "elements")?;
                elements.reserve(n);
                for k in 0..n {
                    let (ln, l) = cur.take(&format!("element {} of {n} in $Elements", k + 1))?;
                    let mut it = l.split_whitespace();
                    let tag: u64 = num(path, ln, it.next(), "an element tag in $Elements")?;
                    let kind: i32 = num(path, ln, it.next(), "an element type in $Elements")?;
                    let ntags: usize = num(
                        path,
                        ln,
                        it.next(),
                        "the number of tags of an element in $Elements",
                    )?;
                    // Bounded by the tokens of the line: each pushes one or fails.
                    let mut tags = Vec::with_capacity(ntags.min(16));
                    for _ in 0..ntags {
                        tags.push(num::<i32>(
                            path,
                            ln,
                            it.next(),
                            "an element tag value in $Elements",
                        )?);
                    }
                    let nn = nodes_per_element(kind)
                        .ok_or_else(|| unsupported_type(path, FilePos::Line(ln), tag, kind))?;
                    let mut en = Vec::with_capacity(nn);
                    for _ in 0..nn {
                        en.push(num::<u64>(
                            path,
                            ln,
                            it.next(),
                            "an element node tag in $Elements",
                        )?);
                    }
                    let physical = match tags.first() {
                        Some(&p) if p != 0 => vec![p],
                        _ => Vec::new(),
                    };
                    elements.push(RawElement {
                        tag,
                        kind,
                        dim: dim_of(kind),
                        nodes: en,
                        physical,
                        pos: FilePos::Line(ln),
                    });
                }
                let (ln, l) = cur.take("$EndElements")?;
                if l != "$EndElements" {
                    return Err(gerr(
                        path,
                        FilePos::Line(ln),
                        format!("expected $EndElements after {n} elements, found `{l}`"),
                    ));
                }
            }
            s if s.starts_with('$') => {
                let end = format!("$End{}", &s[1..]);
                loop {
                    let (_, l) = cur.take(&end)?;
                    if l == end {
                        break;
                    }
                }
            }
            other => {
                return Err(gerr(
                    path,
                    FilePos::Line(ln),
                    format!("expected a section header such as $Nodes, found `{other}`"),
                ));
            }
        }
    }
    if !seen_nodes || !seen_elements {
        return Err(gerr(
            path,
            FilePos::Line(cur.lines.len() + 1),
            format!(
                "file has no {} section (truncated?)",
                if seen_nodes { "$Elements" } else { "$Nodes" }
            ),
        ));
    }
    Ok(RawMsh {
        version: "2.2".into(),
        binary: false,
        nodes,
        elements,
        names,
    })
}

/// Parse `$PhysicalNames` of a 4.1 file (ASCII even in binary files), located by the walk.
fn names_v41(path: &Path, bytes: &[u8], layout: &Layout) -> Result<Vec<PhysicalName>> {
    let Some(span) = layout.sections.iter().find(|s| s.name == "PhysicalNames") else {
        return Ok(Vec::new());
    };
    let shift = |l: usize| l + span.line - 1;
    let mut cur = Lines::new(path, &bytes[span.start..span.end]);
    cur.take("$PhysicalNames")?;
    parse_names(&mut cur)
        .map(|v| {
            v.into_iter()
                .map(|mut n| {
                    if let FilePos::Line(l) = n.pos {
                        n.pos = FilePos::Line(shift(l));
                    }
                    n
                })
                .collect()
        })
        .map_err(|e| match e {
            MeshError::Gmsh {
                file,
                position: FilePos::Line(l),
                message,
            } => MeshError::Gmsh {
                file,
                position: FilePos::Line(shift(l)),
                message,
            },
            e => e,
        })
}

/// What `mshio` returned: the file, or the byte offset of its error and its context chain.
type MshioResult = std::result::Result<mshio::MshFile<u64, i32, f64>, (Option<usize>, String)>;

fn mshio_parse(bytes: &[u8]) -> MshioResult {
    mshio::parse_msh_bytes(bytes).map_err(|e| {
        let offset = e
            .backtrace
            .first()
            .map(|(rest, _)| (rest.as_ptr() as usize).saturating_sub(bytes.as_ptr() as usize));
        let mut ctx: Vec<String> = e.filter_msh_errors().map(|(_, k)| k.to_string()).collect();
        ctx.reverse();
        ctx.dedup();
        (offset, ctx.join(": "))
    })
}

thread_local! {
    /// Set while this thread runs the 4.1 reader: its panics are reported as errors, so the
    /// panic hook stays quiet for them (other threads are not affected).
    static QUIET_PANICS: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    /// Where the last quiet panic happened (`file:line`).
    static PANIC_AT: std::cell::RefCell<String> = const { std::cell::RefCell::new(String::new()) };
}

/// Run `f` with panics caught and, on this thread, not printed; `Err` holds the panic message
/// and its location.
fn catch_quietly<T>(f: impl FnOnce() -> T) -> std::result::Result<T, String> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if QUIET_PANICS.with(|q| q.get()) {
                let at = info
                    .location()
                    .map(|l| format!("{}:{}", l.file(), l.line()))
                    .unwrap_or_default();
                PANIC_AT.with(|p| *p.borrow_mut() = at);
            } else {
                previous(info);
            }
        }));
    });
    let was = QUIET_PANICS.with(|q| q.replace(true));
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    QUIET_PANICS.with(|q| q.set(was));
    r.map_err(|payload| {
        let msg = payload
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "(no message)".into());
        let at = PANIC_AT.with(|p| std::mem::take(&mut *p.borrow_mut()));
        let at = at
            .rsplit_once("/src/")
            .map_or(at.as_str(), |(_, a)| a)
            .to_string();
        if at.is_empty() {
            msg
        } else {
            format!("{msg} (at {at})")
        }
    })
}

/// Which section makes `parse` panic: each section after `$MeshFormat` is given to it alone
/// (with the header), in file order; the first that panics is named.
fn panicking_section(
    parse: fn(&[u8]) -> MshioResult,
    bytes: &[u8],
    layout: &Layout,
) -> Option<usize> {
    let header = layout.sections.first()?;
    let head = &bytes[..header.end];
    if catch_quietly(|| parse(head)).is_err() {
        return Some(0);
    }
    (1..layout.sections.len()).find(|&i| {
        let s = &layout.sections[i];
        let mut one = head.to_vec();
        one.extend_from_slice(&bytes[s.start..s.end]);
        catch_quietly(|| parse(&one)).is_err()
    })
}

fn parse_v41(path: &Path, bytes: &[u8], binary: bool) -> Result<RawMsh> {
    parse_v41_with(path, bytes, binary, mshio_parse)
}

/// [`parse_v41`] with the `mshio` call injectable (tests give it one that panics).
fn parse_v41_with(
    path: &Path,
    bytes: &[u8],
    binary: bool,
    parse: fn(&[u8]) -> MshioResult,
) -> Result<RawMsh> {
    // Every count is checked against the file before mshio sees it (see check41).
    let layout = check_v41(path, bytes, binary)?;
    let names = names_v41(path, bytes, &layout)?;
    let pos_of = |o: usize| {
        if binary {
            FilePos::Byte(o)
        } else {
            FilePos::Line(line_of(bytes, o))
        }
    };
    let msh = match catch_quietly(|| parse(bytes)) {
        Ok(Ok(m)) => m,
        Ok(Err((offset, ctx))) => {
            let pos = offset.map_or(FilePos::File, pos_of);
            let section = offset
                .and_then(|o| layout.section_at(o))
                .map(|s| format!(" in ${}", s.name))
                .unwrap_or_default();
            let at_end = offset.is_some_and(|o| o + 128 >= bytes.len());
            return Err(gerr(
                path,
                pos,
                format!(
                    "malformed MSH 4.1{section}{}: {}",
                    if at_end {
                        " (near the end of the file: truncated?)"
                    } else {
                        ""
                    },
                    if ctx.is_empty() {
                        "parse error".to_string()
                    } else {
                        ctx
                    }
                ),
            ));
        }
        Err(panic) => {
            let (pos, near) = match panicking_section(parse, bytes, &layout) {
                Some(i) => {
                    let s = &layout.sections[i];
                    (pos_of(s.start), format!("near section ${}", s.name))
                }
                None => (
                    FilePos::File,
                    "but no single section reproduces it".to_string(),
                ),
            };
            return Err(gerr(
                path,
                pos,
                format!(
                    "the MSH 4.1 reader failed on this file: {panic}; the file is malformed \
                     {near}. Check that it is complete or re-export it with gmsh"
                ),
            ));
        }
    };
    let data = msh.data;
    let Some(nodes_sec) = data.nodes else {
        return Err(gerr(
            path,
            pos_of(bytes.len()),
            "file has no $Nodes section (truncated?)",
        ));
    };
    let Some(elem_sec) = data.elements else {
        return Err(gerr(
            path,
            pos_of(bytes.len()),
            "file has no $Elements section (truncated?)",
        ));
    };
    // Physical tags per (dim, entity tag).
    let mut phys: std::collections::HashMap<(i32, i32), Vec<i32>> = Default::default();
    if let Some(ent) = &data.entities {
        for p in &ent.points {
            phys.insert((0, p.tag), p.physical_tags.clone());
        }
        for c in &ent.curves {
            phys.insert((1, c.tag), c.physical_tags.clone());
        }
        for s in &ent.surfaces {
            phys.insert((2, s.tag), s.physical_tags.clone());
        }
        for v in &ent.volumes {
            phys.insert((3, v.tag), v.physical_tags.clone());
        }
    }
    // Sized by what was parsed, never by the header's totals.
    let n_nodes = nodes_sec.node_blocks.iter().map(|b| b.nodes.len()).sum();
    let mut nodes = Vec::with_capacity(n_nodes);
    // Non-sparse tags are not kept by mshio: they run min..=max in file order.
    let mut next_tag = nodes_sec.min_node_tag;
    for block in &nodes_sec.node_blocks {
        let tags: Vec<u64> = match &block.node_tags {
            Some(map) => {
                let mut t = vec![0u64; block.nodes.len()];
                for (&tag, &i) in map {
                    if i < t.len() {
                        t[i] = tag;
                    }
                }
                t
            }
            None => {
                let t = (0..block.nodes.len() as u64)
                    .map(|i| next_tag.saturating_add(i))
                    .collect();
                next_tag = next_tag.saturating_add(block.nodes.len() as u64);
                t
            }
        };
        for (n, tag) in block.nodes.iter().zip(tags) {
            nodes.push(RawNode {
                tag,
                x: [n.x, n.y, n.z],
            });
        }
    }
    let n_elements = elem_sec
        .element_blocks
        .iter()
        .map(|b| b.elements.len())
        .sum();
    let mut elements = Vec::with_capacity(n_elements);
    for block in &elem_sec.element_blocks {
        let kind = block.element_type as i32;
        let physical = phys
            .get(&(block.entity_dim, block.entity_tag))
            .cloned()
            .unwrap_or_default();
        for e in &block.elements {
            // The walk recorded each element's line (ASCII) or byte offset (binary).
            let pos = layout
                .element_pos
                .get(elements.len())
                .copied()
                .unwrap_or(FilePos::File);
            if nodes_per_element(kind).is_none() {
                return Err(unsupported_type(path, pos, e.element_tag, kind));
            }
            elements.push(RawElement {
                tag: e.element_tag,
                kind,
                dim: block.entity_dim,
                nodes: e.nodes.clone(),
                physical: physical.clone(),
                pos,
            });
        }
    }
    Ok(RawMsh {
        version: "4.1".into(),
        binary,
        nodes,
        elements,
        names,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixture(name: &str) -> Vec<u8> {
        let p = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fixtures")
            .join(name);
        std::fs::read(p).unwrap()
    }

    /// A stand-in for mshio that panics on any input holding an `$Elements` section.
    fn panics_on_elements(bytes: &[u8]) -> MshioResult {
        if bytes.windows(10).any(|w| w == b"$Elements\n") {
            panic!("simulated reader bug");
        }
        mshio_parse(bytes)
    }

    #[test]
    fn a_reader_panic_becomes_an_error_naming_the_section() {
        for (f, pos) in [
            ("net_v41.msh", "line 114"),
            ("net_v41_bin.msh", "byte offset"),
        ] {
            let b = fixture(f);
            let e = parse_v41_with(Path::new(f), &b, f.contains("bin"), panics_on_elements)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("the MSH 4.1 reader failed on this file: simulated reader bug")
                    && e.contains("near section $Elements")
                    && e.contains(pos),
                "{e}"
            );
        }
        // The hook stays quiet only while the reader runs: the flag is reset.
        assert!(!QUIET_PANICS.with(|q| q.get()));
    }

    #[test]
    fn layout_of_the_fixtures() {
        for f in ["net_v41.msh", "net_v41_bin.msh"] {
            let b = fixture(f);
            let l = check_v41(Path::new(f), &b, f.contains("bin")).unwrap();
            let names: Vec<&str> = l.sections.iter().map(|s| s.name.as_str()).collect();
            assert_eq!(
                names,
                [
                    "MeshFormat",
                    "PhysicalNames",
                    "Entities",
                    "Nodes",
                    "Elements"
                ],
                "{f}"
            );
            assert_eq!(l.element_pos.len(), 38, "{f}");
            assert_eq!(l.sections.last().unwrap().end, b.len(), "{f}");
        }
    }
}
