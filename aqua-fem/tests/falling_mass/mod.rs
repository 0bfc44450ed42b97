//! A mass that falls on a slack rope and snaps it taut: the scene of the extreme-tolerance and
//! snap-resolution tests, with the closed-form peak of the snap.

use aqua_fem::*;

pub const G: f64 = 9.81;
/// Point mass [kg].
pub const M: f64 = 10.0;
/// Rope stiffness EA [N] and unstretched length L0 [m] (k = EA/L0 = 1e5 N/m).
pub const EA: f64 = 1e5;
pub const L0: f64 = 1.0;
/// Rope mass per length [kg/m] (its lumped half at the mass adds 0.05 %).
pub const MU: f64 = 0.01;
/// The mass starts at rest this far above the point where the rope becomes taut [m].
pub const DROP: f64 = 0.5;

/// A rope pinned at the top with a mass at its lower end, held DROP closer to the pin than
/// the rope's length: the mass falls freely, then the rope catches it.
pub fn snap_model() -> Model {
    let env = Environment {
        gravity: G,
        ..Default::default()
    };
    let mut b = ModelBuilder::new(env);
    let g = b.add_group("rope", CableSection::new(EA, MU)).unwrap();
    let top = b.add_node([0.0, 0.0, 0.0]).unwrap();
    let mass = b.add_node([0.0, 0.0, -(L0 - DROP)]).unwrap();
    b.add_cable(top, mass, g, UnstretchedLength::Given(L0))
        .unwrap();
    b.add_point_body(PointBody {
        node: mass,
        mass: M,
        force: [0.0; 3],
        seabed_stiffness: 0.0,
    })
    .unwrap();
    b.fix(top, Dofs::ALL).unwrap();
    b.fix(
        mass,
        Dofs {
            x: true,
            y: true,
            z: false,
        },
    )
    .unwrap();
    b.build().unwrap()
}

/// The rope's largest tension by energy: the mass m (the rope's lumped half included) falls
/// DROP + δ while the rope stores ½kδ², so kδ² − 2mgδ − 2mg·DROP = 0 and T = kδ.
pub fn closed_form_peak() -> f64 {
    let m = M + 0.5 * MU * L0;
    let k = EA / L0;
    let w = m * G;
    let delta = (w + (w * w + 2.0 * k * w * DROP).sqrt()) / k;
    k * delta
}
