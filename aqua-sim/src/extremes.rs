//! Extremes over every accepted step: for each load a design looks at — the net force and the
//! support reactions (components, magnitudes `F_net` and `R`, moment), the largest tension of
//! each structural group (`Tmax_<group>`) and the four line-end loads of each `[[line]]` — the
//! largest and smallest value reached at any accepted dynamic step, with the time it was
//! reached (docs/theory/fem.md#outputs).
//!
//! The output steps sample a run every `output_interval`; a tension peak that falls between
//! two samples is missing from `summary.csv`. The run loop therefore hands every accepted step
//! to [`Extremes::observe`], which evaluates the same quantities as the summary row
//! ([`crate::post`]) into buffers allocated once and keeps the running max and min.
//!
//! Which states count is what `aqua collect` and `aqua study` call the dynamic part: every
//! accepted dynamic step, and the start of the dynamic phase when it is not a static
//! equilibrium (a dynamic-only run). The static equilibrium of a static+dynamic run is its own
//! load case (full current, no ramp) and stands only while no dynamic step has been accepted
//! (an interruption or failure before the first step); a static run's extremes are its static
//! state. Quantities that are not loads (volume, iterations) are not tracked: their extremes
//! come from `summary.csv`.

use crate::build::Built;
use crate::post::{SummaryRow, group_max_tensions, line_end_loads, net_force, support_reactions};
use crate::provider::WaterLoads;
use aqua_fem::{BodyPose, Outputs, State};
use serde::Serialize;
use std::collections::BTreeMap;

/// Columns before the per-group and per-line loads.
const FORCE_COLUMNS: [&str; 11] = [
    "Fx_net", "Fy_net", "Fz_net", "F_net", "Rx", "Ry", "Rz", "R", "Mx", "My", "Mz",
];

/// The extreme values of one column.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Extreme {
    /// Largest value.
    pub max: f64,
    /// Time of the largest value [s] (the first time it was reached).
    pub t_max: f64,
    /// Smallest value.
    pub min: f64,
    /// Time of the smallest value [s] (the first time it was reached).
    pub t_min: f64,
}

/// Running extremes of the load columns over the accepted steps of a run.
#[derive(Debug, Clone)]
pub struct Extremes {
    columns: Vec<String>,
    /// Scratch: the values of the state being observed.
    values: Vec<f64>,
    /// Scratch: largest tension per group.
    groups: Vec<f64>,
    /// Scratch: largest fibre stress per pipe group.
    stresses: Vec<f64>,
    /// Scratch: line-end loads per line.
    ends: Vec<[f64; 4]>,
    max: Vec<f64>,
    t_max: Vec<f64>,
    min: Vec<f64>,
    t_min: Vec<f64>,
    /// States observed.
    states: usize,
    /// The states so far are replaced by the next one observed (a static equilibrium before
    /// the dynamic phase).
    provisional: bool,
}

impl Extremes {
    /// Empty accumulators for the columns of a model.
    pub fn new(built: &Built) -> Self {
        let columns = Self::columns(built);
        let n = columns.len();
        Self {
            columns,
            values: vec![0.0; n],
            groups: vec![0.0; built.group_names.len()],
            stresses: vec![0.0; built.pipes.len()],
            ends: vec![[0.0; 4]; built.line_ends.len()],
            max: vec![f64::NEG_INFINITY; n],
            t_max: vec![f64::NAN; n],
            min: vec![f64::INFINITY; n],
            t_min: vec![f64::NAN; n],
            states: 0,
            provisional: false,
        }
    }

    /// The columns tracked: net force and reaction components and magnitudes (`F_net`, `R`),
    /// the reaction moment, then [`SummaryRow::load_columns`] (names as in `summary.csv`).
    pub fn columns(built: &Built) -> Vec<String> {
        let mut c: Vec<String> = FORCE_COLUMNS.iter().map(|s| s.to_string()).collect();
        c.extend(SummaryRow::load_columns(built));
        c
    }

