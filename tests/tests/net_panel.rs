//! A rigid net panel in a uniform current: the force equals ½ρAU²·(C_D, C_L) of the screen
//! model (docs/theory/hydrodynamics.md#screen-models, S1 of Aarsnes et al.), computed here from the
//! published formula, at normal incidence (the bundled example) and at 30° yaw.

mod common;
use common::*;

fn s1(sn: f64, theta: f64) -> (f64, f64) {
    let c = theta.cos();
    let cd = 0.04 + (-0.04 + sn - 1.24 * sn * sn + 13.7 * sn.powi(3)) * c;
    let cl = (0.57 * sn - 3.54 * sn * sn + 10.1 * sn.powi(3)) * (2.0 * theta).sin();
    (cd, cl)
}

#[test]
fn example_panel_force_is_half_rho_a_u2_cd() {
    let dir = scratch("panel");
    let out = run_file(&root().join("examples/net-panel.toml"), &dir.join("out"));
    let rows = summary(&out);
    assert_eq!(rows.len(), 1, "static run: one output step");
    let q = 0.5 * 1025.0 * 1.0 * 0.5 * 0.5;
    let (cd, _) = s1(0.2, 0.0);
    assert!(
        (rows[0]["Fx_net"] / (q * cd) - 1.0).abs() < 1e-9,
        "{}",
        rows[0]["Fx_net"]
    );
    assert!(rows[0]["Fy_net"].abs() < 1e-9 * q);
    // The supports hold the panel against the drag.
    assert!((rows[0]["Rx"] + rows[0]["Fx_net"]).abs() < 1e-6 * q);
}

#[test]
fn yawed_panel_has_drag_and_lift_of_the_model() {
    let dir = scratch("panel-yaw");
    let theta = 30f64.to_radians();
    let text = example("net-panel.toml").replace(
        "normal = [1.0, 0.0, 0.0]",
        &format!("normal = [{}, {}, 0.0]", theta.cos(), theta.sin()),
    );
    let out = run_text(&dir, "yaw", &text);
    let row = &summary(&out)[0];
    let q = 0.5 * 1025.0 * 1.0 * 0.25;
    let (cd, cl) = s1(0.2, theta);
    // Flow along +x: drag along +x, lift ⟂ flow on the side of the normal (+y).
    assert!(
        (row["Fx_net"] / (q * cd) - 1.0).abs() < 1e-9,
        "drag {}",
        row["Fx_net"]
    );
    assert!(
        (row["Fy_net"] / (q * cl) - 1.0).abs() < 1e-9,
        "lift {}",
        row["Fy_net"]
    );
}
