//! What `aqua check` reports: counts per group, λ and diameters (the mesh summary), which
//! physics are active and which are skipped, and a cost estimate — of a scene that passed the
//! same validation as a run ([`crate::plan::prepare`]).

use crate::build::{Built, resolve_ref};
use crate::diagnostic::Diagnostic;
use crate::error::Result;
use crate::estimate::{Driving, Workload};
use crate::plan::Prepared;
use crate::run::water_loads;
use crate::scene::AnalysisKind;
use aqua_env::Phase;
use aqua_hydro::MorisonModel;
use aqua_mesh::ObjectKind;
use serde::Serialize;

/// One physical effect and whether the scene needs it.
#[derive(Debug, Serialize)]
pub struct Physics {
    /// Name.
    pub name: &'static str,
    /// Computed in this run.
    pub active: bool,
    /// Why (or why not).
    pub why: String,
}

/// The cost estimate.
#[derive(Debug, Serialize)]
pub struct Cost {
    /// Unknowns (free DOFs).
    pub dofs: usize,
    /// Cable elements.
    pub cable_elements: usize,
    /// Water-load elements (panels, lines, points).
    pub load_elements: usize,
    /// Wave components evaluated per point.
    pub wave_components: usize,
    /// Dynamic steps at the nominal step.
    pub steps: usize,
    /// Output steps (`summary.csv` rows).
    pub output_steps: usize,
    /// Steps of the ParaView series (every `paraview_interval`).
    pub paraview_steps: usize,
    /// Estimated static solve [s]: the expected Newton iterations (more the finer the net)
    /// times the cost of one ([`crate::estimate`]).
    pub estimated_static_seconds: f64,
    /// Estimated dynamics [s]: the expected Newton iterations (step halvings included) times
    /// the cost of one ([`crate::estimate`]).
    pub estimated_dynamic_seconds: f64,
    /// Rough wall-time estimate [s], the sum of the two (measured constants of this code on a
    /// 2-core machine; within 2× of the bundled examples' measured wall times,
    /// docs/notes/check-estimate.md).
    pub estimated_seconds: f64,
}

/// Counts per part of one farm.
#[derive(Debug, Serialize)]
pub struct FarmReport {
    /// Farm name.
    pub name: String,
    /// Counts.
    #[serde(flatten)]
    pub counts: aqua_mesh::FarmCounts,
    /// Cage-to-cage wake among its cages.
    pub cage_wake: bool,
}

/// The whole report.
#[derive(Debug, Serialize)]
pub struct Report {
    /// Scene name.
    pub scene: String,
    /// Mesh summary (counts per group, λ, diameters).
    pub mesh: aqua_mesh::MeshSummary,
    /// Counts per part of every `[[farm]]`.
    pub farms: Vec<FarmReport>,
    /// Physics.
    pub physics: Vec<Physics>,
    /// Cost.
    pub cost: Cost,
    /// Warnings (building the model and setting up the water loads).
    pub warnings: Vec<Diagnostic>,
    /// Totals of every `[[point]]` table (in the text only: the JSON has the scene's tables).
    #[serde(skip)]
    pub points: Vec<PointTotals>,
}

/// One `[[point]]` table summed over the nodes it names.
#[derive(Debug, Clone, PartialEq)]
pub struct PointTotals {
    /// Its `nodes` reference.
    pub nodes: String,
    /// Nodes the reference names.
    pub count: usize,
    /// Mass [kg].
    pub mass: f64,
    /// Weight in the scene's gravity [N].
    pub weight: f64,
    /// Force [N].
    pub force: [f64; 3],
    /// Volume [m³].
    pub volume: f64,
}

/// The report of a prepared scene (sets up the water loads, as a run would).
pub fn report(prep: &Prepared) -> Result<Report> {
    let built = &prep.built;
    let (_, load_warnings) = water_loads(prep, Phase::Static)?;
    let ncomp = wave_components(&built.sea);
    Ok(Report {
        scene: prep.scene.name.clone(),
        mesh: built.mesh.summary(),
        farms: built
            .farms
            .iter()
            .map(|f| FarmReport {
                name: f.name.clone(),
                counts: f.counts.clone(),
                cage_wake: f.cage_wake,
            })
            .collect(),
        physics: physics(prep, ncomp),
        cost: cost(prep, ncomp),
        warnings: built
            .diagnostics
            .iter()
            .chain(&load_warnings)
            .cloned()
            .collect(),
        points: point_totals(prep),
    })
}

/// The totals of every `[[point]]` table over its nodes.
fn point_totals(prep: &Prepared) -> Vec<PointTotals> {
    let g = prep.built.sea.constants().gravity;
    let totals = |v: &crate::scene::PointSpec| {
        let count = resolve_ref(&prep.built.mesh, &v.nodes).map_or(0, |n| n.len());
        let k = count as f64;
        PointTotals {
            nodes: v.nodes.clone(),
            count,
            mass: k * v.mass,
            weight: k * v.mass * g,
            force: v.force.map(|f| k * f),
            volume: k * v.volume,
        }
    };
    prep.scene.point.iter().map(|p| totals(&p.value)).collect()
}

