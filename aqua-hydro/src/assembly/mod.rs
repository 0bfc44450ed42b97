//! The load assembly: built once from element lists, it evaluates the sea once per node and
//! fills caller-owned arrays with nodal forces, added mass and Jacobian blocks
//! (docs/theory/hydrodynamics.md#scope-and-principles, #load-jacobians).
//!
//! # Elements and indices
//! Load elements are numbered panels first (in the order given), then lines, then point
//! bodies: element `e` is panel `e` for `e < n_panels`, line `e − n_panels`, and so on.
//!
//! # Jacobian layout (compact)
//! Every element is a sum of *pieces*; a piece has 1–3 of the element's nodes and passes its
//! force in equal shares to them. A triangle, a line and a point are one piece; a quad is four
//! triangles, piece k leaving out corner k (local nodes (k+1, k+2, k+3) mod 4), each weight ½.
//! Hence for the element's local nodes i, j:
//! * ∂f_i/∂v_j = Σ over pieces p containing i and j of `dfdv[velocity_blocks(e).start + p]`
//!   (one 3×3 block per piece, the same for all node pairs of the piece);
//! * ∂f_i/∂x_j = Σ over pieces p containing i and j of
//!   `dfdx[position_blocks(e).start + P·p + q]`, P = nodes per piece, q the position of j in p.
//!
//! [`LoadAssembly::expand`] turns these into the dense 3n×3n element matrices that
//! [`ElementOutput`] holds; [`LoadAssembly::element_load`] fills them directly.
//! All 3×3 blocks are row-major `[[f64; 3]; 3]`, derivatives of the force *on the structure*
//! (∂f/∂v is negative semi-definite for pure drag; the solver's damping is C_h = −∂f/∂v).

use crate::cage_wake::CageWake;
use crate::cylinder::RE_CRISIS;
use crate::error::{HydroError, check_non_negative, check_positive, check_solidity};
use crate::morison_coefficients::MorisonModel;
use crate::morison_line::{self, LineProps};
use crate::net_panel::{self, NetProps};
use crate::net_triangle::TwineMap;
use crate::point_body::{self, PointProps, PointShape};
use crate::screen::{RE_MAX, ScreenModel};
use crate::types::{M3, V3, Want};
use crate::wake::{Wake, WakeCell, WakeModel, WakeUpdate, unramped_current};
use aqua_env::{FlowPoint, Phase, Sea};
use std::ops::Range;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

mod build;
mod bulk;
mod compute;
mod elements;
mod sinks;
mod stats;
mod wake_update;

pub use bulk::Outputs;
pub use elements::{
    Diagnostics, ElementOutput, Elements, LineElement, NetPanel, NetSummary, PanelNodes,
    PointElement, WakeGroup,
};
use sinks::{CompactSink, DenseSink, Sink};
use stats::{Local, Stats};
pub use wake_update::WAKE_TOLERANCE;

/// A row-major 3×3 block.
pub type Block = [[f64; 3]; 3];

/// Most nodes of one load element.
pub const MAX_NODES: usize = 4;
/// Size of a dense element matrix.
pub const MAX_DOFS: usize = 3 * MAX_NODES;

/// Elements per parallel task.
const GRAIN: usize = 1024;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Tri,
    Quad,
    Line,
    Point,
}

#[derive(Debug, Clone, Copy)]
struct Elem {
    kind: Kind,
    nodes: [usize; MAX_NODES],
    n: usize,
    /// Index into panels / lines / points.
    idx: usize,
}

const PIECES_TRI: [[usize; 3]; 1] = [[0, 1, 2]];
const PIECES_QUAD: [[usize; 3]; 4] = [[1, 2, 3], [2, 3, 0], [3, 0, 1], [0, 1, 2]];

impl Elem {
    fn n_pieces(&self) -> usize {
        if self.kind == Kind::Quad { 4 } else { 1 }
    }
    fn piece_len(&self) -> usize {
        match self.kind {
            Kind::Tri | Kind::Quad => 3,
            Kind::Line => 2,
            Kind::Point => 1,
        }
    }
    fn piece(&self, k: usize) -> &'static [usize] {
        match self.kind {
            Kind::Tri => &PIECES_TRI[0],
            Kind::Quad => &PIECES_QUAD[k],
            Kind::Line => &[0, 1],
            Kind::Point => &[0],
        }
    }
}

