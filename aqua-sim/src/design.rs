//! Design warnings (docs/theory/farm.md#design-warnings): things a scene allows but that are
//! rarely what a designer meant.
//!
//! - `design/taut-line`: a `[[line]]` whose unstretched length is shorter than the distance
//!   between its ends as built (at check and build time): it starts straight and stretched,
//!   with no slack to give compliance.
//! - `design/sunk-float`: a buoy, or a node of a floating pipe, whose top is more than its own
//!   vertical size (a sphere's or pipe's diameter, a cylinder's height) below the still-water
//!   level at static equilibrium.
//! - `design/float-on-seabed`: a buoy or floating pipe whose lowest point touches the seabed
//!   at static equilibrium.
//!
//! - `design/on-seabed`: a net (cage or panel) with nodes resting on the seabed as built or at
//!   static equilibrium (a weight landed on the bed, which then carries it).
//! - In dynamics ([`DynamicWatch`], checked at every accepted step): `design/sunk-float` when
//!   a floater's top went more than its own size under the local water surface η(x, y, t),
//!   `design/float-on-seabed` and `design/on-seabed` when a floater or a net touched the bed;
//!   each reported once per floater or net with the worst value and its time.
//! - `design/buoyant-sinker-tube`: a CCT sinker tube (`bottom_ring`, a sealed pipe) whose
//!   buoyancy, less its own weight, cancels more than half of the sinker weight it carries (at
//!   check and build time; docs/theory/cages.md#frame-ropes-and-weights).
//!
//! - `mesh/coarse-net`: a cage whose net has fewer than 12 nodes around or 2 side segments
//!   (at build time; docs/theory/fem.md#mesh-resolution-warnings).
//! - `mesh/coarse-line`: a `[[line]]` (or a farm's anchor line) that sags at static equilibrium
//!   with fewer segments than the bundled chain's segment ladder needed
//!   (docs/theory/fem.md#mesh-resolution-warnings).
//!
//! A floating pipe is a line group meant to float: buoyant (ρ_w·π·d_v²/4 > μ, d_v its volume
//! diameter, μ its mass per length) and built with every node within one d_v of the still-water
//! level (a collar ring). Buoys marked `submerged = true` are meant to be under water and only
//! checked against the seabed.

use crate::diagnostic::Diagnostic;
use aqua_mesh::{Mesh, Role, Section};
use nalgebra::Point3;

/// Something meant to float: a buoy, or the nodes of a floating pipe group.
#[derive(Debug, Clone, PartialEq)]
pub struct Floater {
    /// What and which: `buoy 'b1'`, `floating pipe 'cage0/top_ring'`.
    pub label: String,
    /// Where (diagnostic location): the buoy or group name.
    pub location: String,
    /// Its nodes.
    pub nodes: Vec<usize>,
    /// Vertical size [m] (sphere or pipe diameter, cylinder height; 0 for a point).
    pub size: f64,
    /// True if it may be under water (only the seabed check applies).
    pub submerged: bool,
}

/// The two ends and unstretched length of a `[[line]]`.
#[derive(Debug, Clone, PartialEq)]
pub struct LineLength {
    /// Line name.
    pub name: String,
    /// Anchor node.
    pub anchor: usize,
    /// Fairlead node.
    pub fairlead: usize,
    /// Sum of its elements' unstretched lengths [m].
    pub unstretched: f64,
    /// Its nodes from anchor to fairlead (empty when its elements do not form one chain).
    pub path: Vec<usize>,
}

/// What the design checks look at, gathered when the model is built.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DesignChecks {
    /// Buoys and floating pipes.
    pub floaters: Vec<Floater>,
    /// Lines.
    pub lines: Vec<LineLength>,
    /// Seabed level z = −depth [m] (`None`: infinite depth).
    pub seabed_z: Option<f64>,
    /// Nodes with a point body (buoys, clump weights, point masses): physical kinks of a line.
    pub kinks: Vec<usize>,
    /// Nets (cages, panels) that should not rest on the seabed: (name, nodes).
    pub nets: Vec<(String, Vec<usize>)>,
}