/// Wave components evaluated per point.
fn wave_components(sea: &aqua_env::Sea) -> usize {
    match sea.waves() {
        aqua_env::Waves::Linear { sum, .. } => sum.len(),
        aqua_env::Waves::Stokes2 { .. } => 1,
        aqua_env::Waves::None => 0,
    }
}

/// Which physical effects the run computes, and why (not).
fn physics(prep: &Prepared, ncomp: usize) -> Vec<Physics> {
    let scene = &prep.scene;
    let built = &prep.built;
    let kind = prep.plan.kind;
    let dynamic = kind != AnalysisKind::Static;
    let sea = &built.sea;
    let el = &built.elements;
    let wake_on = el
        .wake_groups
        .iter()
        .any(|w| w.wake.model != aqua_hydro::WakeModel::None);
    let inertia_lines = el
        .lines
        .iter()
        .filter(|l| l.props.added_mass > 0.0 || l.props.froude_krylov)
        .count();
    let drag_lines = el
        .lines
        .iter()
        .filter(|l| l.props.model != MorisonModel::None)
        .count();
    let seabed = built.model.environment().seabed.is_some();
    let seabed_groups = built
        .model
        .groups()
        .iter()
        .filter(|g| g.section.contact_diameter.is_some())
        .count();
    vec![
        Physics {
            name: "current",
            active: sea.has_current(),
            why: if sea.has_current() {
                format!(
                    "{:?} current{}",
                    scene.sea.current.kind,
                    if sea.current_ramps() {
                        ", ramped at the start of dynamics"
                    } else {
                        ""
                    }
                )
            } else {
                "no [sea.current]: skipped".into()
            },
        },
        Physics {
            name: "waves",
            active: sea.has_waves() && dynamic,
            why: match (sea.has_waves(), dynamic) {
                (true, true) => format!("{ncomp} wave components evaluated per node and step"),
                (true, false) => "static analysis: waves are not evaluated".into(),
                (false, _) => "still water: no wave kinematics computed".into(),
            },
        },
        Physics {
            name: "screen panels",
            active: !el.panels.is_empty(),
            why: format!("{} net panels carry drag and lift", el.panels.len()),
        },
        Physics {
            name: "net triangles",
            active: !built.model.net_triangles().is_empty(),
            why: if built.model.net_triangles().is_empty() {
                "off (net.element = \"triangle\" models a net by Priour's triangles)".into()
            } else {
                format!(
                    "{} triangles carry the physical twines; their solidity follows the \
                     twines' stretch (docs/theory/fem.md#net-triangle)",
                    built.model.net_triangles().len()
                )
            },
        },
        Physics {
            name: "Morison drag on lines",
            active: drag_lines > 0,
            why: format!("{drag_lines} of {} line elements", el.lines.len()),
        },
        bending(built),
        Physics {
            name: "wake shielding",
            active: wake_on && sea.has_current(),
            why: if !wake_on {
                "no wake model: skipped".into()
            } else if !sea.has_current() {
                "wake models reduce the current, and there is none: skipped".into()
            } else {
                format!(
                    "{} cage nets shadow their downstream half",
                    el.wake_groups.len()
                )
            },
        },
        Physics {
            name: "cage-to-cage wake",
            active: !built.cage_wake.is_empty() && sea.has_current(),
            why: match (built.cage_wake.sources.len(), sea.has_current()) {
                (0, _) => "off (a [[farm]] turns it on; [wake] cage_to_cage for [[cage]]s)".into(),
                (_, false) => "it reduces the current, and there is none: skipped".into(),
                (n, true) => format!(
                    "{n} cages slow the current behind them by 1 - r_c^2, recovering with \
                     distance (spreading {})",
                    built.cage_wake.spreading
                ),
            },
        },
        Physics {
            name: "added mass and Froude-Krylov inertia",
            active: dynamic && inertia_lines > 0,
            why: if dynamic {
                format!("{inertia_lines} line elements")
            } else {
                "static analysis: no inertia".into()
            },
        },
        Physics {
            name: "seabed contact",
            active: seabed && seabed_groups > 0,
            why: if seabed {
                format!("{seabed_groups} cable groups may touch the seabed at z = -depth")
            } else {
                "no finite water depth: no seabed".into()
            },
        },
        seabed_friction(built, dynamic, seabed && seabed_groups > 0),
        Physics {
            name: "dynamics",
            active: dynamic,
            why: match kind {
                AnalysisKind::Static => "static analysis only".into(),
                AnalysisKind::Dynamic => "dynamics from the as-built state".into(),
                AnalysisKind::StaticDynamic => "statics, then dynamics from equilibrium".into(),
            },
        },
    ]
}

