//! Buoys, segmented lines and design warnings (docs/theory/farm.md#buoys,
//! #segmented-lines, #design-warnings): static equilibria against equations solved here
//! independently, the warnings on a bad and a good scene, and the errors of bad input.

use aqua_sim::scene::{SceneInput, read_scene};
use aqua_sim::{Diagnostic, Frame, Observer, PrepareOptions, Simulation, prepare};
use std::f64::consts::PI;
use std::path::Path;

const RHO: f64 = 1025.0;
const G: f64 = 9.80665;

/// What a run delivered: the last frame's positions and reactions, the diagnostics.
#[derive(Default)]
struct Capture {
    x: Vec<[f64; 3]>,
    reaction: Vec<[f64; 3]>,
    /// Per `[[line]]`: anchor and fairlead reactions, anchor and fairlead element tensions.
    line_ends: Vec<[f64; 4]>,
    codes: Vec<&'static str>,
}

impl Observer for Capture {
    fn diagnostic(&mut self, d: &Diagnostic) {
        self.codes.push(d.code);
    }
    fn frame(&mut self, f: &Frame<'_>) -> aqua_sim::Result<()> {
        self.x = f.state.x.clone();
        self.reaction = f.outputs.reaction.clone();
        self.line_ends = f.row.line_ends.clone();
        Ok(())
    }
}

/// Statics of a scene text: the capture (build and load diagnostics included) and the
/// static iteration count.
fn statics(text: &str) -> (Capture, usize) {
    let scene = scene_of(text, Path::new("buoys-test.toml")).unwrap();
    let prep = prepare(PrepareOptions::scene(scene)).unwrap();
    let mut cap = Capture::default();
    cap.codes.extend(prep.diagnostics().iter().map(|d| d.code));
    let mut sim = Simulation::new(&prep).unwrap();
    let (record, result) = sim.run(&mut cap);
    result.unwrap();
    (cap, record.static_iterations)
}

fn node_of(text: &str, reference: &str) -> usize {
    let scene = scene_of(text, Path::new("buoys-test.toml")).unwrap();
    let prep = prepare(PrepareOptions::scene(scene)).unwrap();
    aqua_sim::resolve_ref(&prep.built.mesh, reference).unwrap()[0]
}

/// The spherical cap of height h of a sphere of radius r [m³].
fn cap(h: f64, r: f64) -> f64 {
    let h = h.clamp(0.0, 2.0 * r);
    PI * h * h * (3.0 * r - h) / 3.0
}

/// The root of a increasing f on [lo, hi] by bisection.
fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

const STATIC: &str = "[analysis]\nkind = \"static\"\n";

#[test]
fn free_sphere_floats_at_the_cap_height() {
    let (d, m) = (1.0, 200.0);
    let text = format!(
        "[sea]\ndepth = 30\n[[buoy]]\nname = \"b\"\nposition = [0, 0, 0]\ndiameter = {d}\n\
         mass = {m}\n[[fix]]\nnodes = \"b/buoy\"\ndofs = [\"x\", \"y\"]\n{STATIC}"
    );
    let (cap_out, iterations) = statics(&text);
    let r = d / 2.0;
    // ρ_w·V_cap(h) = m, h the depth of the lowest point; centre at z = r − h.
    let h = bisect(|h| RHO * cap(h, r) - m, 0.0, d);
    let z = cap_out.x[0][2];
    assert!((z - (r - h)).abs() < 1e-6 * d, "z = {z}, exact {}", r - h);
    assert!(iterations <= 30, "{iterations} static iterations");
    assert!(
        cap_out.codes.iter().all(|c| !c.starts_with("design/")),
        "{:?}",
        cap_out.codes
    );
}