/// How far above the seabed z_b a node counts as on it [m] (the penalty contact lets a
/// resting body sink a little into the bed).
const ON_BED: f64 = 1e-3;

/// Largest turn between consecutive segments of a line at equilibrium [°] above which the line
/// counts as sagging (docs/theory/fem.md#mesh-resolution-warnings).
pub const SAG_TURN_DEG: f64 = 3.0;

/// Fewest segments of a sagging line before `mesh/coarse-line` warns: on the bundled mooring
/// chain's segment ladder the dynamic minimum tension was 17 / 8.3 / 2.2 / 0.6 % low at 10 / 20 /
/// 40 / 80 segments (docs/theory/fem.md#mesh-resolution-warnings).
pub const MIN_SAGGING_SEGMENTS: usize = 40;

/// The largest angle [°] between consecutive segments along `path` at positions `x`, leaving
/// out the nodes in `kinks` (point bodies: buoys and clump weights kink a line physically).
pub fn largest_turn(path: &[usize], x: &[[f64; 3]], kinks: &[usize]) -> f64 {
    let dir = |a: usize, b: usize| {
        let (p, q) = (x[a], x[b]);
        nalgebra::Vector3::new(q[0] - p[0], q[1] - p[1], q[2] - p[2])
    };
    path.windows(3)
        .filter(|w| w.iter().all(|&n| n < x.len()) && !kinks.contains(&w[1]))
        .map(|w| dir(w[0], w[1]).angle(&dir(w[1], w[2])).to_degrees())
        .filter(|a| a.is_finite())
        .fold(0.0, f64::max)
}

/// Relative margin by which a line must be short of its chord to be called taut (round-off of
/// a line built exactly straight).
const TAUT_MARGIN: f64 = 1e-9;

impl DesignChecks {
    /// `design/taut-line` in the as-built geometry.
    pub fn as_built(&self, nodes: &[Point3<f64>]) -> Vec<Diagnostic> {
        let x: Vec<[f64; 3]> = nodes.iter().map(|p| [p.x, p.y, p.z]).collect();
        let mut d = self.taut_lines(&x, "as built");
        d.extend(self.nets_on_bed(&x, "as built"));
        d
    }

    /// `design/on-seabed` for each net with nodes on the seabed in `x` [m], `when` naming
    /// the state.
    fn nets_on_bed(&self, x: &[[f64; 3]], when: &str) -> Vec<Diagnostic> {
        let Some(zb) = self.seabed_z else {
            return Vec::new();
        };
        self.nets
            .iter()
            .filter_map(|(name, nodes)| {
                let z = nodes.iter().filter_map(|&n| x.get(n)).map(|p| p[2]);
                let on = z.clone().filter(|&z| z <= zb + ON_BED).count();
                let lowest = z.fold(f64::INFINITY, f64::min);
                (on > 0).then(|| {
                    Diagnostic::warning(
                        "design/on-seabed",
                        name,
                        format!(
                            "'{name}' rests on the seabed {when}: {on} of its nodes (lowest at z \
                             = {lowest:.3} m, seabed at z = {zb} m); the bed carries what \
                             hangs there (sinkers, a centre weight) and the net's shape and \
                             loads are not those of a hanging net. Make the net or its weights \
                             shallower, or the sea deeper"
                        ),
                    )
                })
            })
            .collect()
    }

    /// The float checks at a static equilibrium `x` [m]. (A line stretched taut at
    /// equilibrium is not reported: a taut mooring may be the design.)
    pub fn at_equilibrium(&self, x: &[[f64; 3]]) -> Vec<Diagnostic> {
        self.floaters
            .iter()
            .filter_map(|f| self.floater(f, x))
            .chain(self.lines.iter().filter_map(|l| self.coarse_line(l, x)))
            .chain(self.nets_on_bed(x, "at static equilibrium"))
            .collect()
    }

