//! The farm of `examples/farm.toml` in its current (statics): mirror symmetry about the grid
//! axis along the current, the anchors holding exactly the water's horizontal force, the
//! upstream lines carrying the most, and the cage-to-cage wake slowing the downstream cages.
//! Bad farm input gives errors that name the file, the key and what is valid.

mod common;
use common::*;

use aqua_env::Phase;
use aqua_fem::{StaticControl, StaticSolution};
use aqua_sim::run::water_loads;
use aqua_sim::static_equilibrium;
use aqua_sim::{PrepareOptions, Prepared, prepare};
use std::collections::HashMap;

/// A solved farm: the scene, the equilibrium, the wall time [s] and the x-drag on each
/// cage's net [N].
struct Solved {
    prep: Prepared,
    sol: StaticSolution,
    wall: f64,
    drag: HashMap<String, f64>,
}

/// The example farm, statics only, solved tightly; `edit` changes the text first.
fn solve(name: &str, edit: impl Fn(String) -> String) -> Solved {
    let dir = scratch(name);
    let text = example("farm.toml").replace(
        "kind = \"static+dynamic\"",
        "kind = \"static\"\n\n[analysis.static]\ntol = 1e-10",
    );
    let path = dir.join("farm.toml");
    std::fs::write(&path, edit(text)).unwrap();
    let prep = prepare(PrepareOptions::file(&path)).unwrap();
    let (mut loads, _) = water_loads(&prep, Phase::Static).unwrap();
    let t0 = std::time::Instant::now();
    let sol = static_equilibrium(
        &prep.built.model,
        &prep.built.mesh,
        &mut loads,
        &prep.plan.statics,
        &mut |_| StaticControl::Continue,
    )
    .unwrap();
    let wall = t0.elapsed().as_secs_f64();
    // The net drag per cage at equilibrium, through the same load assembly.
    let drag = cage_drag(&prep, &loads, &sol);
    Solved {
        prep,
        sol,
        wall,
        drag,
    }
}

/// x-drag on the net elements (panels and twines) of every cage object, by name.
fn cage_drag(
    prep: &Prepared,
    loads: &aqua_sim::provider::WaterLoads,
    sol: &StaticSolution,
) -> HashMap<String, f64> {
    let b = &prep.built;
    let asm = &loads.assembly;
    let nl = b.mesh.lines.len();
    let mut out = HashMap::new();
    let mut eo = aqua_hydro::ElementOutput::default();
    for (e, cell) in b.load_cells.iter().enumerate() {
        if !cell.net {
            continue;
        }
        let object = if cell.cell < nl {
            b.mesh.lines[cell.cell].object
        } else {
            b.mesh.panels[cell.cell - nl].object
        };
        let nodes = asm.element_nodes(e);
        let x: Vec<[f64; 3]> = nodes.iter().map(|&n| sol.state.x[n]).collect();
        let v = vec![[0.0; 3]; nodes.len()];
        asm.element_load(e, &x, &v, aqua_hydro::Want::default(), &mut eo);
        let fx: f64 = eo.force[..nodes.len()].iter().map(|f| f[0]).sum();
        *out.entry(b.mesh.objects[object as usize].name.clone())
            .or_insert(0.0) += fx;
    }
    out
}

/// Node i's mirror image about y = 0 (as built), found by position.
fn mirror_map(prep: &Prepared) -> Vec<usize> {
    let nodes = &prep.built.mesh.nodes;
    let key = |x: f64, y: f64, z: f64| {
        (
            (x * 1e6).round() as i64,
            (y * 1e6).round() as i64,
            (z * 1e6).round() as i64,
        )
    };
    let index: HashMap<_, usize> = nodes
        .iter()
        .enumerate()
        .map(|(i, p)| (key(p.x, p.y, p.z), i))
        .collect();
    nodes
        .iter()
        .map(|p| {
            *index
                .get(&key(p.x, -p.y, p.z))
                .unwrap_or_else(|| panic!("no mirror node of {p:?}"))
        })
        .collect()
}