#[test]
fn sphere_on_a_vertical_tether_floats_where_the_balance_says() {
    // A 1 m sphere of 100 kg on a straight rope of 19.5 m in 10 elements from an anchor at
    // z = −20 m: the rope stretches and the buoy settles partly under water.
    let (d, m, l0, n, dr, mu, ea) = (1.0, 100.0, 19.5, 10usize, 0.02, 1.0, 1.0e6);
    let text = format!(
        "[sea]\ndepth = 30\n[[buoy]]\nname = \"b\"\nposition = [0, 0, -0.5]\ndiameter = {d}\n\
         mass = {m}\n[[line]]\nname = \"tether\"\nanchor = [0, 0, -20]\nfairlead = \"b/buoy\"\n\
         length = {l0}\nsegments = {n}\nshape = \"straight\"\ndiameter = {dr}\n\
         mass_per_length = {mu}\nea = {ea}\nmorison = \"none\"\n{STATIC}"
    );
    let (out, iterations) = statics(&text);
    let buoy = node_of(&text, "b/buoy");
    let r = d / 2.0;
    // Lumped line: element i (1 at the anchor … n at the buoy) carries T_i = T_n − (n − i)·w·le,
    // its length is le·(1 + T_i/EA); the buoy node balances ρ g V_cap = m g + w le/2 + T_n.
    let le = l0 / n as f64;
    let w = (mu - RHO * PI * dr * dr / 4.0) * G;
    let z_top =
        |t: f64| -20.0 + l0 + le / ea * (n as f64 * t - w * le * (n * (n - 1)) as f64 / 2.0);
    let t = bisect(
        |t| m * G + w * le / 2.0 + t - RHO * G * cap(r - z_top(t), r),
        0.0,
        RHO * G * PI * d * d * d / 6.0,
    );
    let z = out.x[buoy][2];
    assert!(
        (z - z_top(t)).abs() < 1e-6 * d,
        "buoy at z = {z}, balance gives {} (tension {t} N)",
        z_top(t)
    );
    // Partly submerged, with the rope taut.
    assert!(z > -r && z < r && t > 1000.0, "{z} {t}");
    // The fairlead is the buoy's free node: its reaction is the rope's pull on the buoy, T_n
    // (not the 0 of a support that is not there); the anchor's is the support force,
    // T_n − (n − 1)·w·le plus the bottom element's half weight that the anchor node carries.
    let [anchor, fairlead, ..] = out.line_ends[0];
    assert!(
        (fairlead - t).abs() < 1e-6 * t,
        "fairlead {fairlead} N, T_n {t} N"
    );
    let t_anchor = t - (n - 1) as f64 * w * le - w * le / 2.0;
    assert!(
        (anchor - t_anchor).abs() < 1e-6 * t,
        "anchor {anchor} N, balance {t_anchor} N"
    );
    assert!(iterations <= 40, "{iterations} static iterations");
    assert!(
        out.codes.iter().all(|c| !c.starts_with("design/")),
        "{:?}",
        out.codes
    );
}

/// (H, V_A) of a fully suspended elastic line of segments (L_k, w_k, EA_k) from an anchor to
/// a point l further and h higher: H the horizontal tension, V_A the vertical one at the anchor.
fn elastic_catenary(segs: &[(f64, f64, f64)], l: f64, h: f64) -> (f64, f64) {
    let span = |hh: f64, va: f64| {
        let (mut x, mut z, mut vb) = (0.0, 0.0, va);
        for &(lk, wk, eak) in segs {
            let vt = vb + wk * lk;
            x += hh / wk * ((vt / hh).asinh() - (vb / hh).asinh()) + hh * lk / eak;
            z += hh / wk * ((1.0 + (vt / hh).powi(2)).sqrt() - (1.0 + (vb / hh).powi(2)).sqrt())
                + (vt * vt - vb * vb) / (2.0 * wk * eak);
            vb = vt;
        }
        (x - l, z - h)
    };
    let (mut hh, mut va) = (1.0e4, 0.0);
    for _ in 0..100 {
        let (f0, f1) = span(hh, va);
        let e = 1e-7 * hh;
        let (a0, a1) = span(hh + e, va);
        let (b0, b1) = span(hh, va + e);
        let j = [
            [(a0 - f0) / e, (b0 - f0) / e],
            [(a1 - f1) / e, (b1 - f1) / e],
        ];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        hh -= (f0 * j[1][1] - f1 * j[0][1]) / det;
        va -= (j[0][0] * f1 - j[1][0] * f0) / det;
    }
    (hh, va)
}

fn chain_rope(extra: &str) -> String {
    format!(
        "[sea]\ndepth = 100\n[[line]]\nname = \"m\"\nanchor = [0, 0, -60]\n\
         fairlead = [70, 0, -1]\nfixed = [\"anchor\", \"fairlead\"]\nmorison = \"none\"\n\
         [[line.segment]]\nname = \"chain\"\nlength = 40\nelements = 80\ndiameter = 0.08\n\
         mass_per_length = 130\nea = 6e8\n\
         [[line.segment]]\nname = \"rope\"\nlength = 60\nelements = 120\ndiameter = 0.06\n\
         mass_per_length = 6\nea = 5e7\n{extra}{STATIC}"
    )
}