    /// `mesh/coarse-line` for a line that sags (a turn of more than [`SAG_TURN_DEG`] between
    /// segments away from point bodies) with fewer than [`MIN_SAGGING_SEGMENTS`] segments.
    fn coarse_line(&self, l: &LineLength, x: &[[f64; 3]]) -> Option<Diagnostic> {
        let segments = l.path.len().checked_sub(1)?;
        if segments >= MIN_SAGGING_SEGMENTS {
            return None;
        }
        let turn = largest_turn(&l.path, x, &self.kinks);
        (turn > SAG_TURN_DEG).then(|| {
            Diagnostic::warning(
                "mesh/coarse-line",
                &l.name,
                format!(
                    "line '{}' sags (its segments turn by up to {turn:.1}° at equilibrium) and \
                     has {segments} segments: on the bundled mooring chain's segment ladder the \
                     dynamic minimum tension was 8 % low at 20 segments and 2 % at 40 \
                     (docs/theory/fem.md#mesh-resolution-warnings). Refine it to at least \
                     {MIN_SAGGING_SEGMENTS} segments (`segments`, or a farm's \
                     `anchor_segments`), or compare with `aqua study --vary segments=...`",
                    l.name
                ),
            )
        })
    }

    fn taut_lines(&self, x: &[[f64; 3]], when: &str) -> Vec<Diagnostic> {
        self.lines
            .iter()
            .filter_map(|l| {
                let (a, b) = (x.get(l.anchor)?, x.get(l.fairlead)?);
                let chord = dist(a, b);
                (l.unstretched < chord * (1.0 - TAUT_MARGIN)).then(|| {
                    Diagnostic::warning(
                        "design/taut-line",
                        &l.name,
                        format!(
                            "line '{}' is taut {when}: its ends are {chord:.3} m apart but its \
                             unstretched length is {:.3} m ({:.2} % short); it hangs straight \
                             and stretched, with no slack to give. Lengthen the line or move \
                             its anchor closer",
                            l.name,
                            l.unstretched,
                            100.0 * (chord - l.unstretched) / l.unstretched
                        ),
                    )
                })
            })
            .collect()
    }

    /// `design/float-on-seabed`, else `design/sunk-float`, for one floater.
    fn floater(&self, f: &Floater, x: &[[f64; 3]]) -> Option<Diagnostic> {
        let half = 0.5 * f.size;
        let z: Vec<f64> = f
            .nodes
            .iter()
            .filter_map(|&n| x.get(n))
            .map(|p| p[2])
            .collect();
        let lowest = z.iter().copied().fold(f64::INFINITY, f64::min);
        if let Some(zb) = self.seabed_z {
            // The penalty contact lets a body sink slightly into the bed.
            let on_bed = z.iter().filter(|&&zi| zi - half <= zb + 1e-3).count();
            if on_bed > 0 {
                return Some(Diagnostic::warning(
                    "design/float-on-seabed",
                    &f.location,
                    format!(
                        "{} lies on the seabed at static equilibrium ({on_bed} of {} nodes; \
                         lowest centre at z = {lowest:.3} m, seabed at z = {zb} m): what should \
                         hold it up is too small for what hangs on it. Give it more volume or \
                         hang less weight on it",
                        f.label,
                        z.len()
                    ),
                ));
            }
        }
        if f.submerged || f.size <= 0.0 {
            return None;
        }
        // Its top more than its own size under the still-water level.
        let sunk = z.iter().filter(|&&zi| zi + half < -f.size).count();
        (sunk > 0).then(|| {
            Diagnostic::warning(
                "design/sunk-float",
                &f.location,
                format!(
                    "{} is under water at static equilibrium: {sunk} of {} nodes have their top \
                     more than its size {} m below the still-water level (deepest top at z = \
                     {:.3} m); it no longer floats. Give it more volume, hang less weight on it, \
                     or lengthen a line that pulls it under{}",
                    f.label,
                    z.len(),
                    f.size,
                    lowest + half,
                    if f.label.starts_with("buoy") {
                        "; if it is meant to be under water, set `submerged = true`"
                    } else {
                        ""
                    }
                ),
            )
        })
    }
}

