//! Pictures of a run and of a study, as PNG files drawn in pure Rust (plotters' bitmap backend,
//! text with the Hack font embedded by `epaint_default_fonts`: no C library, no system fonts).
//!
//! [`plot_run`] draws the time series of a run folder's `summary.csv` (net force and
//! reactions, largest tension per group, volume ratio, line-end loads) and the static solver's
//! convergence from `run.json`; the tension and line-end pictures mark each curve's largest
//! value over every accepted step (`extremes.csv`, with its value and time), which a peak
//! between output steps puts above the curve; [`plot_study`] draws a study's error against its cost. Each
//! function returns what it plotted (the series' extremes), so tests compare the plotted data,
//! not pixels, with the tables.

use crate::study::Study;
use aqua_sim::extremes::read_extremes;
use aqua_sim::{Result, SimError};
use plotters::coord::combinators::IntoLogRange;
use plotters::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// Width and height of every picture [px].
pub const SIZE: (u32, u32) = (1200, 720);

/// One plotted curve.
#[derive(Debug, Clone, Serialize)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// (x, y) points.
    #[serde(skip)]
    pub points: Vec<(f64, f64)>,
    /// Smallest y plotted.
    pub min: f64,
    /// Largest y plotted (incl. the marked peak).
    pub max: f64,
    /// The largest value over every accepted step and its time (t, y), marked on the picture
    /// when it is known (`extremes.csv`): between output steps it is above the curve.
    pub peak: Option<(f64, f64)>,
}

impl Series {
    /// A series with its extremes.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        let min = points.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let max = points.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
        Series {
            name: name.into(),
            points,
            min,
            max,
            peak: None,
        }
    }

    /// The series with its largest value over every step (`t` [s], `value`) marked.
    pub fn with_peak(mut self, t: f64, value: f64) -> Self {
        if t.is_finite() && value.is_finite() {
            self.peak = Some((t, value));
            self.max = self.max.max(value);
        }
        self
    }
}

/// A force or tension as a label: kN from 1 kN, else N.
fn force_text(v: f64) -> String {
    if v.abs() >= 1e3 {
        format!("{:.2} kN", v / 1e3)
    } else {
        format!("{v:.2} N")
    }
}

/// A label of a log axis: only the ticks at 1, 2 and 5 times a power of ten are named (the
/// others stay as unlabelled ticks, so that the labels of a decade do not run into each
/// other), in compact form: 500, 2k, 20k, 1M, 0.05.
fn log_tick_text(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return String::new();
    }
    let mut decade = 10f64.powf(v.log10().floor());
    if (v / decade).round() >= 10.0 {
        decade *= 10.0;
    }
    let mantissa = (v / decade).round();
    if ![1.0, 2.0, 5.0].contains(&mantissa) || (v / decade - mantissa).abs() > 1e-6 * mantissa {
        return String::new();
    }
    let trim = |x: f64| {
        let t = format!("{x:.3}");
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    };
    if v >= 1e6 {
        format!("{}M", trim(v / 1e6))
    } else if v >= 1e3 {
        format!("{}k", trim(v / 1e3))
    } else {
        trim(v)
    }
}

/// A picture written.
#[derive(Debug, Clone, Serialize)]
pub struct Picture {
    /// The PNG file.
    pub path: PathBuf,
    /// Its title.
    pub title: String,
    /// What it shows.
    pub series: Vec<Series>,
}

fn font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is valid TTF; if it were not, text would be missing, not wrong.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            epaint_default_fonts::HACK_REGULAR,
        );
    });
}

fn plot_err(path: &Path) -> impl Fn(String) -> SimError + '_ {
    move |message| SimError::Plot {
        path: path.to_path_buf(),
        message,
    }
}

