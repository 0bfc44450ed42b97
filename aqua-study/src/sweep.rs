//! Load-case sweeps (`aqua sweep cases.toml`) and collecting many run folders into one table
//! (`aqua collect DIR`).
//!
//! A case file names a base scene and a case matrix (docs/guide/study-and-sweep.md#design-load-cases-aqua-sweep-and-aqua-collect):
//!
//! ```toml
//! scene = "reference-cage.toml"        # the base scene, relative to this file
//! out = "cage-cases"                   # case folders go here (default: "<stem>-runs")
//! combine = "factorial"                # or "zip" (the lists advance together)
//! set = { "analysis.dynamic.t_end" = 30.0 }   # changes for every case
//!
//! [vary]                               # dotted path = list of values
//! "sea.current.speed" = [0.25, 0.5, 0.75]
//! "sea.current.direction" = [0.0, 45.0]
//!
//! [[case]]                             # explicit extra cases
//! name = "storm"
//! set = { "sea.current.speed" = 1.2 }
//! ```
//!
//! Case k is run as `aqua sweep cases.toml --case k` into `<out>/case_NNNN/`, whatever the
//! engine (this machine, GNU parallel, a Slurm array); each folder holds the run's files and
//! `case.json` (its parameters, status and wall time), so [`collect`] gives the same table
//! whichever engine ran the cases.

use crate::plot::SummaryTable;
use crate::study::value_text;
use aqua_sim::csv_line;
use aqua_sim::extremes::read_extremes;
use aqua_sim::overrides::{Override, check_path_syntax};
use aqua_sim::{Result, SimError};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use toml::{Table, Value};

/// How the `[vary]` lists combine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Combine {
    /// Every combination (the last list varies fastest).
    #[default]
    Factorial,
    /// The k-th case takes the k-th value of every list (equal lengths).
    Zip,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCases {
    scene: PathBuf,
    #[serde(default)]
    out: Option<PathBuf>,
    #[serde(default)]
    combine: Combine,
    #[serde(default)]
    set: Table,
    #[serde(default)]
    vary: toml::map::Map<String, Value>,
    #[serde(default)]
    case: Vec<RawCase>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCase {
    name: String,
    #[serde(default)]
    set: Table,
}

/// One load case: a name and the changes that make it from the base scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Case {
    /// Position in the sweep (folder `case_NNNN`).
    pub index: usize,
    /// Name (the varied values, or the `[[case]]` name).
    pub name: String,
    /// Changes, the common `set` first.
    #[serde(serialize_with = "overrides_text")]
    pub overrides: Vec<Override>,
}

fn overrides_text<S: serde::Serializer>(
    v: &[Override],
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(v.iter().map(|o| o.to_string()))
}

/// A case file read and expanded.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// The case file (absolute).
    pub file: PathBuf,
    /// The base scene (absolute).
    pub scene: PathBuf,
    /// Where the case folders go.
    pub out: PathBuf,
    /// Every case.
    pub cases: Vec<Case>,
}

