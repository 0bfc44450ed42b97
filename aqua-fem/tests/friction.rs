//! Seabed friction (docs/theory/fem.md#seabed-friction): a straight chain lying on the seabed,
//! dragged along and across its axis, pulled below the friction limit, and sliding freely to
//! a stop. Every expected number comes from the inputs: the submerged weight per metre
//! w = (m' − ρ_w·A)·g, the friction limit μ·w·L, the regularised creep bound and the Coulomb
//! stopping distance v₀²/(2μw/m').

mod common;

use aqua_fem::*;
use common::WaterLines;
use std::f64::consts::PI;

/// Chain: mass per length [kg/m], volume/contact diameter [m], EA [N], length [m], segments.
const MASS: f64 = 50.0;
const DIAM: f64 = 0.09;
const EA: f64 = 5e8;
const LENGTH: f64 = 30.0;
const SEGMENTS: usize = 20;
const DEPTH: f64 = 20.0;
const K_BED: f64 = 3e6;
const MU_A: f64 = 0.7;
const MU_T: f64 = 1.0;
const V_C: f64 = 0.01;
/// Axial damping ratio per element.
const AXIAL_DAMPING: f64 = 0.05;
/// Axial damping ratio of the towed chain: lets the axial ringing of the start die out (the
/// midpoint rule has no numerical damping); at steady sliding the strain rate, and so its
/// force, is 0.
const TOW_DAMPING: f64 = 0.5;

fn environment(friction: SeabedFriction) -> Environment {
    Environment {
        seabed: Some(Seabed::new(DEPTH).with_friction(friction)),
        ..Default::default()
    }
}

fn friction() -> SeabedFriction {
    SeabedFriction {
        axial: MU_A,
        transverse: MU_T,
        slip_velocity: V_C,
    }
}

/// Submerged weight per metre w = (m' − ρ_w·π·d²/4)·g [N/m].
fn submerged_weight(env: &Environment) -> f64 {
    (MASS - env.water_density * PI / 4.0 * DIAM * DIAM) * env.gravity
}

/// A straight chain along x with its nodes `chord` apart in total, resting at the penalty
/// contact's equilibrium penetration w/(k_b·d) (the same at every node of a uniform chain).
fn chain(env: Environment, chord: f64) -> (ModelBuilder, Vec<usize>, f64) {
    damped_chain(env, chord, AXIAL_DAMPING)
}

/// [`chain`] with the axial damping ratio `zeta`.
fn damped_chain(env: Environment, chord: f64, zeta: f64) -> (ModelBuilder, Vec<usize>, f64) {
    let w = submerged_weight(&env);
    let z = -DEPTH - w / (K_BED * DIAM);
    let mut b = ModelBuilder::new(env);
    let g = b
        .add_group(
            "chain",
            CableSection::new(EA, MASS)
                .with_contact(DIAM)
                .with_axial_damping(AxialDamping::Ratio(zeta)),
        )
        .unwrap();
    let nodes: Vec<usize> = (0..=SEGMENTS)
        .map(|i| {
            b.add_node([chord * i as f64 / SEGMENTS as f64, 0.0, z])
                .unwrap()
        })
        .collect();
    for i in 0..SEGMENTS {
        b.add_cable(
            nodes[i],
            nodes[i + 1],
            g,
            UnstretchedLength::Given(LENGTH / SEGMENTS as f64),
        )
        .unwrap();
    }
    (b, nodes, z)
}

/// Buoyancy of the chain (no drag: cd = 0).
fn buoyancy(model: &Model) -> WaterLines {
    WaterLines::new(model, DIAM, 0.0, [0.0; 3])
}

