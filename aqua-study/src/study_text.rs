//! The text form of a [`Study`] (`aqua study`): one row per run (setting, status, wall time,
//! size, its largest error), one row per metric (estimate, finest run, method, observed orders)
//! and the recommendation (docs/guide/study-and-sweep.md#choosing-resolution-aqua-study).

use crate::study::Study;
use std::fmt::Write as _;

impl Study {
    /// The study as text: the runs, the estimates and the recommended run.
    pub fn to_text(&self) -> String {
        let s = self;
        let mut o = String::new();
        let axes: Vec<&str> = s.axes.iter().map(|a| a.path.as_str()).collect();
        let _ = writeln!(
            o,
            "{:>4}  {:<28} {:>11} {:>9} {:>7} {:>7}  {:>14}  worst metric",
            "run",
            axes.join(" / "),
            "status",
            "wall [s]",
            "DOFs",
            "steps",
            "largest error"
        );
        for r in &s.runs {
            let worst = r
                .errors
                .iter()
                .enumerate()
                .filter_map(|(k, e)| e.map(|e| (k, e)))
                .max_by(|a, b| a.1.total_cmp(&b.1));
            let mark = if s.recommended == Some(r.index) {
                "  <- recommended"
            } else {
                ""
            };
            let _ = writeln!(
                o,
                "{:>4}  {:<28} {:>11} {:>9.3} {:>7} {:>7}  {:>14}  {}{mark}",
                r.index,
                r.setting.join(" / "),
                r.status,
                r.wall_s,
                r.dofs,
                r.steps,
                worst
                    .map(|(_, e)| format!("{:.3e}", e))
                    .unwrap_or_else(|| "-".into()),
                worst.map(|(k, _)| s.metrics[k].as_str()).unwrap_or(""),
            );
            if let Some(reason) = &r.reason {
                let _ = writeln!(o, "      reason: {reason}");
            }
        }
        let _ = writeln!(o);
        let _ = writeln!(
            o,
            "{:<40} {:>17} {:>17}  {:<11} observed order per ladder ({})",
            "metric",
            "estimate",
            "finest run",
            "method",
            axes.join(", ")
        );
        for e in &s.estimates {
            let orders: Vec<String> = e
                .orders
                .iter()
                .zip(&e.notes)
                .map(|(p, note)| match (p, note) {
                    (Some(p), _) => format!("{p:.3}"),
                    (None, Some(n)) => format!("- ({n})"),
                    (None, None) => "-".into(),
                })
                .collect();
            let fmt = |v: Option<f64>| v.map(|v| format!("{v:.10e}")).unwrap_or("-".into());
            let _ = writeln!(
                o,
                "{:<40} {:>17} {:>17}  {:<11} {}{}",
                e.metric,
                fmt(e.value),
                fmt(e.finest),
                e.method,
                orders.join("; "),
                if e.negligible {
                    " (negligible: not used)"
                } else {
                    ""
                }
            );
        }
        let _ = writeln!(o);
        if s.estimates.iter().any(|e| e.value.is_none()) {
            let _ = writeln!(
                o,
                "no estimate for some metrics (the reference run, the last value of every ladder, \
             did not complete): nothing can be recommended"
            );
            return o;
        }
        if s.estimates.iter().all(|e| e.method != "richardson") {
            let _ = writeln!(
                o,
                "note: no ladder could be extrapolated, so errors are measured against the finest \
             run, whose own error is unknown; give three geometric values (e.g. 10,5,2.5) to \
             estimate it"
            );
        }
        let _ = match s
            .recommended
            .and_then(|i| s.runs.iter().find(|r| r.index == i))
        {
            Some(r) => writeln!(
                o,
                "recommended: run {} ({}) — {:.3} s, every metric within {} % of its estimate",
                r.index,
                s.axes
                    .iter()
                    .zip(&r.setting)
                    .map(|(a, v)| format!("{}={v}", a.path))
                    .collect::<Vec<_>>()
                    .join(" "),
                r.wall_s,
                100.0 * s.tolerance
            ),
            None => writeln!(
                o,
                "no run has every metric within {} % of its estimate: refine the ladders",
                100.0 * s.tolerance
            ),
        };
        o
    }
}