/// Node data cached by [`LoadAssembly::prepare`]: the surface elevation at the node and the
/// kinematics at the node (or at the surface above it if the node is dry).
#[derive(Debug, Clone, Copy, Default)]
struct NodeFlow {
    eta: f64,
    current: [f64; 3],
    current_acc: [f64; 3],
    wave_vel: [f64; 3],
    wave_acc: [f64; 3],
}

/// Per-group wake bookkeeping.
#[derive(Debug, Clone)]
struct GroupState {
    net_nodes: Vec<usize>,
    members: Vec<usize>,
    computed: bool,
}

/// Loads from the water on a set of panels, lines and point bodies.
///
/// Built once ([`LoadAssembly::new`]); owns every buffer it needs, so [`evaluate`]
/// (bulk) and [`prepare`] + [`element_load`] (per element, for a solver that assembles
/// element by element) allocate nothing.
///
/// [`evaluate`]: LoadAssembly::evaluate
/// [`prepare`]: LoadAssembly::prepare
/// [`element_load`]: LoadAssembly::element_load
#[derive(Debug)]
pub struct LoadAssembly {
    sea: Arc<Sea>,
    rho: f64,
    nu: f64,
    g: f64,
    n_nodes: usize,
    panels: Vec<NetPanel>,
    lines: Vec<LineElement>,
    points: Vec<PointElement>,
    groups: Vec<WakeGroup>,
    group_state: Vec<GroupState>,
    elems: Vec<Elem>,
    voff: Vec<usize>,
    xoff: Vec<usize>,
    used: Vec<usize>,
    all_used: bool,
    scratch_flow: Vec<FlowPoint>,
    flow: Vec<NodeFlow>,
    /// Time t [s] (bits) and phase of the flow in `flow`, and the positions [m] it was
    /// evaluated at (every node if `all_used`, else the `used` nodes in order): a `prepare` at
    /// the same state, bit for bit, reuses it (the solvers re-evaluate a state to form its
    /// Jacobian).
    flow_key: Option<(u64, Phase)>,
    flow_pts: Vec<[f64; 3]>,
    /// `prepare` calls that evaluated the sea, and those that reused its flow.
    sea_counts: (usize, usize),
    wake: Vec<WakeCell>,
    wake_ready: bool,
    /// Cage-to-cage wake: participating cages, and (element, its wake group) of every
    /// element of a participating cage.
    cage_wake: CageWake,
    cage_receivers: Vec<(usize, usize)>,
    /// Cage-to-cage ratio per element (1 outside every upstream cage's shadow).
    cage_factor: Vec<f64>,
    /// The wake update's candidates (committed only if they differ from `wake` and
    /// `cage_factor` by more than [`WAKE_TOLERANCE`]), and its
    /// buffers: the cages' wakes, their order along the flow, net node positions.
    wake_next: Vec<WakeCell>,
    cage_next: Vec<f64>,
    shadows: Vec<crate::cage_wake::CageShadow>,
    shadow_order: Vec<usize>,
    shadow_pts: Vec<[f64; 3]>,
    elem_force: Vec<[[f64; 3]; MAX_NODES]>,
    elem_mass: Vec<Block>,
    stats: Stats,
    warnings: Vec<String>,
}

impl LoadAssembly {
    /// The sea.
    pub fn sea(&self) -> &Arc<Sea> {
        &self.sea
    }

    /// Number of structure nodes the arrays refer to.
    pub fn n_nodes(&self) -> usize {
        self.n_nodes
    }

    /// Number of load elements (panels + lines + points).
    pub fn n_elements(&self) -> usize {
        self.elems.len()
    }

    /// Number of panels (elements 0..n_panels).
    pub fn n_panels(&self) -> usize {
        self.panels.len()
    }

    /// Number of lines (elements n_panels..n_panels + n_lines).
    pub fn n_lines(&self) -> usize {
        self.lines.len()
    }

    /// Global node indices of element `e` (1–4 nodes).
    pub fn element_nodes(&self, e: usize) -> &[usize] {
        let el = &self.elems[e];
        &el.nodes[..el.n]
    }

