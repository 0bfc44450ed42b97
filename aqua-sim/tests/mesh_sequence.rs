//! Mesh sequencing of the static solve (`analysis.static.mesh_sequence`,
//! docs/theory/fem.md#mesh-sequencing): the reference cage at 2.5 m started from its 5 m
//! equilibrium needs far fewer fine iterations than from the as-built net, and the sequenced
//! equilibrium balances its loads.

use aqua_sim::{Frame, Observer, PrepareOptions, RunRecord, SceneInput, Simulation, prepare};
use std::path::Path;

/// The reference cage (examples/reference-cage.toml), statics only.
fn scene(element_length: f64, mesh_sequence: usize) -> String {
    format!(
        r#"
name = "sequenced-cage"

[sea]
depth = 60.0

[sea.current]
kind = "uniform"
velocity = [0.5, 0.0, 0.0]

[[cage]]
type = "SSM"
circumference = 120.0
depth = 15.0
cone_depth = 3.0
element_length = {element_length}
rope_depth = 2.5
frame_offset = 1.0
sinker_weight_per_metre = 392.4
tip_weight = 981.0
fixed = ["top_ring"]
net.twine_diameter = 2.85e-3
net.half_mesh = 25.87e-3
net.screen_model = "S1"
net.wake = {{ model = "loland" }}

[analysis]
kind = "static"

[analysis.static]
mesh_sequence = {mesh_sequence}
"#
    )
}

/// Σ over the nodes of reaction + water load + seabed force at the static state [N] (x, y:
/// gravity has no horizontal part), and Σ |water load| for scale.
#[derive(Default)]
struct Balance {
    sum: [f64; 2],
    scale: f64,
}

impl Observer for Balance {
    fn frame(&mut self, f: &Frame<'_>) -> aqua_sim::Result<()> {
        let o = f.outputs;
        for i in 0..o.reaction.len() {
            for k in 0..2 {
                self.sum[k] += o.reaction[i][k] + o.hydro_force[i][k] + o.seabed_force[i][k];
            }
            self.scale += o.hydro_force[i][0].abs();
        }
        Ok(())
    }
}

fn run(element_length: f64, mesh_sequence: usize) -> (RunRecord, Balance) {
    let text = scene(element_length, mesh_sequence);
    let scene = aqua_sim::read_scene(
        SceneInput::Text {
            text: &text,
            path: Path::new("sequenced-cage.toml"),
        },
        &[],
    )
    .unwrap();
    let prep = prepare(PrepareOptions::scene(scene)).unwrap();
    let mut balance = Balance::default();
    let (record, result) = Simulation::new(&prep).unwrap().run(&mut balance);
    result.unwrap();
    assert_eq!(record.static_converged, Some(true));
    (record, balance)
}

/// The 2.5 m cage takes 119 iterations from the as-built net (release, 2026-12-06) and 73
/// from its 5 m equilibrium (which itself takes 57): the start, not the solver, makes the
/// difference, and with the sequence switched off the bound fails.
#[test]
fn a_coarse_start_bounds_the_fine_iterations() {
    let (plain, _) = run(2.5, 0);
    let (seq, balance) = run(2.5, 1);
    assert!(plain.static_sequence_iterations.is_empty());
    assert_eq!(seq.static_sequence_iterations.len(), 1, "one coarser level");
    assert!(
        seq.static_iterations <= 90,
        "sequenced fine solve: {} iterations (5 m level {:?}); from as built {}",
        seq.static_iterations,
        seq.static_sequence_iterations,
        plain.static_iterations
    );
    assert!(
        plain.static_iterations >= 100,
        "from as built: {}",
        plain.static_iterations
    );
    // The sequenced equilibrium balances its loads: the supports take the current's drag.
    assert!(balance.scale > 1e4, "drag {}", balance.scale);
    for (k, s) in balance.sum.iter().enumerate() {
        assert!(
            s.abs() <= 1e-5 * balance.scale,
            "Σ force along axis {k}: {s} N of {} N",
            balance.scale
        );
    }
}
