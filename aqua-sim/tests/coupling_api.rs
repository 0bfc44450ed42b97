//! The coupling as a vessel code uses it (docs/guide/coupling.md): a rigid body carrying three
//! fairleads, the solver's own step inside long coupling steps, a failed step retried, save
//! and restore, and the structure's tensions mid-run.

use aqua_sim::Coupling;
use aqua_sim::coupling::{BodyTarget, Forces, Target};
use nalgebra::{Rotation3, Vector3};
use std::f64::consts::PI;
use std::path::Path;

/// Three 60 m chains 120° apart from fairleads 10 m from the body centre at z = −5 m.
fn scene(kind: &str, dynamic: &str) -> aqua_sim::Scene {
    let mut text = format!(
        "[sea]\ndepth = 40.0\n[analysis]\nkind = \"{kind}\"\n[analysis.dynamic]\nt_end = 100.0\n{dynamic}\n"
    );
    for (i, deg) in [180.0f64, 60.0, -60.0].iter().enumerate() {
        let (s, c) = deg.to_radians().sin_cos();
        text += &format!(
            r#"
            [[line]]
            name = "l{n}"
            anchor = [{ax}, {ay}, -40.0]
            fairlead = [{fx}, {fy}, -5.0]
            length = 62.0
            segments = 10
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
            nodes = "l{n}/fairlead"
            motion = "coupled"
            "#,
            n = i + 1,
            ax = 60.0 * c,
            ay = 60.0 * s,
            fx = 10.0 * c,
            fy = 10.0 * s,
        );
    }
    aqua_sim::scene::read_scene(
        aqua_sim::scene::SceneInput::Text {
            text: &text,
            path: Path::new("coupled-body.toml"),
        },
        &[],
    )
    .unwrap()
}

const POINTS: [&str; 3] = ["l1/fairlead", "l2/fairlead", "l3/fairlead"];

/// The body's pose and velocity at t: surge, heave, roll, pitch and yaw oscillations.
fn pose(t: f64) -> ([f64; 6], [f64; 6]) {
    let w = 2.0 * PI / 8.0;
    let amp = [1.5, 0.3, 0.4, 0.05, 0.04, 0.08];
    let phase = [0.0, 0.7, 1.3, 0.2, 2.1, 0.9];
    let mut p = [0.0; 6];
    let mut v = [0.0; 6];
    for k in 0..6 {
        p[k] = amp[k] * (w * t + phase[k]).sin() - amp[k] * phase[k].sin();
        v[k] = amp[k] * w * (w * t + phase[k]).cos();
    }
    (p, v)
}

fn norm(f: [f64; 3]) -> f64 {
    (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt()
}

/// The fairlead targets of the body at `p` moving at `v`, written here with nalgebra's
/// roll–pitch–yaw rotation and the angular velocity's Euler-angle rates mapped to the scene
/// frame by ω = ψ̇·e_z + θ̇·R_z·e_y + φ̇·R_z·R_y·e_x.
fn fairlead_targets(c: &Coupling, p: [f64; 6], v: [f64; 6]) -> Vec<(usize, Target)> {
    let r = Rotation3::from_euler_angles(p[3], p[4], p[5]);
    let omega = angular_velocity(p, v);
    POINTS
        .iter()
        .map(|name| {
            let i = c.point(name).unwrap();
            let rest = Vector3::from(c.points()[i].rest[0]);
            let arm = r * rest;
            let x = Vector3::new(p[0], p[1], p[2]) + arm;
            let u = Vector3::new(v[0], v[1], v[2]) + omega.cross(&arm);
            (
                i,
                Target {
                    position: vec![x.into()],
                    velocity: Some(vec![u.into()]),
                    acceleration: None,
                },
            )
        })
        .collect()
}

/// ω in the scene frame from the Euler-angle rates (R = R_z(ψ)·R_y(θ)·R_x(φ)).
fn angular_velocity(p: [f64; 6], v: [f64; 6]) -> Vector3<f64> {
    let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), p[5]);
    let ry = Rotation3::from_axis_angle(&Vector3::y_axis(), p[4]);
    Vector3::z() * v[5] + rz * Vector3::y() * v[4] + rz * ry * Vector3::x() * v[3]
}

/// The body's velocity in the coupling's terms: the reference point's and ω.
fn body_velocity(p: [f64; 6], v: [f64; 6]) -> [f64; 6] {
    let w = angular_velocity(p, v);
    [v[0], v[1], v[2], w[0], w[1], w[2]]
}

