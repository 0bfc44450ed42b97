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
use crate::net_panel::{self, M3, NetProps, V3, Want};
use crate::net_triangle::TwineMap;
use crate::point_body::{self, PointProps, PointShape};
use crate::screen::{RE_MAX, ScreenModel};
use crate::wake::{Wake, WakeCell, WakeModel, WakeUpdate, unramped_current};
use aqua_env::{FlowPoint, Phase, Sea};
use std::ops::Range;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

mod bulk;
mod sinks;
mod stats;
mod wake_update;

pub use bulk::Outputs;
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

/// The nodes of a net panel: a triangle or a (possibly warped) quad in cyclic order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PanelNodes {
    /// Mesh triangle (weight 1).
    Triangle([usize; 3]),
    /// Quad p1..p4, integrated as four triangles of weight ½.
    Quad([usize; 4]),
}

/// A net panel carrying screen-model drag and lift (no buoyancy: twines carry it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetPanel {
    /// Node indices.
    pub nodes: PanelNodes,
    /// Screen model, solidity and twine diameter.
    pub net: NetProps,
    /// Index of the cage copy (wake group) it belongs to, if any.
    pub wake_group: Option<usize>,
    /// The twine map of a net triangle, whose solidity then follows its twines
    /// (docs/theory/hydrodynamics.md#net-triangle-screen); `None`: `net.solidity` holds.
    pub twines: Option<TwineMap>,
}

/// A Morison line element (rope, pipe, chain, numerical net twine).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineElement {
    /// Node indices.
    pub nodes: [usize; 2],
    /// Section, model and coefficients.
    pub props: LineProps,
    /// True for numerical net twines: they belong to the net of their wake group (shadow
    /// test and centroid) and use c = 1 in Cheng's model.
    pub net_twine: bool,
    /// Cage copy it belongs to; ropes and pipes are reduced only if the group's wake has
    /// `apply_to_lines`.
    pub wake_group: Option<usize>,
}

/// A point body on one node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointElement {
    /// Node index.
    pub node: usize,
    /// Volume, height, drag area, added-mass coefficient.
    pub props: PointProps,
}

/// One cage copy for the wake: its wake model and net solidity.
#[derive(Debug, Clone, PartialEq)]
pub struct WakeGroup {
    /// Name for messages (e.g. "cage 1 copy 0").
    pub name: String,
    /// Wake configuration.
    pub wake: Wake,
    /// Net solidity Sn (Løland's C_D0 and Cheng's factor).
    pub solidity: f64,
}

/// Everything the assembly is built from.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Elements {
    /// Net panels.
    pub panels: Vec<NetPanel>,
    /// Lines.
    pub lines: Vec<LineElement>,
    /// Point bodies.
    pub points: Vec<PointElement>,
    /// Wake groups referenced by panels and lines.
    pub wake_groups: Vec<WakeGroup>,
}

/// Dense output of one element, laid out like aqua-fem's `ElementLoad`: local node i,
/// component k → local DOF 3i + k.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementOutput {
    /// Force on each local node [N].
    pub force: [[f64; 3]; MAX_NODES],
    /// Added-mass block per local node [kg].
    pub added_mass: [Block; MAX_NODES],
    /// ∂f_{3i+k}/∂v_{3j+l} [N·s/m] (written if asked).
    pub dfdv: [[f64; MAX_DOFS]; MAX_DOFS],
    /// ∂f_{3i+k}/∂x_{3j+l} [N/m] (written if asked).
    pub dfdx: [[f64; MAX_DOFS]; MAX_DOFS],
}

impl Default for ElementOutput {
    fn default() -> Self {
        Self {
            force: [[0.0; 3]; MAX_NODES],
            added_mass: [[[0.0; 3]; 3]; MAX_NODES],
            dfdv: [[0.0; MAX_DOFS]; MAX_DOFS],
            dfdx: [[0.0; MAX_DOFS]; MAX_DOFS],
        }
    }
}

/// What the run has seen, for the log (warn once each).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Diagnostics {
    /// Range [min, max] of the twine Reynolds number s·dw0/ν over panels with flow.
    pub panel_reynolds: Option<[f64; 2]>,
    /// Range of s·d_Re/ν over lines with flow.
    pub line_reynolds: Option<[f64; 2]>,
    /// Some Reynolds number exceeded 1e7 and was clamped.
    pub reynolds_clamped: bool,
    /// S3/S6 saw Re₃ > 2e5 (drag crisis not modelled).
    pub cylinder_drag_crisis: bool,
    /// M5's X = Re·Sn² was capped at 100.
    pub m5_capped: bool,
}

