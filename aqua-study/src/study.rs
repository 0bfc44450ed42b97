//! The accuracy–speed study (`aqua study`): one scene run over ladders of numerical settings
//! (element length, time step, scheme, …), the converged value of each metric estimated from
//! the ladders, every run's error against it and its cost, and the cheapest setting whose
//! errors are all within a tolerance (docs/guide/study-and-sweep.md#choosing-resolution-aqua-study).
//!
//! **Settings.** Each `--vary PATH=v1,v2,…` is a ladder, listed from coarse to fine; the runs
//! are the full factorial product of the ladders (the last ladder varies fastest) and the last
//! value of every ladder together is the *reference* setting.
//!
//! **Estimate.** For a metric f and a numeric ladder whose last three values are geometric
//! (step h, ratio r = h₁/h₂ = h₂/h₃ > 1; h is the value itself when the ladder decreases, its
//! inverse when it increases, as for a number of segments), with the other ladders at their
//! reference values, the errors are modelled as f(h) = f* + C hᵖ. Three runs give the
//! observed order and the Richardson correction of the finest run
//!
//! ```text
//! p = ln((f₁ − f₂)/(f₂ − f₃)) / ln r,      Δ = (f₃ − f₂)/(rᵖ − 1)
//! ```
//!
//! and with several ladders the corrections add (errors of independent discretisations
//! superpose to leading order): f* = f_ref + Σ Δ_ladder. A ladder that is not numeric, not
//! geometric, shorter than three, whose differences change sign or grow (p ≤ 0), or whose observed
//! order is below 0.9 ([`MIN_ORDER`]: 1/(rᵖ − 1) would amplify the last difference) gives no
//! correction: its finest run stands for the converged value, and the table says so.
//!
//! **Errors and the recommendation.** Each run's error in a metric is |f − f*|/|f*|; the
//! recommended setting is the run of least wall time whose errors are all ≤ the tolerance.
//! A metric whose estimate is negligible (below 1e-9 of the largest metric of the same kind) has
//! no relative error and is left out of the recommendation.

use aqua_sim::Extreme;
use aqua_sim::check::free_dofs;
use aqua_sim::overrides::{Override, check_path_syntax, parse_value};
use aqua_sim::scene::{AnalysisKind, SceneInput, read_scene};
use aqua_sim::{Ending, Frame, Observer, Simulation};
use aqua_sim::{PrepareOptions, prepare};
use aqua_sim::{Result, SimError};
use aqua_sim::{SummaryRow, csv_line};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::Instant;
use toml::Value;

/// One ladder: a scene path (or alias) and its values from coarse to fine.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Axis {
    /// Dotted path or alias (aqua_sim::overrides).
    pub path: String,
    /// The values, coarse to fine (TOML text).
    #[serde(serialize_with = "values_text")]
    pub values: Vec<Value>,
}

fn values_text<S: serde::Serializer>(v: &[Value], s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(v.iter().map(value_text))
}

/// A value as a user typed it (strings without quotes).
pub fn value_text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

impl FromStr for Axis {
    type Err = SimError;

    /// `PATH=v1,v2,…` (at least two values).
    fn from_str(s: &str) -> Result<Self> {
        let err = |m: String| SimError::input(format!("--vary {s}: {m}"));
        let Some((path, list)) = s.split_once('=') else {
            return Err(err(
                "expected PATH=v1,v2,..., e.g. element_length=10,5,2.5 or dt=0.2,0.1,0.05".into(),
            ));
        };
        let path = path.trim();
        check_path_syntax(path).map_err(|e| err(e.to_string()))?;
        let values: Vec<Value> = list
            .split(',')
            .map(str::trim)
            .filter(|v| !v.is_empty())
            .map(parse_value)
            .collect();
        match values.len() {
            0 => Err(err("the ladder is empty: give at least two values".into())),
            1 => Err(err(
                "a ladder of one value measures nothing: give at least two values, coarse to \
                 fine (use --set to fix a value)"
                    .into(),
            )),
            _ => Ok(Axis {
                path: path.to_string(),
                values,
            }),
        }
    }
}

/// How a metric reduces a run's summary rows to one number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stat {
    /// Static value for a static analysis, else the dynamic value of largest magnitude.
    Auto,
    /// The static equilibrium's value.
    Static,
    /// Largest over the dynamic part (over every accepted step for the load columns).
    Max,
    /// Smallest over the dynamic part (over every accepted step for the load columns).
    Min,
    /// Value of largest magnitude (sign kept) over the dynamic part (over every accepted step
    /// for the load columns).
    Absmax,
    /// Time average over the dynamic output steps.
    Mean,
    /// The last output step.
    Final,
}

