//! A static state is the equilibrium of the wake it reports (docs/theory/fem.md#static-solver,
//! docs/theory/hydrodynamics.md#wake-update): on a bottomless net held at its top and weighted
//! by point masses (which feel no current), the horizontal net force and the support
//! reactions balance to round-off, for every wake model; a load that never settles is frozen
//! and solved for, never left out of balance.

mod common;
use aqua_fem::{
    CableSection, DEFAULT_GRAVITY, Dofs, ElementLoad, Environment, LoadError, LoadProvider,
    ModelBuilder, PointBody, StaticSettings, UnstretchedLength, Want, solve_static,
};
use common::*;
use std::f64::consts::PI;
use std::fmt::Write;

/// A model-scale bottomless cylindrical net (radius 0.7 m, 1.4 m deep, 16 meridians, 7
/// rings) as gmsh 2.2 ASCII: quads in `net` with outward normals, the top ring `fixed`, the
/// bottom ring `sinkers`.
fn bottomless_net_msh() -> String {
    let (ns, levels, r, h) = (16usize, 7usize, 0.7, 1.4);
    let id = |i: usize, l: usize| 1 + l * ns + i % ns;
    let mut s = String::from(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n0 1 \"fixed\"\n\
         0 2 \"sinkers\"\n2 3 \"net\"\n$EndPhysicalNames\n$Nodes\n",
    );
    writeln!(s, "{}", ns * levels).unwrap();
    for l in 0..levels {
        for i in 0..ns {
            let a = 2.0 * PI * i as f64 / ns as f64;
            let z = -h * l as f64 / (levels - 1) as f64;
            writeln!(s, "{} {} {} {}", id(i, l), r * a.cos(), r * a.sin(), z).unwrap();
        }
    }
    s.push_str("$EndNodes\n$Elements\n");
    let mut els = Vec::new();
    for i in 0..ns {
        els.push(format!("15 2 1 1 {}", id(i, 0)));
        els.push(format!("15 2 2 2 {}", id(i, levels - 1)));
    }
    for l in 0..levels - 1 {
        for i in 0..ns {
            els.push(format!(
                "3 2 3 3 {} {} {} {}",
                id(i, l),
                id(i, l + 1),
                id(i + 1, l + 1),
                id(i + 1, l)
            ));
        }
    }
    writeln!(s, "{}", els.len()).unwrap();
    for (k, e) in els.iter().enumerate() {
        writeln!(s, "{} {e}", k + 1).unwrap();
    }
    s.push_str("$EndElements\n");
    s
}

fn scene(speed: f64, wake: &str) -> String {
    format!(
        r#"
name = "bottomless"

[sea]
depth = 20.0

[sea.current]
kind = "uniform"
velocity = [{speed}, 0.0, 0.0]

[[mesh]]
name = "net"
file = "net.msh"
net.twine_diameter = 1.5e-3
net.half_mesh = 11.0e-3
net.screen_model = "S1"
net.wake = {wake}

[[point]]
nodes = "net/sinkers"
mass = 0.5

[analysis]
kind = "static"
"#
    )
}

/// Net force = −(support reactions) horizontally, for every wake model, to round-off. Before
/// the fix the Cheng wake changed its factors at the equilibrium without a re-solve, and the
/// net force was evaluated with a wake the state was not the equilibrium of.
#[test]
fn bottomless_net_force_balances_the_supports_for_every_wake_model() {
    let dir = scratch("wake-balance");
    std::fs::write(dir.join("net.msh"), bottomless_net_msh()).unwrap();
    let wakes = [
        r#"{ model = "none" }"#,
        r#"{ model = "factor", factor = 0.8 }"#,
        r#"{ model = "loland" }"#,
        r#"{ model = "cheng" }"#,
    ];
    let mut worst: f64 = 0.0;
    for (k, wake) in wakes.iter().enumerate() {
        for (j, speed) in [0.3, 0.93].iter().enumerate() {
            let out = run_text(&dir, &format!("c{k}{j}"), &scene(*speed, wake));
            let row = &summary(&out)[0];
            let (fx, rx, fy, ry) = (row["Fx_net"], row["Rx"], row["Fy_net"], row["Ry"]);
            assert!(fx > 0.0);
            let err = ((fx + rx).powi(2) + (fy + ry).powi(2)).sqrt() / fx;
            worst = worst.max(err);
            assert!(
                err < 1e-9,
                "{wake} at {speed} m/s: net force ({fx}, {fy}) N, reactions ({rx}, {ry}) N, \
                 imbalance {err:e}"
            );
        }
    }
    eprintln!("worst relative imbalance {worst:e}");
}

