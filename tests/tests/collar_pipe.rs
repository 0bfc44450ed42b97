//! The moored cage's floating collar as a pipe (docs/theory/fem.md#rod), at equilibrium in its
//! current: no node-to-node zig-zag of its heights (the rotation-free hinge let a node rise
//! 0.33 m with its neighbours at −0.23 and 0.00 m), and its largest fibre stress, reported per
//! element and per group, below the yield stress of its polyethylene.

use aqua_env::Phase;
use aqua_fem::StaticControl;
use aqua_mesh::Role;

mod common;
use common::{example, scratch};

/// Yield stress of PE100 pipe polyethylene, the lower end of its 23–25 MPa range [Pa].
const PE100_YIELD: f64 = 23e6;

#[test]
fn moored_collar_in_current_is_smooth_and_below_yield() {
    let dir = scratch("collar-pipe");
    let text =
        example("moored-cage.toml").replace("kind = \"static+dynamic\"", "kind = \"static\"");
    let path = dir.join("moored.toml");
    std::fs::write(&path, text).unwrap();
    let prep = aqua_sim::prepare(aqua_sim::PrepareOptions::file(&path)).unwrap();
    let built = &prep.built;
    let (mut loads, _) = aqua_sim::run::water_loads(&prep, Phase::Static).unwrap();
    let sol = aqua_sim::static_equilibrium(
        &built.model,
        &built.mesh,
        &mut loads,
        &prep.plan.statics,
        &mut |_| StaticControl::Continue,
    )
    .unwrap();
    // The collar's nodes in order round the ring.
    let mesh = &built.mesh;
    let ring = mesh
        .groups
        .iter()
        .find(|g| g.role == Role::TopRing)
        .expect("a top ring");
    let mut next = std::collections::BTreeMap::<usize, Vec<usize>>::new();
    for &e in &ring.lines {
        let [a, b] = mesh.lines[e].nodes;
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    let start = *next.keys().next().unwrap();
    let (mut order, mut prev, mut cur) = (vec![start], usize::MAX, start);
    loop {
        let n = *next[&cur].iter().find(|&&n| n != prev).unwrap();
        if n == start {
            break;
        }
        order.push(n);
        (prev, cur) = (cur, n);
    }
    let n = order.len();
    assert_eq!(n, next.len());
    let z: Vec<f64> = order.iter().map(|&i| sol.state.x[i][2]).collect();
    let d2: Vec<f64> = (0..n)
        .map(|i| z[(i + n - 1) % n] - 2.0 * z[i] + z[(i + 1) % n])
        .collect();
    // A zig-zag is a second difference that flips sign from node to node at full size; a
    // fairlead pulling the collar down gives one large second difference between small ones.
    let zigzag = (0..n)
        .filter(|&i| d2[i] * d2[(i + 1) % n] < 0.0)
        .map(|i| d2[i].abs().min(d2[(i + 1) % n].abs()))
        .fold(0.0, f64::max);
    let range = z.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
        - z.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    eprintln!("collar z range {range:.3} m, zig-zag {zigzag:.4} m; z = {z:.3?}");
    assert!(
        zigzag < 0.1 * range,
        "zig-zag {zigzag} m against a range of {range} m"
    );
    // Stress: reported per group, equal to the largest element stress, below yield.
    let pipe = built
        .pipes
        .iter()
        .position(|p| p.name.ends_with("top_ring"))
        .expect("the collar is a pipe group");
    let mut per_group = vec![0.0; built.pipes.len()];
    aqua_sim::pipe_stress::group_max_stresses(built, &sol.outputs, &mut per_group);
    let mut per_element = vec![0.0; mesh.lines.len()];
    aqua_sim::pipe_stress::fibre_stresses(built, &sol.outputs, &mut per_element);
    let largest = ring
        .lines
        .iter()
        .map(|&e| per_element[e])
        .fold(0.0, f64::max);
    assert_eq!(per_group[pipe], largest);
    eprintln!("largest collar fibre stress {:.2} MPa", largest / 1e6);
    assert!(
        largest > 1e5,
        "the collar carries almost nothing: {largest} Pa"
    );
    assert!(
        largest < PE100_YIELD,
        "collar stress {largest} Pa above yield"
    );
}