/// Net area and twine volume of the panels and net twines (docs/theory/hydrodynamics.md#buoyancy,
/// log at start-up).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NetSummary {
    /// Σ weight·area of all panels [m²].
    pub area: f64,
    /// Σ A·(π/4)·dw0·Sn over panels [m³]: the physical twine volume.
    pub expected_twine_volume: f64,
    /// Σ (π/4)·d_v²·L0 over net-twine lines [m³]: the volume that carries net buoyancy.
    pub twine_volume: f64,
}

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

fn check_node(what: &str, e: usize, node: usize, n_nodes: usize) -> Result<(), HydroError> {
    if node < n_nodes {
        Ok(())
    } else {
        Err(HydroError::range(
            format!("{what}[{e}] node"),
            node,
            format!("node indices must be < {n_nodes} (the structure's node count)"),
        ))
    }
}

fn check_distinct(what: &str, e: usize, nodes: &[usize]) -> Result<(), HydroError> {
    for i in 0..nodes.len() {
        for j in i + 1..nodes.len() {
            if nodes[i] == nodes[j] {
                return Err(HydroError::range(
                    format!("{what}[{e}] nodes"),
                    format!("{nodes:?}"),
                    "the nodes of an element must be distinct",
                ));
            }
        }
    }
    Ok(())
}

fn check_group(what: &str, e: usize, g: Option<usize>, n: usize) -> Result<(), HydroError> {
    match g {
        Some(g) if g >= n => Err(HydroError::range(
            format!("{what}[{e}] wake_group"),
            g,
            format!("must be < {n} (number of wake groups)"),
        )),
        _ => Ok(()),
    }
}

