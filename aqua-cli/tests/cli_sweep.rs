//! `aqua sweep` and `aqua collect` end to end: the same cases run on this machine, through the
//! real GNU parallel and through the emitted Slurm array script (run here task by task with
//! SLURM_ARRAY_TASK_ID set) give identical collected tables; a failing case does not stop the
//! others; bad case files exit 2.

mod common;

use common::{aqua, scratch};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// A short surged chain and a case file: 2 currents × 3 periods, plus one case that fails
/// validation (a time step longer than the run).
fn write_cases(d: &Path) -> PathBuf {
    std::fs::write(
        d.join("chain.toml"),
        "name = \"chain\"\n[sea]\ndepth = 50.0\n[sea.current]\nkind = \"uniform\"\n\
         velocity = [0.0, 0.0, 0.0]\n[[line]]\nname = \"chain\"\nanchor = [0.0, 0.0, -50.0]\n\
         fairlead = [100.0, 0.0, -5.0]\nlength = 120.0\nsegments = 16\ndiameter = 0.1354\n\
         mass_per_length = 113.0\nea = 5.4e8\nhydro_diameter = 0.076\nmorison = \"const\"\n\
         cn = 2.4\nct = 1.15\nadded_mass = 1.0\n[[prescribed]]\nnodes = \"chain/fairlead\"\n\
         motion = \"sine\"\namplitude = [1.5, 0.0, 0.0]\nperiod = 10.0\nramp_time = 2.0\n\
         [analysis]\nkind = \"static+dynamic\"\n[analysis.dynamic]\ndt = 0.1\nt_end = 3.0\n\
         output_interval = 0.5\n",
    )
    .unwrap();
    let cases = d.join("cases.toml");
    std::fs::write(
        &cases,
        "scene = \"chain.toml\"\n\
         [vary]\n\"sea.current.velocity\" = [[0.0, 0.0, 0.0], [0.6, 0.0, 0.0]]\n\
         \"prescribed.0.period\" = [6.0, 8.0, 10.0]\n\
         [[case]]\nname = \"broken\"\nset = { \"analysis.dynamic.dt\" = 50.0 }\n",
    )
    .unwrap();
    cases
}

/// The collected table without the wall-time column (the only one that depends on the engine).
fn collected(out: &Path) -> Vec<Vec<String>> {
    let o = aqua(&["collect", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("collected.csv")).unwrap();
    let rows: Vec<Vec<String>> = text.lines().map(split_csv).collect();
    let wall = rows[0].iter().position(|h| h == "wall_time_s").unwrap();
    rows.into_iter()
        .map(|mut r| {
            r.remove(wall);
            r
        })
        .collect()
}

/// A CSV line split on commas outside double quotes.
fn split_csv(line: &str) -> Vec<String> {
    let (mut out, mut cur, mut quoted) = (Vec::new(), String::new(), false);
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur)),
            c => cur.push(c),
        }
    }
    out.push(cur);
    out
}

fn gnu_parallel() -> bool {
    let found = Command::new("parallel")
        .arg("--version")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("GNU parallel"));
    if !found {
        assert!(
            std::env::var_os("AQUA_REQUIRE_PARALLEL").is_none(),
            "AQUA_REQUIRE_PARALLEL is set but GNU parallel is not installed"
        );
        eprintln!("GNU parallel is not installed: skipping the --emit parallel engine");
    }
    found
}

/// Every case folder of a sweep holds `case.json` and an `aqua.log` in which the case says
/// what it ran and how it ended (whichever engine started it).
fn assert_case_logs(out: &Path, n: usize, engine: &str) {
    for k in 0..n {
        let dir = out.join(format!("case_{k:04}"));
        assert!(
            dir.join("case.json").is_file(),
            "{engine}: {dir:?} has no case.json"
        );
        let log = std::fs::read_to_string(dir.join("aqua.log")).unwrap_or_default();
        let end = if k == 6 { "failed" } else { "completed" };
        assert!(
            log.contains(&format!("--case {k} ")) && log.contains(&format!("case {k} (")),
            "{engine}: case {k}'s aqua.log does not say what ran: {log:?}"
        );
        assert!(
            log.contains(&format!("): {end} in ")),
            "{engine}: case {k}'s aqua.log does not say it {end}: {log:?}"
        );
    }
}

