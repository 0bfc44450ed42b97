//! Seabed friction from a scene file (docs/theory/fem.md#seabed-friction): a chain lying on
//! the bed, towed along its axis by one end through `aqua run`, pulls μ_a·w·(L − ℓ/2); the keys
//! are validated with errors that name them.

mod common;

use common::{run_text, scratch, summary};

const MU_A: f64 = 0.7;
/// Chain: length [m], segments, diameter [m], mass per length [kg/m]; water depth [m].
const LENGTH: f64 = 30.0;
const SEGMENTS: usize = 20;
const DIAM: f64 = 0.09;
const MASS: f64 = 50.0;

/// The towed-chain scene with the given `[sea.seabed]` lines: the fairlead end is towed away
/// from the chain along x, starting smoothly and reaching 0.1 m/s after 1 s.
fn towed_chain(seabed: &str) -> String {
    let (u, t_r) = (0.1, 1.0);
    let rows: Vec<String> = (0..=120)
        .map(|k| {
            let t = k as f64 * 0.05;
            let s = t / t_r;
            let d = if s < 1.0 {
                u * t_r * (s.powi(3) - 0.5 * s.powi(4))
            } else {
                u * (t - 0.5 * t_r)
            };
            format!("[{t:.2}, {d:.9}, 0.0, 0.0]")
        })
        .collect();
    format!(
        r#"name = "towed-chain"

[sea]
depth = 20.0

[sea.seabed]
{seabed}

[[line]]
name = "chain"
anchor = [0.0, 0.0, -20.0]
fairlead = [{LENGTH}, 0.0, -20.0]
length = {LENGTH}
segments = {SEGMENTS}
shape = "straight"
fixed = []
diameter = {DIAM}
mass_per_length = {MASS}
ea = 5e8
axial_damping_ratio = 0.5
morison = "none"

[[prescribed]]
nodes = "chain/fairlead"
motion = "table"
table = [{}]

[analysis]
kind = "dynamic"

[analysis.dynamic]
dt = 0.02
t_end = 4.0
output_interval = 0.1
"#,
        rows.join(", ")
    )
}

/// The pull on the towed end, once the chain slides at 0.1 m/s (10 v_c), is μ_a·w·(L − ℓ/2)
/// with w = (m' − ρ_w·π·d²/4)·g: every node but the towed one presses on the bed with its
/// share of the submerged weight (the towed node is held at the bed level, so the support
/// carries its half element). Without friction the pull is zero.
#[test]
fn a_towed_chain_pulls_its_friction_through_the_scene() {
    let dir = scratch("seabed-friction");
    let w = (MASS - 1025.0 * std::f64::consts::FRAC_PI_4 * DIAM * DIAM) * 9.80665;
    let ell = LENGTH / SEGMENTS as f64;
    let expected = MU_A * w * (LENGTH - 0.5 * ell);
    let out = run_text(
        &dir,
        "towed",
        &towed_chain(&format!(
            "friction_axial = {MU_A}\nfriction_transverse = 1.0"
        )),
    );
    let rows = summary(&out);
    let sliding: Vec<_> = rows.iter().filter(|r| r["t"] >= 2.0).collect();
    assert!(sliding.len() >= 15);
    for r in &sliding {
        let err = r["Rx"] / expected - 1.0;
        assert!(
            err.abs() < 0.01,
            "t = {}: pull {} N vs μ_a·w·(L − ℓ/2) = {expected} N",
            r["t"],
            r["Rx"]
        );
    }
    let out = run_text(&dir, "frictionless", &towed_chain("kbot = 3e6"));
    for r in summary(&out).iter().filter(|r| r["t"] >= 2.0) {
        assert!(
            r["Rx"].abs() < 0.01 * expected,
            "frictionless pull {}",
            r["Rx"]
        );
    }
}

/// Negative coefficients and a non-positive slip velocity are errors naming the key and the
/// valid range.
#[test]
fn invalid_friction_keys_are_named() {
    let dir = scratch("seabed-friction-keys");
    for (name, seabed, key) in [
        (
            "neg-axial",
            "friction_axial = -0.7",
            "sea.seabed.friction_axial",
        ),
        (
            "neg-transverse",
            "friction_axial = 0.7\nfriction_transverse = -1.0",
            "sea.seabed.friction_transverse",
        ),
        (
            "zero-vc",
            "friction_axial = 0.7\nslip_velocity = 0.0",
            "sea.seabed.slip_velocity",
        ),
    ] {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(&scene, towed_chain(seabed)).unwrap();
        let err =
            aqua_cli::commands::run::run_scene(&scene, &[], &dir.join(name), true).expect_err(name);
        let err = format!("{err:#}");
        assert!(err.contains(key) && err.contains(">"), "{name}: {err}");
    }
}
