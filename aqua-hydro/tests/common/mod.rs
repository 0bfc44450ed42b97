//! Helpers of the load assembly tests: seas, net and rope properties, small meshes, and the
//! assembled forces and Jacobian blocks.

#![allow(dead_code)]

use aqua_env::{
    Component, Constants, Current, Depth, LinearSum, Phase, Ramp, Sea, Stretching, Waves,
};
use aqua_hydro::assembly::MAX_DOFS;
use aqua_hydro::{
    Block, ElementOutput, Elements, LineElement, LineProps, LoadAssembly, MorisonModel, NetPanel,
    NetProps, Outputs, PanelNodes, PointElement, PointProps, PointShape, ScreenModel, TwineMap,
    Wake, WakeGroup, WakeModel, WakeUpdate, Want,
};
use std::f64::consts::PI;

pub const RHO: f64 = 1025.0;

pub fn current_sea(u: [f64; 3]) -> Sea {
    Sea::new(Constants::default(), Current::uniform(u), Waves::None)
}

pub fn net(model: ScreenModel, sn: f64) -> NetProps {
    NetProps {
        model,
        solidity: sn,
        twine_diameter: 0.0024,
    }
}

pub fn rope(model: MorisonModel, d: f64, l0: f64) -> LineProps {
    LineProps {
        model,
        hydro_diameter: d,
        reynolds_diameter: d,
        volume_diameter: d,
        rest_length: l0,
        added_mass: 1.0,
        added_mass_axial: 0.0,
        froude_krylov: true,
        knot_correction: false,
    }
}

pub struct Out {
    pub f: Vec<[f64; 3]>,
    pub m: Vec<Block>,
    pub dv: Vec<Block>,
    pub dx: Vec<Block>,
}

pub fn run(asm: &mut LoadAssembly, t: f64, x: &[[f64; 3]], v: &[[f64; 3]]) -> Out {
    run_in(asm, t, Phase::Dynamic, x, v)
}

pub fn run_in(asm: &mut LoadAssembly, t: f64, phase: Phase, x: &[[f64; 3]], v: &[[f64; 3]]) -> Out {
    let n = asm.n_nodes();
    let mut o = Out {
        f: vec![[0.0; 3]; n],
        m: vec![[[0.0; 3]; 3]; n],
        dv: vec![[[0.0; 3]; 3]; asm.n_velocity_blocks()],
        dx: vec![[[0.0; 3]; 3]; asm.n_position_blocks()],
    };
    asm.evaluate(
        t,
        phase,
        x,
        v,
        Outputs {
            forces: &mut o.f,
            added_mass: Some(&mut o.m),
            dfdv: Some(&mut o.dv),
            dfdx: Some(&mut o.dx),
        },
    )
    .unwrap();
    o
}

pub fn total(f: &[[f64; 3]]) -> [f64; 3] {
    f.iter()
        .fold([0.0; 3], |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]])
}

/// A flat 1 m × 1 m panel in the plane spanned by e1 = (cos β… ) rotated about z by θ,
/// divided into k × k quads (or 2k² triangles).
pub fn flat_panel(theta: f64, k: usize, triangles: bool, sn: f64) -> (Vec<[f64; 3]>, Elements) {
    // in-plane horizontal direction t = (−sin θ, cos θ, 0): normal (cos θ, sin θ, 0)
    let t = [-theta.sin(), theta.cos(), 0.0];
    let mut x = Vec::new();
    for j in 0..=k {
        for i in 0..=k {
            let a = i as f64 / k as f64 - 0.5;
            let b = j as f64 / k as f64;
            x.push([a * t[0], a * t[1], -2.0 - b]);
        }
    }
    let id = |i: usize, j: usize| j * (k + 1) + i;
    let mut panels = Vec::new();
    for j in 0..k {
        for i in 0..k {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if triangles {
                for tri in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
                    panels.push(NetPanel {
                        nodes: PanelNodes::Triangle(tri),
                        net: net(ScreenModel::S1, sn),
                        wake_group: None,
                        twines: None,
                    });
                }
            } else {
                panels.push(NetPanel {
                    nodes: PanelNodes::Quad(q),
                    net: net(ScreenModel::S1, sn),
                    wake_group: None,
                    twines: None,
                });
            }
        }
    }
    (
        x,
        Elements {
            panels,
            ..Default::default()
        },
    )
}

/// Dense global matrix from the compact blocks.
pub fn global(asm: &LoadAssembly, blocks: &[Block], position: bool) -> Vec<Vec<f64>> {
    let n = 3 * asm.n_nodes();
    let mut g = vec![vec![0.0; n]; n];
    let mut dense = [[0.0; MAX_DOFS]; MAX_DOFS];
    for e in 0..asm.n_elements() {
        asm.expand(e, blocks, position, &mut dense);
        let nodes = asm.element_nodes(e);
        for (i, &ni) in nodes.iter().enumerate() {
            for (j, &nj) in nodes.iter().enumerate() {
                for r in 0..3 {
                    for c in 0..3 {
                        g[3 * ni + r][3 * nj + c] += dense[3 * i + r][3 * j + c];
                    }
                }
            }
        }
    }
    g
}