/// A displacement history that starts from rest and reaches the speed `u` [m/s] along `dir`
/// smoothly over `t_r` [s] (d = u·t_r·(s³ − s⁴/2) for s = t/t_r < 1, then u·(t − t_r/2)),
/// as a table sampled every 10 ms up to 1 s past `t_end` (the spline's free end stays
/// outside the run).
fn smooth_tow(u: f64, t_r: f64, t_end: f64, dir: [f64; 3]) -> Motion {
    let rows: Vec<[f64; 4]> = (0..=(((t_end + 1.0) / 0.01).ceil() as usize))
        .map(|k| {
            let t = k as f64 * 0.01;
            let s = t / t_r;
            let d = if s < 1.0 {
                u * t_r * (s.powi(3) - 0.5 * s.powi(4))
            } else {
                u * (t - 0.5 * t_r)
            };
            [t, d * dir[0], d * dir[1], d * dir[2]]
        })
        .collect();
    Motion::table(&rows).unwrap()
}

fn hht(dt: f64, t_end: f64) -> DynamicSettings {
    let mut s = DynamicSettings::new(dt, t_end);
    s.output_interval = Some(0.05);
    s
}

fn midpoint(dt: f64, t_end: f64) -> DynamicSettings {
    let mut s = hht(dt, t_end);
    s.midpoint = true;
    s
}

/// Runs the dynamics and returns, per output time after `t_from`, the sum of the reactions
/// of `supports` [N]; also the largest Newton iteration count of a step.
fn tow_reactions(
    model: &Model,
    settings: DynamicSettings,
    start: Option<&State>,
    supports: &[usize],
    t_from: f64,
) -> (Vec<[f64; 3]>, usize) {
    let mut water = buoyancy(model);
    let mut dynamic = DynamicSolver::new(model, settings, start, &mut water).unwrap();
    let mut samples = Vec::new();
    let mut max_iter = 0;
    while !dynamic.is_finished() {
        let report = dynamic.step(&mut water).unwrap();
        if report.t > 0.1 {
            // The first steps from rest are halved a few times with or without friction.
            max_iter = max_iter.max(report.iterations);
        }
        if report.output_time && report.t >= t_from {
            let mut r = [0.0; 3];
            for &s in supports {
                for k in 0..3 {
                    r[k] += dynamic.outputs().reaction[s][k];
                }
            }
            samples.push(r);
        }
    }
    (samples, max_iter)
}

/// Dragged along its axis by one end at 0.1 m/s (10 v_c): the pull equals μ_a·w·L.
#[test]
fn chain_dragged_along_its_axis_pulls_mu_a_w_l() {
    let env = environment(friction());
    let expected = MU_A * submerged_weight(&env) * LENGTH;
    let (u, t_r, t_end) = (0.1, 1.0, 4.0);
    let (mut b, nodes, _) = damped_chain(env, LENGTH, TOW_DAMPING);
    b.prescribe(nodes[0], smooth_tow(u, t_r, t_end, [-1.0, 0.0, 0.0]))
        .unwrap();
    let model = b.build().unwrap();
    for (name, settings) in [
        ("hht", hht(0.02, t_end)),
        ("midpoint", midpoint(0.005, t_end)),
    ] {
        let (samples, max_iter) = tow_reactions(&model, settings, None, &nodes[..1], 2.0);
        assert!(!samples.is_empty());
        let worst = samples
            .iter()
            .map(|r| (-r[0] - expected) / expected)
            .fold(0.0f64, |m, e| if e.abs() > m.abs() { e } else { m });
        eprintln!(
            "axial tow {name}: μ_a·w·L = {expected:.1} N, worst sample {:+.4} %, max Newton iterations {max_iter}",
            100.0 * worst
        );
        for r in &samples {
            // The support pulls towards −x: R_x = −μ_a·w·L.
            let err = (-r[0] - expected) / expected;
            assert!(
                err.abs() < 0.01,
                "{name}: pull {} N vs μ_a·w·L = {expected} N ({:+.3} %)",
                -r[0],
                100.0 * err
            );
        }
        assert!(
            max_iter <= 8,
            "{name}: {max_iter} Newton iterations in a step"
        );
    }
}