#[test]
fn chain_then_rope_matches_the_two_segment_elastic_catenary() {
    let text = chain_rope("");
    let (out, iterations) = statics(&text);
    let anchor = node_of(&text, "m/anchor");
    let fair = node_of(&text, "m/fairlead");
    let wc = (130.0 - RHO * PI * 0.08 * 0.08 / 4.0) * G;
    let wr = (6.0 - RHO * PI * 0.06 * 0.06 / 4.0) * G;
    let (hh, _) = elastic_catenary(&[(40.0, wc, 6e8), (60.0, wr, 5e7)], 70.0, 59.0);
    let h_fem = -out.reaction[anchor][0];
    assert!(
        (h_fem / hh - 1.0).abs() < 1e-4,
        "H = {h_fem} N, elastic catenary {hh} N"
    );
    // The two supports carry the whole submerged weight.
    let vz = out.reaction[anchor][2] + out.reaction[fair][2];
    let weight = wc * 40.0 + wr * 60.0;
    assert!((vz / weight - 1.0).abs() < 1e-6, "{vz} vs {weight}");
    assert!(iterations <= 120, "{iterations} static iterations");
    assert!(
        out.codes.iter().all(|c| !c.starts_with("design/")),
        "{:?}",
        out.codes
    );
}

#[test]
fn a_buoy_at_the_joint_lifts_the_line_by_its_buoyancy() {
    let text = chain_rope(
        "[[buoy]]\nname = \"jb\"\nnode = \"m/joints[0]\"\ndiameter = 1.0\nmass = 80\n\
         submerged = true\n",
    );
    let (out, _) = statics(&text);
    let anchor = node_of(&text, "m/anchor");
    let fair = node_of(&text, "m/fairlead");
    let joint = node_of(&text, "m/joints[0]");
    assert!(out.x[joint][2] < -0.5 - 1e-3, "the buoy stays under water");
    let wc = (130.0 - RHO * PI * 0.08 * 0.08 / 4.0) * G;
    let wr = (6.0 - RHO * PI * 0.06 * 0.06 / 4.0) * G;
    let buoy = (80.0 - RHO * PI / 6.0) * G;
    let vz = out.reaction[anchor][2] + out.reaction[fair][2];
    let weight = wc * 40.0 + wr * 60.0 + buoy;
    assert!((vz / weight - 1.0).abs() < 1e-6, "{vz} vs {weight}");
    assert!(
        out.codes.iter().all(|c| !c.starts_with("design/")),
        "{:?}",
        out.codes
    );
}

fn example(name: &str) -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../examples")
            .join(name),
    )
    .unwrap()
}

/// A collar held by a fixed top ring is not a float: the reference cage (top ring fixed, links
/// pulled under by the net) has no floating pipe to check, the free-floating moored cage has
/// its collar pipe.
#[test]
fn only_free_collars_are_floating_pipes() {
    let floats = |name: &str| {
        let scene = scene_of(&example(name), Path::new(name)).unwrap();
        let prep = prepare(PrepareOptions::scene(scene)).unwrap();
        let labels: Vec<String> = prep
            .built
            .design
            .floaters
            .iter()
            .map(|f| f.label.clone())
            .collect();
        labels
    };
    let held = floats("reference-cage.toml");
    assert!(held.is_empty(), "{held:?}");
    let free = floats("moored-cage.toml");
    assert!(free.iter().any(|l| l.contains("cage/top_ring")), "{free:?}");
}

/// The bundled moored cage floats; the same cage on the old example's heavy chains (50 kg/m,
/// 95 m, 0.35 m collar pipe) sinks its collar, and the run says so. The balance, with the
/// collar's net buoyancy about 74 kN: four chains hanging ≥ 40 m × 426 N/m each plus 28.8 kN of
/// sinkers exceed it; four 10 kg/m chains (≤ 4 × 100 m × 85 N/m) with a 0.5 m pipe do not.
#[test]
fn the_moored_cage_floats_and_its_heavy_variant_is_told_it_sinks() {
    let text =
        example("moored-cage.toml").replace("kind = \"static+dynamic\"", "kind = \"static\"");
    let (out, _) = statics(&text);
    assert!(!out.codes.contains(&"design/sunk-float"), "{:?}", out.codes);
    let heavy = text
        .replace("mass_per_length = 10.0", "mass_per_length = 50.0")
        .replace("length = 100.0", "length = 95.0")
        .replace("collar.pipe_diameter = 0.5", "collar.pipe_diameter = 0.35");
    assert!(heavy.contains("mass_per_length = 50.0") && heavy.contains("pipe_diameter = 0.35"));
    let (out, _) = statics(&heavy);
    assert!(out.codes.contains(&"design/sunk-float"), "{:?}", out.codes);
}