/// A mixed model: a warped quad, a triangle crossing the surface, a rope, a twine and a buoy.
pub fn mixed() -> (Vec<[f64; 3]>, Elements) {
    let x = vec![
        [0.0, 0.0, -2.0],
        [1.0, 0.2, -2.1],
        [1.1, 0.1, -1.0],
        [0.1, -0.1, -0.9],
        [0.5, 1.0, 0.3],
        [2.0, 0.5, -3.0],
        [2.2, 1.5, -0.05],
    ];
    let els = Elements {
        panels: vec![
            NetPanel {
                nodes: PanelNodes::Quad([0, 1, 2, 3]),
                net: net(ScreenModel::S3 { cyl_cd: None }, 0.2),
                wake_group: None,
                twines: None,
            },
            NetPanel {
                nodes: PanelNodes::Triangle([2, 3, 4]),
                net: net(ScreenModel::Bi2014, 0.2),
                wake_group: None,
                twines: None,
            },
            // A net triangle (twines of ~2–4 cm, Sn ≈ 0.2 and changing with the positions).
            NetPanel {
                nodes: PanelNodes::Triangle([2, 3, 4]),
                net: net(ScreenModel::S1, 0.2),
                wake_group: None,
                twines: TwineMap::new([[0.0, 0.0], [50.0, 5.0], [10.0, 60.0]]),
            },
        ],
        lines: vec![
            LineElement {
                nodes: [1, 5],
                props: rope(MorisonModel::M4, 0.03, 2.0),
                net_twine: false,
                wake_group: None,
            },
            LineElement {
                nodes: [5, 6],
                props: rope(MorisonModel::M1, 0.2, 3.2),
                net_twine: false,
                wake_group: None,
            },
        ],
        points: vec![
            PointElement {
                node: 6,
                props: PointProps {
                    volume: 0.5,
                    shape: PointShape::Prism { height: 0.4 },
                    drag_area: 0.3,
                    added_mass: 0.5,
                },
            },
            PointElement {
                // partly wet: centre 0.3 m above still water, radius 0.5 m
                node: 4,
                props: PointProps {
                    volume: 4.0 / 3.0 * PI * 0.125,
                    shape: PointShape::Sphere { radius: 0.5 },
                    drag_area: 0.5 * PI * 0.25,
                    added_mass: 0.5,
                },
            },
        ],
        ..Default::default()
    };
    (x, els)
}

pub fn rel(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale
}

/// A sea with one Airy wave (8 s, 1 m) and a current: its flow depends on time and position.
pub fn wave_sea() -> Sea {
    let c = Constants::default();
    let comp = Component::new(1.0, 8.0, 0.4, 0.3, Depth::Infinite, c.gravity).unwrap();
    Sea::new(
        c,
        Current::uniform([0.4, 0.1, 0.0]),
        Waves::Linear {
            sum: LinearSum::new(vec![comp], Depth::Infinite, c.gravity),
            stretching: Stretching::None,
            ramp: Ramp::off(),
        },
    )
}

/// A rigid cylindrical cage: radius 5 m, 16 sides, 5 rows of 1 m, fan-triangle bottom.
pub fn cage(wake: Wake, sn: f64) -> (Vec<[f64; 3]>, Elements) {
    let (ns, rows, r) = (16, 5, 5.0);
    let mut x = Vec::new();
    for j in 0..=rows {
        for i in 0..ns {
            let a = 2.0 * PI * i as f64 / ns as f64;
            x.push([r * a.cos(), r * a.sin(), -0.5 - j as f64]);
        }
    }
    let centre = x.len();
    x.push([0.0, 0.0, -0.5 - rows as f64]);
    let id = |i: usize, j: usize| j * ns + i % ns;
    let mut panels = Vec::new();
    for j in 0..rows {
        for i in 0..ns {
            panels.push(NetPanel {
                nodes: PanelNodes::Quad([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]),
                net: net(ScreenModel::S1, sn),
                wake_group: Some(0),
                twines: None,
            });
        }
    }
    for i in 0..ns {
        panels.push(NetPanel {
            nodes: PanelNodes::Triangle([id(i, rows), id(i + 1, rows), centre]),
            net: net(ScreenModel::S1, sn),
            wake_group: Some(0),
            twines: None,
        });
    }
    let els = Elements {
        panels,
        wake_groups: vec![WakeGroup {
            name: "cage 0".into(),
            wake,
            solidity: sn,
        }],
        ..Default::default()
    };
    (x, els)
}

pub fn wake(model: WakeModel, update: WakeUpdate) -> Wake {
    Wake {
        model,
        update,
        ..Wake::none()
    }
}

pub fn centroid(asm: &LoadAssembly, x: &[[f64; 3]], e: usize) -> [f64; 3] {
    let nodes = asm.element_nodes(e);
    let mut c = [0.0; 3];
    for &n in nodes {
        for k in 0..3 {
            c[k] += x[n][k] / nodes.len() as f64;
        }
    }
    c
}

/// Per-element total forces via the element path.
pub fn element_forces(asm: &LoadAssembly, x: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut out = ElementOutput::default();
    (0..asm.n_elements())
        .map(|e| {
            let nodes = asm.element_nodes(e);
            let xl: Vec<[f64; 3]> = nodes.iter().map(|&i| x[i]).collect();
            let vl = vec![[0.0; 3]; nodes.len()];
            asm.element_load(e, &xl, &vl, Want::default(), &mut out);
            total(&out.force[..nodes.len()])
        })
        .collect()
}
