//! What `aqua run` says about a finished run: the step-control note, the final summary and
//! the interruption line, as text from the [`RunRecord`] and the [`Written`] files
//! (docs/theory/fem.md#step-control).

use crate::run::RunRecord;
use crate::run_scene::Written;

impl RunRecord {
    /// How often the step control halved the step, and why; `None` when it never did.
    pub fn step_control_note(&self) -> Option<String> {
        let c = self.step_control.as_ref()?;
        if c.halvings == 0 {
            return None;
        }
        let reasons: Vec<String> = c
            .reasons
            .iter()
            .map(|(why, n)| format!("{n}× {why}"))
            .collect();
        Some(format!(
            "note: the time step was halved {} times (smallest {:.3e} s; {}) and grown back {} \
             times; run.json lists them under step_control",
            c.halvings,
            c.smallest_dt,
            reasons.join(", "),
            c.regrowths
        ))
    }

    /// The final summary of a completed run: the last state's loads (if any) and the files,
    /// wall time and per-step cost, one line each.
    pub fn final_text(&self, files: &Written) -> String {
        let mut s = String::new();
        if let Some(last) = &self.last {
            s += &format!(
                "done: t = {} s, net force = [{:.1}, {:.1}, {:.1}] N, reaction = [{:.1}, {:.1}, {:.1}] N, volume ratio {}\n",
                last.t,
                last.net_force[0],
                last.net_force[1],
                last.net_force[2],
                last.reaction[0],
                last.reaction[1],
                last.reaction[2],
                // The ratio is 0 only where there is no enclosed volume to compare with.
                if last.volume_ratio > 0.0 {
                    format!("{:.4}", last.volume_ratio)
                } else {
                    "n/a (no closed net)".to_string()
                }
            );
        }
        s += &format!(
            "{} output steps in {}; wall time {:.2} s{}\n",
            files.steps,
            files.dir.display(),
            self.wall,
            if self.steps > 0 {
                format!(
                    ", {} dynamic steps, {:.2} ms per step, {:.2} Newton iterations per step",
                    self.steps,
                    1e3 * self.dyn_wall / self.steps as f64,
                    self.iterations as f64 / self.steps as f64
                )
            } else {
                String::new()
            }
        );
        s
    }

    /// The line of an interrupted run: where it stopped, whether step 0 is an equilibrium,
    /// and what was kept.
    pub fn interrupted_text(&self, files: &Written) -> String {
        let partial = match (self.static_converged, self.static_load_factor) {
            (Some(false), Some(s)) => {
                let load = if s < 1.0 {
                    format!(" at load factor {s:.4}, not the full load")
                } else {
                    String::new()
                };
                format!(
                    " (step 0 is the last static iterate{load}: NOT converged, \
                     ||r|| = {:.2e}·F_ref; not an equilibrium)",
                    self.static_relative_residual.unwrap_or(f64::NAN)
                )
            }
            _ => String::new(),
        };
        format!(
            "interrupted at t = {} s{partial}: {} output steps kept in {}",
            self.last.as_ref().map(|r| r.t).unwrap_or(0.0),
            files.steps,
            files.pvd.display()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use aqua_fem::dynamics::StepControl;

    fn files() -> Written {
        Written {
            dir: "out".into(),
            pvd: "out/s.pvd".into(),
            steps: 5,
        }
    }

    #[test]
    fn per_step_cost_is_wall_time_over_steps() {
        let r = RunRecord {
            wall: 3.0,
            dyn_wall: 2.0,
            steps: 400,
            iterations: 1000,
            ..Default::default()
        };
        // 2 s / 400 steps = 5 ms; 1000 / 400 = 2.5 iterations.
        assert_eq!(
            r.final_text(&files()),
            "5 output steps in out; wall time 3.00 s, 400 dynamic steps, 5.00 ms per step, \
             2.50 Newton iterations per step\n"
        );
        assert_eq!(r.step_control_note(), None);
    }

    #[test]
    fn interruption_says_when_step_0_is_not_an_equilibrium() {
        let r = RunRecord {
            static_converged: Some(false),
            static_load_factor: Some(0.5),
            static_relative_residual: Some(0.01),
            ..Default::default()
        };
        let t = r.interrupted_text(&files());
        assert!(t.starts_with("interrupted at t = 0 s (step 0"), "{t}");
        assert!(
            t.contains("load factor 0.5000") && t.contains("1.00e-2"),
            "{t}"
        );
        assert!(t.ends_with("5 output steps kept in out/s.pvd"), "{t}");
        let r = RunRecord {
            step_control: Some(StepControl {
                halvings: 3,
                regrowths: 2,
                smallest_dt: 0.0125,
                ..Default::default()
            }),
            ..Default::default()
        };
        let n = r.step_control_note().unwrap();
        assert!(n.contains("halved 3 times (smallest 1.250e-2 s; )"), "{n}");
        assert!(n.contains("grown back 2 times"), "{n}");
    }
}