impl LoadAssembly {
    /// Validates the elements and allocates every buffer.
    ///
    /// Errors name the element and key: solidity outside (0, 1), non-positive diameters or
    /// lengths, negative coefficients, node indices ≥ `n_nodes`, repeated nodes, unknown wake
    /// groups, M5 on a line that is not a net twine, and a wake model (other than none) on a
    /// group with no net panel or net twine to shadow.
    pub fn new(
        sea: impl Into<Arc<Sea>>,
        n_nodes: usize,
        elements: Elements,
    ) -> Result<Self, HydroError> {
        let sea = sea.into();
        let Elements {
            panels,
            lines,
            points,
            wake_groups,
        } = elements;
        let ng = wake_groups.len();
        let mut warnings = Vec::new();
        let mut warned_fit = false;
        let mut warned_high = false;
        let mut warned_s6 = false;
        let mut warned_single = false;
        for (i, g) in wake_groups.iter().enumerate() {
            if g.wake.model != WakeModel::None {
                check_solidity(
                    &format!("wake_groups[{i}] ({}) solidity", g.name),
                    g.solidity,
                )?;
            }
        }
        let mut elems = Vec::with_capacity(panels.len() + lines.len() + points.len());
        for (e, p) in panels.iter().enumerate() {
            let key = |k: &str| format!("panel[{e}] {k}");
            check_solidity(&key("solidity"), p.net.solidity)?;
            check_positive(&key("twine_diameter"), p.net.twine_diameter, "m")?;
            if let ScreenModel::Const { cd, .. } = p.net.model {
                check_non_negative(&key("cd"), cd, "-")?;
            }
            check_group("panel", e, p.wake_group, ng)?;
            let (nodes, n, kind) = match p.nodes {
                PanelNodes::Triangle(t) => ([t[0], t[1], t[2], 0], 3, Kind::Tri),
                PanelNodes::Quad(q) => (q, 4, Kind::Quad),
            };
            for &nd in &nodes[..n] {
                check_node("panel", e, nd, n_nodes)?;
            }
            check_distinct("panel", e, &nodes[..n])?;
            let sn = p.net.solidity;
            let id = p.net.model.id();
            use crate::screen::ScreenModelId as S;
            if matches!(id, S::S1 | S::S2) && !(0.13..=0.35).contains(&sn) && !warned_fit {
                warned_fit = true;
                warnings.push(format!(
                    "screen model {id}: solidity {sn} is outside 0.13-0.35, the range it was fitted for"
                ));
            }
            if sn > 0.5 && !warned_high {
                warned_high = true;
                warnings.push(format!(
                    "net solidity {sn} > 0.5 is outside the data behind every screen model"
                ));
            }
            if id == S::S6 && !warned_s6 {
                warned_s6 = true;
                warnings.push(
                    "screen model S6 is limited: drag only, no lift defined by the source".into(),
                );
            }
            if matches!(id, S::S5 | S::Bi2014)
                && p.wake_group
                    .is_some_and(|g| wake_groups[g].wake.model != WakeModel::None)
                && !warned_single
            {
                warned_single = true;
                warnings.push(format!(
                    "screen model {id} is a single-net fit; it is applied to every panel of a cage"
                ));
            }
            elems.push(Elem {
                kind,
                nodes,
                n,
                idx: e,
            });
        }
        for (e, l) in lines.iter().enumerate() {
            let key = |k: &str| format!("line[{e}] {k}");
            let pr = &l.props;
            let drag = !matches!(pr.model, MorisonModel::None);
            if drag {
                check_positive(&key("hydro_diameter"), pr.hydro_diameter, "m")?;
                check_positive(&key("reynolds_diameter"), pr.reynolds_diameter, "m")?;
            }
            check_positive(&key("volume_diameter"), pr.volume_diameter, "m")?;
            check_positive(&key("rest_length"), pr.rest_length, "m")?;
            check_non_negative(&key("added_mass"), pr.added_mass, "-")?;
            check_non_negative(&key("added_mass_axial"), pr.added_mass_axial, "-")?;
            match pr.model {
                MorisonModel::M5 { solidity } => {
                    if !l.net_twine {
                        return Err(HydroError::key(
                            key("morison"),
                            "model \"M5\" needs a net solidity and is only valid for net twines",
                        ));
                    }
                    check_solidity(&key("solidity"), solidity)?;
                }
                MorisonModel::Const { cn, ct } => {
                    check_non_negative(&key("cn"), cn, "-")?;
                    check_non_negative(&key("ct"), ct, "-")?;
                }
                _ => {}
            }
            check_group("line", e, l.wake_group, ng)?;
            for &nd in &l.nodes {
                check_node("line", e, nd, n_nodes)?;
            }
            check_distinct("line", e, &l.nodes)?;
            elems.push(Elem {
                kind: Kind::Line,
                nodes: [l.nodes[0], l.nodes[1], 0, 0],
                n: 2,
                idx: e,
            });
        }
        for (e, p) in points.iter().enumerate() {
            let key = |k: &str| format!("point[{e}] {k}");
            check_non_negative(&key("volume"), p.props.volume, "m³")?;
            match p.props.shape {
                PointShape::Prism { height } => check_non_negative(&key("height"), height, "m")?,
                PointShape::Sphere { radius } => {
                    let v = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
                    if !(radius.is_finite() && radius > 0.0) {
                        return Err(HydroError::range(key("radius"), radius, "finite and > 0 m"));
                    }
                    if (p.props.volume - v).abs() > 1e-9 * v {
                        return Err(HydroError::range(
                            key("volume"),
                            p.props.volume,
                            format!("4πR³/3 = {v} m³ for a sphere of radius {radius} m"),
                        ));
                    }
                }
            }
            check_non_negative(&key("drag_area"), p.props.drag_area, "m²")?;
            check_non_negative(&key("added_mass_coefficient"), p.props.added_mass, "-")?;
            check_node("point", e, p.node, n_nodes)?;
            elems.push(Elem {
                kind: Kind::Point,
                nodes: [p.node, 0, 0, 0],
                n: 1,
                idx: e,
            });
        }
        // wake groups: net nodes and members
        let mut group_state = vec![
            GroupState {
                net_nodes: Vec::new(),
                members: Vec::new(),
                computed: false,
            };
            ng
        ];
        for (e, el) in elems.iter().enumerate() {
            let (g, is_net, member) = match el.kind {
                Kind::Tri | Kind::Quad => {
                    let g = panels[el.idx].wake_group;
                    (g, true, true)
                }
                Kind::Line => {
                    let l = &lines[el.idx];
                    let apply = l
                        .wake_group
                        .is_some_and(|g| wake_groups[g].wake.apply_to_lines);
                    (l.wake_group, l.net_twine, l.net_twine || apply)
                }
                Kind::Point => (None, false, false),
            };
            if let Some(g) = g {
                let st = &mut group_state[g];
                if is_net {
                    st.net_nodes.extend_from_slice(&el.nodes[..el.n]);
                }
                if member && wake_groups[g].wake.model != WakeModel::None {
                    st.members.push(e);
                }
            }
        }
        for (i, st) in group_state.iter_mut().enumerate() {
            st.net_nodes.sort_unstable();
            st.net_nodes.dedup();
            let model = wake_groups[i].wake.model;
            if model != WakeModel::None && st.net_nodes.is_empty() {
                return Err(HydroError::WakeWithoutNet {
                    group: i,
                    name: wake_groups[i].name.clone(),
                    model: model.id().as_str(),
                });
            }
        }
        let mut voff = Vec::with_capacity(elems.len() + 1);
        let mut xoff = Vec::with_capacity(elems.len() + 1);
        let (mut a, mut b) = (0, 0);
        for el in &elems {
            voff.push(a);
            xoff.push(b);
            a += el.n_pieces();
            b += el.n_pieces() * el.piece_len();
        }
        voff.push(a);
        xoff.push(b);
        let mut used: Vec<usize> = elems.iter().flat_map(|e| e.nodes[..e.n].to_vec()).collect();
        used.sort_unstable();
        used.dedup();
        let all_used = used.len() == n_nodes;
        let n_scratch = if all_used { 0 } else { used.len() };
        let ne = elems.len();
        Ok(Self {
            rho: sea.density(),
            nu: sea.kinematic_viscosity(),
            g: sea.gravity(),
            sea,
            n_nodes,
            panels,
            lines,
            points,
            groups: wake_groups,
            group_state,
            elems,
            voff,
            xoff,
            used,
            all_used,
            scratch_flow: vec![FlowPoint::default(); if all_used { n_nodes } else { n_scratch }],
            flow: vec![NodeFlow::default(); n_nodes],
            flow_key: None,
            sea_counts: (0, 0),
            flow_pts: vec![[0.0; 3]; if all_used { n_nodes } else { n_scratch }],
            wake: vec![WakeCell::default(); ne],
            wake_ready: false,
            cage_wake: CageWake::default(),
            cage_receivers: Vec::new(),
            cage_factor: vec![1.0; ne],
            wake_next: vec![WakeCell::default(); ne],
            cage_next: vec![1.0; ne],
            shadows: Vec::new(),
            shadow_order: Vec::new(),
            shadow_pts: Vec::new(),
            elem_force: vec![[[0.0; 3]; MAX_NODES]; ne],
            elem_mass: vec![[[0.0; 3]; 3]; ne],
            stats: Stats::new(),
            warnings,
        })
    }

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

