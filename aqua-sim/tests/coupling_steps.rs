//! A coupled chain against the same chain run with its fairlead motion in the scene, over
//! enough coupling steps for the clock to matter (docs/theory/fem.md#coupling).
//!
//! The fairlead of one catenary chain surges harmonically. `aqua run` evaluates the motion
//! itself; the coupling gets the same positions, velocities and accelerations at the end of
//! each step from the caller, as a vessel code would. Both are the same solver on the same
//! motion, so their fairlead forces must agree to round-off at every step, also after
//! thousands of steps of 0.005–0.02 s, where a running sum of the steps differs from the step
//! count times the step by more than the solver's landing tolerance.

use aqua_sim::coupling::Target;
use aqua_sim::run::{Frame, Observer};
use aqua_sim::{Coupling, PrepareOptions, Simulation, prepare};
use std::f64::consts::PI;
use std::path::Path;

const FAIRLEAD: [f64; 3] = [-10.0, 0.0, -5.0];
const AMPLITUDE: f64 = 2.0;
const PERIOD: f64 = 14.0;
const RAMP: f64 = 10.0;

fn scene(dt: f64, t_end: f64) -> aqua_sim::Scene {
    let text = format!(
        r#"
        [sea]
        depth = 50.0
        [[line]]
        name = "l1"
        anchor = [-110.0, 0.0, -50.0]
        fairlead = [{}, {}, {}]
        length = 120.0
        segments = 8
        diameter = 0.1354
        hydro_diameter = 0.076
        mass_per_length = 113.0
        ea = 5.4e8
        axial_damping = 2.0e5
        morison = "const"
        cn = 2.4
        ct = 1.15
        added_mass = 1.0
        [[prescribed]]
        nodes = "l1/fairlead"
        motion = "sine"
        amplitude = [{AMPLITUDE}, 0.0, 0.0]
        period = {PERIOD}
        ramp_time = {RAMP}
        [analysis]
        kind = "static+dynamic"
        [analysis.dynamic]
        dt = {dt}
        t_end = {t_end}
        output_interval = {dt}
        "#,
        FAIRLEAD[0], FAIRLEAD[1], FAIRLEAD[2]
    );
    aqua_sim::scene::read_scene(
        aqua_sim::scene::SceneInput::Text {
            text: &text,
            path: Path::new("coupled-chain.toml"),
        },
        &[],
    )
    .unwrap()
}

/// The scene's surge d = r(t)·A·sin(2πt/T) with the smooth start r = 10s³ − 15s⁴ + 6s⁵
/// (s = t/t_r), and its first two derivatives, written out here.
fn surge(t: f64) -> (f64, f64, f64) {
    let (r, dr, ddr) = if t >= RAMP {
        (1.0, 0.0, 0.0)
    } else {
        let s = t / RAMP;
        (
            s * s * s * (10.0 + s * (-15.0 + 6.0 * s)),
            30.0 * s * s * (1.0 - s) * (1.0 - s) / RAMP,
            60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (RAMP * RAMP),
        )
    };
    let w = 2.0 * PI / PERIOD;
    let (sn, cs) = (w * t).sin_cos();
    let g = AMPLITUDE * sn;
    let dg = AMPLITUDE * w * cs;
    let ddg = -AMPLITUDE * w * w * sn;
    (r * g, dr * g + r * dg, ddr * g + 2.0 * dr * dg + r * ddg)
}

/// |F| at the fairlead after every step of `aqua run` (the scene's own motion).
fn run_forces(dt: f64, n: usize) -> Vec<f64> {
    let prep = prepare(PrepareOptions::scene(scene(dt, n as f64 * dt))).unwrap();
    let col = aqua_sim::SummaryRow::columns(&prep.built)
        .iter()
        .position(|c| c == "l1_fairlead_reaction")
        .unwrap();
    struct Keep(usize, Vec<f64>);
    impl Observer for Keep {
        fn frame(&mut self, f: &Frame<'_>) -> aqua_sim::Result<()> {
            self.1.push(f.row.values()[self.0]);
            Ok(())
        }
    }
    let mut keep = Keep(col, Vec::new());
    let (_, result) = Simulation::new(&prep).unwrap().run(&mut keep);
    result.unwrap();
    keep.1.remove(0); // the static state
    keep.1
}