/// Axis range with a margin; a flat series gets a band around its value.
fn range(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    if span <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
        let pad = 0.05 * lo.abs().max(1.0);
        return (lo - pad, hi + pad);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

/// The title's font size: smaller for a long title (a long scene name), so it fits the width.
fn caption_size(title: &str) -> u32 {
    if title.chars().count() > 64 { 20 } else { 26 }
}

/// Most curves in one time-series picture (the legend must fit above them); a group with more
/// shows those with the largest peaks.
const MAX_CURVES: usize = 8;

/// Fraction of a chart's plotting height that a legend of `n` rows takes (16 px font: about
/// 21 px per row and 26 px of box and margin, in a plotting area of about 560 px of `SIZE`).
fn legend_fraction(n: usize) -> f64 {
    ((21 * n + 26) as f64 / 560.0).min(0.6)
}

/// A line chart of `series` against x, linear axes, legend top right above the curves.
pub fn line_chart(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: Vec<Series>,
) -> Result<Picture> {
    font();
    let err = plot_err(path);
    let pts = || series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = range(
        pts().map(|p| p.0).fold(f64::INFINITY, f64::min),
        pts().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max),
    );
    let (y0, y1) = range(
        series.iter().map(|s| s.min).fold(f64::INFINITY, f64::min),
        series
            .iter()
            .map(|s| s.max)
            .fold(f64::NEG_INFINITY, f64::max),
    );
    // Room above the curves for the legend, so that it covers none of them.
    let y1 = y0 + (y1 - y0) / (1.0 - legend_fraction(series.len()));
    {
        let root = BitMapBackend::new(path, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", caption_size(title)))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(110)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        for (i, s) in series.iter().enumerate() {
            let color = Palette99::pick(i).to_rgba();
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().copied(),
                    color.stroke_width(2),
                ))
                .map_err(|e| err(e.to_string()))?
                .label(s.name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
                });
        }
        // The largest value over every step: a triangle in the series' colour, its value and
        // time beside it.
        for (i, s) in series.iter().enumerate() {
            let Some((t, v)) = s.peak else { continue };
            let color = Palette99::pick(i).to_rgba();
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((t, v))
                        + TriangleMarker::new((0, 0), 7, color.filled())
                        + Text::new(
                            format!("max {} at t = {t:.2} s", force_text(v)),
                            (10, -16),
                            ("sans-serif", 14),
                        ),
                ))
                .map_err(|e| err(e.to_string()))?;
        }
        finish(&mut chart, &root, &err)?;
    }
    Ok(Picture {
        path: path.to_path_buf(),
        title: title.to_string(),
        series,
    })
}

/// A log–log chart of `series` (lines through markers), with an optional dashed guide of slope
/// `guide` through the first point of the first series; legend top left.
pub fn loglog_chart(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: Vec<Series>,
    guide: Option<f64>,
) -> Result<Picture> {
    font();
    let err = plot_err(path);
    let pts = || {
        series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
    };
    let (x0, x1) = (
        pts().map(|p| p.0).fold(f64::INFINITY, f64::min) / 1.5,
        pts().map(|p| p.0).fold(0.0, f64::max) * 1.5,
    );
    let (y0, y1) = (
        pts().map(|p| p.1).fold(f64::INFINITY, f64::min) / 2.0,
        pts().map(|p| p.1).fold(0.0, f64::max) * 2.0,
    );
    if !(x0.is_finite() && y0.is_finite() && x1 > x0 && y1 > y0) {
        return Err(err("no positive points to draw on log axes".into()));
    }
    {
        let root = BitMapBackend::new(path, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", caption_size(title)))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(110)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .x_label_formatter(&|v| log_tick_text(*v))
            .y_label_formatter(&|v| log_tick_text(*v))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        if let (Some(slope), Some(&(xa, ya))) =
            (guide, series.first().and_then(|s| s.points.first()))
        {
            let line: Vec<(f64, f64)> = [x0, x1]
                .iter()
                .map(|&x| (x, ya * (x / xa).powf(slope)))
                .collect();
            chart
                .draw_series(DashedLineSeries::new(line, 8, 6, BLACK.stroke_width(1)))
                .map_err(|e| err(e.to_string()))?
                .label(format!("slope {slope}"))
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], BLACK));
        }
        for (i, s) in series.iter().enumerate() {
            let color = Palette99::pick(i).to_rgba();
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().copied(),
                    color.stroke_width(2),
                ))
                .map_err(|e| err(e.to_string()))?
                .label(s.name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
                });
            chart
                .draw_series(s.points.iter().map(|&p| Circle::new(p, 5, color.filled())))
                .map_err(|e| err(e.to_string()))?;
        }
        finish_at(&mut chart, &root, &err, SeriesLabelPosition::UpperLeft)?;
    }
    Ok(Picture {
        path: path.to_path_buf(),
        title: title.to_string(),
        series,
    })
}

/// Draws the legend (top right) and writes the picture.
fn finish<'a, X, Y>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, Cartesian2d<X, Y>>,
    root: &DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>,
    err: &dyn Fn(String) -> SimError,
) -> Result<()>
where
    X: plotters::coord::ranged1d::Ranged,
    Y: plotters::coord::ranged1d::Ranged,
{
    finish_at(chart, root, err, SeriesLabelPosition::UpperRight)
}

