//! The validated analysis of a scene — what `aqua check` reports and `aqua run` runs — and the
//! one validation both go through ([`prepare`]).

use crate::build::{Built, Prescribed, build};
use crate::diagnostic::Diagnostic;
use crate::error::{Result, SimError};
use crate::overrides::Override;
use crate::scene::{AnalysisKind, DEFAULT_DT, Scene, SceneInput, read_scene};
use aqua_fem::{DynamicSettings, ExplicitSettings, StaticSettings};
use std::path::Path;

/// The time integrator of the dynamic phase, with its aqua-fem settings.
#[derive(Debug, Clone, PartialEq)]
pub enum Integrator {
    /// Implicit HHT-α.
    Hht(DynamicSettings),
    /// Explicit lumped mass-spring.
    Explicit(ExplicitSettings),
}

/// What a run of the scene computes, validated.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Static, dynamic or both.
    pub kind: AnalysisKind,
    /// Static solver settings.
    pub statics: StaticSettings,
    /// Dynamic phase (none for a static analysis).
    pub dynamics: Option<Integrator>,
    /// HHT α (0 for statics).
    pub alpha: f64,
    /// Nominal step [s] (0 for statics).
    pub dt: f64,
    /// Output interval [s] (0 for statics): a `summary.csv` row every interval.
    pub output_interval: f64,
    /// Output steps per step of the ParaView series (`paraview_interval / output_interval`,
    /// ≥ 1; 1 for statics): output step n is written to ParaView when n is a multiple of it.
    pub paraview_every: usize,
    /// End time [s] (0 for statics).
    pub t_end: f64,
}

/// A scene read, built and planned: everything `check` reports on and `run` needs.
#[derive(Debug)]
pub struct Prepared {
    /// The scene.
    pub scene: Scene,
    /// Its model.
    pub built: Built,
    /// Its analysis.
    pub plan: Plan,
}

impl Prepared {
    /// Warnings of building the model.
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.built.diagnostics
    }
}

/// Where [`prepare`] takes a scene from.
#[derive(Debug, Clone)]
pub enum SceneSource<'a> {
    /// A scene file (TOML), read and changed by the overrides.
    File(&'a Path),
    /// A scene already read (a Python dict, a test's text); it takes no overrides.
    Scene(Box<Scene>),
}

/// What [`prepare`] reads, changes and builds.
#[derive(Debug, Clone)]
pub struct PrepareOptions<'a> {
    /// The scene.
    pub source: SceneSource<'a>,
    /// Changes of scene keys (`--set`, study ladders, sweep cases), applied in order to a
    /// scene file's text.
    pub overrides: &'a [Override],
    /// How the `[[prescribed]]` nodes move (driven from outside in a coupling).
    pub prescribed: Prescribed,
}

impl<'a> PrepareOptions<'a> {
    /// A scene file as it is.
    pub fn file(path: &'a Path) -> Self {
        Self {
            source: SceneSource::File(path),
            overrides: &[],
            prescribed: Prescribed::AsScene,
        }
    }

    /// A scene already read.
    pub fn scene(scene: Scene) -> Self {
        Self {
            source: SceneSource::Scene(Box::new(scene)),
            overrides: &[],
            prescribed: Prescribed::AsScene,
        }
    }

    /// The same scene changed by `overrides`.
    pub fn with_overrides(self, overrides: &'a [Override]) -> Self {
        Self { overrides, ..self }
    }

    /// The same scene with its `[[prescribed]]` nodes moving as `prescribed` says.
    pub fn with_prescribed(self, prescribed: Prescribed) -> Self {
        Self { prescribed, ..self }
    }
}

/// Reads, builds and plans a scene: the validation of `aqua check` and `aqua run`. An error
/// in building a scene changed by overrides names the changes.
pub fn prepare(options: PrepareOptions<'_>) -> Result<Prepared> {
    let PrepareOptions {
        source,
        overrides,
        prescribed,
    } = options;
    let scene = match source {
        SceneSource::File(path) => read_scene(SceneInput::File(path), overrides)?,
        SceneSource::Scene(scene) if overrides.is_empty() => *scene,
        SceneSource::Scene(scene) => {
            return Err(SimError::input(format!(
                "{}: overrides change a scene file's text; this scene was not read from a file",
                scene.path.display()
            )));
        }
    };
    if overrides.is_empty() {
        return prepare_built(scene, prescribed);
    }
    let changes = scene.overrides.join(" ");
    prepare_built(scene, prescribed).map_err(|e| match e {
        // Where the mistake is stays known; the message says the overrides were applied.
        SimError::Input(mut ie) => {
            ie.message = format!("{} (with --set {changes})", ie.message);
            SimError::Input(ie)
        }
        e if e.is_input() => SimError::input(format!("{} (with --set {changes})", e.chain())),
        e => e,
    })
}

/// Builds and plans a scene already read.
fn prepare_built(scene: Scene, prescribed: Prescribed) -> Result<Prepared> {
    let built = build(&scene, prescribed)?;
    let plan = Plan::of(&scene)?;
    Ok(Prepared { scene, built, plan })
}

