//! Priour's net triangles through a scene (docs/theory/fem.md#net-triangle): a hanging net panel
//! in a current modelled by triangles agrees with the same panel of cables on drag and shape at
//! the same resolution, both settle to one answer on refinement, and a gmsh net drawn as two
//! different triangulations gives the same drag.

mod common;
use common::*;
use std::fmt::Write as _;
use std::path::Path;

/// A 2 m × 2 m panel hanging from its top edge in a 0.25 m/s current, 5 N on each of its
/// bottom nodes' share (`bottom_weight`), static.
fn panel_scene(element: &str, element_length: f64) -> String {
    format!(
        "name = \"hanging-panel\"\n\n[sea]\ndepth = 20.0\n\n[sea.current]\nkind = \"uniform\"\n\
         velocity = [0.25, 0.0, 0.0]\n\n[[panel]]\nname = \"panel\"\nwidth = 2.0\nheight = 2.0\n\
         element_length = {element_length}\ncentre = [0.0, 0.0, -1.2]\nnormal = [1.0, 0.0, 0.0]\n\
         fixed = \"top\"\nbottom_weight = 40.0\nnet.element = \"{element}\"\n\
         net.twine_diameter = 2.0e-3\nnet.half_mesh = 20.0e-3\n\n[analysis]\nkind = \"static\"\n\n\
         [analysis.static]\ntol = 1e-10\n"
    )
}

/// Static positions, iterations and the net force of a scene text.
fn solve(dir: &Path, name: &str, text: &str) -> (Vec<[f64; 3]>, usize, [f64; 3]) {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let (prep, loads, sol) = static_solve(&path);
    let f = aqua_sim::net_force(&prep.built, &loads, &sol.state);
    (sol.state.x, sol.report.iterations, f)
}

/// x of the bottom-centre node of a net of `n` × `n` cells whose first (n + 1)² nodes are the
/// grid, row by row from the top [m].
fn bottom_x(x: &[[f64; 3]], n: usize) -> f64 {
    x[n * (n + 1) + n / 2][0]
}

#[test]
fn triangles_and_cables_agree_on_a_hanging_panel_and_converge_together() {
    let dir = scratch("net-tri-panel");
    let mut rows = Vec::new();
    for h in [0.5, 0.25, 0.125] {
        let mut row = Vec::new();
        for element in ["cable", "triangle"] {
            let (x, it, f) = solve(&dir, &format!("{element}-{h}"), &panel_scene(element, h));
            let n = (2.0 / h) as usize;
            row.push((f[0], bottom_x(&x, n), it));
        }
        let (fc, xc, _) = row[0];
        let (ft, xt, _) = row[1];
        // The drag streams the panel back: both models see it, and agree within 1 %.
        assert!(fc > 1.0 && xc > 0.05, "h {h}: drag {fc} N, bottom x {xc} m");
        assert!((ft / fc - 1.0).abs() < 0.01, "h {h}: drag {ft} vs {fc} N");
        assert!(
            (xt / xc - 1.0).abs() < 0.01,
            "h {h}: bottom x {xt} vs {xc} m"
        );
        rows.push(row);
    }
    // Refinement: each model's drag is settled (changes below 0.5 %), its shape converges (the
    // bottom's change shrinks by a quarter or more per halving), and the two models' shapes
    // draw closer.
    for m in 0..2 {
        let f = |k: usize| rows[k][m].0;
        let x = |k: usize| rows[k][m].1;
        assert!(
            (f(2) / f(1) - 1.0).abs() < 0.005,
            "model {m}: drag {} then {}",
            f(1),
            f(2)
        );
        let (d1, d2) = ((x(1) - x(0)).abs(), (x(2) - x(1)).abs());
        assert!(d2 < 0.75 * d1, "model {m}: shape changes {d1} then {d2} m");
    }
    let gap = |k: usize| (rows[k][1].1 / rows[k][0].1 - 1.0).abs();
    assert!(
        gap(2) < gap(0),
        "shape gap {} at h 0.5, {} at h 0.125",
        gap(0),
        gap(2)
    );
}