    /// The physics of one element with local kinematics, into a sink.
    fn compute<S: Sink>(
        &self,
        e: usize,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        want: Want,
        sink: &mut S,
        local: &mut Local,
    ) {
        let el = &self.elems[e];
        let r = self.wake[e].factor * self.cage_factor[e];
        let fl = |i: usize| &self.flow[el.nodes[i]];
        match el.kind {
            Kind::Tri | Kind::Quad => {
                let panel = &self.panels[el.idx];
                let weight = if el.kind == Kind::Quad { 0.5 } else { 1.0 };
                let mut re_lo = f64::INFINITY;
                let mut re_hi: f64 = 0.0;
                // per node: r·U_c + u_w − v, position, submergence; a piece's relative velocity
                // is the mean over its nodes (for a quad: (sum − left-out node)/3)
                let mut wn = [V3::zeros(); MAX_NODES];
                let mut pn = [V3::zeros(); MAX_NODES];
                let mut zn = [0.0; MAX_NODES];
                let mut wsum = V3::zeros();
                for i in 0..el.n {
                    let f = fl(i);
                    wn[i] = r * V3::from(f.current) + V3::from(f.wave_vel) - V3::from(v[i]);
                    wsum += wn[i];
                    pn[i] = V3::from(x[i]);
                    zn[i] = f.eta - x[i][2];
                }
                for k in 0..el.n_pieces() {
                    let nodes = el.piece(k);
                    let w = if el.kind == Kind::Quad {
                        (wsum - wn[k]) / 3.0
                    } else {
                        wsum / 3.0
                    };
                    let p = [pn[nodes[0]], pn[nodes[1]], pn[nodes[2]]];
                    let zeta = [zn[nodes[0]], zn[nodes[1]], zn[nodes[2]]];
                    // A net triangle's solidity follows its twines, and the position
                    // Jacobian with it (docs/theory/hydrodynamics.md#net-triangle-screen).
                    let (net, dsn) = match &panel.twines {
                        Some(map) => {
                            let (sn, grad) = if want.dfdx {
                                map.solidity_gradient(&p, panel.net.twine_diameter)
                            } else {
                                (map.solidity(&p, panel.net.twine_diameter), [V3::zeros(); 3])
                            };
                            let net = NetProps {
                                solidity: sn,
                                ..panel.net
                            };
                            (net, want.dfdx.then_some(grad))
                        }
                        None => (panel.net, None),
                    };
                    let mut t =
                        net_panel::triangle(&net, p, zeta, w, weight, self.rho, self.nu, want);
                    if let Some(grad) = dsn
                        && grad.iter().any(|g| g.norm_squared() > 0.0)
                    {
                        // ∂F/∂Sn by a central difference of the screen model (any model).
                        let h = 1e-6 * net.solidity;
                        let at = |sn: f64| {
                            let props = NetProps {
                                solidity: sn,
                                ..net
                            };
                            net_panel::triangle(
                                &props,
                                p,
                                zeta,
                                w,
                                weight,
                                self.rho,
                                self.nu,
                                Want::default(),
                            )
                            .force
                        };
                        let dfds = (at(net.solidity + h) - at(net.solidity - h)) / (2.0 * h);
                        for q in 0..3 {
                            t.dfdp[q] += dfds * grad[q].transpose();
                        }
                    }
                    if t.reynolds > 0.0 {
                        re_lo = re_lo.min(t.reynolds);
                        re_hi = re_hi.max(t.reynolds);
                    }
                    let f3 = t.force / 3.0;
                    for &i in nodes {
                        sink.force(i, f3);
                    }
                    if want.dfdv {
                        sink.dv(k, nodes, &(t.dfdw * (-1.0 / 9.0)));
                    }
                    if want.dfdx {
                        for q in 0..3 {
                            sink.dx(k, nodes, q, &(t.dfdp[q] / 3.0));
                        }
                    }
                }
                if re_hi > 0.0 {
                    local.panel[0] = local.panel[0].min(re_lo);
                    local.panel[1] = local.panel[1].max(re_hi);
                    if re_hi > RE_MAX {
                        local.clamped = true;
                    }
                    if matches!(
                        panel.net.model,
                        ScreenModel::S3 { cyl_cd: None } | ScreenModel::S6 { cyl_cd: None }
                    ) && re_hi / (1.0 - panel.net.solidity) > RE_CRISIS
                    {
                        local.crisis = true;
                    }
                }
            }
            Kind::Line => {
                let l = &self.lines[el.idx];
                let (f0, f1) = (fl(0), fl(1));
                let mean = |a: [f64; 3], b: [f64; 3]| 0.5 * (V3::from(a) + V3::from(b));
                let uf = r * mean(f0.current, f1.current) + mean(f0.wave_vel, f1.wave_vel);
                let af = r * mean(f0.current_acc, f1.current_acc) + mean(f0.wave_acc, f1.wave_acc);
                let w = uf - mean(v[0], v[1]);
                let xx = [V3::from(x[0]), V3::from(x[1])];
                let zeta = [f0.eta - x[0][2], f1.eta - x[1][2]];
                let out =
                    morison_line::line(&l.props, xx, zeta, w, af, self.rho, self.nu, self.g, want);
                let half = 0.5 * out.force;
                sink.force(0, half);
                sink.force(1, half);
                let m = 0.5 * out.added_mass;
                sink.mass(0, &m);
                sink.mass(1, &m);
                if want.dfdv {
                    sink.dv(0, &[0, 1], &(out.dfdw * -0.25));
                }
                if want.dfdx {
                    sink.dx(0, &[0, 1], 0, &(0.5 * out.dfdx[0]));
                    sink.dx(0, &[0, 1], 1, &(0.5 * out.dfdx[1]));
                }
                if out.reynolds > 0.0 && !matches!(l.props.model, MorisonModel::None) {
                    local.line[0] = local.line[0].min(out.reynolds);
                    local.line[1] = local.line[1].max(out.reynolds);
                }
                local.clamped |= out.clamped;
                local.capped |= out.capped;
            }
            Kind::Point => {
                let p = &self.points[el.idx];
                let f = fl(0);
                let w = V3::from(f.current) + V3::from(f.wave_vel) - V3::from(v[0]);
                let acc = V3::from(f.current_acc) + V3::from(f.wave_acc);
                let zeta = f.eta - x[0][2];
                let out = point_body::point(&p.props, zeta, w, acc, self.rho, self.g, want);
                sink.force(0, out.force);
                sink.mass(0, &out.added_mass);
                if want.dfdv {
                    sink.dv(0, &[0], &(-out.dfdw));
                }
                if want.dfdx {
                    sink.dx(0, &[0], 0, &out.dfdx);
                }
            }
        }
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
