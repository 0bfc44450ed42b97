//! `aqua check` over deterministically mutated example scenes (issue 10): no mutation may panic,
//! and every mutation that is refused must be refused with a message that names the key it
//! changed (its last path component; for a misspelled key, the misspelled name) and the file.
//!
//! Every `key = value` line of every scene in `examples/` is mutated in turn: its value is
//! replaced by one of the wrong type (string, bool, array, table), a negative number, zero,
//! `nan`, `inf`, a huge number or an empty array; its key is misspelled; and the line is
//! dropped (a required key then goes missing). Each mutated text goes through what
//! `aqua check` runs — [`aqua_sim::prepare`] and [`aqua_sim::check::report`] — and the
//! error is printed as the binary prints it (the error followed by its sources).
//!
//! `AQUA_FUZZ_TRACE=1` prints each mutation before it runs (to find one that aborts the
//! process, e.g. by exhausting memory, which `catch_unwind` cannot catch) and lists the
//! refusals that give no line number.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

mod common;

/// The values a key's value is replaced by.
const VALUES: &[&str] = &[
    "\"fuzz\"",
    "\"\"",
    "true",
    "[1.0, 2.0]",
    "{ fuzz = 1 }",
    "-1.5",
    "-1",
    "0",
    "1e-9",
    "nan",
    "inf",
    "1e300",
    "2147483647",
    "[]",
];

/// A small deterministic PRNG (xorshift64*), so the misspellings are the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A `key = value` line of a scene: its index, the dotted key and the value's byte range.
struct KeyLine {
    index: usize,
    key: String,
    value: std::ops::Range<usize>,
}

/// The byte where a trailing `# comment` starts (outside strings), or the line's end.
fn comment_start(line: &str) -> usize {
    let mut quoted = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '#' if !quoted => return i,
            _ => {}
        }
    }
    line.len()
}

/// The `key = value` lines of a scene text (table headers and comments are not keys).
fn key_lines(text: &str) -> Vec<KeyLine> {
    let mut out = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let t = line.trim_start();
        if t.is_empty() || t.starts_with('#') || t.starts_with('[') {
            continue;
        }
        let Some(eq) = line.find('=') else { continue };
        let key = line[..eq].trim();
        let bare = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.';
        if key.is_empty() || !key.chars().all(bare) {
            continue;
        }
        let end = comment_start(line);
        let start = eq + 1 + (line[eq + 1..].len() - line[eq + 1..].trim_start().len());
        let end = start + line[start..end].trim_end().len();
        out.push(KeyLine {
            index,
            key: key.to_string(),
            value: start..end,
        });
    }
    out
}

/// The key's last path component (`net.twine_diameter` → `twine_diameter`).
fn last(key: &str) -> &str {
    key.rsplit('.').next().unwrap_or(key)
}

/// `name` with two neighbouring letters swapped, or a letter doubled (never `name` itself).
fn misspelled(name: &str, rng: &mut Rng) -> String {
    let c: Vec<char> = name.chars().collect();
    if c.len() >= 3 {
        let i = 1 + rng.below(c.len() - 2);
        if c[i] != c[i + 1] {
            let mut s = c.clone();
            s.swap(i, i + 1);
            return s.into_iter().collect();
        }
    }
    let i = rng.below(c.len());
    let mut s = c;
    s.insert(i, s[i]);
    s.into_iter().collect()
}

/// One mutated scene: what was changed, the key name its error must contain, and the text.
struct Mutation {
    what: String,
    key: String,
    text: String,
}

/// Every mutation of a scene text.
fn mutations(text: &str, rng: &mut Rng) -> Vec<Mutation> {
    let lines: Vec<&str> = text.lines().collect();
    let with_line = |index: usize, new: &str| {
        let mut l = lines.clone();
        l[index] = new;
        l.join("\n") + "\n"
    };
    let mut out = Vec::new();
    for k in key_lines(text) {
        let line = lines[k.index];
        let name = last(&k.key).to_string();
        for v in VALUES {
            let new = format!("{}{v}{}", &line[..k.value.start], &line[k.value.end..]);
            out.push(Mutation {
                what: format!("line {}: {} = {v}", k.index + 1, k.key),
                key: name.clone(),
                text: with_line(k.index, &new),
            });
        }
        let wrong = misspelled(&name, rng);
        let prefix = &k.key[..k.key.len() - name.len()];
        let at = line.find(&k.key).expect("the key is on its line");
        let new = format!(
            "{}{prefix}{wrong}{}",
            &line[..at],
            &line[at + k.key.len()..]
        );
        out.push(Mutation {
            what: format!("line {}: {} misspelled {prefix}{wrong}", k.index + 1, k.key),
            key: wrong,
            text: with_line(k.index, &new),
        });
        out.push(Mutation {
            what: format!("line {}: {} dropped", k.index + 1, k.key),
            key: name,
            text: with_line(k.index, ""),
        });
    }
    out
}