#[test]
fn a_line_shorter_than_its_chord_is_taut_as_built() {
    let text = "[sea]\ndepth = 50\n[[line]]\nanchor = [0, 0, -40]\nfairlead = [30, 0, 0]\n\
                length = 49.9\nsegments = 10\ndiameter = 0.05\nmass_per_length = 10\n\
                ea = 1e8\nfixed = [\"anchor\", \"fairlead\"]\n";
    let scene = scene_of(text, Path::new("taut.toml")).unwrap();
    let prep = prepare(PrepareOptions::scene(scene)).unwrap();
    let taut: Vec<_> = prep
        .diagnostics()
        .iter()
        .filter(|d| d.code == "design/taut-line")
        .collect();
    assert_eq!(taut.len(), 1);
    assert!(
        taut[0].message.contains("50.000 m apart"),
        "{}",
        taut[0].message
    );
    let ok = text.replace("49.9", "50.1");
    let scene = scene_of(&ok, Path::new("taut.toml")).unwrap();
    let prep = prepare(PrepareOptions::scene(scene)).unwrap();
    assert!(
        prep.diagnostics()
            .iter()
            .all(|d| d.code != "design/taut-line")
    );
}

fn error_of(text: &str) -> String {
    let path = Path::new("bad.toml");
    match scene_of(text, path) {
        Err(e) => e.chain(),
        Ok(scene) => prepare(PrepareOptions::scene(scene))
            .map(|_| String::new())
            .unwrap_or_else(|e| e.chain()),
    }
}

#[test]
fn bad_buoys_and_segments_are_named() {
    let e = error_of("[[buoy]]\nposition = [0, 0, 0]\nmass = 10\n");
    assert!(
        e.contains("bad.toml")
            && e.contains("line 1")
            && e.contains("[[buoy]] #1")
            && e.contains("a buoy with zero volume"),
        "{e}"
    );
    let e = error_of("[[buoy]]\nposition = [0, 0, 0]\nvolume = 0\nmass = 10\n");
    assert!(e.contains("volume = 0") && e.contains("zero volume"), "{e}");
    let e = error_of(
        "[[buoy]]\nnode = \"nothing/here\"\ndiameter = 1\n[[line]]\nanchor = [0, 0, -9]\n\
         fairlead = [1, 0, -1]\nlength = 9\nsegments = 2\ndiameter = 0.02\n\
         mass_per_length = 1\nea = 1e6\nfixed = [\"anchor\", \"fairlead\"]\n",
    );
    assert!(
        e.contains("nothing/here") && e.contains("names no node"),
        "{e}"
    );
    let seg = |body: &str| {
        format!(
            "[sea]\ndepth = 50\n[[line]]\nanchor = [0, 0, -40]\nfairlead = [30, 0, 0]\n\
             [[line.segment]]\nlength = 20\nelements = 4\ndiameter = 0.05\nmass_per_length = 10\n\
             ea = 1e8\n[[line.segment]]\n{body}"
        )
    };
    let e = error_of(&seg(
        "length = -5\nelements = 4\ndiameter = 0.05\nmass_per_length = 10\nea = 1e8\n",
    ));
    assert!(
        e.contains("[[line]] #1") && e.contains("segment[1].length") && e.contains("-5"),
        "{e}"
    );
    let e = error_of(&seg(
        "length = 35\nelements = 4\ndiameter = 0.05\nmass_per_length = 10\nea = 1e8\ncolour = 1\n",
    ));
    assert!(
        e.contains("[[line]] #1") && e.contains("colour") && e.contains("elements"),
        "{e}"
    );
}

/// The scene of `text`, named `path` in messages.
fn scene_of(text: &str, path: &Path) -> aqua_sim::error::Result<aqua_sim::Scene> {
    read_scene(SceneInput::Text { text, path }, &[])
}
