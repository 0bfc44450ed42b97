//! The local runner of a sweep (`aqua sweep --local`): every case as its own
//! `<exe> sweep <file> --case K --out <out>` child process, `jobs` at a time on a rayon pool;
//! a failed case does not stop the others. Each child writes its folder's `aqua.log` and
//! `case.json` ([`CaseRecord`]) itself.

use crate::sweep::{Case, CaseRecord, Sweep};
use rayon::prelude::*;
use std::path::Path;
use std::process::{Command, Stdio};

/// Runs every case of `sweep` as a child process of `exe`, `jobs` at a time (`jobs` ≥ 1).
/// A case started after `stop()` turned true is "not run"; `done` is called with each case and
/// its status line as it ends. Returns the status lines in case order ("completed …" for a
/// case that completed).
pub fn run_local(
    sweep: &Sweep,
    exe: &Path,
    jobs: usize,
    stop: &(dyn Fn() -> bool + Sync),
    done: &(dyn Fn(&Case, &str) + Sync),
) -> Result<Vec<String>, rayon::ThreadPoolBuildError> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(jobs).build()?;
    Ok(pool.install(|| {
        sweep
            .cases
            .par_iter()
            .with_max_len(1)
            .map(|c| {
                if stop() {
                    return "not run".to_string();
                }
                let status = run_child(exe, sweep, c.index);
                done(c, &status);
                status
            })
            .collect()
    }))
}

/// The status lines of [`run_local`] that are not a completed case.
pub fn failed_count(outcomes: &[String]) -> usize {
    outcomes
        .iter()
        .filter(|s| !s.starts_with("completed"))
        .count()
}

/// One case as a child process (which writes its folder's `aqua.log` and `case.json`
/// itself); returns its status line.
fn run_child(exe: &Path, sweep: &Sweep, k: usize) -> String {
    let dir = sweep.case_dir(k);
    // A case.json of an earlier sweep must not pass for this run's.
    let _ = std::fs::remove_file(dir.join("case.json"));
    let output = Command::new(exe)
        .arg("sweep")
        .arg(&sweep.file)
        .arg("--case")
        .arg(k.to_string())
        .arg("--out")
        .arg(&sweep.out)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output();
    let record: Option<CaseRecord> = std::fs::read_to_string(dir.join("case.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    // A case that ended before its own log was set up (or crashed): keep what it printed.
    if record.is_none()
        && let Ok(o) = &output
    {
        use std::io::Write;
        let log = std::fs::create_dir_all(&dir).and_then(|_| {
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(dir.join("aqua.log"))
        });
        if let Ok(mut f) = log {
            let _ = f.write_all(&o.stderr);
        }
    }
    let status = output.map(|o| o.status);
    match (status, record) {
        (Ok(_), Some(r)) => format!(
            "{} in {:.2} s{}",
            r.status,
            r.wall_time_s,
            r.error.map(|e| format!(" ({e})")).unwrap_or_default()
        ),
        (Ok(s), None) => format!("failed: exit status {s}, no case.json"),
        (Err(e), _) => format!("failed: cannot start {}: {e}", exe.display()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_completed_cases_count_as_done() {
        let o = [
            "completed in 0.10 s",
            "failed: exit status 1, no case.json",
            "not run",
            "completed in 2.00 s",
        ]
        .map(String::from);
        assert_eq!(failed_count(&o), 2);
    }

    #[test]
    fn a_missing_executable_fails_every_case_and_says_why() {
        let dir = std::env::temp_dir().join(format!("aqua-local-runner-{}", std::process::id()));
        let sweep = Sweep {
            file: dir.join("cases.toml"),
            scene: dir.join("scene.toml"),
            out: dir.clone(),
            cases: (0..3)
                .map(|index| Case {
                    index,
                    name: format!("c{index}"),
                    overrides: Vec::new(),
                })
                .collect(),
        };
        let seen = std::sync::Mutex::new(Vec::new());
        let exe = dir.join("no-such-aqua");
        let o = run_local(&sweep, &exe, 2, &|| false, &|c, _| {
            seen.lock().unwrap().push(c.index)
        })
        .unwrap();
        assert_eq!(o.len(), 3);
        assert_eq!(failed_count(&o), 3);
        assert!(
            o.iter().all(|s| s.starts_with("failed: cannot start")),
            "{o:?}"
        );
        let mut seen = seen.into_inner().unwrap();
        seen.sort();
        assert_eq!(seen, [0, 1, 2]);
        // Stopped before the start: nothing runs, nothing reported.
        let o = run_local(&sweep, &exe, 1, &|| true, &|_, _| panic!("ran")).unwrap();
        assert!(o.iter().all(|s| s == "not run"));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