#[test]
fn farm_in_a_current_along_a_grid_axis() {
    let Solved {
        prep,
        sol,
        wall,
        drag,
    } = solve("farm-static", |t| t);
    let r = &sol.report;
    eprintln!(
        "farm statics: {} iterations, {:.2} s, residual {:.2e}",
        r.iterations, wall, r.relative_residual
    );
    assert!(r.iterations <= 300, "{} iterations", r.iterations);
    let out = &sol.outputs;
    let b = &prep.built;

    // Mirror symmetry of every nodal load and every tension about the centreline y = 0.
    let m = mirror_map(&prep);
    let fmax = out
        .hydro_force
        .iter()
        .map(|f| f[0].abs().max(f[1].abs()).max(f[2].abs()))
        .fold(0.0, f64::max);
    for (i, &j) in m.iter().enumerate() {
        let (a, c) = (out.hydro_force[i], out.hydro_force[j]);
        let d = (a[0] - c[0]).abs() + (a[1] + c[1]).abs() + (a[2] - c[2]).abs();
        assert!(d <= 1e-6 * fmax, "node {i} {a:?} vs mirror {j} {c:?}");
    }
    let elements: HashMap<(usize, usize), usize> = b
        .mesh
        .lines
        .iter()
        .enumerate()
        .map(|(e, l)| ((l.nodes[0].min(l.nodes[1]), l.nodes[0].max(l.nodes[1])), e))
        .collect();
    let tmax = out.tension.iter().map(|t| t.abs()).fold(0.0, f64::max);
    for (e, l) in b.mesh.lines.iter().enumerate() {
        let (p, q) = (m[l.nodes[0]], m[l.nodes[1]]);
        let k = elements[&(p.min(q), p.max(q))];
        assert!(
            (out.tension[e] - out.tension[k]).abs() <= 1e-6 * tmax,
            "element {e}: {} vs mirror {k}: {}",
            out.tension[e],
            out.tension[k]
        );
    }

    // The anchors hold the water's whole horizontal force (frictionless seabed).
    let sum = |v: &[[f64; 3]], k: usize| v.iter().map(|f| f[k]).sum::<f64>();
    let fx = sum(&out.hydro_force, 0);
    let anchors: Vec<usize> = b.line_ends.iter().map(|l| l.anchor).collect();
    let rx: f64 = anchors.iter().map(|&n| out.reaction[n][0]).sum();
    let ry: f64 = anchors.iter().map(|&n| out.reaction[n][1]).sum();
    let rx_all = sum(&out.reaction, 0);
    assert!(fx > 1e4, "water force {fx} N");
    assert!((rx + fx).abs() <= 1e-6 * fx, "anchors {rx} vs water {fx}");
    assert_eq!(rx, rx_all, "only anchors are supported");
    assert!(ry.abs() <= 1e-6 * fx, "anchors y {ry}");

    // Upstream (west, anchored against the current) lines carry the largest loads.
    let load: HashMap<&str, f64> = b
        .line_ends
        .iter()
        .map(|l| {
            let f = out.reaction[l.anchor];
            let name = l.name.strip_prefix("farm/").unwrap();
            (name, (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt())
        })
        .collect();
    assert_eq!(load.len(), 14);
    let max_w = load
        .iter()
        .filter(|(k, _)| k.starts_with("anchor_w"))
        .map(|(_, v)| *v);
    let min_w = max_w.clone().fold(f64::INFINITY, f64::min);
    let others = load
        .iter()
        .filter(|(k, _)| !k.starts_with("anchor_w"))
        .map(|(_, v)| *v);
    let max_other = others.fold(0.0, f64::max);
    assert!(min_w > max_other, "{load:?}");
    let e_max = load
        .iter()
        .filter(|(k, _)| k.starts_with("anchor_e"))
        .map(|(_, v)| *v);
    assert!(e_max.fold(0.0, f64::max) < min_w);

    // The collars float: no node submerged by more than the pipe diameter (0.35 m). Without
    // bending stiffness (issue 12) a collar is a pin-jointed ring: the nodes between the
    // heavily loaded ones ride up by a few decimetres (measured up to 0.45 m), held by the
    // buoyancy of their wet neighbouring elements. The plates hang clear of the seabed.
    let z = |r: &str| {
        let n = aqua_sim::resolve_ref(&b.mesh, r).unwrap();
        let zs: Vec<f64> = n.iter().map(|&i| sol.state.x[i][2]).collect();
        (
            zs.iter().copied().fold(f64::INFINITY, f64::min),
            zs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    };
    let mut collars = Vec::new();
    for r in 1..=2 {
        for c in 1..=3 {
            let (lo, hi) = z(&format!("farm/cage_r{r}c{c}/top_ring"));
            eprintln!("collar r{r}c{c}: z from {lo:.3} to {hi:.3} m");
            collars.push((r, c, lo, hi));
        }
    }
    for (r, c, lo, hi) in collars {
        assert!(lo > -0.35 && hi < 1.0, "collar r{r}c{c}: {lo} .. {hi}");
    }
    let (lo, hi) = z("farm/frame/plates");
    eprintln!("plates: z from {lo:.3} to {hi:.3} m");
    assert!(lo > -40.0 + 5.0 && hi < 0.0, "plates {lo} .. {hi}");
    let (lo, hi) = z("farm/frame/buoys");
    eprintln!("buoys: z from {lo:.3} to {hi:.3} m");
    assert!(lo > -0.6 && hi < 0.6, "buoys {lo} .. {hi}");

    // Downstream cages' drag below the upstream ones' (cage-to-cage wake on).
    for r in 1..=2 {
        let d = |c: usize| drag[&format!("farm/cage_r{r}c{c}")];
        assert!(
            d(1) > d(2) && d(2) > d(3),
            "row {r}: {} {} {}",
            d(1),
            d(2),
            d(3)
        );
    }
}

#[test]
fn cage_wake_off_leaves_the_cages_in_the_free_current() {
    let on = solve("farm-wake-on", |t| t).drag;
    let off = solve("farm-wake-off", |t| {
        t.replace("# cage_wake = true", "cage_wake = false")
    })
    .drag;
    // Upstream cages see the free current either way; downstream ones much less with wake.
    let c = |m: &HashMap<String, f64>, k: usize| m[&format!("farm/cage_r1c{k}")];
    assert!(c(&on, 3) < 0.8 * c(&off, 3), "{on:?} vs {off:?}");
    assert!(
        (c(&on, 1) / c(&off, 1) - 1.0).abs() < 0.1,
        "{on:?} vs {off:?}"
    );
}

#[test]
fn bad_farm_input_names_file_key_and_valid_values() {
    let dir = scratch("farm-bad");
    let check = |name: &str, edit: &dyn Fn(String) -> String, want: &[&str]| {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, edit(example("farm.toml"))).unwrap();
        let e = match prepare(PrepareOptions::file(&path)) {
            Ok(_) => panic!("{name}: accepted"),
            Err(e) => e.chain(),
        };
        assert!(e.contains(&format!("{name}.toml")), "{name}: {e}");
        for w in want {
            assert!(e.contains(w), "{name}: '{w}' not in: {e}");
        }
    };
    check(
        "no-cage",
        &|t| t.replace("columns = 3 ", "columns = 0 "),
        &["[[farm]] #1", "columns", ">= 1"],
    );
    check(
        "no-frame",
        &|t| t.replace("[farm.frame]", "[farm.frame_]"),
        &["[[farm]] #1", "frame_", "unknown field", "bridle"],
    );
    check(
        "missing-bridle",
        &|t| t.replace("[farm.bridle]", "[unused]"),
        &["unknown field", "unused"],
    );
    check(
        "missing-section",
        &|t| t.replace("diameter = 0.040\n", ""),
        &["bridle.diameter", "required"],
    );
    check(
        "unknown-key",
        &|t| t.replace("spacing = 40.0", "spaceing = 40.0"),
        &["line ", "[[farm]] #1", "spaceing", "spacing"],
    );
    check(
        "bad-cage",
        &|t| t.replace("type = \"CSM\"", "type = \"XYZ\""),
        &["[[farm]] #1", "XYZ", "CSM"],
    );
    check(
        "fixed-collar",
        &|t| {
            t.replace(
                "tip_weight = 300.0",
                "tip_weight = 300.0\nfixed = [\"top_ring\"]",
            )
        },
        &["cage.fixed", "collars float"],
    );
}