/// The worst of one check over a run: how much [m] and when [s].
#[derive(Debug, Clone, Copy, PartialEq)]
struct Worst {
    amount: f64,
    t: f64,
}

/// Records `amount` at `t` if it is the largest so far.
fn keep(w: &mut Option<Worst>, amount: f64, t: f64) {
    if w.is_none_or(|w| amount > w.amount) {
        *w = Some(Worst { amount, t });
    }
}

/// The design checks of the dynamic phase, run on every accepted step: per floater the
/// deepest its top went below the local water surface beyond its own size, and whether it
/// touched the bed; per net how deep it went into the bed's contact zone.
#[derive(Debug, Clone, Default)]
pub struct DynamicWatch {
    /// Per floater: excess submergence η − (z + size/2) − size > 0 [m].
    sunk: Vec<Option<Worst>>,
    /// Per floater: depth of its lowest point below z_b + 1 mm [m].
    float_bed: Vec<Option<Worst>>,
    /// Per net: depth of its lowest node below z_b + 1 mm [m].
    net_bed: Vec<Option<Worst>>,
}

impl DynamicWatch {
    /// A watch for the floaters and nets of `checks`.
    pub fn new(checks: &DesignChecks) -> Self {
        Self {
            sunk: vec![None; checks.floaters.len()],
            float_bed: vec![None; checks.floaters.len()],
            net_bed: vec![None; checks.nets.len()],
        }
    }

    /// Checks the state `x` [m] at time `t` [s]; `eta(x, y)` is the water surface there [m].
    pub fn step(
        &mut self,
        checks: &DesignChecks,
        x: &[[f64; 3]],
        t: f64,
        eta: impl Fn(f64, f64) -> f64,
    ) {
        for (k, f) in checks.floaters.iter().enumerate() {
            let half = 0.5 * f.size;
            for p in f.nodes.iter().filter_map(|&n| x.get(n)) {
                if let Some(zb) = checks.seabed_z {
                    let into = zb + ON_BED - (p[2] - half);
                    if into >= 0.0 {
                        keep(&mut self.float_bed[k], into, t);
                    }
                }
                if !f.submerged && f.size > 0.0 {
                    let excess = eta(p[0], p[1]) - (p[2] + half) - f.size;
                    if excess > 0.0 {
                        keep(&mut self.sunk[k], excess, t);
                    }
                }
            }
        }
        if let Some(zb) = checks.seabed_z {
            for (k, (_, nodes)) in checks.nets.iter().enumerate() {
                for p in nodes.iter().filter_map(|&n| x.get(n)) {
                    let into = zb + ON_BED - p[2];
                    if into >= 0.0 {
                        keep(&mut self.net_bed[k], into, t);
                    }
                }
            }
        }
    }

    /// One warning per floater or net that failed a check during the run.
    pub fn diagnostics(&self, checks: &DesignChecks) -> Vec<Diagnostic> {
        let mut d = Vec::new();
        let zb = checks.seabed_z.unwrap_or(f64::NEG_INFINITY);
        for (k, f) in checks.floaters.iter().enumerate() {
            if let Some(w) = self.sunk[k] {
                d.push(Diagnostic::warning(
                    "design/sunk-float",
                    &f.location,
                    format!(
                        "{} went under water during the dynamics: its top was up to {:.3} m \
                         deeper than its own size {} m below the local water surface (at t = \
                         {:.3} s); it no longer floats there, so its buoyancy and the loads of \
                         what hangs on it are those of a sunk body. Give it more volume or \
                         freeboard, or hang less weight on it",
                        f.label, w.amount, f.size, w.t
                    ),
                ));
            }
            if let Some(w) = self.float_bed[k] {
                d.push(Diagnostic::warning(
                    "design/float-on-seabed",
                    &f.location,
                    format!(
                        "{} touched the seabed (z = {zb} m) during the dynamics, deepest at t = \
                         {:.3} s: what should hold it up is too small for what hangs on it",
                        f.label, w.t
                    ),
                ));
            }
        }
        for (k, (name, _)) in checks.nets.iter().enumerate() {
            if let Some(w) = self.net_bed[k] {
                d.push(Diagnostic::warning(
                    "design/on-seabed",
                    name,
                    format!(
                        "'{name}' touched the seabed (z = {zb} m) during the dynamics, deepest at \
                         t = {:.3} s ({:.3} m into the bed's contact): the bed carried part of \
                         the net, whose loads are then not those of a hanging net. Make the net \
                         or its weights shallower, or the sea deeper",
                        w.t,
                        w.amount - ON_BED
                    ),
                ));
            }
        }
        d
    }
}