/// A study metric: a `summary.csv` column (or `F_net`, `R`: magnitudes of the net force and of
/// the support reaction) and how it is reduced over a run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Metric {
    /// Reduction.
    pub stat: Stat,
    /// Column.
    pub column: String,
}

const STATS: &[(&str, Stat)] = &[
    ("static", Stat::Static),
    ("max", Stat::Max),
    ("min", Stat::Min),
    ("absmax", Stat::Absmax),
    ("mean", Stat::Mean),
    ("final", Stat::Final),
];

impl FromStr for Metric {
    type Err = SimError;

    /// `COLUMN` or `STAT:COLUMN` with STAT one of static, max, min, absmax, mean, final.
    fn from_str(s: &str) -> Result<Self> {
        let (stat, column) = match s.split_once(':') {
            None => (Stat::Auto, s),
            Some((name, column)) => {
                let stat = STATS.iter().find(|(n, _)| *n == name).map(|(_, st)| *st);
                let Some(stat) = stat else {
                    let valid: Vec<&str> = STATS.iter().map(|(n, _)| *n).collect();
                    return Err(SimError::input(format!(
                        "--metric {s}: unknown reduction \"{name}\": valid are {}",
                        valid.join(", ")
                    )));
                };
                (stat, column)
            }
        };
        if column.trim().is_empty() {
            return Err(SimError::input(format!(
                "--metric {s}: no column: give a summary.csv column such as Fx_net or Tmax_ropes"
            )));
        }
        Ok(Metric {
            stat,
            column: column.trim().to_string(),
        })
    }
}

impl fmt::Display for Metric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match STATS.iter().find(|(_, st)| *st == self.stat) {
            Some((name, _)) => write!(f, "{name}:{}", self.column),
            None => f.write_str(&self.column),
        }
    }
}

/// The summary rows of one run and where its dynamic part starts.
#[derive(Debug, Clone, Default)]
pub struct RunRows {
    /// Column names (`summary.csv`).
    pub columns: Vec<String>,
    /// Rows, one per output step.
    pub rows: Vec<Vec<f64>>,
    /// Index of the first dynamic row (1 after a static row, 0 without statics).
    pub first_dynamic: usize,
    /// True when the analysis has a dynamic part.
    pub dynamic: bool,
    /// Extremes over every accepted step of the dynamic part ([`aqua_sim::extremes`]), by
    /// column (incl. `F_net` and `R`); empty when not known.
    pub extremes: BTreeMap<String, Extreme>,
}

impl RunRows {
    fn value(&self, row: &[f64], column: &str) -> Option<f64> {
        let get = |name: &str| self.columns.iter().position(|c| c == name).map(|i| row[i]);
        let norm = |names: [&str; 3]| -> Option<f64> {
            let mut s = 0.0;
            for n in names {
                s += get(n)?.powi(2);
            }
            Some(s.sqrt())
        };
        match column {
            "F_net" => norm(["Fx_net", "Fy_net", "Fz_net"]),
            "R" => norm(["Rx", "Ry", "Rz"]),
            c => get(c),
        }
    }

    /// The metric of this run, or why there is none.
    pub fn metric(&self, m: &Metric) -> std::result::Result<f64, MetricMissing> {
        let stat = match m.stat {
            Stat::Auto if self.dynamic => Stat::Absmax,
            Stat::Auto => Stat::Static,
            s => s,
        };
        // Max, min and absmax are taken over every accepted step where known: a peak between
        // two output steps counts (aqua_sim::extremes).
        if let Some(e) = self.extremes.get(&m.column) {
            match stat {
                Stat::Max => return Ok(e.max),
                Stat::Min => return Ok(e.min),
                Stat::Absmax => {
                    return Ok(if e.min.abs() > e.max.abs() {
                        e.min
                    } else {
                        e.max
                    });
                }
                _ => {}
            }
        }
        let rows: &[Vec<f64>] = match stat {
            Stat::Static if self.first_dynamic == 1 || !self.dynamic => {
                &self.rows[..1.min(self.rows.len())]
            }
            Stat::Static => return Err(MetricMissing::NoStatic),
            _ if self.dynamic => &self.rows[self.first_dynamic.min(self.rows.len())..],
            _ => &self.rows[..],
        };
        let vals: Vec<f64> = rows
            .iter()
            .map(|r| self.value(r, &m.column))
            .collect::<Option<Vec<f64>>>()
            .ok_or_else(|| MetricMissing::NoColumn {
                column: m.column.clone(),
                columns: self.columns.join(", "),
            })?;
        let Some(&last) = vals.last() else {
            return Err(MetricMissing::NoRows);
        };
        Ok(match stat {
            Stat::Max => vals.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            Stat::Min => vals.iter().copied().fold(f64::INFINITY, f64::min),
            Stat::Absmax => vals
                .iter()
                .copied()
                .fold(0.0, |a: f64, v| if v.abs() > a.abs() { v } else { a }),
            Stat::Mean => vals.iter().sum::<f64>() / vals.len() as f64,
            Stat::Final | Stat::Static | Stat::Auto => last,
        })
    }
}