/// Dragged sideways by both ends at 0.1 m/s: the two pulls add up to μ_t·w·L. The chain is
/// pretensioned (T₀ = 1 MN) and starts in its steady sliding state — moving at 0.1 m/s with
/// the parabolic lag y = −q·x·(c − x)/(2H) that the friction q = μ_t·w per metre gives a string
/// of tension H (about 5 cm) — so that no stick-slip start sets it vibrating (sliding Coulomb
/// friction does not damp a vibration that never reverses the motion). The end slope
/// q·c/(2H) ≈ 6e-3 brings in axial friction below 1e-3 of the total.
#[test]
fn chain_dragged_sideways_pulls_mu_t_w_l() {
    let env = environment(friction());
    let w = submerged_weight(&env);
    let expected = MU_T * w * LENGTH;
    let q = MU_T * w;
    let (t0, u, t_end) = (1e6, 0.1, 3.0);
    let chord = LENGTH * (1.0 + t0 / EA);
    // Tension of the sagged string: H = EA·(arc/L0 − 1), arc ≈ c + 8s²/(3c), s = q·c²/(8H).
    let mut h = t0;
    for _ in 0..20 {
        let sag = q * chord * chord / (8.0 * h);
        h = EA * ((chord + 8.0 * sag * sag / (3.0 * chord)) / LENGTH - 1.0);
    }
    let (mut b, nodes, z) = chain(env, chord);
    let tow = Motion::table(&[[0.0, 0.0, 0.0, 0.0], [100.0, 0.0, 100.0 * u, 0.0]]).unwrap();
    let ends = [nodes[0], nodes[SEGMENTS]];
    for &end in &ends {
        b.prescribe(end, tow.clone()).unwrap();
    }
    let model = b.build().unwrap();
    let mut start = State::as_built(&model, 0.0);
    for (i, &nd) in nodes.iter().enumerate() {
        let x = chord * i as f64 / SEGMENTS as f64;
        start.x[nd] = [x, -q * x * (chord - x) / (2.0 * h), z];
        start.v[nd] = [0.0, u, 0.0];
    }
    for (name, settings) in [
        ("hht", hht(0.02, t_end)),
        ("midpoint", midpoint(0.02, t_end)),
    ] {
        let (samples, max_iter) = tow_reactions(&model, settings, Some(&start), &ends, 0.0);
        assert!(!samples.is_empty());
        let worst = samples
            .iter()
            .map(|r| (r[1] - expected) / expected)
            .fold(0.0f64, |m, e| if e.abs() > m.abs() { e } else { m });
        eprintln!(
            "transverse tow {name}: μ_t·w·L = {expected:.1} N, worst sample {:+.4} %, max Newton iterations {max_iter}",
            100.0 * worst
        );
        for r in &samples {
            // The supports pull towards +y: R_y = +μ_t·w·L.
            let err = (r[1] - expected) / expected;
            assert!(
                err.abs() < 0.01,
                "{name}: pull {} N vs μ_t·w·L = {expected} N ({:+.3} %)",
                r[1],
                100.0 * err
            );
        }
        assert!(
            max_iter <= 8,
            "{name}: {max_iter} Newton iterations in a step"
        );
    }
}

/// A load element of one node with a force ramped linearly to `force` over `ramp` [s], plus
/// the chain's buoyancy.
struct Pulled {
    water: WaterLines,
    node: [usize; 1],
    force: [f64; 3],
    ramp: f64,
}

impl Pulled {
    fn at(&self, t: f64) -> [f64; 3] {
        let r = (t / self.ramp).clamp(0.0, 1.0);
        self.force.map(|f| f * r)
    }
}

impl LoadProvider for Pulled {
    fn n_elements(&self) -> usize {
        self.water.n_elements() + 1
    }
    fn element_nodes(&self, e: usize) -> &[usize] {
        if e < self.water.n_elements() {
            self.water.element_nodes(e)
        } else {
            &self.node
        }
    }
    fn element_load(
        &self,
        e: usize,
        t: f64,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        want: Want,
        out: &mut ElementLoad,
    ) -> std::result::Result<(), LoadError> {
        if e < self.water.n_elements() {
            return self.water.element_load(e, t, x, v, want, out);
        }
        out.force[0] = self.at(t);
        if want.dfdv {
            out.has_dfdv = true;
        }
        if want.dfdx {
            out.has_dfdx = true;
        }
        Ok(())
    }
}