impl Sweep {
    /// Reads a case file; every case is checked against the base scene (unknown paths, wrong
    /// types) before anything runs.
    pub fn read(file: &Path) -> Result<Sweep> {
        let file = std::path::absolute(file).map_err(|source| SimError::Io {
            what: "resolving",
            path: file.to_path_buf(),
            source,
        })?;
        let text = aqua_sim::scene::read_text(&file)?;
        let err = |m: String| SimError::input(format!("{}: {m}", file.display()));
        let raw: RawCases = toml::from_str(&text).map_err(|e| err(e.to_string()))?;
        let dir = file.parent().unwrap_or(Path::new("."));
        let scene = dir.join(&raw.scene);
        if !scene.is_file() {
            return Err(err(format!(
                "scene = \"{}\": no such file ({}); the base scene is found relative to the case file",
                raw.scene.display(),
                scene.display()
            )));
        }
        let stem = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "sweep".into());
        let out = dir.join(
            raw.out
                .clone()
                .unwrap_or_else(|| format!("{stem}-runs").into()),
        );
        let list_err = |e: CaseFileError| err(e.to_string());
        let common = overrides_of(&raw.set, "set").map_err(list_err)?;
        let mut cases = matrix(&raw, &common).map_err(list_err)?;
        for (k, c) in raw.case.iter().enumerate() {
            let mut o = common.clone();
            o.extend(overrides_of(&c.set, &format!("[[case]] #{} set", k + 1)).map_err(list_err)?);
            if c.name.trim().is_empty() {
                return Err(err(format!("[[case]] #{}: name is empty", k + 1)));
            }
            cases.push(Case {
                index: 0,
                name: c.name.clone(),
                overrides: o,
            });
        }
        if cases.is_empty() {
            return Err(err(
                "no cases: give a [vary] table of dotted paths with lists of values, or [[case]] tables"
                    .into(),
            ));
        }
        for (i, c) in cases.iter_mut().enumerate() {
            c.index = i;
        }
        let sweep = Sweep {
            file,
            scene,
            out,
            cases,
        };
        for c in &sweep.cases {
            aqua_sim::scene::read_scene(
                aqua_sim::scene::SceneInput::File(&sweep.scene),
                &c.overrides,
            )
            .map_err(|e| {
                SimError::input(format!(
                    "{}: case {} ({}): {}",
                    sweep.file.display(),
                    c.index,
                    c.name,
                    e.chain()
                ))
            })?;
        }
        Ok(sweep)
    }

    /// The folder of case `k`.
    pub fn case_dir(&self, k: usize) -> PathBuf {
        self.out.join(case_folder(k))
    }

    /// `EXE sweep FILE --case K [--out DIR]` with absolute paths, for another process or host
    /// (`k` may be a shell expression such as `"$SLURM_ARRAY_TASK_ID"`, passed through as is;
    /// `--out` when the sweep was given one).
    pub fn case_command(&self, exe: &Path, k: &str, with_out: bool) -> String {
        let mut cmd = format!(
            "{} sweep {} --case {k}",
            shell_word(&exe.to_string_lossy()),
            shell_word(&self.file.to_string_lossy())
        );
        if with_out {
            cmd += &format!(" --out {}", shell_word(&self.out.to_string_lossy()));
        }
        cmd
    }

    /// A Slurm job-array script: one case per array task calling `exe`, Slurm's own output
    /// of each task in the case's folder (which the caller creates: Slurm does not create
    /// the folder of an `--output` file).
    pub fn slurm_script(&self, exe: &Path, with_out: bool) -> String {
        let stem = self
            .file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "sweep".into());
        let job: String = stem
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        format!(
            "#!/bin/bash\n\
             # {n} load cases of {scene}: one Slurm array task per case.\n\
             # Submit with: sbatch {job}.sbatch   (collect afterwards: aqua collect {out})\n\
             #SBATCH --job-name=aqua-{job}\n\
             #SBATCH --array=0-{last}\n\
             #SBATCH --ntasks=1\n\
             #SBATCH --cpus-per-task=1\n\
             #SBATCH --output={out_dir}/case_%4a/slurm-%A_%a.log\n\
             set -euo pipefail\n\
             : \"${{SLURM_ARRAY_TASK_ID:?run this script with sbatch (or set SLURM_ARRAY_TASK_ID)}}\"\n\
             exec {cmd}\n",
            n = self.cases.len(),
            out_dir = self.out.display(),
            scene = self.scene.display(),
            out = self.out.display(),
            last = self.cases.len() - 1,
            cmd = self.case_command(exe, "\"$SLURM_ARRAY_TASK_ID\"", with_out),
        )
    }
}

/// `case_NNNN`.
pub fn case_folder(k: usize) -> String {
    format!("case_{k:04}")
}

/// What is wrong with a case file's `set`, `[vary]` or `combine`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum CaseFileError {
    /// A path that is no scene key path; `at` names the table (`set: `, `[vary] `).
    #[error("{at}{source}")]
    Path {
        /// Where, with its separator.
        at: String,
        /// Why the path is not valid.
        source: aqua_sim::overrides::OverrideError,
    },
    /// A `[vary]` list without values.
    #[error("[vary] \"{path}\" = []: give at least one value")]
    EmptyList {
        /// The varied path.
        path: String,
    },
    /// A `[vary]` value that is no list.
    #[error("[vary] \"{path}\" = {value}: a list of values, e.g. [0.5, 1.0]")]
    NotList {
        /// The varied path.
        path: String,
        /// The value given.
        value: String,
    },
    /// Zipped lists of different lengths.
    #[error(
        "combine = \"zip\" needs lists of one length: \"{first}\" has {n} values, \"{path}\" \
         has {len}"
    )]
    ZipLengths {
        /// The first list's path.
        first: String,
        /// Its length.
        n: usize,
        /// A list of another length.
        path: String,
        /// Its length.
        len: usize,
    },
}

/// `PATH = VALUE` pairs of a `set` table.
fn overrides_of(t: &Table, what: &str) -> std::result::Result<Vec<Override>, CaseFileError> {
    t.iter()
        .map(|(path, value)| {
            check_path_syntax(path).map_err(|m| CaseFileError::Path {
                at: format!("{what}: "),
                source: m,
            })?;
            Ok(Override {
                path: path.clone(),
                value: value.clone(),
            })
        })
        .collect()
}