/// One run of the study.
#[derive(Debug, Clone, Serialize)]
pub struct StudyRun {
    /// Position in the factorial order.
    pub index: usize,
    /// The value of each ladder (TOML text).
    pub setting: Vec<String>,
    /// "completed", "failed" or "interrupted".
    pub status: &'static str,
    /// Why it failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Wall time: building the model and solving [s].
    pub wall_s: f64,
    /// Free DOFs.
    pub dofs: usize,
    /// Dynamic steps taken.
    pub steps: usize,
    /// Static Newton iterations.
    pub static_iterations: usize,
    /// Each metric's value (None: failed run or missing column).
    pub values: Vec<Option<f64>>,
    /// Each metric's relative error against the estimate.
    pub errors: Vec<Option<f64>>,
    #[serde(skip)]
    rows: Option<RunRows>,
}

/// The converged value of one metric.
#[derive(Debug, Clone, Serialize)]
pub struct Estimate {
    /// The metric (`stat:column`).
    pub metric: String,
    /// Estimated converged value.
    pub value: Option<f64>,
    /// The reference (finest) run's value.
    pub finest: Option<f64>,
    /// "richardson" when at least one ladder corrected the finest run, else "finest run".
    pub method: &'static str,
    /// Observed order per ladder (None where none could be observed).
    pub orders: Vec<Option<f64>>,
    /// Per ladder: why it gave no correction.
    pub notes: Vec<Option<String>>,
    /// True when the estimate is negligible and relative errors are not used.
    pub negligible: bool,
}

/// A finished (or interrupted) study.
#[derive(Debug, Clone, Serialize)]
pub struct Study {
    /// The scene file.
    pub scene: PathBuf,
    /// `--set` changes applied to every run.
    pub base: Vec<String>,
    /// The ladders.
    pub axes: Vec<Axis>,
    /// Metric names.
    pub metrics: Vec<String>,
    /// Every run, in factorial order (only those run when interrupted).
    pub runs: Vec<StudyRun>,
    /// Estimates, one per metric.
    pub estimates: Vec<Estimate>,
    /// Relative tolerance of the recommendation.
    pub tolerance: f64,
    /// Index of the recommended run.
    pub recommended: Option<usize>,
    /// True when stopped before all runs were made.
    pub interrupted: bool,
    /// Wall time of the whole study [s].
    pub wall_s: f64,
    /// Wall time outside the runs (reading, estimating) [s].
    pub overhead_s: f64,
}

/// What a caller sees of a study as it goes.
pub trait StudyObserver {
    /// Run `index` of `total` starts with `setting` (one `PATH=VALUE` per ladder).
    fn run_started(&mut self, _index: usize, _total: usize, _setting: &str) {}
    /// A run ended.
    fn run_finished(&mut self, _run: &StudyRun) {}
    /// True to stop (polled between output steps and between runs).
    fn stop_requested(&self) -> bool {
        false
    }
}

/// What to study.
#[derive(Debug, Clone)]
pub struct StudySpec {
    /// Scene file.
    pub scene: PathBuf,
    /// Changes for every run.
    pub base: Vec<Override>,
    /// Ladders (at least one).
    pub axes: Vec<Axis>,
    /// Metrics (empty: [`default_metrics`]).
    pub metrics: Vec<Metric>,
    /// Relative tolerance of the recommendation (e.g. 0.01).
    pub tolerance: f64,
}