    /// Adds a state (its outputs evaluated at it, `poses` its rigid bodies') to the extremes;
    /// allocates nothing.
    pub fn observe(
        &mut self,
        built: &Built,
        loads: &WaterLoads,
        state: &State,
        out: &Outputs,
        poses: &[BodyPose],
    ) {
        let f = net_force(built, loads, state);
        let (r, m) = support_reactions(built, &state.x, out);
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let head = [
            f[0],
            f[1],
            f[2],
            norm(f),
            r[0],
            r[1],
            r[2],
            norm(r),
            m[0],
            m[1],
            m[2],
        ];
        self.values[..head.len()].copy_from_slice(&head);
        group_max_tensions(built, out, &state.x, &mut self.groups);
        crate::pipe_stress::group_max_stresses(built, out, &mut self.stresses);
        line_end_loads(built, out, &mut self.ends);
        let k = head.len();
        let g = self.groups.len();
        self.values[k..k + g].copy_from_slice(&self.groups);
        let p = self.stresses.len();
        self.values[k + g..k + g + p].copy_from_slice(&self.stresses);
        for (dst, src) in self.values[k + g + p..].chunks_exact_mut(4).zip(&self.ends) {
            dst.copy_from_slice(src);
        }
        let b = k + g + p + 4 * self.ends.len();
        for (dst, pose) in self.values[b..].chunks_exact_mut(6).zip(poses) {
            dst[..3].copy_from_slice(&pose.centre);
            for (d, a) in dst[3..].iter_mut().zip(pose.angles) {
                *d = a.to_degrees();
            }
        }
        self.add(state.t);
    }

    /// Folds `self.values` at time `t` into the extremes.
    fn add(&mut self, t: f64) {
        if self.provisional {
            self.reset();
        }
        for (i, &v) in self.values.iter().enumerate() {
            // + 0.0 turns −0 into 0.
            let v = v + 0.0;
            if v > self.max[i] {
                self.max[i] = v;
                self.t_max[i] = t;
            }
            if v < self.min[i] {
                self.min[i] = v;
                self.t_min[i] = t;
            }
        }
        self.states += 1;
    }

    fn reset(&mut self) {
        self.max.fill(f64::NEG_INFINITY);
        self.min.fill(f64::INFINITY);
        self.t_max.fill(f64::NAN);
        self.t_min.fill(f64::NAN);
        self.states = 0;
        self.provisional = false;
    }

    /// Marks the states observed so far (a static equilibrium) as standing only until the next
    /// state is observed.
    pub fn until_next(&mut self) {
        self.provisional = true;
    }

    /// States the extremes are taken over.
    pub fn states(&self) -> usize {
        self.states
    }

    /// Column names.
    pub fn column_names(&self) -> &[String] {
        &self.columns
    }

    /// The extremes of every column (empty before any state was observed).
    pub fn table(&self) -> Vec<(&str, Extreme)> {
        if self.states == 0 {
            return Vec::new();
        }
        self.columns
            .iter()
            .enumerate()
            .map(|(i, c)| {
                (
                    c.as_str(),
                    Extreme {
                        max: self.max[i],
                        t_max: self.t_max[i],
                        min: self.min[i],
                        t_min: self.t_min[i],
                    },
                )
            })
            .collect()
    }

    /// The extremes of one column.
    pub fn get(&self, column: &str) -> Option<Extreme> {
        self.table()
            .into_iter()
            .find(|(c, _)| *c == column)
            .map(|(_, e)| e)
    }

    /// `run.json`'s `extremes` object: {column: {max, t_max, min, t_min}}, in column order.
    pub fn to_json(&self) -> serde_json::Value {
        let mut map = serde_json::Map::new();
        for (c, e) in self.table() {
            map.insert(c.to_string(), serde_json::json!(e));
        }
        serde_json::Value::Object(map)
    }

    /// `extremes.csv`: a header `column,max,t_max,min,t_min` and one row per column (numbers
    /// written so that they read back exactly).
    pub fn csv(&self) -> String {
        let mut s = String::from("column,max,t_max,min,t_min\n");
        for (c, e) in self.table() {
            s.push_str(&format!(
                "{},{},{},{},{}\n",
                crate::csv::csv_field(c),
                e.max,
                e.t_max,
                e.min,
                e.t_min
            ));
        }
        s
    }
}

