//! `[[body]]` free rigid bodies in a scene (docs/theory/farm.md#rigid-bodies): a box barge's
//! draft, heel, heave and roll periods against the closed forms of a wall-sided box, the pose
//! columns of `summary.csv`, and the errors of bad input.

use aqua_sim::scene::{SceneInput, read_scene};
use aqua_sim::{Diagnostic, Frame, Observer, PrepareOptions, Simulation, prepare};
use std::f64::consts::PI;
use std::path::Path;

const RHO: f64 = 1025.0;
const G: f64 = 9.80665;
/// The barge: 24 × 12 × 3 m box, draft 1.0 m at equilibrium (a layer boundary of its 0.5 m
/// layers), centre of gravity 2.0 m above the keel.
const L: f64 = 24.0;
const B: f64 = 12.0;
const H: f64 = 3.0;
const KG: f64 = 2.0;

fn mass() -> f64 {
    RHO * L * B * 1.0
}

/// Roll inertia about the centre of gravity [kg·m²] (any physical value; a box's).
fn ixx() -> f64 {
    mass() * (B * B + H * H) / 12.0
}

/// A barge scene: keel at `keel` as built, centre of gravity `yg` to the side of the hull's
/// centre line, hull added-mass coefficient `ca`, no drag; `extra` appended.
fn barge(keel: f64, yg: f64, ca: f64, extra: &str) -> String {
    let m = mass();
    let (iyy, izz) = (m * (L * L + H * H) / 12.0, m * (L * L + B * B) / 12.0);
    format!(
        "[sea]\ndepth = 40\n[[body]]\nname = \"barge\"\ncentre = [0, {yg}, {zg}]\nmass = {m}\n\
         inertia = [{ixx}, {iyy}, {izz}]\n[body.hull]\nlength = {L}\nwidth = {B}\nheight = {H}\n\
         centre = [0, {hy}, {hz}]\ncolumns = [4, 4]\nlayers = 6\ndrag_coefficient = 0\n\
         added_mass_coefficient = {ca}\n[[body.point]]\nname = \"a\"\nposition = [5, {hy}, 0]\n\
         [[body.point]]\nname = \"b\"\nposition = [-5, {hy}, 0]\n{extra}",
        zg = keel + KG,
        ixx = ixx(),
        hy = -yg,
        hz = H / 2.0 - KG,
    )
}

/// Last frame's summary row and every row's time and body columns.
#[derive(Default)]
struct Capture {
    rows: Vec<(f64, Vec<f64>)>,
    codes: Vec<&'static str>,
}

impl Observer for Capture {
    fn diagnostic(&mut self, d: &Diagnostic) {
        self.codes.push(d.code);
    }
    fn frame(&mut self, f: &Frame<'_>) -> aqua_sim::Result<()> {
        self.rows.push((f.row.t, f.row.bodies[0].to_vec()));
        Ok(())
    }
}

fn run(text: &str) -> Capture {
    let scene = read_scene(
        SceneInput::Text {
            text,
            path: Path::new("bodies-test.toml"),
        },
        &[],
    )
    .unwrap();
    let prep = prepare(PrepareOptions::scene(scene)).unwrap();
    let mut cap = Capture::default();
    let mut sim = Simulation::new(&prep).unwrap();
    let (_, result) = sim.run(&mut cap);
    result.unwrap();
    cap
}

/// Held in x and y at two points on the centre of gravity's level (no yaw, no drift; heave,
/// roll and pitch free), statics only.
const STATICS: &str = "[[fix]]\nnodes = \"barge/a\"\ndofs = [\"x\", \"y\"]\n[[fix]]\n\
                       nodes = \"barge/b\"\ndofs = [\"x\", \"y\"]\n[analysis]\nkind = \"static\"\n";