impl StudySpec {
    /// The factorial settings: per run, the index of each ladder's value.
    pub fn settings(&self) -> Vec<Vec<usize>> {
        let mut out = vec![vec![]];
        for axis in &self.axes {
            out = out
                .into_iter()
                .flat_map(|s| {
                    (0..axis.values.len()).map(move |k| {
                        let mut s = s.clone();
                        s.push(k);
                        s
                    })
                })
                .collect();
        }
        out
    }

    /// The changes of one setting: the base changes, then one per ladder.
    fn overrides(&self, setting: &[usize]) -> Vec<Override> {
        let mut o = self.base.clone();
        o.extend(self.axes.iter().zip(setting).map(|(a, &k)| Override {
            path: a.path.clone(),
            value: a.values[k].clone(),
        }));
        o
    }

    /// Checks the spec before any run: ladders given, tolerance positive, and every setting a
    /// valid scene file (unknown paths and wrong types are input errors, not failed runs).
    pub fn validate(&self) -> Result<()> {
        if self.axes.is_empty() {
            return Err(SimError::input(
                "aqua study needs at least one --vary PATH=v1,v2,... ladder",
            ));
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(SimError::input(format!(
                "--tolerance {}: a relative error in (0, 1), e.g. 0.01 for 1 %",
                self.tolerance
            )));
        }
        for s in self.settings() {
            read_scene(SceneInput::File(&self.scene), &self.overrides(&s))?;
        }
        Ok(())
    }
}

/// Collects a run's summary rows and passes stop requests on.
struct Collector<'a> {
    rows: Vec<Vec<f64>>,
    outer: &'a dyn StudyObserver,
}

impl Observer for Collector<'_> {
    fn frame(&mut self, f: &Frame<'_>) -> Result<()> {
        self.rows.push(f.row.values());
        Ok(())
    }
    fn stop_requested(&self) -> bool {
        self.outer.stop_requested()
    }
}

/// Runs one setting.
fn run_one(spec: &StudySpec, index: usize, setting: &[usize], obs: &dyn StudyObserver) -> StudyRun {
    let t0 = Instant::now();
    let mut run = StudyRun {
        index,
        setting: spec
            .axes
            .iter()
            .zip(setting)
            .map(|(a, &k)| value_text(&a.values[k]))
            .collect(),
        status: "failed",
        reason: None,
        wall_s: 0.0,
        dofs: 0,
        steps: 0,
        static_iterations: 0,
        values: vec![],
        errors: vec![],
        rows: None,
    };
    let prep =
        match prepare(PrepareOptions::file(&spec.scene).with_overrides(&spec.overrides(setting))) {
            Ok(p) => p,
            Err(e) => {
                run.reason = Some(e.chain());
                run.wall_s = t0.elapsed().as_secs_f64();
                return run;
            }
        };
    run.dofs = free_dofs(&prep.built);
    let mut collector = Collector {
        rows: vec![],
        outer: obs,
    };
    let outcome = Simulation::new(&prep).map(|mut sim| sim.run(&mut collector));
    run.wall_s = t0.elapsed().as_secs_f64();
    match outcome {
        Err(e) => run.reason = Some(e.chain()),
        Ok((record, result)) => {
            run.steps = record.steps;
            run.static_iterations = record.static_iterations;
            run.status = record.ending.as_str();
            if let Err(e) = result {
                run.reason = Some(e.chain());
                run.status = Ending::Failed.as_str();
            } else if record.ending == Ending::Completed {
                let kind = prep.plan.kind;
                run.rows = Some(RunRows {
                    columns: SummaryRow::columns(&prep.built),
                    rows: collector.rows,
                    first_dynamic: usize::from(kind == AnalysisKind::StaticDynamic),
                    dynamic: kind != AnalysisKind::Static,
                    extremes: record
                        .extremes
                        .as_ref()
                        .map(|e| {
                            e.table()
                                .into_iter()
                                .map(|(c, x)| (c.to_string(), x))
                                .collect()
                        })
                        .unwrap_or_default(),
                });
            }
        }
    }
    run
}