    /// Length of the `dfdv` slice of [`Outputs`].
    pub fn n_velocity_blocks(&self) -> usize {
        self.voff[self.elems.len()]
    }

    /// Length of the `dfdx` slice of [`Outputs`].
    pub fn n_position_blocks(&self) -> usize {
        self.xoff[self.elems.len()]
    }

    /// The velocity blocks of element `e` (one per piece).
    pub fn velocity_blocks(&self, e: usize) -> Range<usize> {
        self.voff[e]..self.voff[e + 1]
    }

    /// The position blocks of element `e` (per piece, one per piece node).
    pub fn position_blocks(&self, e: usize) -> Range<usize> {
        self.xoff[e]..self.xoff[e + 1]
    }

    /// Local node indices of piece `k` of element `e` (see the module docs).
    pub fn piece_nodes(&self, e: usize, k: usize) -> &'static [usize] {
        self.elems[e].piece(k)
    }

    /// Build-time warnings (fit ranges, limited models), each once.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// What the evaluations so far have seen (Reynolds ranges, clamps).
    pub fn diagnostics(&self) -> Diagnostics {
        let s = &self.stats;
        Diagnostics {
            panel_reynolds: s.panel_re.get(),
            line_reynolds: s.line_re.get(),
            reynolds_clamped: s.clamped.load(Ordering::Relaxed),
            cylinder_drag_crisis: s.crisis.load(Ordering::Relaxed),
            m5_capped: s.capped.load(Ordering::Relaxed),
        }
    }

    /// Net-to-net wake state per element within its own cage (index as elements; lines and
    /// points outside any shadow have r = 1), for the `in_shadow` cell data.
    pub fn wake(&self) -> &[WakeCell] {
        &self.wake
    }

    /// The cage-to-cage ratio of element `e` (1 unless an upstream cage shadows it;
    /// docs/theory/hydrodynamics.md#cage-to-cage-wake).
    pub fn cage_wake_factor(&self, e: usize) -> f64 {
        self.cage_factor[e]
    }

    /// The factor multiplying the current on element `e`: its own cage's wake factor times
    /// the cage-to-cage ratio (the `wake_factor` cell data).
    pub fn wake_factor(&self, e: usize) -> f64 {
        self.wake[e].factor * self.cage_factor[e]
    }

    /// Net area and twine volumes at positions `x` (log at start-up,
    /// docs/theory/hydrodynamics.md#buoyancy).
    pub fn net_summary(&self, x: &[[f64; 3]]) -> NetSummary {
        let mut s = NetSummary::default();
        let v = |i: usize| V3::from(x[i]);
        let tri_area =
            |a: usize, b: usize, c: usize| 0.5 * (v(b) - v(a)).cross(&(v(c) - v(a))).norm();
        for p in &self.panels {
            let area = match p.nodes {
                PanelNodes::Triangle([a, b, c]) => tri_area(a, b, c),
                PanelNodes::Quad(q) => {
                    0.5 * (tri_area(q[1], q[2], q[3])
                        + tri_area(q[2], q[3], q[0])
                        + tri_area(q[3], q[0], q[1])
                        + tri_area(q[0], q[1], q[2]))
                }
            };
            s.area += area;
            s.expected_twine_volume +=
                area * std::f64::consts::FRAC_PI_4 * p.net.twine_diameter * p.net.solidity;
        }
        for l in self.lines.iter().filter(|l| l.net_twine) {
            let d = l.props.volume_diameter;
            s.twine_volume += std::f64::consts::FRAC_PI_4 * d * d * l.props.rest_length;
        }
        s
    }

    fn check_len(&self, what: &str, n: usize) -> Result<(), HydroError> {
        if n == self.n_nodes {
            Ok(())
        } else {
            Err(HydroError::range(
                format!("{what} length"),
                n,
                format!("must equal the node count {}", self.n_nodes),
            ))
        }
    }

    /// Evaluates the sea at every node used by an element (once per node; dry nodes take the
    /// kinematics of the surface above them) and, on the first call, the wake.
    ///
    /// `x` are node positions [m] at time t [s]; `phase` selects statics (full current, no
    /// waves) or dynamics.
    pub fn prepare(&mut self, t: f64, phase: Phase, x: &[[f64; 3]]) -> Result<(), HydroError> {
        self.check_len("positions", x.len())?;
        if !self.wake_ready {
            self.update_wake(t, x)?;
        }
        if self.flow_is_current(t, phase, x) {
            self.sea_counts.1 += 1;
            return Ok(());
        }
        self.sea_counts.0 += 1;
        // Keyed only once the flow below is complete.
        self.flow_key = None;
        if self.all_used {
            self.flow_pts.copy_from_slice(x);
        } else {
            for (p, &nd) in self.flow_pts.iter_mut().zip(&self.used) {
                *p = x[nd];
            }
        }
        let sea = &*self.sea;
        if self.all_used {
            sea.eval(t, phase, x, &mut self.scratch_flow);
            for (nf, fp) in self.flow.iter_mut().zip(&self.scratch_flow) {
                *nf = node_flow(fp);
            }
            for (i, fp) in self.scratch_flow.iter().enumerate() {
                if fp.submergence < 0.0 {
                    self.flow[i] = surface_flow(sea, x[i], fp.eta, t, phase);
                }
            }
        } else {
            sea.eval(t, phase, &self.flow_pts, &mut self.scratch_flow);
            for (fp, &nd) in self.scratch_flow.iter().zip(&self.used) {
                self.flow[nd] = if fp.submergence < 0.0 {
                    surface_flow(sea, x[nd], fp.eta, t, phase)
                } else {
                    node_flow(fp)
                };
            }
        }
        self.flow_key = Some((t.to_bits(), phase));
        Ok(())
    }

    /// How many `prepare` calls evaluated the sea, and how many reused the flow of the same
    /// state (time, phase and positions bit for bit).
    pub fn sea_evaluations(&self) -> (usize, usize) {
        self.sea_counts
    }

    /// Whether `flow` already holds the sea at positions `x` at (t, phase): same time and
    /// phase bit for bit, same position of every used node.
    fn flow_is_current(&self, t: f64, phase: Phase, x: &[[f64; 3]]) -> bool {
        if self.flow_key != Some((t.to_bits(), phase)) {
            return false;
        }
        let same = |a: &[f64; 3], b: &[f64; 3]| a.map(f64::to_bits) == b.map(f64::to_bits);
        if self.all_used {
            self.flow_pts.iter().zip(x).all(|(p, q)| same(p, q))
        } else {
            self.used
                .iter()
                .zip(&self.flow_pts)
                .all(|(&nd, p)| same(&x[nd], p))
        }
    }

    /// Loads of element `e` at local positions `x` and velocities `v` (the element's nodes
    /// in [`element_nodes`](Self::element_nodes) order), using the flow cached by the last
    /// [`prepare`](Self::prepare). Overwrites `out` (force and added mass always; `dfdv`,
    /// `dfdx` in the leading 3n×3n block when asked). Safe to call in parallel.
    pub fn element_load(
        &self,
        e: usize,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        want: Want,
        out: &mut ElementOutput,
    ) {
        let n = self.elems[e].n;
        for i in 0..n {
            out.force[i] = [0.0; 3];
            out.added_mass[i] = [[0.0; 3]; 3];
        }
        if want.dfdv {
            for row in out.dfdv.iter_mut().take(3 * n) {
                row[..3 * n].fill(0.0);
            }
        }
        if want.dfdx {
            for row in out.dfdx.iter_mut().take(3 * n) {
                row[..3 * n].fill(0.0);
            }
        }
        let mut local = Local::new();
        self.compute(e, x, v, want, &mut DenseSink(out), &mut local);
        self.stats.publish(&local);
    }
}

fn node_flow(fp: &FlowPoint) -> NodeFlow {
    NodeFlow {
        eta: fp.eta,
        current: fp.current,
        current_acc: fp.current_acc,
        wave_vel: fp.wave_vel,
        wave_acc: fp.wave_acc,
    }
}

/// A dry node takes the kinematics of the surface point above (below) it, so an element
/// that is partly out of the water sees the water's velocity on its wet part.
fn surface_flow(sea: &Sea, p: [f64; 3], eta: f64, t: f64, phase: Phase) -> NodeFlow {
    let fp = sea.at([p[0], p[1], eta], t, phase);
    NodeFlow {
        eta,
        ..node_flow(&fp)
    }
}
