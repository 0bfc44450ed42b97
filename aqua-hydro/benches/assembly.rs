//! Load assembly for 10 000 quad net panels and 5 000 rope elements in a current plus an
//! irregular sea: forces, added mass and velocity Jacobians per call (issue target < 2 ms).

use aqua_env::{BuildOptions, Constants, Current, Phase, Sea, SeaSpec, Waves};
use aqua_hydro::{
    Block, Elements, LineElement, LineProps, LoadAssembly, MorisonModel, NetPanel, NetProps,
    Outputs, PanelNodes, ScreenModel, Wake, WakeGroup, WakeModel, WakeUpdate,
};
use criterion::{Criterion, criterion_group, criterion_main};
use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Duration;

/// A cylindrical cage: 100 sides × 100 rows of quads (radius 20 m, 20 m deep); ropes on the
/// ring edges of the top 50 rows.
fn model() -> (Vec<[f64; 3]>, Elements) {
    let (ns, rows, r) = (100, 100, 20.0);
    let mut x = Vec::new();
    for j in 0..=rows {
        for i in 0..ns {
            let a = 2.0 * PI * i as f64 / ns as f64;
            x.push([r * a.cos(), r * a.sin(), -0.5 - 0.2 * j as f64]);
        }
    }
    let id = |i: usize, j: usize| j * ns + i % ns;
    let net = NetProps {
        model: ScreenModel::S1,
        solidity: 0.2,
        twine_diameter: 0.0024,
    };
    let mut panels = Vec::new();
    for j in 0..rows {
        for i in 0..ns {
            panels.push(NetPanel {
                nodes: PanelNodes::Quad([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]),
                net,
                wake_group: Some(0),
                twines: None,
            });
        }
    }
    let rope = LineProps {
        model: MorisonModel::M4,
        hydro_diameter: 0.02,
        reynolds_diameter: 0.02,
        volume_diameter: 0.02,
        rest_length: 2.0 * PI * r / ns as f64,
        added_mass: 1.0,
        added_mass_axial: 0.0,
        froude_krylov: true,
        knot_correction: false,
    };
    let mut lines = Vec::new();
    for j in 0..50 {
        for i in 0..ns {
            lines.push(LineElement {
                nodes: [id(i, j), id(i + 1, j)],
                props: rope,
                net_twine: false,
                wake_group: Some(0),
            });
        }
    }
    let els = Elements {
        panels,
        lines,
        points: Vec::new(),
        wake_groups: vec![WakeGroup {
            name: "bench cage".into(),
            wake: Wake {
                model: WakeModel::Loland { cd0: None },
                update: WakeUpdate::Step,
                margin: 0.0,
                apply_to_lines: true,
            },
            solidity: 0.2,
        }],
    };
    (x, els)
}

fn irregular(components: usize) -> Sea {
    let spec = SeaSpec::from_toml(&format!(
        "depth = 60\n[current]\nkind = \"uniform\"\nvelocity = [0.5, 0, 0]\n[waves]\n\
         kind = \"irregular\"\n[waves.spectrum]\nhs = 3\ntp = 9\ncomponents = {components}\n\
         spreading_s = 8\n"
    ))
    .expect("sea spec");
    spec.build(&BuildOptions::default()).expect("sea").0
}

fn bench(c: &mut Criterion) {
    let (x, els) = model();
    let n = x.len();
    let v = vec![[0.01, -0.02, 0.005]; n];
    let mut g = c.benchmark_group("hydro_10k_panels_5k_lines");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(3));
    let seas = [
        (
            "current",
            Sea::new(
                Constants::default(),
                Current::uniform([0.5, 0.0, 0.0]),
                Waves::None,
            ),
        ),
        ("current+irregular_50", irregular(50)),
        ("current+irregular_200", irregular(200)),
    ];
    for (name, sea) in seas {
        let mut asm = LoadAssembly::new(sea, n, els.clone()).expect("assembly");
        let mut f = vec![[0.0; 3]; n];
        let mut m: Vec<Block> = vec![[[0.0; 3]; 3]; n];
        let mut dv: Vec<Block> = vec![[[0.0; 3]; 3]; asm.n_velocity_blocks()];
        let t = 123.4;
        g.bench_function(format!("{name}/forces+damping (sea eval included)"), |b| {
            b.iter(|| {
                asm.evaluate(
                    black_box(t),
                    Phase::Dynamic,
                    &x,
                    &v,
                    Outputs {
                        forces: &mut f,
                        added_mass: Some(&mut m),
                        dfdv: Some(&mut dv),
                        dfdx: None,
                    },
                )
                .expect("evaluate");
            })
        });
        if name == "current+irregular_200" {
            asm.prepare(t, Phase::Dynamic, &x).expect("prepare");
            g.bench_function(format!("{name}/forces+damping (flow cached)"), |b| {
                b.iter(|| {
                    asm.assemble(
                        &x,
                        &v,
                        Outputs {
                            forces: &mut f,
                            added_mass: Some(&mut m),
                            dfdv: Some(&mut dv),
                            dfdx: None,
                        },
                    )
                    .expect("assemble");
                })
            });
            g.bench_function(format!("{name}/sea eval only (prepare)"), |b| {
                b.iter(|| {
                    asm.prepare(black_box(t), Phase::Dynamic, &x)
                        .expect("prepare")
                })
            });
        }
        black_box(&f);
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