/// Which members bend and with which element (docs/theory/fem.md#bending-of-sections).
fn bending(built: &Built) -> Physics {
    let model = &built.model;
    let (rods, hinges) = (model.rod_vertices().len(), model.hinges().len());
    let mut parts = Vec::new();
    if rods > 0 {
        let names: Vec<&str> = built.pipes.iter().map(|p| p.name.as_str()).collect();
        parts.push(format!(
            "rods (bending, torsion, stress) on {}: {} rods, {rods} vertices",
            names.join(", "),
            model.n_rods()
        ));
    }
    if hinges > 0 {
        parts.push(format!(
            "{hinges} rotation-free hinges (bending only, no torsion)"
        ));
    }
    Physics {
        name: "bending",
        active: rods + hinges > 0,
        why: if parts.is_empty() {
            "no member bends (ropes, chains and twines are cables)".into()
        } else {
            parts.join("; ")
        },
    }
}

/// The unknowns of the model: its DOFs that are neither fixed nor prescribed.
pub fn free_dofs(built: &Built) -> usize {
    let model = &built.model;
    (0..model.n_nodes())
        .map(|i| (0..3).filter(|&k| !model.is_constrained(i, k)).count())
        .sum()
}

/// The cost estimate: unknowns, elements, steps and a wall-time guess.
fn cost(prep: &Prepared, ncomp: usize) -> Cost {
    let built = &prep.built;
    let el = &built.elements;
    let kind = prep.plan.kind;
    let dynamic = kind != AnalysisKind::Static;
    let (dt, out_int, t_end) = (prep.plan.dt, prep.plan.output_interval, prep.plan.t_end);
    let free = free_dofs(built);
    let output_steps = if dynamic {
        ((t_end / out_int).floor() as usize).saturating_add(1)
    } else {
        1
    };
    let steps = if dynamic {
        (t_end / dt).ceil() as usize
    } else {
        0
    };
    // The wall-time model: crate::estimate (data in docs/notes/check-estimate.md).
    let lines_only = el.panels.is_empty()
        && !el.lines.iter().any(|l| l.net_twine)
        && built.design.floaters.is_empty();
    let driving = if !dynamic {
        Driving::None
    } else if !built.design.floaters.is_empty() && ncomp > 0 {
        Driving::FloatingInWaves
    } else if built.model.n_prescribed_motions() > 0 {
        Driving::Prescribed
    } else {
        Driving::Steady
    };
    let work = Workload {
        free_dofs: free,
        elements: built.model.elements().len() + el.panels.len() + el.lines.len() + el.points.len(),
        net_dofs_squared: net_dofs_squared(built),
        wave_points: ncomp * built.model.n_nodes(),
        lines_only,
        statics: kind != AnalysisKind::Dynamic,
        mesh_sequence: prep.plan.statics.mesh_sequence,
        driving,
        midpoint: matches!(&prep.plan.dynamics, Some(crate::plan::Integrator::Hht(s)) if s.midpoint),
        bodies: built.model.rigid_bodies().len(),
        steps,
        t_end,
    };
    let estimated_static = work.static_seconds();
    let estimated_dynamic = work.dynamic_seconds();
    Cost {
        dofs: free,
        cable_elements: built.model.elements().len(),
        load_elements: el.panels.len() + el.lines.len() + el.points.len(),
        wave_components: ncomp,
        steps,
        output_steps,
        // Output steps 0, k, 2k, … (Plan::paraview_step).
        paraview_steps: (output_steps - 1) / prep.plan.paraview_every.max(1) + 1,
        estimated_static_seconds: estimated_static,
        estimated_dynamic_seconds: estimated_dynamic,
        estimated_seconds: estimated_static + estimated_dynamic,
    }
}

/// Σ over the nets (cages, panels, imported meshes) of their free DOFs squared: what their
/// factorisations cost ([`crate::estimate`]).
fn net_dofs_squared(built: &Built) -> f64 {
    let (mesh, model) = (&built.mesh, &built.model);
    let mut nets: std::collections::HashMap<(u32, u32), usize> = Default::default();
    for (i, &owner) in mesh.node_owner.iter().enumerate().take(model.n_nodes()) {
        let net = mesh.objects.get(owner.0 as usize).is_some_and(|o| {
            matches!(
                o.kind,
                ObjectKind::Cage(_) | ObjectKind::Panel | ObjectKind::Gmsh
            )
        });
        if net {
            *nets.entry(owner).or_default() +=
                (0..3).filter(|&k| !model.is_constrained(i, k)).count();
        }
    }
    nets.values().map(|&n| (n as f64).powi(2)).sum()
}

/// The seabed-friction line of `aqua check` (docs/theory/fem.md#seabed-friction).
fn seabed_friction(built: &Built, dynamic: bool, contact: bool) -> Physics {
    let friction = built
        .model
        .environment()
        .seabed
        .map(|s| s.friction)
        .unwrap_or_default();
    Physics {
        name: "seabed friction",
        active: friction.is_active() && contact && dynamic,
        why: if !friction.is_active() {
            "sea.seabed.friction_axial = 0: frictionless bed".into()
        } else if !contact {
            "no seabed contact: no friction".into()
        } else if !dynamic {
            "static analysis: friction is omitted in statics".into()
        } else {
            format!(
                "regularised Coulomb, mu_a = {}, mu_t = {}, v_c = {} m/s (dynamics only)",
                friction.axial, friction.transverse, friction.slip_velocity
            )
        },
    }
}