#[test]
fn local_gnu_parallel_and_slurm_give_the_same_collected_table() {
    let d = scratch("sweep", "engines");
    let cases = write_cases(&d);
    let cases_s = cases.to_str().unwrap();

    // This machine, two at a time: the broken case fails, the others complete.
    let local = d.join("local");
    let o = aqua(&[
        "sweep",
        cases_s,
        "--local",
        "--jobs",
        "2",
        "--out",
        local.to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let table = collected(&local);
    assert_eq!(table.len(), 1 + 7);
    assert_case_logs(&local, 7, "--local");
    let status = table[0].iter().position(|h| h == "status").unwrap();
    let statuses: Vec<&str> = table[1..].iter().map(|r| r[status].as_str()).collect();
    assert_eq!(
        statuses.iter().filter(|s| **s == "completed").count(),
        6,
        "{statuses:?}"
    );
    assert_eq!(statuses[6], "failed");
    for p in [
        "sea.current.velocity",
        "prescribed.0.period",
        "analysis.dynamic.dt",
    ] {
        assert!(table[0].iter().any(|h| h == p), "no parameter column {p}");
    }

    // The collected statistics against summary.csv read here: case 4 (current 0.6 m/s,
    // period 8 s), the fairlead reaction over the dynamic rows (after the static row).
    let summary = std::fs::read_to_string(local.join("case_0004/summary.csv")).unwrap();
    let mut lines = summary.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = head
        .iter()
        .position(|h| *h == "chain_fairlead_reaction")
        .unwrap();
    let v: Vec<f64> = lines
        .skip(1)
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect();
    let max = v.iter().copied().fold(f64::MIN, f64::max);
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let col = |name: &str| table[0].iter().position(|h| h == name).unwrap();
    let got = |name: &str| table[5][col(name)].parse::<f64>().unwrap();
    // The max is over every accepted step (the case's extremes.csv), at or above the
    // sampled one.
    let extremes = std::fs::read_to_string(local.join("case_0004/extremes.csv")).unwrap();
    let per_step: f64 = extremes
        .lines()
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|f| f[0] == "chain_fairlead_reaction")
        .unwrap()[1]
        .parse()
        .unwrap();
    assert!(per_step >= max, "{per_step} < sampled {max}");
    assert!((got("chain_fairlead_reaction max") - per_step).abs() <= 1e-9 * per_step);
    assert!((got("chain_fairlead_reaction mean") - mean).abs() <= 1e-9 * mean);
    assert_eq!(table[5][col("prescribed.0.period")], "8.0");

    // Slurm: the emitted array script is valid bash and runs each task by its index.
    let slurm = d.join("slurm");
    let o = aqua(&[
        "sweep",
        cases_s,
        "--emit",
        "slurm",
        "--out",
        slurm.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let script = d.join("cases.sbatch");
    std::fs::write(&script, &o.stdout).unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("#SBATCH --array=0-6"), "{text}");
    // Slurm's own output of each task goes into the case's folder, which must exist before
    // the task starts (Slurm does not create it).
    assert!(
        text.contains(&format!("#SBATCH --output={}/case_%4a/", slurm.display())),
        "{text}"
    );
    assert!((0..7).all(|k| slurm.join(format!("case_{k:04}")).is_dir()));
    let syntax = Command::new("bash")
        .arg("-n")
        .arg(&script)
        .status()
        .unwrap();
    assert!(syntax.success());
    for k in 0..7 {
        let s = Command::new("bash")
            .arg(&script)
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .unwrap();
        assert_eq!(s.success(), k != 6, "task {k}");
    }
    assert_eq!(collected(&slurm), table, "Slurm and --local tables differ");
    assert_case_logs(&slurm, 7, "Slurm");

    // GNU parallel, fed the emitted command lines.
    if gnu_parallel() {
        let par = d.join("parallel");
        let o = aqua(&[
            "sweep",
            cases_s,
            "--emit",
            "parallel",
            "--out",
            par.to_str().unwrap(),
        ]);
        assert!(o.status.success());
        assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 7);
        let mut child = Command::new("parallel")
            .args(["--will-cite", "--jobs", "2"])
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        use std::io::Write;
        child.stdin.take().unwrap().write_all(&o.stdout).unwrap();
        // GNU parallel's exit status is the number of failed jobs.
        assert_eq!(child.wait().unwrap().code(), Some(1));
        assert_eq!(
            collected(&par),
            table,
            "GNU parallel and --local tables differ"
        );
        assert_case_logs(&par, 7, "GNU parallel");
    }
}

#[test]
fn bad_case_files_exit_2_naming_the_problem() {
    let d = scratch("sweep", "bad");
    write_cases(&d);
    let cases: &[(&str, &str)] = &[
        (
            "scene = \"missing.toml\"\n[vary]\n\"dt\" = [0.1]\n",
            "missing.toml",
        ),
        (
            "scene = \"chain.toml\"\n[vary]\n\"line.0.segmnts\" = [4, 8]\n",
            "segmnts",
        ),
        (
            "scene = \"chain.toml\"\n[vary]\n\"line.0.segments\" = [\"many\"]\n",
            "line.0.segments=many",
        ),
        ("scene = \"chain.toml\"\n", "no cases"),
        (
            "scene = \"chain.toml\"\ncases = 3\n",
            "unknown field `cases`",
        ),
        (
            "scene = \"chain.toml\"\ncombine = \"zip\"\n[vary]\n\"a\" = [1, 2]\n\"b\" = [1]\n",
            "one length",
        ),
    ];
    for (k, (text, needle)) in cases.iter().enumerate() {
        let f = d.join(format!("bad{k}.toml"));
        std::fs::write(&f, text).unwrap();
        let o = aqua(&["sweep", f.to_str().unwrap(), "--local"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{text}: {err}");
        assert!(err.contains(needle), "{text}: {err}");
    }
    let good = d.join("cases.toml");
    let o = aqua(&["sweep", good.to_str().unwrap(), "--case", "7"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("has 7 cases"), "{err}");
    let o = aqua(&["collect", d.join("nothing-here").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
}