/// Extremes read back from a run folder: `extremes.csv`, else `run.json`'s `extremes`; `None`
/// for a run written before they existed (or with no state).
pub fn read_extremes(dir: &std::path::Path) -> Option<BTreeMap<String, Extreme>> {
    if let Ok(text) = std::fs::read_to_string(dir.join("extremes.csv")) {
        let mut map = BTreeMap::new();
        for line in text.lines().skip(1) {
            // Column names hold no commas (summary.csv replaces them), so a plain split works.
            let f: Vec<&str> = line.split(',').collect();
            let [c, max, t_max, min, t_min] = f[..] else {
                return None;
            };
            let num = |s: &str| s.parse::<f64>().ok();
            map.insert(
                c.to_string(),
                Extreme {
                    max: num(max)?,
                    t_max: num(t_max)?,
                    min: num(min)?,
                    t_min: num(t_min)?,
                },
            );
        }
        return (!map.is_empty()).then_some(map);
    }
    let text = std::fs::read_to_string(dir.join("run.json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    let obj = json.get("extremes")?.as_object()?;
    let mut map = BTreeMap::new();
    for (c, e) in obj {
        let num = |k: &str| e.get(k).and_then(|v| v.as_f64());
        map.insert(
            c.clone(),
            Extreme {
                max: num("max")?,
                t_max: num("t_max")?,
                min: num("min")?,
                t_min: num("t_min")?,
            },
        );
    }
    (!map.is_empty()).then_some(map)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Result;
    use crate::{Frame, Observer, PrepareOptions, RunRecord, Simulation, prepare};
    use std::path::Path;

    /// A line shorter than its 109.7 m chord: taut throughout.
    const TAUT: f64 = 108.0;

    /// A 10-segment chain of `length` [m] (120: slack, lying partly on the seabed) whose
    /// fairlead is surged ±1 m (heaved ±0.3 m) at a 2 s period, run for 3 s at `dt` [s] with
    /// `scheme` and output every `output_interval` [s]: its record and the summary rows of the
    /// dynamic part (the static row left out), with their column names.
    fn run_line(
        length: f64,
        scheme: &str,
        dt: f64,
        output_interval: f64,
    ) -> (RunRecord, Vec<String>, Vec<Vec<f64>>) {
        let text = format!(
            r#"
            name = "chain"
            [sea]
            depth = 50.0
            [[line]]
            name = "chain"
            anchor = [0.0, 0.0, -50.0]
            fairlead = [100.0, 0.0, -5.0]
            length = {length}
            segments = 10
            diameter = 0.1354
            mass_per_length = 113.0
            ea = 5.4e7
            [[prescribed]]
            nodes = "chain/fairlead"
            motion = "sine"
            amplitude = [1.0, 0.0, 0.3]
            period = 2.0
            ramp_time = 0.5
            [analysis]
            kind = "static+dynamic"
            [analysis.dynamic]
            scheme = "{scheme}"
            dt = {dt}
            t_end = 3.0
            output_interval = {output_interval}
        "#
        );
        let scene = crate::scene::read_scene(
            crate::scene::SceneInput::Text {
                text: &text,
                path: Path::new("chain.toml"),
            },
            &[],
        )
        .unwrap();
        let prep = prepare(PrepareOptions::scene(scene)).unwrap();
        struct Rows(Vec<Vec<f64>>);
        impl Observer for Rows {
            fn frame(&mut self, f: &Frame<'_>) -> Result<()> {
                self.0.push(f.row.values());
                Ok(())
            }
        }
        let mut rows = Rows(Vec::new());
        let (record, result) = Simulation::new(&prep).unwrap().run(&mut rows);
        result.unwrap();
        let mut rows = rows.0;
        rows.remove(0); // the static equilibrium
        (record, SummaryRow::columns(&prep.built), rows)
    }

    /// Largest and smallest value of a column over the rows, with the time of each; `F_net`
    /// and `R` are the magnitudes of their components.
    fn sampled(columns: &[String], rows: &[Vec<f64>], column: &str) -> Extreme {
        let at = |name: &str| columns.iter().position(|c| c == name).unwrap();
        let value = |r: &Vec<f64>| match column {
            "F_net" | "R" => {
                let names: [&str; 3] = if column == "R" {
                    ["Rx", "Ry", "Rz"]
                } else {
                    ["Fx_net", "Fy_net", "Fz_net"]
                };
                names.iter().map(|n| r[at(n)].powi(2)).sum::<f64>().sqrt()
            }
            c => r[at(c)] + 0.0,
        };
        let t = at("t");
        let mut e = Extreme {
            max: f64::NEG_INFINITY,
            t_max: f64::NAN,
            min: f64::INFINITY,
            t_min: f64::NAN,
        };
        for r in rows {
            let v = value(r);
            if v > e.max {
                (e.max, e.t_max) = (v, r[t]);
            }
            if v < e.min {
                (e.min, e.t_min) = (v, r[t]);
            }
        }
        e
    }

    #[test]
    fn every_step_extremes_bound_the_sampled_ones_and_equal_them_when_every_step_is_sampled() {
        // Every step an output step (a taut line: the midpoint rule keeps its step): the
        // extremes are those of the summary rows, exactly, times included.
        let (record, columns, rows) = run_line(TAUT, "midpoint", 0.02, 0.02);
        let extremes = record.extremes.as_ref().unwrap();
        assert_eq!(rows.len(), 150, "one row per step of 0.02 s over 3 s");
        assert_eq!(
            extremes.states(),
            150,
            "every accepted step, not the static state"
        );
        let table = extremes.table();
        assert_eq!(
            table.len(),
            FORCE_COLUMNS.len() + 1 + 4,
            "forces, one group, one line"
        );
        for (c, e) in &table {
            assert_eq!(*e, sampled(&columns, &rows, c), "{c}");
        }
        // Output every 0.3 s: the sampled extremes lie within the per-step ones, on the taut
        // line and on the slack chain, whose snaps make the midpoint rule halve steps (the
        // halved steps count too).
        for length in [TAUT, 120.0] {
            let (coarse, columns, rows) = run_line(length, "midpoint", 0.02, 0.3);
            assert_eq!(rows.len(), 10);
            let per_step = coarse.extremes.as_ref().unwrap();
            assert_eq!(per_step.states(), coarse.steps, "{length}");
            assert!(coarse.steps >= 150, "{length}: {} steps", coarse.steps);
            for (c, e) in per_step.table() {
                let s = sampled(&columns, &rows, c);
                assert!(
                    e.max >= s.max && e.min <= s.min,
                    "{length} {c}: {e:?} vs sampled {s:?}"
                );
            }
        }
    }

    #[test]
    fn a_peak_between_output_steps_is_kept_with_its_time() {
        let (_, dense_columns, dense_rows) = run_line(TAUT, "midpoint", 0.02, 0.02);
        let (coarse, columns, rows) = run_line(TAUT, "midpoint", 0.02, 0.3);
        for c in ["chain_fairlead_element_tension", "R"] {
            let per_step = coarse.extremes.as_ref().unwrap().get(c).unwrap();
            let every_step_sampled = sampled(&dense_columns, &dense_rows, c);
            let coarse_sampled = sampled(&columns, &rows, c);
            // The peak falls between the coarse output steps ...
            assert!(
                per_step.max > coarse_sampled.max * 1.01,
                "{c}: per step {per_step:?}, sampled {coarse_sampled:?}"
            );
            // ... and is the one a run writing every step sees, at the same time (the steps
            // are the same: the output times lie on the step grid; landing on them rounds the
            // step times differently, hence the round-off tolerance).
            let d = every_step_sampled;
            assert!(
                (per_step.max - d.max).abs() <= 1e-8 * d.max.abs()
                    && (per_step.min - d.min).abs() <= 1e-8 * d.max.abs()
                    && (per_step.t_max - d.t_max).abs() < 1e-9
                    && (per_step.t_min - d.t_min).abs() < 1e-9,
                "{c}: {per_step:?} vs every step sampled {d:?}"
            );
        }
    }

    #[test]
    fn csv_and_json_read_back_to_the_same_extremes() {
        let (record, _, _) = run_line(120.0, "midpoint", 0.02, 0.3);
        let e = record.extremes.unwrap();
        let dir = std::env::temp_dir().join(format!("aqua-extremes-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("extremes.csv"), e.csv()).unwrap();
        let from_csv = read_extremes(&dir).unwrap();
        std::fs::remove_file(dir.join("extremes.csv")).unwrap();
        let json = serde_json::json!({ "extremes": e.to_json() });
        std::fs::write(dir.join("run.json"), json.to_string()).unwrap();
        let from_json = read_extremes(&dir).unwrap();
        // The CSV reads back exactly; serde_json's parser may be off by an ulp.
        let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs());
        assert_eq!(from_json.len(), e.table().len());
        for (c, x) in e.table() {
            assert_eq!(from_csv[c], x, "{c}");
            let j = from_json[c];
            assert!(
                close(j.max, x.max)
                    && close(j.t_max, x.t_max)
                    && close(j.min, x.min)
                    && close(j.t_min, x.t_min),
                "{c}: {j:?} vs {x:?}"
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