impl Plan {
    /// The plan of a scene's `[analysis]`, validated.
    pub fn of(scene: &Scene) -> Result<Plan> {
        let kind = scene.analysis.kind;
        let statics = scene.analysis.statics.clone();
        if kind == AnalysisKind::Static {
            return Ok(Plan {
                kind,
                statics,
                dynamics: None,
                alpha: 0.0,
                dt: 0.0,
                output_interval: 0.0,
                paraview_every: 1,
                t_end: 0.0,
            });
        }
        let (dt, output_interval, t_end) = timing(scene)?;
        let paraview_every = paraview_every(scene, output_interval)?;
        // The midpoint rule has no α; an α given for HHT is still validated.
        let alpha = match alpha(scene)? {
            _ if scene.analysis.dynamic.scheme == crate::scene::Scheme::Midpoint => 0.0,
            a => a,
        };
        let d = &scene.analysis.dynamic;
        // Validated for every scheme, so that θ given with an explicit one is not ignored.
        let theta = theta(scene)?;
        let extreme_tolerance = extreme_tolerance(scene)?;
        let integrator = match d.scheme.explicit() {
            None => {
                let mut s = DynamicSettings::new(dt, t_end);
                s.alpha = alpha;
                s.dt_min = d.dt_min;
                s.tol = d.tol;
                s.max_iter = d.max_iter;
                s.mass_matrix = d.mass_matrix;
                s.rayleigh = d.rayleigh;
                s.output_interval = Some(output_interval);
                s.max_strain = d.max_strain;
                s.reuse_factor = d.reuse_factor;
                s.linear_solver = d.linear_solver;
                s.line_relaxation = d.line_relaxation;
                s.extreme_tolerance = extreme_tolerance;
                s.midpoint = d.scheme == crate::scene::Scheme::Midpoint;
                s.theta = theta;
                Integrator::Hht(s)
            }
            Some(scheme) => {
                let mut s = ExplicitSettings::new(t_end);
                s.scheme = scheme;
                s.cfl = d.cfl;
                // An upper bound only: the stable estimate when not given.
                s.dt = d.dt;
                s.dt_fixed = d.dt_fixed;
                s.output_interval = Some(output_interval);
                Integrator::Explicit(s)
            }
        };
        Ok(Plan {
            kind,
            statics,
            dynamics: Some(integrator),
            alpha,
            dt,
            output_interval,
            paraview_every,
            t_end,
        })
    }

    /// The interval of the ParaView series [s] (0 for statics).
    pub fn paraview_interval(&self) -> f64 {
        self.output_interval * self.paraview_every as f64
    }

    /// Whether output step `n` (0 = the first, static or initial state) goes to the ParaView
    /// series as well as to `summary.csv`.
    pub fn paraview_step(&self, n: usize) -> bool {
        n.is_multiple_of(self.paraview_every.max(1))
    }
}

/// The HHT α the scene asks for (default 0.3), validated.
fn alpha(scene: &Scene) -> Result<f64> {
    let d = &scene.analysis.dynamic;
    let file = scene.path.display();
    match (d.alpha, d.rho_inf) {
        (Some(_), Some(_)) => Err(SimError::input(format!(
            "{file}: [analysis.dynamic]: give either alpha or rho_inf, not both"
        ))),
        (Some(a), None) => {
            if (0.0..=1.0 / 3.0).contains(&a) {
                Ok(a)
            } else {
                Err(SimError::invalid(
                    &scene.path,
                    "analysis.dynamic.alpha",
                    a,
                    format!(
                        "{file}: analysis.dynamic.alpha = {a}: valid is 0 <= alpha <= 1/3 (our convention; \
                     the original HHT/Code_Aster ALPHA is -alpha, in [-1/3, 0])"
                    ),
                ))
            }
        }
        (None, Some(r)) => DynamicSettings::alpha_from_rho_inf(r)
            .map_err(|e| SimError::at(format!("{file}: analysis.dynamic.rho_inf"), e)),
        (None, None) => Ok(aqua_fem::DEFAULT_ALPHA),
    }
}

/// The midpoint rule's velocity weight θ (docs/theory/fem.md#energy-decaying-midpoint).
fn theta(scene: &Scene) -> Result<f64> {
    let d = &scene.analysis.dynamic;
    let file = scene.path.display();
    match d.theta {
        None => Ok(aqua_fem::DEFAULT_THETA),
        Some(t) if d.scheme != crate::scene::Scheme::Midpoint && t != aqua_fem::DEFAULT_THETA => {
            let hint = if d.scheme == crate::scene::Scheme::Hht {
                "HHT-alpha damps through alpha or rho_inf"
            } else {
                "an explicit scheme has no theta; remove the key or use scheme = \"midpoint\""
            };
            Err(SimError::invalid(
                &scene.path,
                "analysis.dynamic.theta",
                t,
                format!(
                    "{file}: analysis.dynamic.theta = {t}: only with scheme = \"midpoint\" ({hint})"
                ),
            ))
        }
        Some(t) if (0.5..=1.0).contains(&t) => Ok(t),
        Some(t) => Err(SimError::invalid(
            &scene.path,
            "analysis.dynamic.theta",
            t,
            format!(
                "{file}: analysis.dynamic.theta = {t}: valid is 0.5 <= theta <= 1 \
             (0.5 conserves the energy; above it each step removes (theta - 1/2)*|v1 - v0|^2_M)"
            ),
        )),
    }
}

