//! Structural check of an MSH 4.1 file (ASCII or binary) before it is handed to `mshio`.
//!
//! `mshio` 0.4 trusts the counts it reads: a data size other than 1, 2, 4, 8 or 16 in a binary
//! file reaches `unimplemented!()`, a data size beyond `i32` an `unwrap()` in its header parser,
//! a node or element count of 0 a `u64` subtraction that overflows (a panic in debug builds), and
//! the totals of `$Nodes` / `$Elements` are never compared with what the blocks hold (this crate
//! used to reserve that many nodes or elements: "capacity overflow", or an 80 GB allocation that
//! aborts). This walk reads every count of `$MeshFormat`, `$Entities`, `$Nodes` and
//! `$Elements` the way `mshio` does, checks each against the bytes left in the file before it is
//! used (a count the file cannot hold is reported with its line or byte offset and value), and
//! checks the declared totals against the blocks. It allocates only the position of each element
//! it walks past (so the 4.1 readers can report element lines too), bounded by the file size.

use super::reader::{nodes_per_element, unsupported_type};
use crate::error::{FilePos, MeshError, Result};
use std::path::Path;

/// A section of the file: `$<name>` … `$End<name>`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Span {
    /// Name without `$` (`Nodes`).
    pub name: String,
    /// Byte offset of the `$` of the header.
    pub start: usize,
    /// Byte offset just past the `$End<name>` line.
    pub end: usize,
    /// 1-based line of the header.
    pub line: usize,
}

/// What the walk learnt about the file.
#[derive(Debug, Clone, Default)]
pub(crate) struct Layout {
    /// Sections in file order, `$MeshFormat` first.
    pub sections: Vec<Span>,
    /// Position of every element of `$Elements`, in file order.
    pub element_pos: Vec<FilePos>,
}

impl Layout {
    /// The section holding byte `offset` (or the last one that starts before it).
    pub fn section_at(&self, offset: usize) -> Option<&Span> {
        self.sections
            .iter()
            .find(|s| s.start <= offset && offset < s.end)
            .or_else(|| self.sections.iter().rev().find(|s| s.start <= offset))
    }
}

struct Cur<'a> {
    path: &'a Path,
    b: &'a [u8],
    pos: usize,
    /// 1-based line of `pos` (meaningful in ASCII files).
    line: usize,
    binary: bool,
    size_t: usize,
    big_endian: bool,
    section: String,
}

fn shown(b: &[u8]) -> String {
    let s = String::from_utf8_lossy(b);
    let s = s.trim();
    if s.chars().count() > 40 {
        format!("{}…", s.chars().take(40).collect::<String>())
    } else {
        s.to_string()
    }
}

impl<'a> Cur<'a> {
    fn here(&self) -> FilePos {
        if self.binary {
            FilePos::Byte(self.pos)
        } else {
            FilePos::Line(self.line)
        }
    }

    fn err(&self, at: FilePos, msg: impl AsRef<str>) -> MeshError {
        MeshError::Gmsh {
            file: self.path.to_path_buf(),
            position: at,
            message: format!("in {}: {}", self.section, msg.as_ref()),
        }
    }

    fn rest(&self) -> usize {
        self.b.len() - self.pos
    }

    fn advance(&mut self, n: usize) {
        self.line += self.b[self.pos..self.pos + n]
            .iter()
            .filter(|&&c| c == b'\n')
            .count();
        self.pos += n;
    }