/// A MSH 2.2 file of a 2 m × 2 m net in the plane x = 0, top edge at z = −0.2 (group `fixed`),
/// bottom nodes in `nodes:bottom`, `n` cells a side. `centred`: each cell cut into four
/// triangles about a centre node; else into two along alternating diagonals.
fn net_msh(dir: &Path, name: &str, n: usize, centred: bool) {
    let h = 2.0 / n as f64;
    let mut nodes = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            nodes.push([0.0, -1.0 + i as f64 * h, -0.2 - j as f64 * h]);
        }
    }
    let id = |i: usize, j: usize| j * (n + 1) + i + 1;
    let mut tris = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if centred {
                nodes.push([
                    0.0,
                    -1.0 + (i as f64 + 0.5) * h,
                    -0.2 - (j as f64 + 0.5) * h,
                ]);
                let m = nodes.len();
                tris.extend([[a, b, m], [b, c, m], [c, d, m], [d, a, m]]);
            } else if (i + j) % 2 == 0 {
                tris.extend([[a, b, c], [a, c, d]]);
            } else {
                tris.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    let mut s = String::from(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n2 1 \"net\"\n0 2 \"fixed\"\n\
         0 3 \"nodes:bottom\"\n$EndPhysicalNames\n$Nodes\n",
    );
    writeln!(s, "{}", nodes.len()).unwrap();
    for (k, p) in nodes.iter().enumerate() {
        writeln!(s, "{} {:.17e} {:.17e} {:.17e}", k + 1, p[0], p[1], p[2]).unwrap();
    }
    s += "$EndNodes\n$Elements\n";
    writeln!(s, "{}", tris.len() + 2 * (n + 1)).unwrap();
    let mut e = 1;
    for t in &tris {
        writeln!(s, "{e} 2 2 1 1 {} {} {}", t[0], t[1], t[2]).unwrap();
        e += 1;
    }
    for i in 0..=n {
        writeln!(s, "{e} 15 2 2 2 {}", id(i, 0)).unwrap();
        e += 1;
        writeln!(s, "{e} 15 2 3 3 {}", id(i, n)).unwrap();
        e += 1;
    }
    s += "$EndElements\n";
    std::fs::write(dir.join(format!("{name}.msh")), s).unwrap();
}

fn gmsh_scene(name: &str, n: usize) -> String {
    format!(
        "[sea]\ndepth = 20.0\n\n[sea.current]\nkind = \"uniform\"\nvelocity = [0.25, 0.0, 0.0]\n\n\
         [[mesh]]\nname = \"m\"\nfile = \"{name}.msh\"\nnet.element = \"triangle\"\n\
         net.twine_diameter = 2.0e-3\nnet.half_mesh = 20.0e-3\n\n[[point]]\n\
         nodes = \"m/bottom\"\nforce = [0.0, 0.0, {}]\n\n[analysis]\nkind = \"static\"\n\n\
         [analysis.static]\ntol = 1e-10\n",
        -40.0 / (n + 1) as f64
    )
}

#[test]
fn two_triangulations_of_a_gmsh_net_give_the_same_drag() {
    let dir = scratch("net-tri-gmsh");
    let n = 8;
    let mut drag = Vec::new();
    for (name, centred) in [("diagonal", false), ("centred", true)] {
        net_msh(&dir, name, n, centred);
        let (x, _, f) = solve(&dir, name, &gmsh_scene(name, n));
        drag.push((f[0], bottom_x(&x, n)));
    }
    // Same net, same edge nodes; the triangulations differ in the interior.
    assert!(drag[0].0 > 1.0, "{drag:?}");
    assert!((drag[1].0 / drag[0].0 - 1.0).abs() < 0.01, "{drag:?}");
    assert!((drag[1].1 / drag[0].1 - 1.0).abs() < 0.02, "{drag:?}");
    // And the panel builder's net of the same size and resolution (cables) agrees.
    let (_, _, fc) = solve(&dir, "cable", &panel_scene("cable", 0.25));
    assert!(
        (drag[0].0 / fc[0] - 1.0).abs() < 0.02,
        "{} vs {}",
        drag[0].0,
        fc[0]
    );
}

#[test]
fn net_triangle_keys_are_checked() {
    let dir = scratch("net-tri-keys");
    let text = panel_scene("triangle", 0.5).replace(
        "net.element = \"triangle\"",
        "net.element = \"triangle\"\nnet.drag = \"morison\"",
    );
    std::fs::write(dir.join("m.toml"), &text).unwrap();
    let e = aqua_sim::read_scene(aqua_sim::SceneInput::File(&dir.join("m.toml")), &[])
        .and_then(|s| aqua_sim::prepare(aqua_sim::PrepareOptions::scene(s)))
        .unwrap_err()
        .to_string();
    assert!(e.contains("net.drag") && e.contains("triangle"), "{e}");
    let text = panel_scene("hexagon", 0.5);
    std::fs::write(dir.join("h.toml"), &text).unwrap();
    let e = format!(
        "{:#}",
        aqua_sim::read_scene(aqua_sim::SceneInput::File(&dir.join("h.toml")), &[]).unwrap_err()
    );
    assert!(e.contains("element") && e.contains("triangle"), "{e}");
}
