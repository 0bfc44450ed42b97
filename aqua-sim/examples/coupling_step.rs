//! Time of one coupling step from Rust: the example chain with 160 segments, its fairlead
//! surged as in `examples/mooring-chain.toml` (1.5 m, 10 s) for 200 steps of 0.1 s.
//! Compare with `tests/python/time_coupling.py` (the same steps from Python).
//!
//! ```sh
//! cargo run --release -p aqua-sim --example coupling_step
//! ```

use aqua_sim::coupling::Target;
use aqua_sim::{Coupling, SimError};
use std::path::Path;
use std::time::Instant;

fn main() -> Result<(), SimError> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("examples/mooring-chain.toml"))
        .map_err(|e| SimError::input(e.to_string()))?
        .replace("segments = 80", "segments = 160");
    let scene = aqua_sim::scene::read_scene(
        aqua_sim::scene::SceneInput::Text {
            text: &text,
            path: &root.join("examples/chain160.toml"),
        },
        &[],
    )?;
    let mut c = Coupling::new(scene)?;
    c.init()?;
    let (dt, n) = (0.1, 200);
    let w = 2.0 * std::f64::consts::PI / 10.0;
    let t0 = Instant::now();
    let mut f = Vec::new();
    for k in 1..=n {
        let t1 = k as f64 * dt;
        let (r, dr, _) = aqua_fem::smooth_ramp(t1, 10.0);
        let d = r * 1.5 * (w * t1).sin();
        let v = dr * 1.5 * (w * t1).sin() + r * 1.5 * w * (w * t1).cos();
        let target = Target {
            position: vec![[100.0 + d, 0.0, -5.0]],
            velocity: Some(vec![[v, 0.0, 0.0]]),
            acceleration: None,
        };
        f = c.step(c.time(), dt, &[(0, target)], &[])?;
    }
    let per_step = t0.elapsed().as_secs_f64() / n as f64;
    println!(
        "rust: {n} coupling steps of a 160-segment chain: {:.3} ms per step (last force {:?} N)",
        1e3 * per_step,
        f[0][0]
    );
    c.close()?;
    Ok(())
}