/// |F| at the fairlead after every coupling step, the caller's clock being k·dt.
fn coupled_forces(dt: f64, n: usize) -> Vec<f64> {
    let mut c = Coupling::new(scene(dt, n as f64 * dt)).unwrap();
    c.init().unwrap();
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let t1 = (k + 1) as f64 * dt;
        let (d, v, a) = surge(t1);
        let target = Target {
            position: vec![[FAIRLEAD[0] + d, FAIRLEAD[1], FAIRLEAD[2]]],
            velocity: Some(vec![[v, 0.0, 0.0]]),
            acceleration: Some(vec![[a, 0.0, 0.0]]),
        };
        let f = c.step(k as f64 * dt, dt, &[(0, target)], &[]).unwrap();
        let f = f[0][0];
        out.push((f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt());
    }
    c.close().unwrap();
    out
}

/// Steps of a check: past 9 169 steps of 0.005, 0.01 or 0.02 s, the running sum of the step
/// exceeds k·Δt by more than 1e-9·Δt.
const STEPS: usize = 9_400;
/// The window compared: the last 300 steps.
const WINDOW: usize = 300;

fn check(dt: f64) {
    let reference = run_forces(dt, STEPS);
    let coupled = coupled_forces(dt, STEPS);
    assert_eq!(reference.len(), STEPS);
    // A physical floor: the chain's submerged weight of the hanging part cannot vanish while
    // the fairlead moves by ±2 m; take half the smallest force of the reference window.
    let floor = 0.5
        * reference[STEPS - WINDOW..]
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
    let mut worst = (0usize, 0.0f64);
    for k in STEPS - WINDOW..STEPS {
        let e = (coupled[k] - reference[k]).abs() / reference[k];
        if e > worst.1 {
            worst = (k, e);
        }
        assert!(
            coupled[k] >= floor,
            "dt = {dt}: the fairlead force {:.1} N at t = {:.3} s is below {floor:.1} N",
            coupled[k],
            (k + 1) as f64 * dt
        );
    }
    println!(
        "dt = {dt}: largest difference {:.2e} of aqua run's force, smallest force {:.1} N",
        worst.1,
        coupled[STEPS - WINDOW..]
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min)
    );
    // The same solver on the same motion: round-off apart (the issue asks for 1 %).
    assert!(
        worst.1 <= 1e-6,
        "dt = {dt}: coupled {:.1} N against aqua run {:.1} N at t = {:.3} s ({:.2} %)",
        coupled[worst.0],
        reference[worst.0],
        (worst.0 + 1) as f64 * dt,
        100.0 * worst.1
    );
}

#[test]
fn coupled_chain_matches_aqua_run_after_many_steps_of_0_01_s() {
    check(0.01);
}

#[test]
fn coupled_chain_matches_aqua_run_after_many_steps_of_0_005_s() {
    check(0.005);
}

#[test]
fn coupled_chain_matches_aqua_run_after_many_steps_of_0_02_s() {
    check(0.02);
}

/// |F| at the fairlead after every coupling step, the caller giving positions only.
fn coupled_forces_from_positions(dt: f64, n: usize) -> Vec<f64> {
    let mut c = Coupling::new(scene(dt, n as f64 * dt)).unwrap();
    c.init().unwrap();
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let (d, _, _) = surge((k + 1) as f64 * dt);
        let target = Target {
            position: vec![[FAIRLEAD[0] + d, FAIRLEAD[1], FAIRLEAD[2]]],
            ..Target::default()
        };
        let f = c.step(c.time(), dt, &[(0, target)], &[]).unwrap()[0][0];
        out.push((f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt());
    }
    out
}

/// Positions alone are a first-order description of the motion: the force they give departs
/// from that of the exact (p, v, a) by O(Δt), halving with the step. (The cubic's end
/// acceleration through backward-difference velocities, minus twice the motion's, left a fixed
/// 0.65 % of the force at every step.)
#[test]
fn positions_alone_converge_to_the_exact_motion_with_the_step() {
    let t_end = 20.0;
    let error = |dt: f64| {
        let n = (t_end / dt).round() as usize;
        let exact = coupled_forces(dt, n);
        let approx = coupled_forces_from_positions(dt, n);
        (0..n)
            .map(|k| (approx[k] - exact[k]).abs() / exact[k])
            .fold(0.0, f64::max)
    };
    let (e1, e2) = (error(0.02), error(0.01));
    println!("positions only: largest difference {e1:.2e} at 0.02 s, {e2:.2e} at 0.01 s");
    assert!(
        e2 < 0.6 * e1,
        "{e1:.2e} at 0.02 s, {e2:.2e} at 0.01 s: not first order"
    );
    assert!(e2 < 1e-3, "{e2:.2e} at 0.01 s");
}