/// Share of the sinker weight a sinker tube's net lift may cancel before
/// `design/buoyant-sinker-tube` warns.
pub const SINKER_TUBE_LIFT_SHARE: f64 = 0.5;

/// Fewest nodes around a cage (NT) before `mesh/coarse-net` warns
/// (docs/theory/fem.md#mesh-resolution-warnings).
pub const MIN_NET_NODES_AROUND: usize = 12;

/// Fewest side segments of a cage (NN) before `mesh/coarse-net` warns.
pub const MIN_NET_SIDE_SEGMENTS: usize = 2;

/// `mesh/coarse-net` for every cage whose net has fewer than [`MIN_NET_NODES_AROUND`] nodes
/// around or fewer than [`MIN_NET_SIDE_SEGMENTS`] side segments: on the small cage's
/// element-length ladder its static volume ratio was 43–48 % below the converged one there,
/// 7 % at 12 nodes and 3 segments (docs/theory/fem.md#mesh-resolution-warnings).
pub fn coarse_nets(mesh: &Mesh) -> Vec<Diagnostic> {
    mesh.objects
        .iter()
        .filter_map(|o| {
            let c = o.counts()?;
            (c.nt < MIN_NET_NODES_AROUND || c.nn < MIN_NET_SIDE_SEGMENTS).then(|| {
                Diagnostic::warning(
                    "mesh/coarse-net",
                    &o.name,
                    format!(
                        "the net of '{}' has {} nodes around and {} side segments: too few to \
                         give its shape. On a small cage's element-length ladder the static \
                         volume ratio was 43-48 % low with fewer than {MIN_NET_NODES_AROUND} \
                         nodes around or {MIN_NET_SIDE_SEGMENTS} side segments, 7 % low at 12 \
                         and 3, 2 % at 24 and 5 (docs/theory/fem.md#mesh-resolution-warnings). \
                         Use a shorter element_length, or compare with `aqua study --vary \
                         element_length=...`",
                        o.name, c.nt, c.nn
                    ),
                )
            })
        })
        .collect()
}

