//! A chain lying on the seabed in a current along it: the current acts on the laid part as on
//! any other (docs/theory/environment.md#flow-at-a-point: below the seabed plane the flow is the
//! flow at the bed, so the contact overlap of the penalty seabed does not hide the chain).

mod common;
use common::*;

/// The chain lies straight along x on the bed, anchored at its upstream end and free at the
/// other; the current runs along it. In equilibrium the anchor holds the whole tangential drag,
/// ½·ρ_w·d·C_t·U²·L (Morison drag of a cylinder in flow along its axis), computed here from the
/// group's constants.
#[test]
fn laid_chain_in_a_current_along_it_carries_the_tangential_drag() {
    let (rho, d, ct, u, l) = (1025.0, 0.05, 1.15, 0.5, 12.0);
    let text = format!(
        r#"name = "laid"

[sea]
depth = 20.0

[sea.current]
kind = "uniform"
velocity = [{u}, 0.0, 0.0]

[[line]]
name = "chain"
anchor = [0.0, 0.0, -20.0]
fairlead = [{l}, 0.0, -20.0]
length = {l}
segments = 12
shape = "straight"
diameter = {d}
mass_per_length = 50.0
ea = 2.0e8

[[group]]
name = "chain"
morison = "const"
cn = 2.4
ct = {ct}

[analysis]
kind = "static"
"#
    );
    let dir = scratch("laid-chain");
    let out = run_text(&dir, "laid", &text);
    let row = &summary(&out)[0];
    let drag = 0.5 * rho * d * ct * u * u * l;
    let rx = row["Rx"];
    assert!(
        (rx.abs() / drag - 1.0).abs() < 1e-4,
        "anchor holds {rx} N along the current, closed form {drag} N"
    );
    // The chain does lie on the bed (it sinks into the penalty seabed by its contact overlap).
    assert!(row["Ry"].abs() < 1e-6 * drag, "{row:?}");
}
