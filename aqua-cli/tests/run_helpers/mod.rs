//! Helpers of the end-to-end tests of the `aqua` binary: running it, scratch folders, scenes,
//! and reading back `.pvd`/`.vtm` outputs.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("aqua-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub fn aqua(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The `.vtm` files a `.pvd` lists, with their times.
pub fn pvd_entries(pvd: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(pvd).unwrap();
    text.lines()
        .filter(|l| l.contains("<DataSet"))
        .map(|l| {
            let attr = |name: &str| {
                let start = l.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
                let end = start + l[start..].find('"').unwrap();
                l[start..end].to_string()
            };
            (attr("timestep").parse().unwrap(), attr("file"))
        })
        .collect()
}

/// Asserts the `.pvd` lists exactly the step `.vtm` files in its directory (not the undeformed
/// `_reference.vtm`), at increasing times, and that every block file each one names exists.
pub fn assert_consistent(pvd: &Path) -> Vec<(f64, String)> {
    let entries = pvd_entries(pvd);
    let dir = pvd.parent().unwrap();
    let mut on_disk: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".vtm") && !n.ends_with("_reference.vtm"))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = entries
        .iter()
        .map(|(_, f)| {
            Path::new(f)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    listed.sort();
    assert_eq!(listed, on_disk, "pvd and directory disagree");
    for f in &listed {
        let vtm = std::fs::read_to_string(dir.join(f)).unwrap();
        let blocks: Vec<&str> = vtm
            .split("file=\"")
            .skip(1)
            .map(|r| &r[..r.find('"').unwrap()])
            .collect();
        assert!(!blocks.is_empty(), "{f} names no block");
        for b in blocks {
            assert!(dir.join(b).is_file(), "{f} names {b}, which is not on disk");
        }
    }
    assert!(
        entries.windows(2).all(|w| w[1].0 > w[0].0),
        "times must increase"
    );
    entries
}

pub fn chain_scene(dir: &Path, t_end: f64, extra: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/mooring-chain.toml"))
        .unwrap()
        .replace("t_end = 60.0", &format!("t_end = {t_end}"))
        .replace("output_interval = 0.5", "output_interval = 0.1")
        + extra;
    let p = dir.join("chain.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// `aqua run SCENE --out OUT --quiet` in the background, stderr captured.
pub fn spawn_quiet_run(scene: &Path, out: &Path) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args([
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Waits until `child` has used `cpu` of processor time (its threads summed, from
/// `/proc/PID/stat`) or has ended, so that a test interrupts it after a given amount of work
/// rather than of wall time, which a loaded machine stretches. Gives up after ten times `cpu`
/// of wall time.
pub fn wait_for_cpu_time(child: &std::process::Child, cpu: Duration) {
    // utime and stime are fields 14 and 15 of the stat line, in ticks of 1/100 s (the fixed
    // USER_HZ of Linux's user interface); the command name before them is in parentheses.
    let used = || -> Option<Duration> {
        let stat = std::fs::read_to_string(format!("/proc/{}/stat", child.id())).ok()?;
        let fields: Vec<&str> = stat[stat.rfind(')')? + 2..].split(' ').collect();
        let ticks: u64 =
            fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
        Some(Duration::from_millis(ticks * 10))
    };
    let start = Instant::now();
    while start.elapsed() < cpu * 10 {
        match used() {
            Some(t) if t < cpu => std::thread::sleep(Duration::from_millis(100)),
            _ => return,
        }
    }
}

/// Sends `signal` (`INT` as Ctrl-C in a terminal, `TERM` as `kill` and Slurm's time limit).
pub fn send_signal(child: &std::process::Child, signal: &str) {
    let status = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

/// A chain run stopped by `signal` after five output steps: exit 128 + the signal, run.json
/// `interrupted`, the `.pvd` consistent and one summary row per step it lists.
pub fn interrupt_dynamics(signal: &str, code: i32) {
    let dir = scratch(&format!("interrupt-{signal}"));
    let scene = chain_scene(&dir, 100_000.0, "");
    let out = dir.join("out");
    let child = spawn_quiet_run(&scene, &out);
    let pvd = out.join("mooring-chain.pvd");
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(120) {
        if pvd.exists() && pvd_entries(&pvd).len() >= 5 {
            break;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    send_signal(&child, signal);
    let result = child.wait_with_output().unwrap();
    assert_eq!(
        result.status.code(),
        Some(code),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let entries = assert_consistent(&pvd);
    assert!(entries.len() >= 5);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "interrupted");
    assert_eq!(json["output_steps"].as_u64(), Some(entries.len() as u64));
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(
        csv.lines().count(),
        entries.len() + 1,
        "one summary row per output step"
    );
    // The extremes reached before the signal: in extremes.csv and in run.json, the same, and
    // bounding those of the output steps written.
    let extremes = assert_extremes_agree(&out);
    assert!(extremes.len() >= 4, "{extremes:?}");
    for (c, max, min) in &extremes {
        let Some(k) = csv.lines().next().unwrap().split(',').position(|h| h == c) else {
            continue; // F_net, R: magnitudes, not summary columns
        };
        // The dynamic part: after the static row.
        for line in csv.lines().skip(2) {
            let v: f64 = line.split(',').nth(k).unwrap().parse().unwrap();
            assert!(*min <= v && v <= *max, "{c}: {v} outside [{min}, {max}]");
        }
    }
}

/// Asserts `DIR/extremes.csv` and `DIR/run.json`'s `extremes` hold the same columns and
/// numbers (to an ulp: serde_json's parser may round the last digit); returns (column, max,
/// min) of each.
pub fn assert_extremes_agree(dir: &Path) -> Vec<(String, f64, f64)> {
    let text = std::fs::read_to_string(dir.join("extremes.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("column,max,t_max,min,t_min"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap();
    let obj = json["extremes"].as_object().expect("run.json has extremes");
    let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs());
    let mut out = Vec::new();
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let e = &obj[f[0]];
        for (k, key) in ["max", "t_max", "min", "t_min"].iter().enumerate() {
            let v: f64 = f[k + 1].parse().unwrap();
            assert!(
                close(v, e[key].as_f64().unwrap()),
                "{} {key}: {v} vs {e}",
                f[0]
            );
        }
        out.push((
            f[0].to_string(),
            f[1].parse().unwrap(),
            f[3].parse().unwrap(),
        ));
    }
    assert_eq!(out.len(), obj.len());
    out
}

/// The Python interpreter with the `vtk` package (tests/python/requirements.txt), or a printed
/// note and `None`.
pub fn vtk_python() -> Option<String> {
    match std::env::var("AQUA_VTK_PYTHON") {
        Ok(p) => Some(p),
        Err(_) => {
            eprintln!(
                "note: AQUA_VTK_PYTHON is not set; the independent VTK read-back runs in CI \
                 (.ci/run installs tests/python/requirements.txt)"
            );
            None
        }
    }
}

/// Runs tests/python/check_series.py on a `.pvd` with expectations; (passed, output).
pub fn check_series(
    python: &str,
    pvd: &Path,
    expect: &serde_json::Value,
    single: Option<&Path>,
) -> (bool, String) {
    let ef = pvd.with_extension("expect.json");
    std::fs::write(&ef, expect.to_string()).unwrap();
    let mut cmd = Command::new(python);
    cmd.arg(root().join("tests/python/check_series.py"))
        .arg(pvd)
        .arg("--expect")
        .arg(&ef);
    if let Some(s) = single {
        cmd.arg("--single").arg(s);
    }
    let out = cmd.output().expect("cannot run AQUA_VTK_PYTHON");
    (
        out.status.success(),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    )
}

/// A small moored cage (CSM cage + four named chains) in current only, 1 s of dynamics.
pub fn moored_cage_scene(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/moored-cage.toml")).unwrap();
    let a = text.find("[sea.waves]").unwrap();
    let b = text.find("[[cage]]").unwrap();
    let text = format!("{}{}", &text[..a], &text[b..])
        .replace("element_length = 4.0", "element_length = 5.0")
        .replace("top_ring[6]", "top_ring[4]")
        .replace("top_ring[12]", "top_ring[8]")
        .replace("top_ring[18]", "top_ring[12]")
        .replace("t_end = 60.0", "t_end = 1.0")
        .replace("output_interval = 1.0", "output_interval = 0.5");
    assert!(text.contains("t_end = 1.0") && text.contains("top_ring[12]"));
    let p = dir.join("moored.toml");
    std::fs::write(&p, text).unwrap();
    p
}

pub fn run_quiet(scene: &Path, out: &Path) {
    let (code, _, err) = aqua(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
}

/// Nodes of examples/moored-cage.toml: the cage's 153 and, per line, one per segment (its
/// fairlead is a collar node).
pub fn moored_points() -> u64 {
    let scene = std::fs::read_to_string(root().join("examples/moored-cage.toml")).unwrap();
    let line_nodes: u64 = scene
        .lines()
        .filter_map(|l| l.trim().strip_prefix("segments = "))
        .map(|n| n.trim().parse::<u64>().unwrap())
        .sum();
    153 + line_nodes
}

pub const MOORED_BLOCKS: [&str; 11] = [
    "cage/lines",
    "cage/panels",
    "cage/points",
    "m_east/lines",
    "m_east/points",
    "m_north/lines",
    "m_north/points",
    "m_west/lines",
    "m_west/points",
    "m_south/lines",
    "m_south/points",
];

/// `pvbatch` (or `AQUA_PVBATCH`), or a printed note and `None`.
pub fn pvbatch() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("AQUA_PVBATCH") {
        return Some(PathBuf::from(p));
    }
    for name in ["pvbatch", "pvpython"] {
        if let Some(p) = std::env::var_os("PATH").and_then(|paths| {
            std::env::split_paths(&paths)
                .map(|d| d.join(name))
                .find(|p| p.is_file())
        }) {
            return Some(p);
        }
    }
    eprintln!(
        "note: skipped: ParaView is not installed (no pvbatch or pvpython on PATH, AQUA_PVBATCH \
         unset); the script open_in_paraview.py was not run"
    );
    None
}

pub fn on_path(name: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(name).is_file()))
}

/// `pvbatch` under a display (a real one, or a virtual one through xvfb-run), or `None` (and
/// a note) when neither is available.
pub fn pvbatch_with_display(pv: &Path) -> Option<Command> {
    if std::env::var_os("DISPLAY").is_some() {
        return Some(Command::new(pv));
    }
    if on_path("xvfb-run") {
        let mut c = Command::new("xvfb-run");
        c.arg("-a").arg(pv);
        return Some(c);
    }
    eprintln!("note: no display and no xvfb-run: the ParaView script runs without a picture");
    None
}

/// Width and height of a PNG file (its IHDR chunk).
pub fn png_size(png: &[u8]) -> (u32, u32) {
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n") && &png[12..16] == b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    (be(&png[16..20]), be(&png[20..24]))
}

/// Runs `cmd` and asserts it succeeds. `xvfb-run -a` can lose the race for a display number to
/// another X server starting at the same moment (another test, another user); ParaView then
/// reports "bad X server connection" before running anything, and the command is run again
/// (at most 3 times).
pub fn run_ok(mut cmd: Command) {
    for attempt in 1..=3 {
        let res = cmd.output().unwrap();
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&res.stdout),
            String::from_utf8_lossy(&res.stderr)
        );
        let lost_display =
            text.contains("bad X server connection") || text.contains("Xvfb failed to start");
        if res.status.success() || !lost_display || attempt == 3 {
            assert!(res.status.success(), "{text}");
            return;
        }
        eprintln!("note: the virtual display was lost to another X server; running again");
        std::thread::sleep(Duration::from_millis(500 * attempt));
    }
}

pub fn read_json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// The moored cage of [`moored_cage_scene`] in its waves, 2 s, an output every second: a series
/// whose shape changes from step to step.
pub fn moored_cage_in_waves(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/moored-cage.toml"))
        .unwrap()
        .replace("element_length = 4.0", "element_length = 5.0")
        .replace("top_ring[6]", "top_ring[4]")
        .replace("top_ring[12]", "top_ring[8]")
        .replace("top_ring[18]", "top_ring[12]")
        .replace("t_end = 60.0", "t_end = 2.0");
    assert!(text.contains("t_end = 2.0") && text.contains("[sea.waves]"));
    let p = dir.join("moored-waves.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// A 1 × 2 farm, statics only: block names from object names with `/`.
pub fn small_farm(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/farm.toml")).unwrap();
    let a = text.find("[sea.waves]").unwrap();
    let b = text.find("[[farm]]").unwrap();
    let c = text.find("[analysis]").unwrap();
    let text = format!(
        "{}{}[analysis]\nkind = \"static\"\n",
        &text[..a],
        &text[b..c]
    )
    .replace("rows = 2 ", "rows = 1 ")
    .replace("columns = 3 ", "columns = 2 ");
    assert!(text.contains("rows = 1 ") && text.contains("columns = 2 "));
    let p = dir.join("farm.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// The cells of every dataset a `.vtm` lists, by `block/dataset` path (read from the `.vtu`
/// files' `NumberOfCells`).
pub fn vtm_cells(vtm: &Path) -> Vec<(String, u64)> {
    let text = std::fs::read_to_string(vtm).unwrap();
    let attr = |line: &str, key: &str| -> String {
        let k = format!("{key}=\"");
        let i = line.find(&k).unwrap() + k.len();
        line[i..].split('"').next().unwrap().to_string()
    };
    let mut block = String::new();
    let mut out = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("<Block ") {
            block = attr(line, "name");
        } else if line.trim_start().starts_with("<DataSet ") {
            let vtu =
                std::fs::read_to_string(vtm.parent().unwrap().join(attr(line, "file"))).unwrap();
            let n: u64 = attr(&vtu, "NumberOfCells").parse().unwrap();
            out.push((format!("{block}/{}", attr(line, "name")), n));
        }
    }
    out
}

pub fn interrupt_statics(signal: &str, code: i32) {
    // The reference cage at 1.25 m elements takes ~25 s of statics in release; a stop signal
    // during it must stop the solve promptly, write the last accepted state as step 0, say
    // that it is not converged, and exit 128 + the signal.
    let dir = scratch(&format!("interrupt-statics-{signal}"));
    let out = dir.join("out");
    let scene = dir.join("fine-cage.toml");
    let text = std::fs::read_to_string(root().join("examples/reference-cage.toml")).unwrap();
    std::fs::write(
        &scene,
        text.replace("element_length = 2.5", "element_length = 1.25"),
    )
    .unwrap();
    let child = spawn_quiet_run(&scene, &out);
    // 6 s of the run's own processor time, however loaded the machine is.
    wait_for_cpu_time(&child, Duration::from_secs(6));
    let pvd = out.join("reference-cage.pvd");
    assert!(
        !pvd.exists() || pvd_entries(&pvd).is_empty(),
        "statics finished before the interrupt; the test needs a longer static solve"
    );
    let sent = Instant::now();
    send_signal(&child, signal);
    let result = child.wait_with_output().unwrap();
    let waited = sent.elapsed();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(code), "{stderr}");
    assert!(stderr.contains("NOT converged"), "{stderr}");
    // Generous bound (debug build, loaded CI): the solver polls between Newton iterations.
    assert!(waited < Duration::from_secs(20), "stopped after {waited:?}");
    let entries = assert_consistent(&pvd);
    assert_eq!(entries.len(), 1, "the static state is step 0");
    assert_eq!(entries[0].0, 0.0);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "interrupted");
    assert_eq!(json["output_steps"].as_u64(), Some(1));
    // The full load at once: the iterate is one of the full current.
    assert_eq!(json["static_load_factor"].as_f64(), Some(1.0));
    assert_eq!(json["static_converged"], false);
    assert!(
        json["static_relative_residual"]
            .as_f64()
            .is_some_and(|r| r > 0.0)
    );
    let hist = json["static_residual_history"].as_array().unwrap();
    assert!(!hist.is_empty());
    assert!(hist.iter().all(|v| v.as_f64().is_some_and(f64::is_finite)));
    // Step 0 is the last accepted iterate under the full current, not the as-built net (all
    // twines slack, no reaction, volume ratio 1), which is what the last converged load
    // increment would be when the full load is applied at once.
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap_or(f64::NAN))
        .collect();
    let col = |name: &str| row[head.iter().position(|h| *h == name).unwrap()];
    // An iterate, not an equilibrium: only that it has moved from the as-built net is sure.
    assert!(col("Fx_net") > 0.0, "Fx_net {}", col("Fx_net"));
    let reaction = col("Rx").abs() + col("Rz").abs();
    assert!(reaction > 0.0, "the as-built net, with no reactions");
    // The as-built net's ratio is 1 to the last bit (the same volume over the same nodes).
    assert!(
        (col("volume_ratio") - 1.0).abs() > 1e-9,
        "the net has not moved: volume ratio {}",
        col("volume_ratio")
    );
    // The extremes are those of the one state reached, the iterate written as step 0.
    for (c, max, min) in assert_extremes_agree(&out) {
        if head.contains(&c.as_str()) {
            assert_eq!((max, min), (col(&c), col(&c)), "{c}");
        }
    }
}

/// Largest value of `column` over the rows of a `summary.csv` after the static row.
pub fn sampled_max(csv: &str, column: &str) -> (f64, f64) {
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = head.iter().position(|h| *h == column).unwrap();
    lines
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            (f[0], f[k])
        })
        .fold(
            (f64::NAN, f64::NEG_INFINITY),
            |a, b| if b.1 > a.1 { b } else { a },
        )
}

/// Every file under `dir`, relative, sorted.
pub fn files_under(dir: &Path) -> Vec<String> {
    fn walk(base: &Path, d: &Path, out: &mut Vec<String>) {
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            out.push(p.strip_prefix(base).unwrap().to_string_lossy().into_owned());
            if p.is_dir() {
                walk(base, &p, out);
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}