/// `design/buoyant-sinker-tube` for every sinker tube (`bottom_ring` group) of `mesh`: its net
/// lift ρ_w·g·π/4·d_v²·L − μ·g·L (d_v its volume diameter, μ its mass per length, L its as-built
/// length; `sections` with the scene's overrides) against the weights on its cage's `sinkers`.
pub fn sinker_tubes(
    mesh: &Mesh,
    sections: &[Option<(aqua_fem::GroupId, Section)>],
    water_density: f64,
    gravity: f64,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for (gi, g) in mesh.groups.iter().enumerate() {
        if g.role != Role::BottomRing {
            continue;
        }
        let Some((_, s)) = sections.get(gi).and_then(|s| s.as_ref()) else {
            continue;
        };
        let area = std::f64::consts::FRAC_PI_4 * s.volume_diameter.powi(2);
        let lift_per_metre = (water_density * area - s.linear_mass()) * gravity;
        let length: f64 = g
            .lines
            .iter()
            .map(|&e| mesh.line_length(e) * mesh.lines[e].section_scale)
            .sum();
        let lift = lift_per_metre * length;
        let weight: f64 = mesh
            .weights
            .iter()
            .filter(|w| {
                let wg = &mesh.groups[w.group];
                wg.object == g.object && wg.role == Role::Sinkers
            })
            .map(|w| w.weight)
            .sum();
        if weight > 0.0 && lift > SINKER_TUBE_LIFT_SHARE * weight {
            let name = format!("{}/{}", mesh.objects[g.object as usize].name, g.name);
            out.push(Diagnostic::warning(
                "design/buoyant-sinker-tube",
                &name,
                format!(
                    "the sinker tube '{name}' is a sealed pipe (volume diameter {:.3} m, {:.1} kg/m) \
                     that lifts {lift_per_metre:.1} N/m: {:.1} kN over its {length:.1} m, {:.0} % of \
                     the {:.1} kN sinker weight it carries, so only {:.1} kN holds the net down \
                     (docs/theory/cages.md#frame-ropes-and-weights). If that is not the design, \
                     raise `sinker_weight_per_metre` or set `groups.bottom_ring` (a flooded tube: \
                     `volume_diameter` of its wall, or a `mass_per_length` with the ballast)",
                    s.volume_diameter,
                    s.linear_mass(),
                    lift / 1e3,
                    100.0 * lift / weight,
                    weight / 1e3,
                    (weight - lift) / 1e3,
                ),
            ));
        }
    }
    out
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default CCT sinker tube (sealed 0.25 m HDPE pipe, 0.0185 m wall, 958 kg/m³) lifts
    /// (ρ_w·π/4·D² − μ)·g over its 48 chords at radius R_t + f: more than half of the default
    /// 392.4 N/m × 120 m of sinkers. Four times the sinker weight does not warn.
    #[test]
    fn buoyant_sinker_tube_warns() {
        let (rho, g) = (1025.0, 9.80665);
        let tube = |w: f64| {
            let mut p = aqua_mesh::CageParams::new(aqua_mesh::CageType::Cct);
            p.sinker_weight_per_metre = Some(w);
            let m = p.build().unwrap();
            let sections: Vec<_> = m
                .groups
                .iter()
                .map(|gr| gr.section.clone().map(|s| (aqua_fem::GroupId(0), s)))
                .collect();
            sinker_tubes(&m, &sections, rho, g)
        };
        let d = tube(392.4);
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].code, "design/buoyant-sinker-tube");
        // Independent numbers: lift per metre and the tube's length 48·2(R+1)·sin(π/48).
        let area = |d: f64| std::f64::consts::FRAC_PI_4 * d * d;
        let mu = 958.0 * (area(0.25) - area(0.25 - 2.0 * 0.25 / 13.6));
        let lift = (rho * area(0.25) - mu) * g;
        let r = 120.0 / (2.0 * std::f64::consts::PI) + 1.0;
        let length = 48.0 * 2.0 * r * (std::f64::consts::PI / 48.0).sin();
        let share = lift * length / (392.4 * 120.0);
        assert!((lift - 367.7).abs() < 0.5, "{lift}");
        assert!(
            d[0].message.contains(&format!("{:.0} %", 100.0 * share)),
            "{}",
            d[0].message
        );
        assert!(tube(4.0 * 392.4).is_empty());
    }

    fn checks() -> DesignChecks {
        DesignChecks {
            floaters: vec![Floater {
                label: "buoy 'b'".into(),
                location: "b".into(),
                nodes: vec![2],
                size: 1.0,
                submerged: false,
            }],
            lines: vec![LineLength {
                name: "m".into(),
                anchor: 0,
                fairlead: 1,
                unstretched: 10.0,
                path: vec![0, 1],
            }],
            seabed_z: Some(-20.0),
            kinks: Vec::new(),
            nets: vec![("net".into(), vec![3])],
        }
    }

    #[test]
    fn each_warning_fires_at_its_threshold_only() {
        let c = checks();
        let codes = |x: &[[f64; 3]]| -> Vec<&'static str> {
            c.at_equilibrium(x).iter().map(|d| d.code).collect()
        };
        // taut as built: 10.05 m apart; slack: 10 m apart
        let p = |x: [f64; 3]| Point3::from(x);
        let taut = [
            p([0.0, 0.0, -20.0]),
            p([6.03, 0.0, -11.96]),
            p([6.0, 0.0, 0.0]),
        ];
        let built: Vec<_> = c.as_built(&taut).iter().map(|d| d.code).collect();
        assert_eq!(built, vec!["design/taut-line"]);
        let slack = [
            p([0.0, 0.0, -20.0]),
            p([6.0, 0.0, -12.0]),
            p([6.0, 0.0, 0.0]),
        ];
        assert!(c.as_built(&slack).is_empty());
        // buoy floating
        assert!(codes(&[[0.0, 0.0, -20.0], [6.0, 0.0, -12.0], [6.0, 0.0, 0.0]]).is_empty());
        // top exactly one diameter under water: not yet; a bit deeper: sunk
        assert!(codes(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, -1.5 + 1e-9]]).is_empty());
        assert_eq!(
            codes(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, -1.6]]),
            vec!["design/sunk-float"]
        );
        // on the seabed: that, not sunk
        assert_eq!(
            codes(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, -19.5]]),
            vec!["design/float-on-seabed"]
        );
        let mut c2 = checks();
        c2.floaters[0].submerged = true;
        assert!(
            c2.at_equilibrium(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, -5.0]])
                .is_empty()
        );
        // a net node 1 mm above the bed rests on it (the contact tolerance); 2 mm is free
        let net_at = |z: f64| [[0.0; 3], [1.0, 0.0, 0.0], [6.0, 0.0, 0.0], [3.0, 0.0, z]];
        assert!(codes(&net_at(-19.998)).is_empty());
        assert_eq!(codes(&net_at(-19.9995)), vec!["design/on-seabed"]);
        let on_bed: Vec<_> = [-20.0, -11.0, 0.0, -20.0]
            .iter()
            .map(|&z| p([0.0, 0.0, z]))
            .collect();
        let built: Vec<_> = c.as_built(&on_bed).iter().map(|d| d.code).collect();
        assert!(built.contains(&"design/on-seabed"), "{built:?}");
    }

    #[test]
    fn the_dynamic_watch_reports_the_worst_against_the_local_surface_once() {
        let c = checks();
        let mut w = DynamicWatch::new(&c);
        // A 1 m buoy whose centre is 1.2 m under still water: its top 0.7 m down, less than its
        // size; under a 2 m crest it is 2.7 m down, 1.7 m more than its size; in a 1 m trough
        // it is afloat. The deepest excess is the one reported, with its time.
        let x = |zb: f64| [[0.0; 3], [1.0, 0.0, 0.0], [5.0, 0.0, -1.2], [3.0, 0.0, zb]];
        w.step(&c, &x(-10.0), 1.0, |_, _| 0.0);
        assert!(w.diagnostics(&c).is_empty());
        w.step(&c, &x(-10.0), 2.0, |_, _| -1.0);
        w.step(
            &c,
            &x(-10.0),
            3.0,
            |xx, _| if xx == 5.0 { 2.0 } else { 0.0 },
        );
        w.step(&c, &x(-10.0), 4.0, |_, _| 1.5);
        let d = w.diagnostics(&c);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].code, "design/sunk-float");
        assert!(d[0].message.contains("1.700 m"), "{}", d[0].message);
        assert!(d[0].message.contains("t = 3.000 s"), "{}", d[0].message);
        // The net touches the bed once, at t = 5 s: one more warning.
        w.step(&c, &x(-19.9995), 5.0, |_, _| 0.0);
        let codes: Vec<_> = w.diagnostics(&c).iter().map(|d| d.code).collect();
        assert_eq!(codes, vec!["design/sunk-float", "design/on-seabed"]);
    }
}