#[test]
fn a_barge_floats_at_its_draft_and_heels_by_its_metacentric_height() {
    // Built 0.2 m high, with its centre of gravity 0.21 m off the centre line.
    let yg = 0.21;
    let cap = run(&barge(-0.8, yg, 1.0, STATICS));
    let p = &cap.rows.last().unwrap().1;
    // Wall-sided box: GM = T/2 + B²/(12·T) − KG with the Archimedes draft T = M/(ρ·L·B) =
    // 1.0 m; a small heel tan φ = y_g/GM.
    let t = mass() / (RHO * L * B);
    let gm = t / 2.0 + B * B / (12.0 * t) - KG;
    // It heels towards +y, the weight's side: a negative rotation about x.
    let phi = -(yg / gm).atan();
    assert!(
        (p[3] - phi.to_degrees()).abs() < 0.01 * phi.to_degrees().abs(),
        "roll {} deg, wall-sided box {} deg",
        p[3],
        phi.to_degrees()
    );
    // The waterline of a wall-sided box turns about its centre line, which keeps the draft T
    // along the body's axis; the centre of gravity, (y_G, KG) from the keel's centre line in
    // the body, sits at (KG − T)·cos φ + y_G·sin φ.
    let z = (KG - t) * phi.cos() + yg * phi.sin();
    assert!((p[2] - z).abs() < 2e-5, "centre at z = {}, box {z}", p[2]);
    assert!(p[4].abs() < 1e-6 && p[5].abs() < 1e-6, "pitch/yaw {:?}", p);
    assert!(
        cap.codes.iter().all(|c| !c.starts_with("design/")),
        "{:?}",
        cap.codes
    );
}