/// Runs the study: every setting, then the estimates, errors and recommendation.
pub fn run_study(spec: &StudySpec, obs: &mut dyn StudyObserver) -> Result<Study> {
    spec.validate()?;
    let t0 = Instant::now();
    let settings = spec.settings();
    let mut runs = Vec::with_capacity(settings.len());
    let mut interrupted = false;
    for (i, s) in settings.iter().enumerate() {
        if obs.stop_requested() {
            interrupted = true;
            break;
        }
        let label: Vec<String> = spec
            .axes
            .iter()
            .zip(s)
            .map(|(a, &k)| format!("{}={}", a.path, value_text(&a.values[k])))
            .collect();
        obs.run_started(i, settings.len(), &label.join(" "));
        let run = run_one(spec, i, s, &*obs);
        interrupted |= run.status == Ending::Interrupted.as_str();
        obs.run_finished(&run);
        runs.push(run);
        if interrupted {
            break;
        }
    }
    let metrics = if spec.metrics.is_empty() {
        runs.iter()
            .rev()
            .find_map(|r| r.rows.as_ref())
            .map(default_metrics)
            .unwrap_or_default()
    } else {
        spec.metrics.clone()
    };
    let mut study = Study {
        scene: spec.scene.clone(),
        base: spec.base.iter().map(|o| o.to_string()).collect(),
        axes: spec.axes.clone(),
        metrics: metrics.iter().map(|m| m.to_string()).collect(),
        runs,
        estimates: vec![],
        tolerance: spec.tolerance,
        recommended: None,
        interrupted,
        wall_s: 0.0,
        overhead_s: 0.0,
    };
    evaluate(&mut study, &metrics, &settings);
    study.wall_s = t0.elapsed().as_secs_f64();
    study.overhead_s = study.wall_s - study.runs.iter().map(|r| r.wall_s).sum::<f64>();
    Ok(study)
}

/// The metrics that matter when none are named: net drag and reaction magnitudes, the volume
/// ratio of nets, the largest tension of every group and the loads at every line end.
pub fn default_metrics(rows: &RunRows) -> Vec<Metric> {
    let mut m: Vec<Metric> = ["F_net", "R"]
        .iter()
        .map(|c| Metric {
            stat: Stat::Auto,
            column: c.to_string(),
        })
        .collect();
    for c in &rows.columns {
        let wanted = c == "volume_ratio"
            || c.starts_with("Tmax_")
            || c.ends_with("_anchor_reaction")
            || c.ends_with("_fairlead_reaction");
        if wanted {
            m.push(Metric {
                stat: Stat::Auto,
                column: c.clone(),
            });
        }
    }
    // Quantities that are zero in this scene (no net, slack groups) measure nothing.
    m.retain(|metric| rows.metric(metric).is_ok_and(|v| v.abs() > 0.0));
    m
}

/// Fills metric values, estimates, errors and the recommendation.
fn evaluate(study: &mut Study, metrics: &[Metric], settings: &[Vec<usize>]) {
    for run in &mut study.runs {
        run.values = metrics
            .iter()
            .map(|m| run.rows.as_ref().and_then(|r| r.metric(m).ok()))
            .collect();
    }
    let n_axes = study.axes.len();
    let reference: Vec<usize> = study.axes.iter().map(|a| a.values.len() - 1).collect();
    let run_at = |s: &[usize]| settings.iter().position(|x| x == s);
    for (j, m) in metrics.iter().enumerate() {
        let value_of = |s: &[usize]| {
            run_at(s)
                .and_then(|i| study.runs.get(i))
                .and_then(|r| r.values[j])
        };
        let finest = value_of(&reference);
        let mut est = Estimate {
            metric: m.to_string(),
            value: finest,
            finest,
            method: "finest run",
            orders: vec![None; n_axes],
            notes: vec![None; n_axes],
            negligible: false,
        };
        for (a, axis) in study.axes.iter().enumerate() {
            let ladder: Vec<Option<f64>> = (0..axis.values.len())
                .map(|k| {
                    let mut s = reference.clone();
                    s[a] = k;
                    value_of(&s)
                })
                .collect();
            match richardson(&axis.values, &ladder) {
                Ok((p, correction)) => {
                    est.orders[a] = Some(p);
                    if let Some(v) = est.value.as_mut() {
                        *v += correction;
                        est.method = "richardson";
                    }
                }
                Err(why) => est.notes[a] = Some(why.to_string()),
            }
        }
        study.estimates.push(est);
    }
    mark_negligible(&mut study.estimates, metrics);
    for run in &mut study.runs {
        run.errors = run
            .values
            .iter()
            .zip(&study.estimates)
            .map(|(v, e)| match (v, e.value) {
                (Some(v), Some(x)) if !e.negligible => Some((v - x).abs() / x.abs()),
                _ => None,
            })
            .collect();
    }
    // Without an estimate of every metric that counts, nothing can be recommended.
    if study
        .estimates
        .iter()
        .any(|e| e.value.is_none() && !e.negligible)
    {
        return;
    }
    study.recommended = study
        .runs
        .iter()
        .filter(|r| r.status == "completed" && !r.errors.is_empty())
        .filter(|r| {
            r.errors
                .iter()
                .zip(&study.estimates)
                .all(|(e, est)| est.negligible || e.is_some_and(|e| e <= study.tolerance))
        })
        .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s))
        .map(|r| r.index);
}