/// Held below the limit, the chain only creeps. In the linear zone (every node slower than
/// v_c) the friction on node i is μ_a·N_i·v_i/v_c with N_i = w·ℓ_i, so the momentum
/// P = Σ m_i·v_i obeys dP/dt = F(t) − (μ_a·w/(m'·v_c))·P. From rest and with F(t)
/// non-decreasing, P(t) ≤ F(t)·m'·v_c/(μ_a·w), i.e. the mass-weighted mean velocity is at most
/// v_c·F/(μ_a·w·L), and the mean displacement over the run at most v_c·∫F dt/(μ_a·w·L).
/// Without friction the same force would move the chain by ∫∫F/(m'L) (metres, not mm).
#[test]
fn pull_below_the_limit_only_creeps_within_the_regularisation_bound() {
    let env = environment(friction());
    let w = submerged_weight(&env);
    let limit = MU_A * w * LENGTH;
    let (f0, ramp, t_end) = (0.5 * limit, 1.0, 6.0);
    let (b, nodes, _) = chain(env, LENGTH);
    let model = b.build().unwrap();
    let creep_bound = V_C * f0 * (t_end - 0.5 * ramp) / limit;
    let frictionless = f0 / (MASS * LENGTH) * (t_end * t_end / 2.0 - ramp * t_end / 2.0);
    for (name, settings) in [
        ("hht", hht(0.02, t_end)),
        ("midpoint", midpoint(0.02, t_end)),
    ] {
        let mut pulled = Pulled {
            water: buoyancy(&model),
            node: [nodes[SEGMENTS]],
            force: [f0, 0.0, 0.0],
            ramp,
        };
        let mut dynamic = DynamicSolver::new(&model, settings, None, &mut pulled).unwrap();
        let mut top_speed: f64 = 0.0;
        while !dynamic.is_finished() {
            dynamic.step(&mut pulled).unwrap();
            for v in &dynamic.state().v {
                top_speed = top_speed.max(v[0].hypot(v[1]));
            }
        }
        let s = dynamic.state();
        let masses: Vec<f64> = (0..=SEGMENTS)
            .map(|i| if i == 0 || i == SEGMENTS { 0.5 } else { 1.0 })
            .collect();
        let mean_dx = nodes
            .iter()
            .zip(&masses)
            .map(|(&i, m)| m * (s.x[i][0] - model.nodes()[i][0]))
            .sum::<f64>()
            / SEGMENTS as f64;
        eprintln!(
            "creep {name}: mean {mean_dx:.5} m, bound {creep_bound:.5} m, frictionless {frictionless:.2} m, top speed {top_speed:.5} m/s"
        );
        assert!(top_speed < V_C, "{name}: a node slid at {top_speed} m/s");
        assert!(
            mean_dx <= creep_bound * 1.005 && mean_dx > 0.5 * creep_bound,
            "{name}: mean creep {mean_dx} m vs bound {creep_bound} m (frictionless: {frictionless} m)"
        );
    }
}

/// Mechanical energy of the chain: kinetic + strain + submerged weight + seabed penalty [J].
fn mechanical_energy(model: &Model, dynamic: &DynamicSolver, w: f64) -> f64 {
    let e = dynamic.energies();
    let x = &dynamic.state().x;
    let ell = LENGTH / SEGMENTS as f64;
    let mut pot = 0.0;
    for (i, xi) in x.iter().enumerate() {
        let share = if i == 0 || i == SEGMENTS { 0.5 } else { 1.0 };
        let pen = (-DEPTH - xi[2]).max(0.0);
        pot += share * ell * (w * xi[2] + 0.5 * K_BED * DIAM * pen * pen);
    }
    let _ = model;
    e.kinetic + e.strain + pot
}