/// The cases of `[vary]`.
fn matrix(raw: &RawCases, common: &[Override]) -> std::result::Result<Vec<Case>, CaseFileError> {
    let mut lists: Vec<(&String, &Vec<Value>)> = Vec::new();
    for (path, v) in &raw.vary {
        check_path_syntax(path).map_err(|m| CaseFileError::Path {
            at: "[vary] ".into(),
            source: m,
        })?;
        match v {
            Value::Array(a) if !a.is_empty() => lists.push((path, a)),
            Value::Array(_) => return Err(CaseFileError::EmptyList { path: path.clone() }),
            other => {
                return Err(CaseFileError::NotList {
                    path: path.clone(),
                    value: other.to_string(),
                });
            }
        }
    }
    if lists.is_empty() {
        return Ok(Vec::new());
    }
    let settings: Vec<Vec<usize>> = match raw.combine {
        Combine::Factorial => lists.iter().fold(vec![vec![]], |acc, (_, vals)| {
            acc.into_iter()
                .flat_map(|s| {
                    (0..vals.len()).map(move |k| {
                        let mut s = s.clone();
                        s.push(k);
                        s
                    })
                })
                .collect()
        }),
        Combine::Zip => {
            let n = lists[0].1.len();
            if let Some((p, v)) = lists.iter().find(|(_, v)| v.len() != n) {
                return Err(CaseFileError::ZipLengths {
                    first: lists[0].0.clone(),
                    n,
                    path: p.to_string(),
                    len: v.len(),
                });
            }
            (0..n).map(|k| vec![k; lists.len()]).collect()
        }
    };
    Ok(settings
        .into_iter()
        .map(|s| {
            let mut o = common.to_vec();
            let mut name = Vec::new();
            for ((path, vals), &k) in lists.iter().zip(&s) {
                o.push(Override {
                    path: (*path).clone(),
                    value: vals[k].clone(),
                });
                name.push(format!("{path}={}", value_text(&vals[k])));
            }
            Case {
                index: 0,
                name: name.join(" "),
                overrides: o,
            }
        })
        .collect())
}

/// What a case folder says of its run (`case.json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CaseRecord {
    /// Case index.
    pub index: usize,
    /// Case name.
    pub name: String,
    /// Changes as `PATH=VALUE`.
    pub set: Vec<String>,
    /// "completed", "failed", "interrupted".
    pub status: String,
    /// Why it failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Wall time of the case [s].
    pub wall_time_s: f64,
}

impl CaseRecord {
    /// Writes it as `dir/case.json`.
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        std::fs::write(dir.join("case.json"), text)
    }
}

/// The warnings of the run in `dir`, as its `run.json` lists them (`diagnostics`), one text
/// each; none when there is no readable `run.json`.
pub fn run_diagnostics(dir: &Path) -> Vec<String> {
    let list = read_json(&dir.join("run.json"))
        .and_then(|v| v.get("diagnostics").and_then(|d| d.as_array()).cloned())
        .unwrap_or_default();
    list.iter()
        .map(|d| d.as_str().map_or_else(|| d.to_string(), str::to_string))
        .collect()
}

/// One collected run folder.
#[derive(Debug, Clone)]
pub struct Collected {
    /// Folder name.
    pub folder: String,
    /// Case name (folder name for a plain run).
    pub name: String,
    /// `PATH=VALUE` changes.
    pub set: Vec<String>,
    /// Status.
    pub status: String,
    /// Wall time [s].
    pub wall_time_s: f64,
    /// Per summary column: (name, min, max, mean, std) over the dynamic part; min and max over
    /// every accepted step where the run wrote its extremes (`extremes.csv`), else over the
    /// output steps of `summary.csv`.
    pub stats: Vec<(String, [f64; 4])>,
    /// True when min and max of the load columns are over every accepted step (the run
    /// wrote `extremes.csv` or `run.json`'s `extremes`), false when over output steps only.
    pub every_step: bool,
    /// Error text.
    pub error: Option<String>,
}

/// The merged table of a folder of runs.
#[derive(Debug, Clone)]
pub struct Collection {
    /// Every run folder, by folder name.
    pub runs: Vec<Collected>,
    /// Changed paths (one parameter column each), in first-seen order.
    pub parameters: Vec<String>,
    /// Summary columns, in first-seen order.
    pub columns: Vec<String>,
}