/// Estimates below 1e-9 of the largest of their kind (force-like or ratio) are negligible.
fn mark_negligible(estimates: &mut [Estimate], metrics: &[Metric]) {
    let is_ratio = |m: &Metric| m.column.contains("ratio");
    for ratio in [false, true] {
        let scale = estimates
            .iter()
            .zip(metrics)
            .filter(|(_, m)| is_ratio(m) == ratio)
            .filter_map(|(e, _)| e.value.map(f64::abs))
            .fold(0.0, f64::max);
        for (e, m) in estimates.iter_mut().zip(metrics) {
            if is_ratio(m) == ratio {
                e.negligible = e.value.is_some_and(|v| !(v.abs() > 1e-9 * scale));
            }
        }
    }
}

/// The lowest observed order that is extrapolated.
pub const MIN_ORDER: f64 = 0.9;

/// Why a run has no value of a metric.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MetricMissing {
    /// A static metric of a run without a static phase.
    #[error("the run has no static equilibrium")]
    NoStatic,
    /// The column is not in summary.csv.
    #[error("no column {column} in summary.csv (columns: {columns}; F_net, R)")]
    NoColumn {
        /// The column asked for.
        column: String,
        /// The columns there are, comma separated.
        columns: String,
    },
    /// summary.csv has no row.
    #[error("the run wrote no output step")]
    NoRows,
}

/// Why the finest value of a ladder is not extrapolated (the finest run then stands).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NoExtrapolation {
    /// Fewer than three values.
    #[error("fewer than three values: the finest run stands")]
    TooFew,
    /// A value of the ladder is not a number.
    #[error("not numeric: the finest run stands")]
    NotNumeric,
    /// A value of the ladder is zero or negative.
    #[error("values not all positive: the finest run stands")]
    NotPositive,
    /// The values neither rise nor fall throughout.
    #[error("not monotone: the finest run stands")]
    NotMonotone,
    /// The last three values are not a geometric sequence.
    #[error("not geometric (ratios {r1:.3} and {r2:.3}): the finest run stands")]
    NotGeometric {
        /// The two refinement ratios.
        r1: f64,
        /// The second ratio.
        r2: f64,
    },
    /// A run of the last three has no value.
    #[error("a run of the last three failed: the finest run stands")]
    RunFailed,
    /// The three runs agree to round-off.
    #[error("converged: the runs agree to round-off")]
    Converged,
    /// The finest two runs agree exactly while the coarser differs.
    #[error("the finest two runs agree exactly: no order to observe")]
    FinestEqual,
    /// The differences change sign or grow.
    #[error(
        "differences {e12:.3e}, {e23:.3e} change sign or do not shrink: not yet in the \
         asymptotic range, the finest run stands"
    )]
    NotAsymptotic {
        /// Coarse minus middle value.
        e12: f64,
        /// Middle minus finest value.
        e23: f64,
    },
    /// The observed order is below [`MIN_ORDER`].
    #[error(
        "observed order {order:.2} < {min}: too low to extrapolate safely, the finest run \
         stands",
        min = MIN_ORDER
    )]
    OrderTooLow {
        /// The observed order.
        order: f64,
    },
}