/// True if `msg` contains `word` not inside a longer identifier (`depth` is not named by
/// `cone_depth`).
fn names(msg: &str, word: &str) -> bool {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    msg.match_indices(word).any(|(i, _)| {
        let before = msg[..i].chars().next_back();
        let after = msg[i + word.len()..].chars().next();
        !before.is_some_and(ident) && !after.is_some_and(ident)
    })
}

/// True if `msg` gives a line number ("line 12").
fn has_line(msg: &str) -> bool {
    msg.match_indices("line ").any(|(i, w)| {
        msg[i + w.len()..]
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_digit())
    })
}

/// What `aqua check` says about a scene file: `None` if valid, else its error message.
fn check(path: &Path) -> Option<String> {
    let prep = match aqua_sim::prepare(aqua_sim::PrepareOptions::file(path)) {
        Ok(p) => p,
        Err(e) => return Some(e.chain()),
    };
    aqua_sim::check::report(&prep).err().map(|e| e.chain())
}

/// The scenes of `examples/` (not the sweep case files, nor the sea-only files, which
/// `aqua check` refuses as having no structure, nor the full-scale farm: 100 000 DOFs built
/// for every mutation would take minutes; aqua-cli's cli_examples checks it).
fn example_scenes() -> Vec<PathBuf> {
    let dir = common::root().join("examples");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter(|p| !p.to_string_lossy().contains("full-scale"))
        .filter(|p| {
            let text = std::fs::read_to_string(p).unwrap();
            let starts = |h: &str| text.lines().any(|l| l.trim_start().starts_with(h));
            !starts("scene =")
                && ["[[cage]]", "[[panel]]", "[[line]]", "[[mesh]]", "[[farm]]"]
                    .iter()
                    .any(|h| starts(h))
        })
        .collect();
    files.sort();
    files
}

#[test]
fn every_refused_mutation_names_its_key_and_none_panics() {
    let scenes = example_scenes();
    assert!(scenes.len() >= 5, "{scenes:?}");
    let dir = common::scratch("scene-fuzz");
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut total, mut refused) = (0, 0);
    let mut keyless = Vec::new();
    // Refusals that name the file but no line (build-time checks of values that are not
    // parse errors): reported, not failed.
    let mut lineless = Vec::new();
    let mut panics = Vec::new();
    let started = std::time::Instant::now();
    for scene in &scenes {
        let file = scene.file_name().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(scene).unwrap();
        assert_eq!(check(scene), None, "{file} itself must be valid");
        let path = dir.join(&file);
        for m in mutations(&text, &mut rng) {
            total += 1;
            std::fs::write(&path, &m.text).unwrap();
            if std::env::var_os("AQUA_FUZZ_TRACE").is_some() {
                eprintln!("{file}: {}", m.what);
            }
            match catch_unwind(AssertUnwindSafe(|| check(&path))) {
                Ok(None) => {}
                Ok(Some(msg)) => {
                    refused += 1;
                    if !names(&msg, &m.key) || !msg.contains(&file) {
                        keyless.push(format!("{file}: {}\n    -> {msg}", m.what));
                    }
                    if !has_line(&msg) {
                        lineless.push(format!("{file}: {}\n    -> {msg}", m.what));
                    }
                }
                Err(p) => {
                    let why = p
                        .downcast_ref::<String>()
                        .cloned()
                        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                        .unwrap_or_default();
                    panics.push(format!("{file}: {}: panic {why}\n{}", m.what, m.text));
                }
            }
        }
    }
    println!(
        "{total} mutations of {} scenes in {:.1} s: {refused} refused, {} without their key, \
         {} without a line number, {} panics",
        scenes.len(),
        started.elapsed().as_secs_f64(),
        keyless.len(),
        lineless.len(),
        panics.len()
    );
    if std::env::var_os("AQUA_FUZZ_TRACE").is_some() {
        for l in &lineless {
            println!("no line: {l}");
        }
    }
    for k in &keyless {
        println!("{k}");
    }
    assert!(panics.is_empty(), "{}", panics.join("\n\n"));
    assert!(total > 1000 && refused > total / 2, "{total} {refused}");
    assert!(
        keyless.is_empty(),
        "{} of {refused} refusals do not name their key (or the file):\n{}",
        keyless.len(),
        keyless.join("\n")
    );
}