/// The governing cases of one summary column.
#[derive(Debug, Clone, PartialEq)]
pub struct Governing {
    /// The column.
    pub column: String,
    /// Folder and value of the largest maximum.
    pub largest: (String, f64),
    /// Folder and value of the smallest minimum.
    pub smallest: (String, f64),
}

/// Columns of `summary.csv` that are bookkeeping, not results.
const NOT_RESULTS: &[&str] = &["t", "newton_iterations", "dt"];

/// Reads every sub-folder of `dir` that holds `case.json` or `run.json`.
pub fn collect(dir: &Path) -> Result<Collection> {
    if !dir.is_dir() {
        return Err(SimError::input(format!(
            "{}: no such folder (give the folder that holds the case_NNNN or run folders)",
            dir.display()
        )));
    }
    let entries = std::fs::read_dir(dir).map_err(|source| SimError::Io {
        what: "reading the folder",
        path: dir.to_path_buf(),
        source,
    })?;
    let mut folders: Vec<PathBuf> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.join("case.json").is_file() || p.join("run.json").is_file())
        .collect();
    folders.sort();
    if folders.is_empty() {
        return Err(SimError::input(format!(
            "{}: no run folders (sub-folders with case.json or run.json) to collect",
            dir.display()
        )));
    }
    let mut runs = Vec::new();
    for f in &folders {
        runs.push(collect_one(f)?);
    }
    let mut parameters: Vec<String> = Vec::new();
    let mut columns: Vec<String> = Vec::new();
    for r in &runs {
        for s in &r.set {
            let path = s.split_once('=').map(|p| p.0).unwrap_or(s).to_string();
            if !parameters.contains(&path) {
                parameters.push(path);
            }
        }
        for (c, _) in &r.stats {
            if !columns.contains(c) {
                columns.push(c.clone());
            }
        }
    }
    Ok(Collection {
        runs,
        parameters,
        columns,
    })
}

fn read_json(path: &Path) -> Option<serde_json::Value> {
    serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()
}

fn collect_one(folder: &Path) -> Result<Collected> {
    let name = folder
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let run = read_json(&folder.join("run.json"));
    let case: Option<CaseRecord> =
        read_json(&folder.join("case.json")).and_then(|v| serde_json::from_value(v).ok());
    let str_list = |v: Option<&serde_json::Value>| -> Vec<String> {
        v.and_then(|v| v.as_array())
            .map(|a| {
                a.iter()
                    .filter_map(|s| s.as_str().map(String::from))
                    .collect()
            })
            .unwrap_or_default()
    };
    let mut c = Collected {
        folder: name.clone(),
        name: case.as_ref().map(|c| c.name.clone()).unwrap_or(name),
        set: case
            .as_ref()
            .map(|c| c.set.clone())
            .unwrap_or_else(|| str_list(run.as_ref().and_then(|r| r.get("overrides")))),
        status: case
            .as_ref()
            .map(|c| c.status.clone())
            .or_else(|| run.as_ref()?.get("status")?.as_str().map(String::from))
            .unwrap_or_else(|| "unknown".into()),
        wall_time_s: case
            .as_ref()
            .map(|c| c.wall_time_s)
            .or_else(|| run.as_ref()?.get("wall_time_s")?.as_f64())
            .unwrap_or(f64::NAN),
        stats: vec![],
        every_step: false,
        error: case
            .as_ref()
            .and_then(|c| c.error.clone())
            .or_else(|| run.as_ref()?.get("error")?.as_str().map(String::from)),
    };
    let summary = folder.join("summary.csv");
    if !summary.is_file() {
        return Ok(c);
    }
    let table = SummaryTable::read(&summary)?;
    let kind = run
        .as_ref()
        .and_then(|r| {
            r.pointer("/scene/analysis/kind")?
                .as_str()
                .map(String::from)
        })
        .unwrap_or_default();
    // The dynamic part: after the static row of a static+dynamic run; the only row of a
    // static one.
    let rows = match (kind.as_str(), table.rows.len()) {
        ("static+dynamic", n) if n > 1 => &table.rows[1..],
        _ => &table.rows[..],
    };
    // The extremes over every accepted step, where the run wrote them (aqua_sim::extremes).
    let extremes = read_extremes(folder);
    c.every_step = extremes.is_some();
    for (k, col) in table.columns.iter().enumerate() {
        if NOT_RESULTS.contains(&col.as_str()) || rows.is_empty() {
            continue;
        }
        let v: Vec<f64> = rows.iter().map(|r| r[k]).collect();
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
        let (min, max) = match extremes.as_ref().and_then(|e| e.get(col)) {
            Some(e) => (e.min, e.max),
            None => (
                v.iter().copied().fold(f64::INFINITY, f64::min),
                v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            ),
        };
        c.stats.push((col.clone(), [min, max, mean, var.sqrt()]));
    }
    Ok(c)
}