/// A push that flips whenever the state is accepted beyond (or short of) a threshold that
/// lies between its two equilibria: a wake that never settles.
struct FlippingPush {
    node: [usize; 1],
    threshold: f64,
    forces: [f64; 2],
    on: bool,
}

impl LoadProvider for FlippingPush {
    fn n_elements(&self) -> usize {
        1
    }
    fn element_nodes(&self, _e: usize) -> &[usize] {
        &self.node
    }
    fn accept_state(&mut self, _t: f64, x: &[[f64; 3]]) -> Result<bool, LoadError> {
        // Strong push below the threshold, weak push beyond it.
        let on = x[self.node[0]][0] <= self.threshold;
        let changed = on != self.on;
        self.on = on;
        Ok(changed)
    }
    fn element_load(
        &self,
        _e: usize,
        _t: f64,
        _x: &[[f64; 3]],
        _v: &[[f64; 3]],
        want: Want,
        out: &mut ElementLoad,
    ) -> Result<(), LoadError> {
        out.force[0] = [self.forces[usize::from(self.on)], 0.0, 0.0];
        out.has_dfdv = want.dfdv;
        out.has_dfdx = want.dfdx;
        Ok(())
    }
}

/// A wake that never settles ends as the documented fixed point: the load is frozen, the state
/// is its equilibrium (the support holds exactly the load reported), and the solve warns.
#[test]
fn a_load_that_never_settles_is_frozen_and_balanced() {
    let (l, ea, w) = (10.0, 1e6, 1000.0);
    let mut b = ModelBuilder::new(Environment::default());
    let g = b.add_group("rope", CableSection::new(ea, 1e-6)).unwrap();
    let top = b.add_node([0.0, 0.0, 0.0]).unwrap();
    let bob = b.add_node([0.0, 0.0, -l]).unwrap();
    b.add_cable(top, bob, g, UnstretchedLength::Given(l))
        .unwrap();
    b.fix(top, Dofs::ALL).unwrap();
    b.add_point_body(PointBody {
        node: bob,
        mass: w / DEFAULT_GRAVITY,
        force: [0.0; 3],
        seabed_stiffness: 0.0,
    })
    .unwrap();
    let m = b.build().unwrap();
    // x(F) = l·F/√(F² + W²): 200 N puts the bob at ~1.96 m, 600 N at ~5.15 m; the threshold
    // at 3.5 m sends every equilibrium to the other push.
    let mut push = FlippingPush {
        node: [bob],
        threshold: 3.5,
        forces: [200.0, 600.0],
        on: false,
    };
    let sol = solve_static(&m, &mut push, &StaticSettings::default()).unwrap();
    let applied = push.forces[usize::from(push.on)];
    let held = sol.outputs.reaction[top][0];
    assert!(
        (applied + held).abs() < 1e-9 * applied,
        "push {applied} N reported, support holds {held} N"
    );
    assert!(
        (sol.outputs.hydro_force[bob][0] - applied).abs() < 1e-12 * applied,
        "{:?}",
        sol.outputs.hydro_force[bob]
    );
    assert!(
        sol.report.warnings.iter().any(|w| w.contains("frozen")),
        "{:?}",
        sol.report.warnings
    );
}