#[test]
fn a_body_moves_its_fairleads_rigidly_and_returns_their_force_and_moment() {
    let dt = 0.1;
    let mut body = Coupling::new(scene("static+dynamic", "dt = 0.1")).unwrap();
    let b = body.add_body("barge", &POINTS, [0.0; 3]).unwrap();
    let mut points = Coupling::new(scene("static+dynamic", "dt = 0.1")).unwrap();
    body.init().unwrap();
    points.init().unwrap();
    let mut largest_moment = 0.0f64;
    for k in 0..120 {
        let t1 = (k + 1) as f64 * dt;
        let (p, v) = pose(t1);
        let target = BodyTarget {
            pose: p,
            velocity: Some(body_velocity(p, v)),
            acceleration: None,
        };
        let fb = body.step(k as f64 * dt, dt, &[], &[(b, target)]).unwrap();
        let targets = fairlead_targets(&points, p, v);
        let fp = points.step(k as f64 * dt, dt, &targets, &[]).unwrap();
        // The same fairlead motion, one way through the body and one written out here.
        for (a, c) in fb.iter().flatten().zip(fp.iter().flatten()) {
            assert!(
                norm([a[0] - c[0], a[1] - c[1], a[2] - c[2]]) <= 1e-7 * norm(*c),
                "t = {t1}: {a:?} against {c:?}"
            );
        }
        // The wrench about the reference point, summed here from the point forces.
        let w = body.body_wrench(b, &fb).unwrap();
        let (mut f, mut m) = (Vector3::zeros(), Vector3::zeros());
        for (i, t) in &targets {
            let fi = Vector3::from(fb[*i][0]);
            let arm = Vector3::from(t.position[0]) - Vector3::new(p[0], p[1], p[2]);
            f += fi;
            m += arm.cross(&fi);
        }
        for k in 0..3 {
            assert!((w[k] - f[k]).abs() <= 1e-9 * f.norm(), "F {w:?} {f}");
            assert!(
                (w[3 + k] - m[k]).abs() <= 1e-9 * m.norm().max(1.0),
                "M {w:?} {m}"
            );
        }
        largest_moment = largest_moment.max(m.norm());
    }
    // The yaw and the pitch load the spread: a moment of kN·m, not round-off.
    assert!(largest_moment > 1e4, "{largest_moment}");
}

/// |F| of point 0 after each coupling step of `call` s up to `t_end`, the points held where
/// built, from the as-built state (the chains fall and swing).
fn falling(solver_dt: &str, call: f64, t_end: f64) -> Vec<(f64, f64)> {
    let mut c = Coupling::new(scene("dynamic", solver_dt)).unwrap();
    c.init().unwrap();
    let n = (t_end / call).round() as usize;
    (0..n)
        .map(|k| {
            let f = c.step(k as f64 * call, call, &[], &[]).unwrap();
            (c.time(), norm(f[0][0]))
        })
        .collect()
}

#[test]
fn the_solver_keeps_its_own_step_inside_long_coupling_steps() {
    // Coupling steps of 0.05 s and of 5 ms with the solver at the scene's 5 ms: the same
    // integration (the motion is held, no step is halved), so the same forces to round-off.
    // The chains' fall after their release is not resolved by 0.05 s steps of the solver
    // itself (the step of a scene that gives none).
    let long = falling("dt = 0.005", 0.05, 1.0);
    let short = falling("dt = 0.005", 0.005, 1.0);
    let coarse = falling("", 0.05, 1.0);
    let (mut worst, mut off) = (0.0f64, 0.0f64);
    for (k, (t, f)) in long.iter().enumerate() {
        let (ts, fs) = short[10 * k + 9];
        assert!((t - ts).abs() < 1e-9, "{t} {ts}");
        worst = worst.max((f - fs).abs() / fs);
        off = off.max((coarse[k].1 - fs).abs() / fs);
    }
    assert!(
        worst < 1e-6,
        "long calls differ from short ones by {worst:e}"
    );
    assert!(off > 1e-2, "a 0.05 s solver step should differ: {off:e}");
}

#[test]
fn a_failed_step_leaves_the_coupling_where_it_was_to_be_retried() {
    let strict = "dt = 0.1\nmax_strain = 0.05";
    let mut c = Coupling::new(scene("static+dynamic", strict)).unwrap();
    c.init().unwrap();
    let i = c.point("l1/fairlead").unwrap();
    let rest = c.points()[i].rest[0];
    let go = |dx: f64| Target {
        position: vec![[rest[0] + dx, rest[1], rest[2]]],
        velocity: None,
        acceleration: None,
    };
    // 30 m away from its anchor in one step: the chain would stretch past the strain guard.
    let e = c.step(0.0, 0.1, &[(i, go(30.0))], &[]).unwrap_err();
    assert!(matches!(e, aqua_sim::SimError::Dynamic(_)), "{}", e.chain());
    assert_eq!(c.time(), 0.0);
    // The call again, smaller: as if the failed one had not been made.
    let f = c.step(0.0, 0.05, &[(i, go(0.2))], &[]).unwrap();
    let mut fresh = Coupling::new(scene("static+dynamic", strict)).unwrap();
    fresh.init().unwrap();
    let g = fresh.step(0.0, 0.05, &[(i, go(0.2))], &[]).unwrap();
    assert!((c.time() - 0.05).abs() < 1e-15);
    for (a, b) in f.iter().flatten().zip(g.iter().flatten()) {
        assert!(
            norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]]) <= 1e-8 * norm(*b),
            "{a:?} {b:?}"
        );
    }
}