/// Launched at 2 m/s at 30° to its axis, the free chain slides to a stop. Each direction
/// decelerates at μ·w/m' on its own (the per-direction clamp), so the chain stops after
/// v_a²/(2μ_a·w/m') along and v_t²/(2μ_t·w/m') across its axis (the regularisation adds a
/// relative (v_c/v)² ≈ 1e-4); its mechanical energy never increases on the way.
#[test]
fn free_sliding_chain_stops_at_the_coulomb_distance_and_only_loses_energy() {
    let env = environment(friction());
    let w = submerged_weight(&env);
    let (b, nodes, _) = chain(env, LENGTH);
    let model = b.build().unwrap();
    let (v0, angle) = (2.0, 30f64.to_radians());
    let (va, vt) = (v0 * angle.cos(), v0 * angle.sin());
    let stop_a = va * va / (2.0 * MU_A * w / MASS);
    let stop_t = vt * vt / (2.0 * MU_T * w / MASS);
    let mut start = State::as_built(&model, 0.0);
    for v in &mut start.v {
        *v = [va, vt, 0.0];
    }
    let t_end = 0.6;
    let check = |name: &str, x: &[[f64; 3]]| {
        let mid = nodes[SEGMENTS / 2];
        let (dx, dy) = (
            x[mid][0] - model.nodes()[mid][0],
            x[mid][1] - model.nodes()[mid][1],
        );
        eprintln!(
            "free slide {name}: along {dx:.5} m vs {stop_a:.5} m ({:+.3} %), across {dy:.6} m vs {stop_t:.6} m ({:+.3} %)",
            100.0 * (dx - stop_a) / stop_a,
            100.0 * (dy - stop_t) / stop_t
        );
        assert!(
            ((dx - stop_a) / stop_a).abs() < 0.01,
            "{name}: axial slide {dx} m vs {stop_a} m"
        );
        assert!(
            ((dy - stop_t) / stop_t).abs() < 0.01,
            "{name}: transverse slide {dy} m vs {stop_t} m"
        );
    };
    for (name, settings) in [
        ("hht", hht(0.005, t_end)),
        ("midpoint", midpoint(0.005, t_end)),
    ] {
        let mut water = buoyancy(&model);
        let mut dynamic = DynamicSolver::new(&model, settings, Some(&start), &mut water).unwrap();
        let mut e_prev = mechanical_energy(&model, &dynamic, w);
        let kinetic0 = dynamic.energies().kinetic;
        let mut rise: f64 = 0.0;
        while !dynamic.is_finished() {
            dynamic.step(&mut water).unwrap();
            let e = mechanical_energy(&model, &dynamic, w);
            rise = rise.max(e - e_prev);
            assert!(
                e <= e_prev + 1e-9 * kinetic0,
                "{name}: energy rose from {e_prev} J to {e} J at t = {}",
                dynamic.time()
            );
            e_prev = e;
        }
        eprintln!(
            "free slide {name}: largest energy rise in a step {rise:.3e} J of {kinetic0:.1} J"
        );
        check(name, &dynamic.state().x);
    }
    let mut water = buoyancy(&model);
    let settings = ExplicitSettings {
        scheme: ExplicitScheme::Rk4,
        ..ExplicitSettings::new(t_end)
    };
    let mut explicit = ExplicitSolver::new(&model, settings, Some(&start), &mut water).unwrap();
    while !explicit.is_finished() {
        explicit.step(&mut water).unwrap();
    }
    check("rk4", &explicit.state().x);
}

/// Off by default: μ = 0 leaves the dynamics exactly as without friction, and statics never
/// see friction.
#[test]
fn zero_friction_changes_nothing() {
    let run = |fr: SeabedFriction| {
        let (b, _, _) = chain(environment(fr), LENGTH);
        let model = b.build().unwrap();
        let mut start = State::as_built(&model, 0.0);
        for v in &mut start.v {
            *v = [0.5, 0.2, 0.0];
        }
        let mut water = buoyancy(&model);
        let mut d = DynamicSolver::new(&model, hht(0.01, 0.1), Some(&start), &mut water).unwrap();
        while !d.is_finished() {
            d.step(&mut water).unwrap();
        }
        d.state().x.clone()
    };
    let off = run(SeabedFriction::default());
    let zero = run(SeabedFriction {
        slip_velocity: 0.5,
        ..SeabedFriction::default()
    });
    assert_eq!(off, zero);
    // And with friction it does change (the test above is not vacuous).
    assert_ne!(off, run(friction()));
}