impl Collection {
    /// The merged CSV: one row per run folder; its parameters, status, wall time, what min
    /// and max are taken over (`every step` or `output steps`), and min/max/mean/std of every
    /// summary column.
    pub fn csv(&self) -> String {
        let mut head: Vec<String> = vec!["folder".into(), "name".into()];
        head.extend(self.parameters.iter().cloned());
        head.extend(["status", "wall_time_s", "extremes_over"].map(String::from));
        for c in &self.columns {
            for s in ["min", "max", "mean", "std"] {
                head.push(format!("{c} {s}"));
            }
        }
        head.push("error".into());
        let mut out = csv_line(&head);
        for r in &self.runs {
            let mut row = vec![r.folder.clone(), r.name.clone()];
            for p in &self.parameters {
                let v = r
                    .set
                    .iter()
                    .rev()
                    .find_map(|s| s.split_once('=').filter(|(k, _)| k == p).map(|x| x.1))
                    .unwrap_or("");
                row.push(v.to_string());
            }
            row.push(r.status.clone());
            row.push(format!("{:.3}", r.wall_time_s));
            row.push(
                if r.every_step {
                    "every step"
                } else {
                    "output steps"
                }
                .to_string(),
            );
            for c in &self.columns {
                match r.stats.iter().find(|(n, _)| n == c) {
                    Some((_, s)) => row.extend(s.iter().map(|x| format!("{x:.10e}"))),
                    None => row.extend(std::iter::repeat_n(String::new(), 4)),
                }
            }
            row.push(r.error.clone().unwrap_or_default());
            out += &csv_line(&row);
        }
        out
    }

    /// Per summary column, the run with the largest maximum and the one with the smallest
    /// minimum (the governing cases); columns that are zero in every run are left out.
    pub fn governing(&self) -> Vec<Governing> {
        let all_zero = |c: &String| {
            self.runs.iter().all(|r| {
                r.stats
                    .iter()
                    .find(|(n, _)| n == c)
                    .is_none_or(|(_, s)| s.iter().all(|v| *v == 0.0))
            })
        };
        self.columns
            .iter()
            .filter(|c| !all_zero(c))
            .filter_map(|c| {
                let of = |k: usize| {
                    self.runs.iter().filter_map(move |r| {
                        r.stats
                            .iter()
                            .find(|(n, _)| n == c)
                            .map(|(_, s)| (r.folder.clone(), s[k]))
                    })
                };
                let hi = of(1).max_by(|a, b| a.1.total_cmp(&b.1))?;
                let lo = of(0).min_by(|a, b| a.1.total_cmp(&b.1))?;
                Some(Governing {
                    column: c.clone(),
                    largest: hi,
                    smallest: lo,
                })
            })
            .collect()
    }
}

/// A word for a POSIX shell: single-quoted unless it is plainly safe.
fn shell_word(s: &str) -> String {
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-+=:,@%".contains(c))
    {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw(text: &str) -> RawCases {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn factorial_and_zip_matrices() {
        let r = raw("scene = \"s.toml\"\n[vary]\n\"a.b\" = [1, 2]\n\"c\" = [3, 4, 5]\n");
        let cases = matrix(&r, &[]).unwrap();
        assert_eq!(cases.len(), 6);
        assert_eq!(cases[1].name, "a.b=1 c=4");
        let r =
            raw("scene = \"s.toml\"\ncombine = \"zip\"\n[vary]\n\"a\" = [1, 2]\n\"c\" = [3, 4]\n");
        let cases = matrix(&r, &[]).unwrap();
        assert_eq!(cases.len(), 2);
        assert_eq!(cases[1].name, "a=2 c=4");
        let r = raw("scene = \"s.toml\"\ncombine = \"zip\"\n[vary]\n\"a\" = [1, 2]\n\"c\" = [3]\n");
        assert!(
            matrix(&r, &[])
                .unwrap_err()
                .to_string()
                .contains("one length")
        );
        let r = raw("scene = \"s.toml\"\n[vary]\n\"a\" = []\n");
        assert_eq!(
            matrix(&r, &[]).unwrap_err(),
            CaseFileError::EmptyList { path: "a".into() }
        );
        assert!(
            matrix(&r, &[])
                .unwrap_err()
                .to_string()
                .contains("at least one value")
        );
    }
}