fn run(c: &mut Coupling, b: usize, from: usize, n: usize, dt: f64) -> (Forces, Vec<f64>) {
    let mut last = Vec::new();
    for k in from..from + n {
        let (p, v) = pose((k + 1) as f64 * dt);
        let target = BodyTarget {
            pose: p,
            velocity: Some(body_velocity(p, v)),
            acceleration: None,
        };
        last = c.step(k as f64 * dt, dt, &[], &[(b, target)]).unwrap();
    }
    (last, c.tensions().unwrap())
}

#[test]
fn restore_repeats_the_steps_after_save_bit_for_bit() {
    let dt = 0.1;
    let mut c = Coupling::new(scene("static+dynamic", "dt = 0.1")).unwrap();
    let b = c.add_body("barge", &POINTS, [0.0; 3]).unwrap();
    c.init().unwrap();
    run(&mut c, b, 0, 30, dt);
    let saved = c.save().unwrap();
    let first = run(&mut c, b, 30, 20, dt);
    c.restore(&saved).unwrap();
    assert_eq!(c.time(), saved.time());
    let again = run(&mut c, b, 30, 20, dt);
    assert_eq!(first, again);
    // The tensions read mid-run: as many as elements, named by group, and the fairlead's
    // force is the top element's tension within the weight of half an element (113 kg/m).
    let table = c.elements();
    assert_eq!(again.1.len(), table.elements.len());
    let i = c.point("l1/fairlead").unwrap();
    let node = c.points()[i].nodes[0];
    let top = (0..table.elements.len())
        .find(|&e| table.elements[e].contains(&node))
        .unwrap();
    assert!(table.group_names[table.groups[top]].starts_with("l1/"));
    let half_weight = 0.5 * 6.2 * 113.0 * 9.81;
    let f = norm(again.0[i][0]);
    assert!(
        (f - again.1[top]).abs() <= half_weight * 1.5,
        "{f} {}",
        again.1[top]
    );
}

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (head, rows)
}

#[test]
fn a_coupled_run_writes_its_rows_series_and_extremes_without_the_failed_call() {
    let dir = std::env::temp_dir().join(format!("aqua-coupled-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let dt = 0.1;
    let mut c = Coupling::new(scene("static+dynamic", "dt = 0.1\nmax_strain = 0.05")).unwrap();
    let b = c.add_body("barge", &POINTS, [0.0; 3]).unwrap();
    c.write_to(&dir).unwrap();
    let f0 = c.init().unwrap();
    let i = c.point("l1/fairlead").unwrap();
    let mut forces = vec![norm(f0[i][0])];
    let mut times = vec![0.0];
    for k in 0..20 {
        if k == 10 {
            // A call that fails and is put back: no row, no extreme.
            let rest = c.points()[i].rest[0];
            let far = Target {
                position: vec![[rest[0] + 30.0, rest[1], rest[2]]],
                velocity: None,
                acceleration: None,
            };
            assert!(c.step(c.time(), dt, &[(i, far)], &[]).is_err());
        }
        let (p, v) = pose((k + 1) as f64 * dt);
        let target = BodyTarget {
            pose: p,
            velocity: Some(body_velocity(p, v)),
            acceleration: None,
        };
        let f = c.step(k as f64 * dt, dt, &[], &[(b, target)]).unwrap();
        forces.push(norm(f[i][0]));
        times.push(c.time());
    }
    c.close().unwrap();
    // A row per call after the equilibrium's, holding the forces the calls returned.
    let (head, rows) = read_csv(&dir.join("summary.csv"));
    assert_eq!(rows.len(), 21);
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let (t, r) = (col("t"), col("l1_fairlead_reaction"));
    for (k, row) in rows.iter().enumerate() {
        let (tk, fk): (f64, f64) = (row[t].parse().unwrap(), row[r].parse().unwrap());
        assert!((tk - times[k]).abs() < 1e-12, "{tk} {}", times[k]);
        assert!(
            (fk - forces[k]).abs() <= 1e-12 * forces[k],
            "row {k}: {fk} {}",
            forces[k]
        );
    }
    // A ParaView step per row, and the extremes over every accepted step bound the rows'.
    let pvd = std::fs::read_to_string(dir.join("coupled-body.pvd"))
        .or_else(|_| {
            let p = std::fs::read_dir(&dir)
                .unwrap()
                .flatten()
                .find(|e| e.path().extension().is_some_and(|x| x == "pvd"))
                .unwrap()
                .path();
            std::fs::read_to_string(p)
        })
        .unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 21);
    let (_, ext) = read_csv(&dir.join("extremes.csv"));
    let line = ext.iter().find(|e| e[0] == "l1_fairlead_reaction").unwrap();
    let max: f64 = line[1].parse().unwrap();
    let largest = forces[1..].iter().cloned().fold(0.0, f64::max);
    assert!(max >= largest && max < 1.5 * largest, "{max} {largest}");
    let _ = std::fs::remove_dir_all(&dir);
}