/// Observed order and Richardson correction of the finest value of a ladder (values coarse to
/// fine; `f` the metric at each), or why there is none.
pub fn richardson(
    values: &[Value],
    f: &[Option<f64>],
) -> std::result::Result<(f64, f64), NoExtrapolation> {
    let n = values.len();
    if n < 3 {
        return Err(NoExtrapolation::TooFew);
    }
    let x: Vec<f64> = values[n - 3..]
        .iter()
        .map(|v| match v {
            Value::Integer(i) => Some(*i as f64),
            Value::Float(x) => Some(*x),
            _ => None,
        })
        .collect::<Option<Vec<f64>>>()
        .ok_or(NoExtrapolation::NotNumeric)?;
    if x.iter().any(|v| !(*v > 0.0)) {
        return Err(NoExtrapolation::NotPositive);
    }
    let h: Vec<f64> = if x[0] > x[1] && x[1] > x[2] {
        x
    } else if x[0] < x[1] && x[1] < x[2] {
        x.iter().map(|v| 1.0 / v).collect()
    } else {
        return Err(NoExtrapolation::NotMonotone);
    };
    let (r1, r2) = (h[0] / h[1], h[1] / h[2]);
    if ((r1 - r2) / r2).abs() > 0.01 {
        return Err(NoExtrapolation::NotGeometric { r1, r2 });
    }
    let [Some(f1), Some(f2), Some(f3)] = [f[n - 3], f[n - 2], f[n - 1]] else {
        return Err(NoExtrapolation::RunFailed);
    };
    let r = (r1 * r2).sqrt();
    let (e12, e23) = (f1 - f2, f2 - f3);
    if e12.abs().max(e23.abs()) <= 1e-9 * f3.abs() {
        return Err(NoExtrapolation::Converged);
    }
    if e23 == 0.0 {
        return if e12 == 0.0 {
            Ok((f64::INFINITY, 0.0))
        } else {
            Err(NoExtrapolation::FinestEqual)
        };
    }
    let q = e12 / e23;
    if !(q > 1.0) {
        return Err(NoExtrapolation::NotAsymptotic { e12, e23 });
    }
    let p = q.ln() / r.ln();
    // Below first order the correction 1/(rᵖ − 1) of the last difference grows without bound
    // and the ladder is pre-asymptotic in practice: report, do not extrapolate.
    if p < MIN_ORDER {
        return Err(NoExtrapolation::OrderTooLow { order: p });
    }
    Ok((p, (f3 - f2) / (r.powf(p) - 1.0)))
}

/// Writes `study.csv` (one row per run), `estimates.csv` and `study.json` into `dir`.
pub fn write_tables(study: &Study, dir: &Path) -> Result<()> {
    let io = |what: &'static str, path: &Path| {
        let path = path.to_path_buf();
        move |source| SimError::Io { what, path, source }
    };
    std::fs::create_dir_all(dir).map_err(io("creating the study directory", dir))?;
    let path = dir.join("study.csv");
    std::fs::write(&path, runs_csv(study)).map_err(io("writing", &path))?;
    let path = dir.join("estimates.csv");
    std::fs::write(&path, estimates_csv(study)).map_err(io("writing", &path))?;
    let path = dir.join("study.json");
    let json = serde_json::to_string_pretty(study).unwrap_or_default();
    std::fs::write(&path, json).map_err(io("writing", &path))?;
    Ok(())
}

fn num(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.10e}")).unwrap_or_default()
}

/// The runs table.
pub fn runs_csv(study: &Study) -> String {
    let mut head: Vec<String> = vec!["run".into()];
    head.extend(study.axes.iter().map(|a| a.path.clone()));
    head.extend(
        ["status", "wall_s", "dofs", "steps", "static_iterations"]
            .iter()
            .map(|s| s.to_string()),
    );
    for m in &study.metrics {
        head.push(m.clone());
        head.push(format!("{m} error"));
    }
    head.push("recommended".into());
    head.push("reason".into());
    let mut out = head.join(",") + "\n";
    for r in &study.runs {
        let mut row: Vec<String> = vec![r.index.to_string()];
        row.extend(r.setting.iter().cloned());
        row.push(r.status.into());
        row.push(format!("{:.4}", r.wall_s));
        row.extend([r.dofs, r.steps, r.static_iterations].map(|v| v.to_string()));
        for k in 0..study.metrics.len() {
            row.push(num(r.values.get(k).copied().flatten()));
            row.push(num(r.errors.get(k).copied().flatten()));
        }
        row.push((study.recommended == Some(r.index)).to_string());
        row.push(r.reason.clone().unwrap_or_default());
        out += &csv_line(&row);
    }
    out
}

