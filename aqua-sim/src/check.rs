//! What `aqua check` reports: counts per group, λ and diameters (the mesh summary), which
//! physics are active and which are skipped, and a cost estimate — of a scene that passed the
//! same validation as a run ([`crate::plan::prepare`]).

use crate::build::Built;
use crate::diagnostic::Diagnostic;
use crate::error::Result;
use crate::plan::Prepared;
use crate::run::water_loads;
use crate::scene::AnalysisKind;
use aqua_env::Phase;
use aqua_hydro::MorisonModel;
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
    /// Estimated static solve [s]: the expected iterations (100 + 0.012 per free DOF; 1 when
    /// nothing is free) at 6 units of Newton work each.
    pub estimated_static_seconds: f64,
    /// Estimated dynamics [s]: ~4 Newton iterations per nominal step.
    pub estimated_dynamic_seconds: f64,
    /// Rough wall-time estimate [s], the sum of the two (measured constants of this code on a
    /// 2-core machine; within 3× of the bundled examples' measured wall times).
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
    })
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
            name: "Morison drag on lines",
            active: drag_lines > 0,
            why: format!("{drag_lines} of {} line elements", el.lines.len()),
        },
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
    // Calibrated separately on the bundled examples (release build, 2 cores; figures in
    // docs/theory/fem.md#static-solver). One Newton iteration of the structure costs about
    // 1.2 µs per cable element + 0.6 µs per load element, plus, in dynamics only, 200 ns per
    // wave component and node (the static phase sees the current alone).
    let per_iter = 1.2e-6 * built.model.elements().len() as f64
        + 0.6e-6 * (el.panels.len() + el.lines.len() + el.points.len()) as f64;
    let per_iter_dynamic = per_iter + 200e-9 * (ncomp * built.model.n_nodes()) as f64;
    // Statics (Levenberg–Marquardt, docs/theory/fem.md#static-solver): the iterations grow
    // slowly with the free DOFs (10 m cage 60 for ~250, buoy mooring 92 for 129, moored cage
    // 94 for 1143, reference cage 130 for 3027, 1.25 m cage 274 for ~12 000), each about 2.5
    // of these units (factorisation, Jacobian with finite-difference water-load derivatives,
    // trial evaluations). Measured against `analysis.kind = "static"` runs (2026-12-05):
    // reference cage 1.3 s estimated for 1.41–1.44 s, farm 1.6 s for 1.24–1.30 s, moored cage
    // 0.3 s for 0.20 s, buoy mooring 20 ms for 10 ms, mooring chain 5.4 ms for 4–5 ms.
    // Lines alone (no net, as panels or twines; nothing floating) start from their stretched touchdown
    // shape and take 12–15 iterations at 80–1280 segments (2026-12-05).
    let lines_only = el.panels.is_empty()
        && !el.lines.iter().any(|l| l.net_twine)
        && built.design.floaters.is_empty();
    let static_iterations = if free == 0 {
        1.0
    } else if lines_only {
        15.0
    } else {
        100.0 + 0.012 * free as f64
    };
    let estimated_static = if kind != AnalysisKind::Dynamic {
        2.5 * per_iter * static_iterations
    } else {
        0.0
    };
    // Dynamics: Newton iterations per nominal step, step halvings included (measured on the
    // bundled examples): 10 when something floats on slack lines in waves (collars, buoys),
    // where the step is halved to milliseconds and grows back only partly (with the midpoint
    // rule's line relaxation, 2026-12-04: moored cage 55, farm 34; 2026-12-05 with the run on
    // a pool worker, the GMRES rescue and θ = 0.75 for the farm: moored 46, farm 20). The unit
    // cost above overestimates theirs 3–5× since their loops run on both cores, so 10 keeps
    // both within 2× of the measured wall: moored 29 s for 28 s, farm 50 s for 29 s); ~2 where a
    // prescribed motion drives a stiff line (mooring chain 3.5; 2.0 since its line relaxation
    // and seabed relaxation, 2026-12-05); otherwise ~1.5 (reference
    // cage 1.0, buoy mooring in a current 1.0).
    let iterations_per_step = if !built.design.floaters.is_empty() && ncomp > 0 {
        10.0
    } else if built.model.n_prescribed_motions() > 0 {
        2.0
    } else {
        1.5
    };
    let estimated_dynamic = per_iter_dynamic * iterations_per_step * steps as f64;
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