/// Draws the legend at `at` and writes the picture.
fn finish_at<'a, X, Y>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, Cartesian2d<X, Y>>,
    root: &DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>,
    err: &dyn Fn(String) -> SimError,
    at: SeriesLabelPosition,
) -> Result<()>
where
    X: plotters::coord::ranged1d::Ranged,
    Y: plotters::coord::ranged1d::Ranged,
{
    chart
        .configure_series_labels()
        .position(at)
        .label_font(("sans-serif", 16))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(e.to_string()))?;
    root.present().map_err(|e| err(e.to_string()))
}

/// A run folder's `summary.csv` read back: column names and rows.
#[derive(Debug, Clone, Default)]
pub struct SummaryTable {
    /// Column names.
    pub columns: Vec<String>,
    /// Rows.
    pub rows: Vec<Vec<f64>>,
}

impl SummaryTable {
    /// Reads `summary.csv`.
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|source| SimError::Io {
            what: "reading",
            path: path.to_path_buf(),
            source,
        })?;
        let mut lines = text.lines();
        let columns: Vec<String> = lines
            .next()
            .unwrap_or_default()
            .split(',')
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for (k, line) in lines.enumerate() {
            let row: Option<Vec<f64>> = line.split(',').map(|v| v.parse().ok()).collect();
            match row {
                Some(r) if r.len() == columns.len() => rows.push(r),
                _ => {
                    return Err(SimError::input(format!(
                        "{}: line {}: expected {} numbers separated by commas",
                        path.display(),
                        k + 2,
                        columns.len()
                    )));
                }
            }
        }
        Ok(SummaryTable { columns, rows })
    }

    /// The (t, column) points of a column.
    pub fn series(&self, column: &str) -> Option<Series> {
        let t = self.columns.iter().position(|c| c == "t")?;
        let k = self.columns.iter().position(|c| c == column)?;
        Some(Series::new(
            column,
            self.rows.iter().map(|r| (r[t], r[k])).collect(),
        ))
    }

    fn matching(&self, keep: impl Fn(&str) -> bool) -> Vec<Series> {
        self.columns
            .iter()
            .filter(|c| keep(c))
            .filter_map(|c| self.series(c))
            .collect()
    }
}

/// A time-series picture: file, title, y label and which columns it shows.
type TimePicture = (&'static str, &'static str, &'static str, fn(&str) -> bool);

/// Draws the pictures of a run folder into `dir/plots/` and returns them: time series when the
/// run has more than one output step, the static convergence when `run.json` records one.
pub fn plot_run(dir: &Path) -> Result<Vec<Picture>> {
    if !dir.join("summary.csv").is_file() {
        return Err(SimError::input(format!(
            "{}: no summary.csv: give the output folder of `aqua run` (its --out)",
            dir.display()
        )));
    }
    let table = SummaryTable::read(&dir.join("summary.csv"))?;
    let out = dir.join("plots");
    std::fs::create_dir_all(&out).map_err(|source| SimError::Io {
        what: "creating",
        path: out.clone(),
        source,
    })?;
    let scene = scene_name(dir);
    let mut pictures = Vec::new();
    if table.rows.len() > 1 {
        let groups: [TimePicture; 4] = [
            (
                "forces.png",
                // Fx_net … is the whole water load on the nets (post::net_force): drag, lift
                // and, in Fz_net, the twines' buoyancy.
                "Water load on the nets (drag, lift, twine buoyancy), support reactions",
                "force [N]",
                |c| c.ends_with("_net") || matches!(c, "Rx" | "Ry" | "Rz"),
            ),
            (
                "tensions.png",
                "Largest tension per group",
                "tension [N]",
                |c| c.starts_with("Tmax_"),
            ),
            (
                "line_ends.png",
                "Line-end loads (anchor reaction, fairlead tension)",
                "force [N]",
                // The fairlead's element tension, not its reaction: a fairlead attached to a
                // collar or plate has no reaction (the column is 0), only a line tension.
                |c| c.ends_with("_anchor_reaction") || c.ends_with("_fairlead_element_tension"),
            ),
            (
                "volume.png",
                "Enclosed net volume relative to the undeformed net",
                "volume ratio [-]",
                |c| c == "volume_ratio",
            ),
        ];
        // The largest values over every accepted step, where the run wrote them.
        let extremes = read_extremes(dir).unwrap_or_default();
        for (file, title, y, keep) in groups {
            let mut series = table.matching(keep);
            if matches!(file, "tensions.png" | "line_ends.png") {
                series = series
                    .into_iter()
                    .map(|s| match extremes.get(&s.name) {
                        Some(e) => s.with_peak(e.t_max, e.max),
                        None => s,
                    })
                    .collect();
            }
            if file == "volume.png" {
                // An open net (no enclosed volume) has nothing to show.
                series.retain(|s| s.max > 0.0);
            }
            if series.is_empty() {
                continue;
            }
            let title = if series.len() > MAX_CURVES {
                // A farm has dozens of line ends: draw the most loaded, say how many there are.
                let n = series.len();
                series.sort_by(|a, b| b.max.total_cmp(&a.max));
                series.truncate(MAX_CURVES);
                format!("{scene}: {title}: the {MAX_CURVES} largest of {n}")
            } else {
                format!("{scene}: {title}")
            };
            pictures.push(line_chart(
                &out.join(file),
                &title,
                "time t [s]",
                y,
                series,
            )?);
        }
    }
    if let Some(history) = static_history(&dir.join("run.json")) {
        let s = Series::new(
            "‖r‖ / F_ref",
            history
                .iter()
                .enumerate()
                .map(|(i, r)| (i as f64, *r))
                .filter(|p| p.1 > 0.0)
                .collect(),
        );
        if s.points.len() > 1 {
            pictures.push(log_y_chart(
                &out.join("static_convergence.png"),
                &format!("{scene}: static solver, relative residual per Newton iteration"),
                "iteration",
                "relative residual [-]",
                s,
            )?);
        }
    }
    Ok(pictures)
}

/// The scene's name (`run.json`'s `scene.name`), else the folder's name: every picture's title
/// starts with it.
fn scene_name(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("run.json"))
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
        .and_then(|v| v["scene"]["name"].as_str().map(str::to_string))
        .unwrap_or_else(|| {
            let abs = std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf());
            abs.file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
        })
}

