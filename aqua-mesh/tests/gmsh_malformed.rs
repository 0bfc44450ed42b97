//! Malformed gmsh files (issue 10, "Also found"): absurd, negative or non-numeric counts in
//! every count field of the three fixtures (2.2 ASCII, 4.1 ASCII, 4.1 binary) must give an
//! `Err` naming the section, never a panic, an abort or a huge allocation; plus a proptest that
//! overwrites counts and bytes of the fixtures at random.
//!
//! A count that the reader trusted used to become `Vec::with_capacity(count)` (capacity
//! overflow, or an 80 GB allocation that aborts the process) or reached `unwrap()`/
//! `unimplemented!()` inside mshio's header parser. An abort cannot be caught, so a
//! regression here kills the test binary rather than failing one assertion; the corpus test
//! lists the cases it runs (`--nocapture`) so the culprit is the last one printed.

use aqua_mesh::io::gmsh::{RawMsh, import_raw, parse_msh};
use aqua_mesh::{GmshParams, MeshError};
use proptest::prelude::*;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn fixture(name: &str) -> Vec<u8> {
    let p: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// One mutated file: its name, the section the error must name, the bytes.
struct Case {
    name: String,
    section: &'static str,
    bytes: Vec<u8>,
}

/// Text values put in place of an ASCII count.
const TEXT_VALUES: &[&str] = &[
    "18446744073709551615", // u64::MAX
    "99999999999999999999", // overflows u64
    "4294967296",           // 2^32
    "1000000000",           // 1e9: an 80 GB Vec<RawElement>
    "-1",
    "-18446744073709551615",
    "abc",
    "3.5",
    "1e9",
];

/// Replace the first occurrence of `from` (which must exist) by `to`.
fn replace_once(s: &str, from: &str, to: &str) -> String {
    assert!(s.contains(from), "fixture changed: `{from}` not found");
    s.replacen(from, to, 1)
}

/// ASCII mutations: (label, section, text before the value, value, text after).
fn ascii_cases(file: &str, sites: &[(&str, &'static str, &str, &str, &str)]) -> Vec<Case> {
    let s = String::from_utf8(fixture(file)).unwrap();
    let mut out = Vec::new();
    for &(label, section, before, orig, after) in sites {
        for v in TEXT_VALUES {
            let from = format!("{before}{orig}{after}");
            let to = format!("{before}{v}{after}");
            out.push(Case {
                name: format!("{file}: {label} = {v}"),
                section,
                bytes: replace_once(&s, &from, &to).into_bytes(),
            });
        }
    }
    out
}

fn v22_cases() -> Vec<Case> {
    ascii_cases(
        "net_v22.msh",
        &[
            ("node count", "$Nodes", "$Nodes\n", "31", "\n"),
            ("element count", "$Elements", "$Elements\n", "38", "\n"),
            (
                "physical name count",
                "$PhysicalNames",
                "$PhysicalNames\n",
                "5",
                "\n",
            ),
            (
                "number of element tags",
                "$Elements",
                "\n15 2 ",
                "2",
                " 1 2 2 18 11\n",
            ),
        ],
    )
}

fn v41_ascii_cases() -> Vec<Case> {
    let mut out = ascii_cases(
        "net_v41.msh",
        &[
            (
                "node entity block count",
                "$Nodes",
                "$Nodes\n",
                "17",
                " 31 1 31\n",
            ),
            ("node count", "$Nodes", "$Nodes\n17 ", "31", " 1 31\n"),
            (
                "node count in block",
                "$Nodes",
                "$EndEntities\n$Nodes\n17 31 1 31\n0 1 0 ",
                "1",
                "\n",
            ),
            (
                "node count in a later block",
                "$Nodes",
                "\n2 1 0 ",
                "6",
                "\n24\n",
            ),
            (
                "element entity block count",
                "$Elements",
                "$Elements\n",
                "7",
                " 38 1 38\n",
            ),
            (
                "element count",
                "$Elements",
                "$Elements\n7 ",
                "38",
                " 1 38\n",
            ),
            (
                "element count in block",
                "$Elements",
                "\n2 1 3 ",
                "12",
                "\n15 ",
            ),
            (
                "point entity count",
                "$Entities",
                "$Entities\n",
                "7",
                " 8 2 0\n",
            ),
            (
                "curve entity count",
                "$Entities",
                "$Entities\n7 ",
                "8",
                " 2 0\n",
            ),
            (
                "physical tag count of a point",
                "$Entities",
                "\n7 0 0 2 ",
                "1",
                " 5 \n",
            ),
            (
                "bounding point count of a curve",
                "$Entities",
                "\n8 0 0 0 0 0 2 1 4 ",
                "2",
                " 1 -7 \n",
            ),
            (
                "physical name count",
                "$PhysicalNames",
                "$PhysicalNames\n",
                "5",
                "\n",
            ),
            ("data size", "$MeshFormat", "$MeshFormat\n4.1 0 ", "8", "\n"),
        ],
    );
    // A count of zero where the reader subtracts one.
    let s = String::from_utf8(fixture("net_v41.msh")).unwrap();
    for (label, section, from, to) in [
        (
            "node count = 0",
            "$Nodes",
            "$Nodes\n17 31 1 31\n",
            "$Nodes\n17 0 1 31\n",
        ),
        (
            "element count = 0",
            "$Elements",
            "$Elements\n7 38 1 38\n",
            "$Elements\n7 0 1 38\n",
        ),
    ] {
        out.push(Case {
            name: format!("net_v41.msh: {label}"),
            section,
            bytes: replace_once(&s, from, to).into_bytes(),
        });
    }
    out
}

/// Offset of the first byte after `pat` in `b`.
fn after(b: &[u8], pat: &[u8]) -> usize {
    b.windows(pat.len())
        .position(|w| w == pat)
        .unwrap_or_else(|| {
            panic!(
                "fixture changed: {:?} not found",
                String::from_utf8_lossy(pat)
            )
        })
        + pat.len()
}

fn v41_binary_cases() -> Vec<Case> {
    let b = fixture("net_v41_bin.msh");
    let ent = after(&b, b"$Entities\n");
    let nodes = after(&b, b"$Nodes\n");
    let elems = after(&b, b"$Elements\n");
    // size_t fields (8 bytes, little endian): (label, section, offset).
    let size_t_sites: Vec<(&str, &'static str, usize)> = vec![
        ("point entity count", "$Entities", ent),
        ("curve entity count", "$Entities", ent + 8),
        ("surface entity count", "$Entities", ent + 16),
        // point 1: tag (4), x y z (24), then its number of physical tags.
        ("physical tag count of a point", "$Entities", ent + 32 + 28),
        ("node entity block count", "$Nodes", nodes),
        ("node count", "$Nodes", nodes + 8),
        // first node block: dim, tag, parametric (3 × 4), then the node count.
        ("node count in block", "$Nodes", nodes + 32 + 12),
        ("element entity block count", "$Elements", elems),
        ("element count", "$Elements", elems + 8),
        ("element count in block", "$Elements", elems + 32 + 12),
    ];
    let values: [u64; 6] = [u64::MAX, 1 << 62, 1 << 40, 1_000_000_000, 10_000_000, 0];
    let mut out = Vec::new();
    for (label, section, off) in size_t_sites {
        for v in values {
            if b[off..off + 8] == v.to_le_bytes() {
                continue;
            }
            let mut m = b.clone();
            m[off..off + 8].copy_from_slice(&v.to_le_bytes());
            out.push(Case {
                name: format!("net_v41_bin.msh: {label} = {v}"),
                section,
                bytes: m,
            });
        }
    }
    // int fields (4 bytes): the node block's parametric flag and the element type.
    for (label, off) in [
        ("node block parametric flag", nodes + 32 + 8),
        ("element type", elems + 32 + 8),
    ] {
        for v in [-1i32, i32::MAX, 7] {
            let mut m = b.clone();
            m[off..off + 4].copy_from_slice(&v.to_le_bytes());
            out.push(Case {
                name: format!("net_v41_bin.msh: {label} = {v}"),
                section: if label.starts_with("node") {
                    "$Nodes"
                } else {
                    "$Elements"
                },
                bytes: m,
            });
        }
    }
    // The header's data size (sizeof(size_t)) and the endianness word.
    let s = String::from_utf8_lossy(&b[..20]).to_string();
    assert!(s.starts_with("$MeshFormat\n4.1 1 8\n"));
    for v in ["3", "0", "99999999999999999999", "-8", "x"] {
        let mut m = format!("$MeshFormat\n4.1 1 {v}\n").into_bytes();
        m.extend_from_slice(&b[20..]);
        out.push(Case {
            name: format!("net_v41_bin.msh: data size = {v}"),
            section: "$MeshFormat",
            bytes: m,
        });
    }
    let mut m = b.clone();
    m[20..24].copy_from_slice(&7i32.to_le_bytes());
    out.push(Case {
        name: "net_v41_bin.msh: endianness word = 7".into(),
        section: "$MeshFormat",
        bytes: m,
    });
    out
}

fn corpus() -> Vec<Case> {
    let mut c = v22_cases();
    c.extend(v41_ascii_cases());
    c.extend(v41_binary_cases());
    c
}

/// Parse and import `bytes`; `Err` carries the message. Panics propagate to the caller.
fn run(name: &str, bytes: &[u8]) -> Result<RawMsh, String> {
    let path = Path::new(name);
    let raw = parse_msh(path, bytes).map_err(|e| e.to_string())?;
    import_raw(
        &GmshParams {
            file: path.to_path_buf(),
            ..Default::default()
        },
        &raw,
    )
    .map_err(|e| e.to_string())?;
    Ok(raw)
}

/// The vectors of a parse result must be sized by the file, not by a count in it.
fn assert_sized_by_file(raw: &RawMsh, len: usize) -> Result<(), String> {
    let caps = [
        raw.nodes.capacity(),
        raw.elements.capacity(),
        raw.names.capacity(),
    ];
    if caps.iter().any(|&c| c > len) {
        return Err(format!(
            "vectors of capacity {caps:?} from a file of {len} bytes"
        ));
    }
    Ok(())
}

#[test]
fn corpus_of_absurd_counts_gives_errors_naming_the_section() {
    let cases = corpus();
    assert!(cases.len() > 150, "{} cases", cases.len());
    // `AQUA_GMSH_CASE=<i>` runs case i alone (to find an abort, which kills the process).
    let only: Option<usize> = std::env::var("AQUA_GMSH_CASE")
        .ok()
        .and_then(|v| v.parse().ok());
    let mut failures = Vec::new();
    for (i, c) in cases.iter().enumerate() {
        if only.is_some_and(|k| k != i) {
            continue;
        }
        println!("case {i}: {}", c.name);
        let t0 = Instant::now();
        let r = catch_unwind(AssertUnwindSafe(|| run("bad.msh", &c.bytes)));
        let dt = t0.elapsed();
        match r {
            Err(p) => {
                let msg = p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                failures.push(format!("{}: PANIC {msg}", c.name));
            }
            Ok(Ok(raw)) => failures.push(format!(
                "{}: accepted ({} nodes, {} elements)",
                c.name,
                raw.nodes.len(),
                raw.elements.len()
            )),
            Ok(Err(e)) => {
                if !e.starts_with("bad.msh: ") || !e.contains(c.section) {
                    failures.push(format!(
                        "{}: message does not name {}: {e}",
                        c.name, c.section
                    ));
                }
            }
        }
        if dt > Duration::from_secs(1) {
            failures.push(format!("{}: took {dt:?}", c.name));
        }
    }
    for f in &failures {
        println!("FAILED {f}");
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn corpus_errors_carry_positions() {
    // 4.1 ASCII: a bad count is reported on its line (line 42 holds the node section header).
    let s = String::from_utf8(fixture("net_v41.msh")).unwrap();
    let line = s.lines().position(|l| l == "17 31 1 31").unwrap() + 1;
    let bad = s.replacen("17 31 1 31", "17 1000000000 1 31", 1);
    let e = run("n.msh", bad.as_bytes()).unwrap_err();
    assert!(
        e.starts_with(&format!("n.msh: line {line}: ")) && e.contains("1000000000"),
        "{e}"
    );
    // 2.2: the same.
    let s = String::from_utf8(fixture("net_v22.msh")).unwrap();
    let bad = s.replacen("$Elements\n38\n", "$Elements\n4294967296\n", 1);
    let line = s.lines().position(|l| l == "$Elements").unwrap() + 2;
    let e = run("e.msh", bad.as_bytes()).unwrap_err();
    assert!(
        e.starts_with(&format!("e.msh: line {line}: ")) && e.contains("4294967296"),
        "{e}"
    );
    // 4.1 binary: a byte offset.
    let b = fixture("net_v41_bin.msh");
    let off = after(&b, b"$Elements\n") + 8;
    let mut m = b.clone();
    m[off..off + 8].copy_from_slice(&1_000_000_000u64.to_le_bytes());
    let e = run("b.msh", &m).unwrap_err();
    assert!(
        e.starts_with(&format!("b.msh: byte offset {off}: ")) && e.contains("1000000000"),
        "{e}"
    );
}

#[test]
fn v41_element_errors_have_a_line_number() {
    let s = String::from_utf8(fixture("net_v41.msh")).unwrap();
    // Zero-length rope segment 12 (nodes 1 22 → 1 1).
    let bad = s.replacen("\n12 1 22 \n", "\n12 1 1 \n", 1);
    let line = bad.lines().position(|l| l == "12 1 1 ").unwrap() + 1;
    let e = run("z.msh", bad.as_bytes()).unwrap_err();
    assert!(
        e.starts_with(&format!("z.msh: line {line}: ")) && e.contains("element 12"),
        "{e}"
    );
}

/// Byte ranges of the decimal digit runs of a file that start a number (not the digits after
/// a decimal point or inside a word).
fn number_spans(s: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < s.len() {
        let starts = s[i].is_ascii_digit()
            && (i == 0 || !s[i - 1].is_ascii_alphanumeric() && s[i - 1] != b'.');
        if starts {
            let mut j = i;
            while j < s.len() && s[j].is_ascii_digit() {
                j += 1;
            }
            out.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// Overwrite the `k`-th number of an ASCII file by `v`.
fn set_kth_number(s: &[u8], k: usize, v: &str) -> Vec<u8> {
    let spans = number_spans(s);
    let (a, b) = spans[k % spans.len()];
    let mut out = s[..a].to_vec();
    out.extend_from_slice(v.as_bytes());
    out.extend_from_slice(&s[b..]);
    out
}

/// Indices (in [`number_spans`]) of the numbers on the line after each section header: the
/// format line and the counts of `$PhysicalNames`, `$Entities`, `$Nodes`, `$Elements`.
fn header_numbers(s: &[u8]) -> Vec<usize> {
    // Byte ranges of the lines that follow a section header.
    let mut ranges = Vec::new();
    let mut start = 0;
    let mut after_header = false;
    for line in s.split(|&c| c == b'\n') {
        if after_header {
            ranges.push((start, start + line.len()));
        }
        after_header = line.starts_with(b"$") && !line.starts_with(b"$End");
        start += line.len() + 1;
    }
    number_spans(s)
        .iter()
        .enumerate()
        .filter(|(_, (a, _))| ranges.iter().any(|(r0, r1)| r0 <= a && a < r1))
        .map(|(k, _)| k)
        .collect()
}

fn check_quick(name: &str, bytes: &[u8]) -> Result<(), TestCaseError> {
    let t0 = Instant::now();
    let r = catch_unwind(AssertUnwindSafe(|| run(name, bytes)));
    let dt = t0.elapsed();
    prop_assert!(r.is_ok(), "panicked");
    if let Ok(Ok(raw)) = &r {
        prop_assert!(
            assert_sized_by_file(raw, bytes.len()).is_ok(),
            "{:?}",
            assert_sized_by_file(raw, bytes.len())
        );
    }
    prop_assert!(dt < Duration::from_secs(2), "took {dt:?}");
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// Any number of an ASCII fixture replaced by an absurd or random value.
    #[test]
    fn ascii_numbers_mutated(
        which in 0usize..2,
        k in 0usize..1000,
        header in any::<Option<prop::sample::Index>>(),
        v in prop_oneof![
            Just("0".to_string()),
            Just("18446744073709551615".to_string()),
            Just("99999999999999999999".to_string()),
            Just("1000000000".to_string()),
            Just("-1".to_string()),
            (0u64..u64::MAX).prop_map(|x| x.to_string()),
            (0u64..100).prop_map(|x| x.to_string()),
        ],
    ) {
        let file = ["net_v22.msh", "net_v41.msh"][which];
        let b = fixture(file);
        // Half of the cases hit a section's count line, where the absurd values matter.
        let k = header.map_or(k, |i| *i.get(&header_numbers(&b)));
        check_quick(file, &set_kth_number(&b, k, &v))?;
    }

    /// Any aligned 4- or 8-byte word of the binary fixture replaced by an absurd value, or
    /// random bytes overwritten.
    #[test]
    fn binary_words_mutated(
        off in 0usize..4100,
        wide in any::<bool>(),
        v in prop_oneof![Just(u64::MAX), Just(1u64 << 40), Just(1_000_000_000u64), Just(0u64), any::<u64>()],
        noise in proptest::collection::vec((0usize..4100, any::<u8>()), 0..4),
    ) {
        let mut b = fixture("net_v41_bin.msh");
        let n = if wide { 8 } else { 4 };
        let off = off % (b.len() - n);
        b[off..off + n].copy_from_slice(&v.to_le_bytes()[..n]);
        for (o, x) in noise {
            let o = o % b.len();
            b[o] = x;
        }
        check_quick("net_v41_bin.msh", &b)?;
    }

    /// Truncated files and random byte noise in all three fixtures.
    #[test]
    fn truncated_or_noisy(
        which in 0usize..3,
        cut in 0.0f64..=1.0,
        noise in proptest::collection::vec((any::<usize>(), any::<u8>()), 0..6),
    ) {
        let file = ["net_v22.msh", "net_v41.msh", "net_v41_bin.msh"][which];
        let mut b = fixture(file);
        b.truncate((b.len() as f64 * cut) as usize);
        if !b.is_empty() {
            for (o, x) in noise {
                let o = o % b.len();
                b[o] = x;
            }
        }
        check_quick(file, &b)?;
    }
}

#[test]
fn fixtures_still_parse() {
    for f in ["net_v22.msh", "net_v41.msh", "net_v41_bin.msh"] {
        let b = fixture(f);
        let raw = run(f, &b).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((raw.nodes.len(), raw.elements.len()), (31, 38), "{f}");
        assert_sized_by_file(&raw, b.len()).unwrap();
    }
    // A MeshError is what the library returns (not a string or a panic).
    let e: MeshError = parse_msh(Path::new("x.msh"), b"$MeshFormat\n4.1 0 8\n").unwrap_err();
    assert!(matches!(e, MeshError::Gmsh { .. }), "{e}");
}

/// A first-order tetrahedral mesh (MSH 4.1 and 2.2, written by hand).
const TET41: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"net\"\n\
$EndPhysicalNames\n$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n$Nodes\n1 4 1 4\n\
3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n\
1 1 2 3 4\n$EndElements\n";
const TET22: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n\
3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n1\n1 4 2 1 1 1 2 3 4\n$EndElements\n";

#[test]
fn volume_elements_are_named_as_such_not_as_higher_order() {
    for (name, text, line) in [("t41.msh", TET41, 27), ("t22.msh", TET22, 13)] {
        let e = run(name, text.as_bytes()).unwrap_err();
        assert!(e.starts_with(&format!("{name}: line {line}: ")), "{e}");
        assert!(
            e.contains("4-node tetrahedron") && e.contains("volume elements are not supported"),
            "{e}"
        );
        assert!(
            e.contains("1 (2-node line), 2 (3-node triangle), 3 (4-node quadrangle)"),
            "{e}"
        );
        assert!(
            !e.contains("first-order"),
            "a first-order mesh told to re-mesh: {e}"
        );
    }
    // A second-order triangle is told to re-mesh with first-order elements.
    let tri6 = TET22.replace("1 4 2 1 1 1 2 3 4", "1 9 2 1 1 1 2 3 4 1 2");
    let e = run("t6.msh", tri6.as_bytes()).unwrap_err();
    assert!(e.contains("Mesh.ElementOrder = 1"), "{e}");
}

#[test]
fn v41_missing_sections_are_reported_with_a_line() {
    let cut = &TET41[..TET41.find("$Elements").unwrap()];
    let e = run("c.msh", cut.as_bytes()).unwrap_err();
    let last = cut.lines().count() + 1;
    assert!(
        e.starts_with(&format!("c.msh: line {last}: ")) && e.contains("no $Elements"),
        "{e}"
    );
}

#[test]
fn every_unknown_physical_name_is_reported_at_once() {
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 1 \"cable\"\n\
                1 2 \"ropes\"\n0 3 \"weights\"\n$EndPhysicalNames\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n\
                3 2 0 0\n$EndNodes\n$Elements\n3\n1 1 2 1 1 1 2\n2 1 2 2 2 2 3\n\
                3 15 2 3 3 3\n$EndElements\n";
    let raw = parse_msh(Path::new("n.msh"), text.as_bytes()).unwrap();
    let params = GmshParams {
        file: PathBuf::from("n.msh"),
        ..Default::default()
    };
    let e = import_raw(&params, &raw).unwrap_err().to_string();
    assert!(
        e.contains("2 physical group names are not understood"),
        "{e}"
    );
    assert!(
        e.contains("`cable` (line 6)") && e.contains("`weights` (line 8)"),
        "{e}"
    );
    assert!(!e.contains("`ropes`"), "ropes is valid: {e}");
    assert!(e.contains("valid names: net (alias net_panels"), "{e}");
}