/// Mean period of the oscillation of column `k` about its mean, from upward zero crossings
/// (linear interpolation) after `t0`.
fn period(rows: &[(f64, Vec<f64>)], k: usize, t0: f64) -> f64 {
    let after: Vec<(f64, f64)> = rows
        .iter()
        .filter(|(t, _)| *t >= t0)
        .map(|(t, v)| (*t, v[k]))
        .collect();
    let mean = after.iter().map(|p| p.1).sum::<f64>() / after.len() as f64;
    let mut ups = Vec::new();
    for w in after.windows(2) {
        let (a, b) = (w[0].1 - mean, w[1].1 - mean);
        if a < 0.0 && b >= 0.0 {
            ups.push(w[0].0 + (w[1].0 - w[0].0) * (-a) / (b - a));
        }
    }
    assert!(ups.len() >= 4, "{} crossings", ups.len());
    (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64
}

fn dynamics(dt: f64, t_end: f64) -> String {
    format!(
        "[analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\ndt = {dt}\nt_end = {t_end}\n\
         output_interval = {dt}\n"
    )
}

#[test]
fn a_free_barge_heaves_at_the_period_of_its_mass_and_waterplane() {
    // Released 0.1 m high with no drag: heave at T = 2π·√((M + A33)/(ρ·g·L·B)).
    for ca in [0.0, 1.0] {
        let cap = run(&barge(-0.9, 0.0, ca, &dynamics(0.01, 12.0)));
        // The hull's added mass is C_a·ρ·V_wet; V_wet = L·B·T at the mean draft T = 1 m.
        let a33 = ca * RHO * L * B * 1.0;
        let exact = 2.0 * PI * ((mass() + a33) / (RHO * G * L * B)).sqrt();
        let got = period(&cap.rows, 2, 0.0);
        assert!(
            (got - exact).abs() < 0.01 * exact,
            "C_a {ca}: heave period {got} s, closed form {exact} s"
        );
    }
}

#[test]
fn a_free_barge_rolls_at_the_period_of_its_inertia_and_metacentric_height() {
    // Released level with its centre of gravity y_G = 0.21 m off the centre line (no added
    // mass, no drag): it rolls about its heeled equilibrium. About G, with the waterplane's
    // centroid y_G to the side, roll and heave are coupled by the stiffness K34 = ρ·g·A·y_G:
    //   K33 = ρ·g·A,  K44 = ρ·g·(I_wp + A·y_G² + V·(z_B − z_G)),  masses M and I_xx,
    // solved here for the roll mode (the lower root of det(K − ω²·M) = 0).
    let yg = 0.21;
    let cap = run(&barge(-1.0, yg, 0.0, &dynamics(0.01, 12.0)));
    let (a, v) = (L * B, L * B * 1.0);
    let k33 = RHO * G * a;
    let k44 = RHO * G * (L * B.powi(3) / 12.0 + a * yg * yg + v * (0.5 - KG));
    let k34 = RHO * G * a * yg;
    let (m33, m44) = (mass(), ixx());
    // (k33 − w m33)(k44 − w m44) − k34² = 0 in w = ω².
    let (qa, qb, qc) = (m33 * m44, -(k33 * m44 + k44 * m33), k33 * k44 - k34 * k34);
    let w = (-qb - (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa);
    let exact = 2.0 * PI / w.sqrt();
    let got = period(&cap.rows, 3, 0.0);
    assert!(
        (got - exact).abs() < 0.005 * exact,
        "roll period {got} s, coupled closed form {exact} s"
    );
    // Uncoupled, T = 2π·√(I_xx/(M·g·GM)) would be 1 % shorter: the test sees the coupling.
    let gm = 0.5 + B * B / 12.0 - KG;
    let uncoupled = 2.0 * PI * (ixx() / (mass() * G * gm)).sqrt();
    assert!((exact - uncoupled) / exact > 0.008, "{exact} {uncoupled}");
    // Released from level, it swings through about twice the equilibrium heel atan(y_G/GM).
    let roll: Vec<f64> = cap.rows.iter().map(|r| r.1[3]).collect();
    let span = roll.iter().cloned().fold(f64::MIN, f64::max)
        - roll.iter().cloned().fold(f64::MAX, f64::min);
    let heel = (yg / gm).atan().to_degrees();
    assert!(
        (span - 2.0 * heel).abs() < 0.05 * 2.0 * heel,
        "peak to peak {span} deg, 2·heel {} deg",
        2.0 * heel
    );
}

/// An error and its sources, as the binary prints them.
fn chain(e: &dyn std::error::Error) -> String {
    let mut out = e.to_string();
    let mut s = e.source();
    while let Some(c) = s {
        out.push_str(&format!(": {c}"));
        s = c.source();
    }
    out
}

#[test]
fn a_body_with_the_midpoint_rule_is_warned_and_with_hht_not() {
    let codes = |scheme: &str| {
        let text = barge(
            -1.0,
            0.0,
            1.0,
            &format!(
                "[analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\nscheme = \"{scheme}\"\n\
                 t_end = 0.1\n"
            ),
        );
        let scene = read_scene(
            SceneInput::Text {
                text: &text,
                path: Path::new("bodies-test.toml"),
            },
            &[],
        )
        .unwrap();
        let prep = prepare(PrepareOptions::scene(scene)).unwrap();
        prep.diagnostics()
            .iter()
            .map(|d| d.code)
            .collect::<Vec<_>>()
    };
    assert!(codes("midpoint").contains(&"fem/body-scheme"));
    assert!(!codes("hht").contains(&"fem/body-scheme"));
}

#[test]
fn bad_bodies_are_refused_naming_the_key() {
    let read = |text: &str| {
        read_scene(
            SceneInput::Text {
                text,
                path: Path::new("bodies-test.toml"),
            },
            &[],
        )
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
    };
    let ok = barge(-1.0, 0.0, 1.0, "");
    let e = read(&ok.replace(&format!("inertia = [{}", ixx()), "inertia = [1e9"));
    assert!(
        e.contains("bodies-test.toml") && e.contains("[[body]] #1") && e.contains("inertia"),
        "{e}"
    );
    let e = read(&ok.replace("mass = ", "mass = -"));
    assert!(e.contains("mass = -") && e.contains("> 0"), "{e}");
    let e = read(&ok.replace("layers = 6", "layers = 0"));
    assert!(e.contains("hull.layers"), "{e}");
    let e = read(&ok.replace("[body.hull]", "[body.hull]\nlenght = 3"));
    assert!(e.contains("lenght"), "{e}");
    // A body needs an implicit scheme.
    let text = barge(
        -1.0,
        0.0,
        1.0,
        "[analysis]\nkind = \"dynamic\"\n[analysis.dynamic]\nscheme = \"rk4\"\nt_end = 1\n",
    );
    let scene = read_scene(
        SceneInput::Text {
            text: &text,
            path: Path::new("bodies-test.toml"),
        },
        &[],
    )
    .unwrap();
    let e = prepare(PrepareOptions::scene(scene))
        .and_then(|p| {
            let mut cap = Capture::default();
            let mut sim = Simulation::new(&p)?;
            sim.run(&mut cap).1
        })
        .err()
        .map(|e| chain(&e))
        .unwrap_or_default();
    assert!(e.contains("implicit") && e.contains("barge"), "{e}");
}