/// The implicit schemes' `extreme_tolerance` (docs/theory/fem.md#extremes-to-a-tolerance),
/// validated: a relative error in (0, 0.5), not with an explicit scheme (whose step is set by
/// stability, not halved).
fn extreme_tolerance(scene: &Scene) -> Result<Option<f64>> {
    let d = &scene.analysis.dynamic;
    let file = scene.path.display();
    let Some(e) = d.extreme_tolerance else {
        return Ok(None);
    };
    let why = if d.scheme.explicit().is_some() {
        "only with scheme = \"hht\" or \"midpoint\" (an explicit scheme's step is set by \
         stability)"
    } else if !(e > 0.0 && e < 0.5) {
        "valid is 0 < extreme_tolerance < 0.5, a relative error (e.g. 0.01)"
    } else {
        return Ok(Some(e));
    };
    Err(SimError::invalid(
        &scene.path,
        "analysis.dynamic.extreme_tolerance",
        e,
        format!("{file}: analysis.dynamic.extreme_tolerance = {e}: {why}"),
    ))
}

/// Most nominal steps a dynamic run may take (t_end / dt; more is likely a unit mistake).
pub const MAX_STEPS: f64 = 1.0e9;

/// The nominal step, output interval and end time, validated.
fn timing(scene: &Scene) -> Result<(f64, f64, f64)> {
    let d = &scene.analysis.dynamic;
    let file = scene.path.display();
    if !(d.t_end > 0.0 && d.t_end.is_finite()) {
        return Err(SimError::invalid(
            &scene.path,
            "analysis.dynamic.t_end",
            d.t_end,
            format!(
                "{file}: analysis.dynamic.t_end = {}: a duration > 0 in s",
                d.t_end
            ),
        ));
    }
    if d.reuse_factor == 0 {
        return Err(SimError::invalid(
            &scene.path,
            "analysis.dynamic.reuse_factor",
            0,
            format!("{file}: analysis.dynamic.reuse_factor = 0: an integer >= 1 (1 = full Newton)"),
        ));
    }
    let dt = d.dt.unwrap_or(DEFAULT_DT);
    if !(dt > 0.0 && dt <= d.t_end) {
        return Err(SimError::invalid(
            &scene.path,
            "analysis.dynamic.dt",
            dt,
            format!(
                "{file}: analysis.dynamic.dt = {dt}: a time step > 0 s and <= t_end ({} s)",
                d.t_end
            ),
        ));
    }
    if d.t_end / dt > MAX_STEPS {
        return Err(SimError::invalid(
            &scene.path,
            "analysis.dynamic.t_end",
            d.t_end,
            format!(
                "{file}: analysis.dynamic.t_end = {} s with dt = {dt} s: {:.3e} steps; at most \
             {MAX_STEPS:e} (times are in seconds)",
                d.t_end,
                d.t_end / dt
            ),
        ));
    }
    // 200 output steps over the run at most, by default.
    let out = d.output_interval.unwrap_or(dt.max(d.t_end / 200.0));
    if !(out > 0.0) {
        return Err(SimError::invalid(
            &scene.path,
            "analysis.dynamic.output_interval",
            out,
            format!("{file}: analysis.dynamic.output_interval = {out}: an interval > 0 in s"),
        ));
    }
    Ok((dt, out.max(dt), d.t_end))
}

/// Output steps per ParaView step: `analysis.dynamic.paraview_interval` (default the output
/// interval `out` [s]) over `out`, validated to be a whole number ≥ 1.
fn paraview_every(scene: &Scene, out: f64) -> Result<usize> {
    let Some(p) = scene.analysis.dynamic.paraview_interval else {
        return Ok(1);
    };
    let ratio = p / out;
    let k = ratio.round();
    // A relative tolerance: 0.3 / 0.1 is 2.9999999999999996 in floating point.
    if p.is_finite() && k >= 1.0 && (ratio - k).abs() <= 1e-6 * k && k <= MAX_STEPS {
        return Ok(k as usize);
    }
    Err(SimError::invalid(
        &scene.path,
        "analysis.dynamic.paraview_interval",
        p,
        format!(
            "{}: analysis.dynamic.paraview_interval = {p}: a whole multiple (1, 2, 3, …) of the \
         output interval, {out} s (`output_interval`; every summary.csv row is an output step \
         and every k-th of them also a ParaView step)",
            scene.path.display()
        ),
    ))
}