fn static_history(path: &Path) -> Option<Vec<f64>> {
    let text = std::fs::read_to_string(path).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    v.get("static_residual_history")?
        .as_array()?
        .iter()
        .map(|x| x.as_f64())
        .collect()
}

/// One series on a logarithmic y axis.
fn log_y_chart(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    s: Series,
) -> Result<Picture> {
    font();
    let err = plot_err(path);
    let x1 = s.points.iter().map(|p| p.0).fold(1.0, f64::max);
    let (y0, y1) = (s.min * 0.5, s.max * 2.0);
    {
        let root = BitMapBackend::new(path, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", caption_size(title)))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(110)
            .build_cartesian_2d(0.0..x1, (y0..y1).log_scale())
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        chart
            .draw_series(LineSeries::new(
                s.points.iter().copied(),
                BLUE.stroke_width(2),
            ))
            .map_err(|e| err(e.to_string()))?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok(Picture {
        path: path.to_path_buf(),
        title: title.to_string(),
        series: vec![s],
    })
}

/// Draws a study's largest relative error over its metrics against the wall time of each run
/// (log–log), the tolerance as a line and the recommended run ringed, into `path`.
pub fn plot_study(study: &Study, path: &Path) -> Result<Picture> {
    font();
    let err = plot_err(path);
    let points: Vec<(f64, f64, String, bool)> = study
        .runs
        .iter()
        .filter_map(|r| {
            let worst = r.errors.iter().flatten().copied().fold(f64::NAN, f64::max);
            (worst.is_finite() && r.wall_s > 0.0).then(|| {
                (
                    r.wall_s,
                    worst.max(1e-12),
                    r.setting.join(", "),
                    study.recommended == Some(r.index),
                )
            })
        })
        .collect();
    let series = Series::new(
        "largest relative error",
        points.iter().map(|p| (p.0, p.1)).collect(),
    );
    let xs = || points.iter().map(|p| p.0);
    let (x0, x1) = (
        xs().fold(f64::INFINITY, f64::min).min(1.0) * 0.5,
        xs().fold(0.0, f64::max).max(1e-3) * 2.0,
    );
    let tol = study.tolerance;
    let y0 = series.min.min(tol).max(1e-12) * 0.3;
    let y1 = series.max.max(tol).max(y0 * 10.0) * 3.0;
    let axes = study
        .axes
        .iter()
        .map(|a| a.path.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    {
        let root = BitMapBackend::new(path, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!("Accuracy against cost ({axes})"),
                ("sans-serif", 24),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(110)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("wall time of the run [s]")
            .y_desc("largest relative error over the metrics [-]")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        chart
            .draw_series(LineSeries::new(
                vec![(x0, tol), (x1, tol)],
                RED.stroke_width(2),
            ))
            .map_err(|e| err(e.to_string()))?
            .label(format!("tolerance {:.3} %", 100.0 * tol))
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], RED.stroke_width(3)));
        chart
            .draw_series(points.iter().map(|(x, y, label, best)| {
                let style = if *best { GREEN.filled() } else { BLUE.filled() };
                EmptyElement::at((*x, *y))
                    + Circle::new((0, 0), if *best { 9 } else { 6 }, style)
                    + Text::new(label.clone(), (10, -8), ("sans-serif", 15))
            }))
            .map_err(|e| err(e.to_string()))?
            .label("run (green: recommended)")
            .legend(|(x, y)| Circle::new((x + 12, y), 6, BLUE.filled()));
        finish(&mut chart, &root, &err)?;
    }
    Ok(Picture {
        path: path.to_path_buf(),
        title: "accuracy against cost".into(),
        series: vec![series],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A log axis names 1, 2 and 5 times a power of ten compactly and leaves the other ticks
    /// of the decade (60 000, 70 000, …, which ran into each other) unnamed.
    #[test]
    fn log_ticks_name_one_two_and_five_of_each_decade() {
        let named: Vec<String> = [
            5_000.0,
            6_000.0,
            10_000.0,
            20_000.0,
            30_000.0,
            50_000.0,
            60_000.0,
            70_000.0,
            99_999.999_999,
            200_000.0,
            2e6,
            0.05,
            0.07,
            500.0,
            1.0,
        ]
        .iter()
        .map(|&v| log_tick_text(v))
        .collect();
        assert_eq!(
            named,
            [
                "5k", "", "10k", "20k", "", "50k", "", "", "100k", "200k", "2M", "0.05", "", "500",
                "1"
            ]
        );
        assert_eq!(log_tick_text(0.0), "");
        assert_eq!(log_tick_text(f64::NAN), "");
    }

    /// A farm-like run folder with more line ends than a legend can hold: the picture keeps
    /// the curves with the largest peaks, says how many there were, leaves the all-zero
    /// reaction columns of attached fairleads out, and puts its legend above the curves.
    #[test]
    fn many_line_ends_keep_the_most_loaded_above_the_legend() {
        let dir = std::env::temp_dir().join(format!("aqua-plot-many-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let n = 12;
        let mut header = vec!["t".to_string()];
        for i in 0..n {
            header.push(format!("l{i}_anchor_reaction"));
            header.push(format!("l{i}_fairlead_reaction"));
            header.push(format!("l{i}_fairlead_element_tension"));
        }
        let mut text = header.join(",") + "\n";
        for k in 0..3 {
            let mut row = vec![format!("{k}")];
            for i in 0..n {
                let peak = 1000.0 * (i + 1) as f64;
                row.push(format!("{}", 0.5 * peak + k as f64));
                row.push("0".into());
                row.push(format!("{}", peak - k as f64));
            }
            text += &(row.join(",") + "\n");
        }
        std::fs::write(dir.join("summary.csv"), text).unwrap();
        std::fs::write(dir.join("run.json"), r#"{"scene": {"name": "many-lines"}}"#).unwrap();
        let pictures = plot_run(&dir).unwrap();
        let ends = pictures
            .iter()
            .find(|p| p.path.ends_with("line_ends.png"))
            .unwrap();
        assert!(
            ends.title.starts_with("many-lines: ") && ends.title.ends_with("the 8 largest of 24"),
            "{}",
            ends.title
        );
        assert_eq!(ends.series.len(), MAX_CURVES);
        // Largest peaks first: the fairlead tensions of lines 11, 10, … then anchor reactions.
        let peaks: Vec<f64> = ends.series.iter().map(|s| s.max).collect();
        assert!(peaks.windows(2).all(|w| w[0] >= w[1]), "{peaks:?}");
        assert_eq!(ends.series[0].name, "l11_fairlead_element_tension");
        assert!(
            ends.series
                .iter()
                .all(|s| !s.name.ends_with("_fairlead_reaction"))
        );
        // Legend room: 8 rows of legend leave the curves at least half of the y range.
        assert!(legend_fraction(MAX_CURVES) < 0.5);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