/// The estimates table: metric, estimate, finest run, method, observed order per ladder.
pub fn estimates_csv(study: &Study) -> String {
    let mut head = vec!["metric", "estimate", "finest", "method"]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>();
    head.extend(study.axes.iter().map(|a| format!("order {}", a.path)));
    let mut out = head.join(",") + "\n";
    for e in &study.estimates {
        let mut row = vec![
            e.metric.clone(),
            num(e.value),
            num(e.finest),
            e.method.into(),
        ];
        row.extend(
            e.orders
                .iter()
                .map(|p| p.map(|p| format!("{p:.4}")).unwrap_or_default()),
        );
        out += &csv_line(&row);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn floats(v: &[f64]) -> Vec<Value> {
        v.iter().map(|x| Value::Float(*x)).collect()
    }

    #[test]
    fn richardson_recovers_order_and_limit_of_a_power_law() {
        // f(h) = 3 + 2 h^1.7 on h = 0.4, 0.2, 0.1: exact for the three-level model.
        let h: [f64; 3] = [0.4, 0.2, 0.1];
        let f: Vec<Option<f64>> = h.iter().map(|h| Some(3.0 + 2.0 * h.powf(1.7))).collect();
        let (p, d) = richardson(&floats(&h), &f).unwrap();
        assert!((p - 1.7).abs() < 1e-9, "{p}");
        assert!((f[2].unwrap() + d - 3.0).abs() < 1e-12);
        // Counts (segments 10, 20, 40) are refined upwards: h = 1/N.
        let n = [Value::Integer(10), Value::Integer(20), Value::Integer(40)];
        let f: Vec<Option<f64>> = [10.0, 20.0, 40.0]
            .iter()
            .map(|n: &f64| Some(5.0 - 7.0 / (n * n)))
            .collect();
        let (p, d) = richardson(&n, &f).unwrap();
        assert!((p - 2.0).abs() < 1e-9 && (f[2].unwrap() + d - 5.0).abs() < 1e-12);
    }

    #[test]
    fn richardson_refuses_what_it_cannot_model() {
        let ok = [Some(1.0), Some(0.5), Some(0.25)];
        assert!(richardson(&floats(&[0.2, 0.1]), &ok[..2]).is_err());
        assert!(richardson(&floats(&[0.3, 0.2, 0.05]), &ok).is_err()); // not geometric
        assert!(
            richardson(
                &floats(&[0.4, 0.2, 0.1]),
                &[Some(1.0), Some(0.5), Some(0.6)]
            )
            .is_err()
        );
        assert!(richardson(&floats(&[0.4, 0.2, 0.1]), &[Some(1.0), None, Some(0.6)]).is_err());
        // Order 0.5: refused rather than amplified.
        let f: Vec<Option<f64>> = [0.4f64, 0.2, 0.1].iter().map(|h| Some(h.sqrt())).collect();
        let why = richardson(&floats(&[0.4, 0.2, 0.1]), &f).unwrap_err();
        assert!(
            matches!(why, NoExtrapolation::OrderTooLow { order } if (order - 0.5).abs() < 1e-9),
            "{why:?}"
        );
        assert!(why.to_string().contains("0.50 < 0.9: too low"), "{why}");
        let words = vec![
            Value::String("hht".into()),
            Value::String("rk4".into()),
            Value::String("x".into()),
        ];
        assert!(richardson(&words, &ok).is_err());
    }

    #[test]
    fn ladders_and_metrics_parse_with_clear_errors() {
        let a: Axis = "dt=0.2, 0.1,0.05".parse().unwrap();
        assert_eq!(a.values.len(), 3);
        let e = "dt=".parse::<Axis>().unwrap_err().to_string();
        assert!(e.contains("empty"), "{e}");
        let e = "dt=0.1".parse::<Axis>().unwrap_err().to_string();
        assert!(e.contains("one value"), "{e}");
        let m: Metric = "max:Tmax_ropes".parse().unwrap();
        assert_eq!((m.stat, m.column.as_str()), (Stat::Max, "Tmax_ropes"));
        assert!(
            "top:Fx"
                .parse::<Metric>()
                .unwrap_err()
                .to_string()
                .contains("absmax")
        );
    }

    #[test]
    fn factorial_settings_vary_the_last_ladder_fastest() {
        let spec = StudySpec {
            scene: PathBuf::new(),
            base: vec![],
            axes: vec!["a=1,2".parse().unwrap(), "b=3,4,5".parse().unwrap()],
            metrics: vec![],
            tolerance: 0.01,
        };
        let s = spec.settings();
        assert_eq!(s.len(), 6);
        assert_eq!(s[1], vec![0, 1]);
        assert_eq!(s[5], vec![1, 2]);
    }
}