    fn skip_ws(&mut self) {
        while let Some(&c) = self.b.get(self.pos) {
            if !c.is_ascii_whitespace() {
                break;
            }
            if c == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
    }

    /// The next text line (after blank space), trimmed, with its position.
    fn text_line(&mut self) -> (FilePos, &'a [u8]) {
        self.skip_ws();
        let at = self.here();
        let s = self.pos;
        let e = self.b[s..]
            .iter()
            .position(|&c| c == b'\n')
            .map_or(self.b.len(), |i| s + i);
        self.pos = e;
        if self.pos < self.b.len() {
            self.pos += 1;
            self.line += 1;
        }
        (at, self.b[s..e].trim_ascii())
    }

    fn ended(&self, at: FilePos, what: &str) -> MeshError {
        self.err(
            at,
            format!("the section or file ends early (truncated?): expected {what}"),
        )
    }

    /// Next whitespace-separated token of an ASCII section.
    fn token(&mut self, what: &str) -> Result<(FilePos, &'a str)> {
        self.skip_ws();
        let at = self.here();
        let s = self.pos;
        let mut e = s;
        while e < self.b.len() && !self.b[e].is_ascii_whitespace() {
            e += 1;
        }
        if e == s || self.b[s] == b'$' {
            return Err(self.ended(at, what));
        }
        self.pos = e;
        let t = std::str::from_utf8(&self.b[s..e]).map_err(|_| {
            self.err(
                at,
                format!("{what} is not text: `{}`", shown(&self.b[s..e])),
            )
        })?;
        Ok((at, t))
    }

    /// Next `n` raw bytes of a binary section.
    fn raw(&mut self, n: usize, what: &str) -> Result<(FilePos, &'a [u8])> {
        let at = self.here();
        if self.rest() < n {
            return Err(self.ended(at, what));
        }
        let w = &self.b[self.pos..self.pos + n];
        self.pos += n;
        Ok((at, w))
    }

    fn uint_of(&self, w: &[u8]) -> u128 {
        let f = |acc: u128, &c: &u8| (acc << 8) | u128::from(c);
        if self.big_endian {
            w.iter().fold(0, f)
        } else {
            w.iter().rev().fold(0, f)
        }
    }

    fn size_t(&mut self, what: &str) -> Result<(FilePos, u64)> {
        if self.binary {
            let (at, w) = self.raw(self.size_t, what)?;
            let v = self.uint_of(w);
            let v = u64::try_from(v)
                .map_err(|_| self.err(at, format!("{what} = {v} does not fit in 64 bits")))?;
            Ok((at, v))
        } else {
            let (at, t) = self.token(what)?;
            if !t.bytes().all(|c| c.is_ascii_digit()) {
                return Err(self.err(
                    at,
                    format!("cannot read {what} from `{t}`: expected an integer ≥ 0"),
                ));
            }
            let v = t.parse::<u64>().map_err(|_| {
                self.err(at, format!("{what} = {t} is too large (more than 64 bits)"))
            })?;
            Ok((at, v))
        }
    }

    fn int(&mut self, what: &str) -> Result<(FilePos, i32)> {
        if self.binary {
            let (at, w) = self.raw(4, what)?;
            let v = self.uint_of(w) as u32;
            Ok((at, v as i32))
        } else {
            let (at, t) = self.token(what)?;
            let v = t.parse::<i32>().map_err(|_| {
                self.err(
                    at,
                    format!("cannot read {what} from `{t}`: expected a 32-bit integer"),
                )
            })?;
            Ok((at, v))
        }
    }

    fn doubles(&mut self, n: usize, what: &str) -> Result<()> {
        if self.binary {
            self.raw(8 * n, what)?;
        } else {
            for _ in 0..n {
                let (at, t) = self.token(what)?;
                t.parse::<f64>().map_err(|_| {
                    self.err(
                        at,
                        format!("cannot read {what} from `{t}`: expected a number"),
                    )
                })?;
            }
        }
        Ok(())
    }

    fn ints(&mut self, n: usize, what: &str) -> Result<()> {
        for _ in 0..n {
            self.int(what)?;
        }
        Ok(())
    }

    /// Minimum size of an int, a size_t and a double: binary widths, or one character and a
    /// separator in ASCII.
    fn widths(&self) -> (usize, usize, usize) {
        if self.binary {
            (4, self.size_t, 8)
        } else {
            (2, 2, 2)
        }
    }

    /// A count of items of at least `min_bytes` each, checked against the rest of the file.
    fn count(&mut self, what: &str, item: &str, min_bytes: usize) -> Result<(FilePos, usize)> {
        let (at, n) = self.size_t(what)?;
        let room = self.rest() / min_bytes.max(1);
        if n > room as u64 {
            return Err(self.err(
                at,
                format!(
                    "{what} = {n} is more than the rest of the file can hold: {} bytes remain \
                     and each {item} takes at least {min_bytes} bytes: a corrupt count, or a truncated file?",
                    self.rest()
                ),
            ));
        }
        Ok((at, n as usize))
    }
}

/// Walk an MSH 4.1 file; `Err` names the section, the position and the bad value.
pub(crate) fn check_v41(path: &Path, bytes: &[u8], binary: bool) -> Result<Layout> {
    let mut c = Cur {
        path,
        b: bytes,
        pos: 0,
        line: 1,
        binary,
        size_t: 8,
        big_endian: false,
        section: "$MeshFormat".into(),
    };
    let mut layout = Layout::default();
    // $MeshFormat (the first line was checked by the caller).
    c.text_line();
    let (at, fmt) = c.text_line();
    let fmt = String::from_utf8_lossy(fmt).to_string();
    let size = fmt.split_whitespace().nth(2).unwrap_or("");
    let size_t = match size.parse::<usize>() {
        Ok(s @ (4 | 8)) => s,
        _ => {
            return Err(c.err(
                at,
                format!(
                    "data size `{size}` in `{fmt}` is not supported: gmsh writes 8 \
                     (sizeof(size_t)); 4 is read too"
                ),
            ));
        }
    };
    c.size_t = size_t;
    if binary {
        let (at, w) = c.raw(4, "the endianness word (1) of a binary file")?;
        let w: [u8; 4] = w.try_into().unwrap_or([0; 4]);
        if i32::from_le_bytes(w) == 1 {
            c.big_endian = false;
        } else if i32::from_be_bytes(w) == 1 {
            c.big_endian = true;
        } else {
            return Err(c.err(
                at,
                format!(
                    "the endianness word of a binary file must be the integer 1, found bytes \
                     {w:02x?}"
                ),
            ));
        }
    }
    let (at, l) = c.text_line();
    if l != b"$EndMeshFormat" {
        return Err(c.err(at, format!("expected $EndMeshFormat, found `{}`", shown(l))));
    }
    layout.sections.push(Span {
        name: "MeshFormat".into(),
        start: 0,
        end: c.pos,
        line: 1,
    });

    loop {
        c.skip_ws();
        if c.pos >= bytes.len() {
            break;
        }
        let (start, line) = (c.pos, c.line);
        let (at, l) = c.text_line();
        let Some(name) = l
            .strip_prefix(b"$")
            .filter(|n| !n.is_empty() && !n.starts_with(b"End"))
        else {
            let prev = layout.sections.last().map_or("", |s| s.name.as_str());
            c.section = format!("the file after ${prev}");
            return Err(c.err(
                at,
                format!(
                    "expected a section header such as $Nodes, found `{}`",
                    shown(l)
                ),
            ));
        };
        let name = String::from_utf8_lossy(name).to_string();
        c.section = format!("${name}");
        let end_tag = format!("$End{name}");
        match name.as_str() {
            "Entities" => entities(&mut c)?,
            "Nodes" => nodes(&mut c)?,
            "Elements" => elements(&mut c, &mut layout.element_pos)?,
            _ => {
                // Skipped here ($PhysicalNames, $Periodic, data sections, …).
                let tail = &bytes[c.pos..];
                let Some(e) = tail
                    .windows(end_tag.len())
                    .position(|w| w == end_tag.as_bytes())
                else {
                    return Err(c.err(
                        at,
                        format!("{end_tag} is missing: the section is not closed (truncated?)"),
                    ));
                };
                c.advance(e);
            }
        }
        let (at, l) = c.text_line();
        if l != end_tag.as_bytes() {
            return Err(c.err(
                at,
                format!(
                    "expected {end_tag}, found `{}` (a count in the section does not match its \
                     content?)",
                    shown(l)
                ),
            ));
        }
        layout.sections.push(Span {
            name,
            start,
            end: c.pos,
            line,
        });
    }
    Ok(layout)
}

fn entities(c: &mut Cur<'_>) -> Result<()> {
    let (wi, ws, wd) = c.widths();
    let (_, np) = c.count(
        "the number of point entities",
        "point entity",
        wi + 3 * wd + ws,
    )?;
    let curve = wi + 6 * wd + 2 * ws;
    let (_, nc) = c.count("the number of curve entities", "curve entity", curve)?;
    let (_, ns) = c.count("the number of surface entities", "surface entity", curve)?;
    let (_, nv) = c.count("the number of volume entities", "volume entity", curve)?;
    for _ in 0..np {
        let (_, tag) = c.int("a point entity tag")?;
        c.doubles(3, "a point coordinate")?;
        let (_, k) = c.count(
            &format!("the number of physical tags of point entity {tag}"),
            "physical tag",
            wi,
        )?;
        c.ints(k, "a physical tag")?;
    }
    for (kind, n, bound) in [
        ("curve", nc, "point"),
        ("surface", ns, "curve"),
        ("volume", nv, "surface"),
    ] {
        for _ in 0..n {
            let (_, tag) = c.int(&format!("a {kind} entity tag"))?;
            c.doubles(
                6,
                &format!("a bounding-box coordinate of {kind} entity {tag}"),
            )?;
            let (_, k) = c.count(
                &format!("the number of physical tags of {kind} entity {tag}"),
                "physical tag",
                wi,
            )?;
            c.ints(k, "a physical tag")?;
            let (_, m) = c.count(
                &format!("the number of bounding {bound}s of {kind} entity {tag}"),
                &format!("bounding {bound} tag"),
                wi,
            )?;
            c.ints(m, &format!("a bounding {bound} tag"))?;
        }
    }
    Ok(())
}

/// The header shared by `$Nodes` and `$Elements`: blocks, total, min and max tags.
fn totals(
    c: &mut Cur<'_>,
    item: &str,
    block_min: usize,
    item_min: usize,
) -> Result<(usize, usize, FilePos)> {
    let (_, nb) = c.count(
        &format!("the number of {item} entity blocks"),
        &format!("{item} block"),
        block_min,
    )?;
    let (at, n) = c.count(&format!("the total number of {item}s"), item, item_min)?;
    if n == 0 {
        return Err(c.err(
            at,
            format!("the file declares 0 {item}s; aqua needs a mesh"),
        ));
    }
    let (at_min, min) = c.size_t(&format!("the minimum {item} tag"))?;
    if min == 0 {
        return Err(c.err(
            at_min,
            format!("the minimum {item} tag is 0; gmsh tags start at 1"),
        ));
    }
    let (at_max, max) = c.size_t(&format!("the maximum {item} tag"))?;
    if max < min {
        return Err(c.err(
            at_max,
            format!("the maximum {item} tag {max} is below the minimum {min}"),
        ));
    }
    Ok((nb, n, at))
}

fn nodes(c: &mut Cur<'_>) -> Result<()> {
    let (wi, ws, wd) = c.widths();
    let node_min = ws + 3 * wd;
    let (nb, n, at_n) = totals(c, "node", 3 * wi + ws, node_min)?;
    let mut sum = 0usize;
    for b in 1..=nb {
        let (_, dim) = c.int(&format!("the entity dimension of node block {b}"))?;
        let (_, tag) = c.int(&format!("the entity tag of node block {b}"))?;
        let (at, p) = c.int(&format!("the parametric flag of node block {b}"))?;
        if p != 0 {
            return Err(c.err(
                at,
                format!(
                    "node block {b} (entity {dim}/{tag}) has parametric flag {p}; aqua reads \
                     non-parametric nodes only (0)"
                ),
            ));
        }
        let (_, k) = c.count(
            &format!("the number of nodes in node block {b}"),
            "node",
            node_min,
        )?;
        for _ in 0..k {
            c.size_t(&format!("a node tag of node block {b}"))?;
        }
        c.doubles(3 * k, &format!("a node coordinate of node block {b}"))?;
        sum += k;
    }
    if sum != n {
        return Err(c.err(
            at_n,
            format!("the header declares {n} nodes, but its {nb} blocks hold {sum}"),
        ));
    }
    Ok(())
}

fn elements(c: &mut Cur<'_>, pos: &mut Vec<FilePos>) -> Result<()> {
    let (wi, ws, _) = c.widths();
    let (nb, n, at_n) = totals(c, "element", 3 * wi + ws, 2 * ws)?;
    let mut sum = 0usize;
    for b in 1..=nb {
        c.int(&format!("the entity dimension of element block {b}"))?;
        c.int(&format!("the entity tag of element block {b}"))?;
        let (_, kind) = c.int(&format!("the element type of element block {b}"))?;
        let nn = nodes_per_element(kind);
        let (_, k) = c.count(
            &format!("the number of elements in element block {b}"),
            "element",
            (1 + nn.unwrap_or(1)) * ws,
        )?;
        for _ in 0..k {
            let (at, tag) = c.size_t(&format!("an element tag of element block {b}"))?;
            let Some(nn) = nn else {
                return Err(unsupported_type(c.path, at, tag, kind));
            };
            for _ in 0..nn {
                c.size_t(&format!("a node tag of element {tag}"))?;
            }
            pos.push(at);
        }
        sum += k;
    }
    if sum != n {
        return Err(c.err(
            at_n,
            format!("the header declares {n} elements, but its {nb} blocks hold {sum}"),
        ));
    }
    Ok(())
}
