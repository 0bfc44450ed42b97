//! Static equilibrium: a Levenberg–Marquardt Newton method whose damping is steered by an
//! energy merit (strain and seabed energy, the work of the other loads by the trapezoidal
//! rule along the step), a backtracking
//! line search on that merit, a retry without it when a solve fails, load continuation only
//! when that fails too, and a
//! round-off convergence floor (docs/theory/fem.md#static-solver).

mod settings;
mod support;

pub use settings::{StaticControl, StaticProgress, StaticReport, StaticSettings, StaticSolution};
use support::{check_held_horizontally, check_held_up, check_supported, parts};

use crate::cable;
use crate::error::{FemError, Result, invalid};
use crate::failure::FailureReason;
use crate::loads::LoadProvider;
use crate::model::Model;
use crate::seabed::BedLaw;
use crate::state::{Outputs, State};
use crate::system::{Coef, EvalOptions, NONE, System};

/// Failure of one Newton solve.
struct NewtonFail {
    reason: FailureReason,
    history: Vec<f64>,
    /// The observer asked to stop (not a failure of the method).
    stopped: bool,
    /// An error that no smaller load increment can mend (the load provider's), returned as is.
    fatal: Option<Box<FemError>>,
}

/// Share of the nodal damping Σ EA/L0 kept at every node beside the line elements' stretch
/// damping (`stretch_damping`; docs/theory/fem.md#stretch-damping): a cage drifting on its
/// bridles is damped only by this share (full-scale farm: 665 → 456–486 iterations; 0 leaves
/// a free part's drift undamped).
const NODAL_SHARE: f64 = 0.1;

/// Smallest and largest Levenberg–Marquardt damping μ.
const MU_MIN: f64 = 1e-14;
const MU_MAX: f64 = 1e6;
/// μ after a rejection from μ = 0.
const MU_RESTART: f64 = 1e-8;
/// Backtracking halvings along a rejected step.
const BACKTRACKS: usize = 8;
/// Re-solves at full load when the loads' wake membership changed at the equilibrium
/// (docs/theory/fem.md#static-solver).
const MAX_WAKE_PASSES: usize = 5;
/// At full load the iterate is handed to the loads once, when ‖r‖ first falls to this fraction
/// of F_ref, so that their discontinuous data (wake membership) are those of a state near the
/// equilibrium before Newton converges (12 static cases: 1 174 iterations without, 1 087 at
/// 0.1, 1 128 at 0.01, 1 094 at 0.3; docs/theory/fem.md#static-solver).
const FOLLOW_LOADS_RESIDUAL: f64 = 0.1;

/// A step is accepted when the merit falls by this fraction of the predicted decrease.
const RHO_ACCEPT: f64 = 1e-4;
/// Round-off level of the equilibrium (F_noise) above which the solve warns, relative to
/// the loads (`round_off_warning`).
const NOISE_WARNING: f64 = 1e-4;
/// A full step the merit rejects is taken on trial (watchdog) only if its residual is at most
/// this multiple of the iterate's.
const WATCH_GROWTH: f64 = 1e3;

/// The watchdog acts only once μ is this small, in Newton's regime, where the merit's
/// rejection of full steps is the Maratos effect (measured on 12 static cases: total
/// iterations 1 288 without the watchdog, 1 129 at 1e-7, 1 316 at any μ;
/// docs/theory/fem.md#watchdog).
const WATCH_MAX_MU: f64 = 1e-7;

/// ... and only while ‖r‖ ≥ this fraction of F_ref: closer to the solution the plain
/// iteration converges on its own, and trial steps there would only blur its last iterations.
const WATCH_MIN_RESIDUAL: f64 = 1e-2;

/// Verdict on a trial step.
enum Trial {
    /// Accepted, with the ratio to steer μ by.
    Accept(f64),
    /// Full step rejected by the merit but taken on trial; its predicted decrease [J].
    Watch(f64),
    /// No point along the step was acceptable.
    Reject,
}

/// The iterate a watched (trial) step left from, kept to check and undo it.
struct Watched {
    x: Vec<[f64; 3]>,
    len: Vec<f64>,
    bend: f64,
    f_frozen: Vec<f64>,
    r_x: Vec<f64>,
    dx: Vec<f64>,
    step: (f64, f64, f64),
    rn: f64,
    pred: f64,
    merit_noise: f64,
}

struct Ctx<'m, 'p, 'o, P: LoadProvider + ?Sized> {
    model: &'m Model,
    prov: &'p mut P,
    sys: System,
    st: StaticSettings,
    x: Vec<[f64; 3]>,
    zero: Vec<[f64; 3]>,
    /// The nodal part of the damping matrix D [N/m]: Σ EA/L0 at each node, or with
    /// `stretch_damping` the net triangles' and links' diagonal plus `NODAL_SHARE` of it
    /// (`damping_diagonal`), the line elements then adding their stretch,
    /// Σ_e (EA/L0)·|Δx_a − Δx_b|², in `damped_step`.
    d_node: Vec<f64>,
    /// External force without the seabed on the free DOFs at the iterate (one end of the
    /// merit's trapezoidal work) [N].
    f_frozen: Vec<f64>,
    /// Element lengths at the iterate [m].
    len_x: Vec<f64>,
    /// Bending energy of the hinges at the iterate [J].
    bend_x: f64,
    /// Free residual at the iterate (kept while trial points overwrite `r`) [N].
    r_x: Vec<f64>,
    r: Vec<f64>,
    dx: Vec<f64>,
    x_trial: Vec<[f64; 3]>,
    f_ref: f64,
    f_floor: f64,
    /// Round-off level of ‖r‖₂ at the current iterate [N] (see `noise_floor`).
    f_noise: f64,
    /// Round-off level of the merit's change from the iterate [J] (`merit_round_off`); below
    /// it the residual judges a step instead of the merit.
    merit_noise: f64,
    noise_buf: Vec<f64>,
    l_ref: f64,
    iterations: usize,
    rejected_steps: usize,
    backtracked_steps: usize,
    /// Progress reported so far (load factor, damping).
    progress: StaticProgress,
    history: Vec<f64>,
    /// Backtracking along rejected steps is off (the retry of a failed increment, see
    /// `solve_static_observed`).
    no_backtracking: bool,
    observer: &'o mut dyn FnMut(&StaticProgress) -> StaticControl,
}

/// The warning that the equilibrium's forces are exact only to F_noise [N], when that is more
/// than `NOISE_WARNING` of the loads: the external forces `fext` at the equilibrium, or the
/// weights and point forces alone where buoyancy cancels them (a neutral line).
fn round_off_warning(
    model: &Model,
    fext: &[[f64; 3]],
    f_noise: f64,
    max_ea: f64,
) -> Option<String> {
    let (mut fe, mut fw) = (0.0, 0.0);
    for ((f, w), p) in fext.iter().zip(&model.weight).zip(&model.point_force) {
        for k in 0..3 {
            fe += f[k] * f[k];
            fw += (w[k] + p[k]).powi(2);
        }
    }
    let loads = fe.sqrt().max(fw.sqrt());
    (f_noise > NOISE_WARNING * loads).then(|| {
        format!(
            "the static equilibrium's forces at the nodes are exact only to about {f_noise:.3e} N \
             ({:.2} % of the loads, {loads:.3e} N), and resultants such as reactions may be \
             several times further off: tensions are EA times a length difference, and with EA \
             up to {max_ea:.3e} N their round-off is that large; a smaller EA (a line this stiff \
             is rigid either way) gives the same shape with exact forces",
            100.0 * f_noise / loads,
        )
    })
}

/// Solves for static equilibrium starting from the as-built geometry.
pub fn solve_static<P: LoadProvider + ?Sized>(
    model: &Model,
    provider: &mut P,
    settings: &StaticSettings,
) -> Result<StaticSolution> {
    solve_static_observed(model, provider, settings, &mut |_| StaticControl::Continue)
}

/// [`solve_static`] that reports every Newton iteration to `observer` (progress display,
/// Ctrl-C). When the observer answers [`StaticControl::Stop`] the solve returns the last
/// accepted state (outputs evaluated there) with `report.interrupted = true`.
pub fn solve_static_observed<P: LoadProvider + ?Sized>(
    model: &Model,
    provider: &mut P,
    settings: &StaticSettings,
    observer: &mut dyn FnMut(&StaticProgress) -> StaticControl,
) -> Result<StaticSolution> {
    solve_static_from(model, provider, settings, None, observer)
}

/// [`solve_static_observed`] from the node positions `start` [m] instead of the as-built
/// geometry (e.g. the equilibrium of a coarser mesh carried to this one,
/// docs/theory/fem.md#mesh-sequencing); constrained DOFs keep their prescribed positions.
/// `None` starts from the as-built geometry.
pub fn solve_static_from<P: LoadProvider + ?Sized>(
    model: &Model,
    provider: &mut P,
    settings: &StaticSettings,
    start: Option<&[[f64; 3]]>,
    observer: &mut dyn FnMut(&StaticProgress) -> StaticControl,
) -> Result<StaticSolution> {
    settings.validate()?;
    if let Some(x0) = start {
        if x0.len() != model.n_nodes() {
            return Err(invalid(
                "static start positions (nodes)",
                x0.len() as f64,
                "one position per node of the model",
            ));
        }
        if x0.iter().flatten().any(|v| !v.is_finite()) {
            return Err(FemError::NonFinite("static start positions".into()));
        }
    }
    let part = parts(model, &*provider);
    check_supported(model, &*provider, &part)?;
    check_held_up(model, &*provider, &part)?;
    let sys = System::new(model, &*provider)?;
    let n = model.n_nodes();
    let nf = sys.n_free();
    let max_ea = model.max_axial_stiffness();
    let wsum: f64 = model.weight.iter().map(|w| w[2].abs()).sum::<f64>()
        + model
            .point_force
            .iter()
            .map(|f| f.iter().map(|c| c.abs()).sum::<f64>())
            .sum::<f64>();
    let mut ctx = Ctx {
        model,
        prov: provider,
        sys,
        st: settings.clone(),
        x: start.map_or_else(|| model.nodes().to_vec(), <[[f64; 3]]>::to_vec),
        zero: vec![[0.0; 3]; n],
        d_node: if settings.stretch_damping {
            damping_diagonal(model)
        } else {
            node_axial_stiffness(model)
        },
        f_frozen: vec![0.0; nf],
        len_x: vec![0.0; model.elements().len()],
        bend_x: 0.0,
        r_x: vec![0.0; nf],
        r: vec![0.0; nf],
        dx: vec![0.0; nf],
        x_trial: vec![[0.0; 3]; n],
        f_ref: 1.0,
        f_floor: (1e-6 * wsum).max(1e-9 * max_ea).max(1e-12),
        f_noise: 0.0,
        merit_noise: 0.0,
        noise_buf: vec![0.0; n],
        l_ref: model.mean_length,
        iterations: 0,
        rejected_steps: 0,
        backtracked_steps: 0,
        progress: StaticProgress {
            load_factor: 0.0,
            damping: settings.stabilisation,
            iteration: 0,
            relative_residual: f64::NAN,
        },
        history: Vec::new(),
        no_backtracking: false,
        observer,
    };
    // A part that nothing holds horizontally cannot balance a horizontal load: say so now
    // instead of after hundreds of iterations of drift.
    ctx.eval(1.0, false, false)?;
    check_held_horizontally(model, &part, &ctx.sys.fext)?;
    let mut report = StaticReport::default();
    let t = settings.time;
    let mut mu = settings.stabilisation;
    let mut s_acc = 0.0;
    let mut ds = 1.0 / settings.load_steps as f64;
    let mut x_acc = ctx.x.clone();
    let mut wake_passes = 0;
    let mut s_stop = 0.0;
    loop {
        let s = if s_acc + ds > 1.0 - 1e-12 {
            1.0
        } else {
            s_acc + ds
        };
        ctx.x.copy_from_slice(&x_acc);
        apply_constraints(model, t, s, &mut ctx.x);
        ctx.progress.load_factor = s;
        // The loads follow the iterate in full-load solves before the first wake pass: a wake
        // pass starts from an equilibrium they have just seen.
        match ctx.levenberg_marquardt(s, &mut mu, s >= 1.0 && wake_passes == 0) {
            Ok((iters, hist)) => {
                report.last_residual_history = hist;
                report.increments += 1;
                x_acc.copy_from_slice(&ctx.x);
                s_acc = s;
                if s >= 1.0 {
                    // The wake follows the equilibrium: re-solve while it changes. After
                    // MAX_WAKE_PASSES re-solves the last wake is kept (frozen) and solved for
                    // once more, so the state is the equilibrium of the wake it reports.
                    if wake_passes > MAX_WAKE_PASSES
                        || !crate::loads::accept_state(&mut *ctx.prov, t, &ctx.x)?
                    {
                        break;
                    }
                    if wake_passes == MAX_WAKE_PASSES {
                        report.warnings.push(format!(
                            "the wake still changed after {MAX_WAKE_PASSES} re-solves at full \
                             load; it is frozen as of the last equilibrium and the state is \
                             the equilibrium of that frozen wake (docs/theory/fem.md#static-solver)"
                        ));
                    }
                    wake_passes += 1;
                    continue;
                }
                if iters <= 10 {
                    ds = (2.0 * ds).min(1.0 - s_acc);
                }
            }
            Err(NewtonFail { fatal: Some(e), .. }) => return Err(*e),
            Err(f) if f.stopped => {
                // The last accepted iterate of this increment (not the last converged
                // increment: with the full load at once that would be the start).
                report.interrupted = true;
                s_stop = s;
                break;
            }
            Err(_) if settings.line_search && !ctx.no_backtracking => {
                // With loads that have no potential, backtracked steps (which keep μ small) may
                // circle the equilibrium: the increment is solved once more from the same start
                // with full damped steps only, before any load step is halved
                // (docs/theory/fem.md#static-solver).
                report.rejected_increments += 1;
                ctx.no_backtracking = true;
                mu = settings.stabilisation;
            }
            Err(f) => {
                ctx.no_backtracking = false;
                report.rejected_increments += 1;
                ds *= 0.5;
                if ds < settings.min_load_step {
                    return Err(ctx.failure(s, ds, f));
                }
                mu = mu.max(settings.stabilisation);
            }
        }
    }
    // Final evaluation for outputs at the equilibrium (or last accepted) state.
    let s_out = if report.interrupted { s_stop } else { 1.0 };
    ctx.eval(s_out, false, false)?;
    let mut outputs = Outputs::new(model);
    outputs.update(model, &ctx.sys, false);
    let rn = ctx.residual(false);
    report.iterations = ctx.iterations;
    report.rejected_steps = ctx.rejected_steps;
    report.backtracked_steps = ctx.backtracked_steps;
    report.residual_history = std::mem::take(&mut ctx.history);
    report.f_ref = ctx.f_ref;
    report.load_factor = s_out;
    report.relative_residual = rn / ctx.f_ref;
    report.noise_level = ctx.f_noise / ctx.f_ref;
    report.block_solve = ctx.sys.block_solve_shape();
    if !report.interrupted {
        report
            .warnings
            .extend(round_off_warning(model, &ctx.sys.fext, ctx.f_noise, max_ea));
    }
    if ctx.x.iter().flatten().any(|v| !v.is_finite()) {
        return Err(FemError::NonFinite("static solution positions".into()));
    }
    let state = State {
        t,
        x: ctx.x,
        v: vec![[0.0; 3]; n],
        a: vec![[0.0; 3]; n],
    };
    Ok(StaticSolution {
        state,
        outputs,
        report,
    })
}

/// The nodal part of the Levenberg–Marquardt stretch damping [N/m]
/// (docs/theory/fem.md#stretch-damping):
/// the net triangles' and rigid links' diagonal, which the line elements' stretch damping
/// leaves out, plus `NODAL_SHARE` of the whole nodal diagonal Σ EA/L0.
fn damping_diagonal(model: &Model) -> Vec<f64> {
    let full = node_axial_stiffness(model);
    let mut d = full.clone();
    for e in model.elements().iter().filter(|e| e.l0 > 0.0) {
        d[e.a] -= e.ea / e.l0;
        d[e.b] -= e.ea / e.l0;
    }
    d.iter()
        .zip(&full)
        .map(|(v, f)| v.max(0.0) + NODAL_SHARE * f)
        .collect()
}

/// Σ EA/L0 over the elements at each node [N/m].
fn node_axial_stiffness(model: &Model) -> Vec<f64> {
    let mut d = vec![0.0; model.n_nodes()];
    for e in model.elements() {
        d[e.a] += e.ea / e.l0;
        d[e.b] += e.ea / e.l0;
    }
    // Net triangles: the diagonal of their taut stiffness, A_uv·(a_k² + b_k²)·EA/l_p.
    for t in model.net_triangles() {
        let (gu, gv) = t.shape_gradients();
        let k = t.uv_area() * t.twine.ea / t.twine.l0;
        for (j, &nd) in t.nodes.iter().enumerate() {
            d[nd] += k * (gu[j] * gu[j] + gv[j] * gv[j]);
        }
    }
    // Rigid links: k on the point and the centre, k·|p|² on the rotation carrier.
    for l in &model.links {
        let p2: f64 = l.offset.iter().map(|c| c * c).sum();
        d[l.node] += l.stiffness;
        d[l.centre] += l.stiffness;
        d[l.rotation] += l.stiffness * p2.max(1.0);
    }
    d
}

fn apply_constraints(model: &Model, t: f64, s: f64, x: &mut [[f64; 3]]) {
    let n = x.len();
    let mut v = vec![[0.0; 3]; n];
    let mut a = vec![[0.0; 3]; n];
    model.apply_constraints(t, s, x, &mut v, &mut a);
}

impl<P: LoadProvider + ?Sized> Ctx<'_, '_, '_, P> {
    /// Evaluates forces at `self.x` or `self.x_trial`, with the static tangent if `jac`.
    fn eval(&mut self, s: f64, trial: bool, jac: bool) -> Result<()> {
        let o = EvalOptions {
            t: self.st.time,
            load_scale: s,
            dynamic: false,
            jacobian: jac.then_some(Coef {
                m: 0.0,
                k: 1.0,
                c: 0.0,
            }),
            inertia: false,
            consistent_mass: false,
            rayleigh: (0.0, 0.0),
            fd_dfdx: self.st.fd_position_jacobian,
            clamp_geometric: true,
        };
        let x = if trial { &self.x_trial } else { &self.x };
        self.sys
            .evaluate(self.model, &mut *self.prov, x, &self.zero, &self.zero, &o)
    }

    /// Fills `self.r` (free residual at `self.x` or `self.x_trial`, from the last evaluation)
    /// and updates F_ref; returns ‖r‖₂.
    fn residual(&mut self, trial: bool) -> f64 {
        let mut rn = 0.0;
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            let r = self.sys.q[gd / 3][gd % 3];
            self.r[f] = r;
            rn += r * r;
        }
        let fe: f64 = self.sys.fext.iter().flatten().map(|f| f * f).sum();
        self.f_ref = fe.sqrt().max(self.f_floor);
        self.f_noise = self.noise_floor(trial);
        let rn = rn.sqrt();
        if rn.is_finite() { rn } else { f64::INFINITY }
    }

    /// Round-off level of the free residual: a tension computed from a length difference is
    /// exact only to about ε_mach·EA·(max(|x_a|, |x_b|) + L0)/L0, so ‖r‖₂ cannot fall much below
    /// the root sum of squares of these over the elements at free nodes (×2 margin). With it
    /// the test ‖r‖ ≤ max(tol·F_ref, F_noise) reaches the arithmetic's limit on any EA instead
    /// of stalling near 1e-8·F_ref for EA = 1e10 (docs/theory/fem.md#static-solver).
    fn noise_floor(&mut self, trial: bool) -> f64 {
        let x = if trial { &self.x_trial } else { &self.x };
        let noise = &mut self.noise_buf;
        noise.iter_mut().for_each(|v| *v = 0.0);
        for e in self.model.elements() {
            let xa = x[e.a].iter().fold(0.0f64, |m, c| m.max(c.abs()));
            let xb = x[e.b].iter().fold(0.0f64, |m, c| m.max(c.abs()));
            let t = f64::EPSILON * e.ea * (xa.max(xb) + e.l0) / e.l0;
            noise[e.a] += t * t;
            noise[e.b] += t * t;
        }
        for tr in self.model.net_triangles() {
            let xm = tr
                .nodes
                .iter()
                .flat_map(|&nd| x[nd])
                .fold(0.0f64, |m, c| m.max(c.abs()));
            let (gu, gv) = tr.shape_gradients();
            let l = tr.twine.l0;
            let t = f64::EPSILON
                * tr.twine.ea
                * (xm * gu.iter().chain(&gv).map(|g| g.abs()).sum::<f64>() + l)
                / l;
            for (j, &nd) in tr.nodes.iter().enumerate() {
                let f = tr.uv_area() * t * (gu[j].abs() + gv[j].abs());
                noise[nd] += f * f;
            }
        }
        // Rigid links: x_p − x_c − R·p is exact to about ε_mach·(max(|x_p|, |x_c|) + |p|).
        for l in &self.model.links {
            let xm = [x[l.node], x[l.centre]]
                .iter()
                .flatten()
                .fold(0.0f64, |m, c| m.max(c.abs()));
            let p = l.offset.iter().map(|c| c * c).sum::<f64>().sqrt();
            let t = f64::EPSILON * l.stiffness * (xm + p);
            noise[l.node] += t * t;
            noise[l.centre] += t * t;
            noise[l.rotation] += (t * p) * (t * p);
        }
        let mut s2 = 0.0;
        for &gd in &self.sys.dof_of_free {
            s2 += noise[gd / 3];
        }
        2.0 * s2.sqrt()
    }

    /// Stores what the merit and a rejected step need at the iterate, from the last
    /// evaluation and residual at `self.x`: element lengths, bending energy, the external force
    /// without the seabed, and the residual.
    fn freeze(&mut self) {
        for (l, c) in self.len_x.iter_mut().zip(&self.sys.cable) {
            *l = c.length;
        }
        self.bend_x = self.sys.element_energy();
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            let (i, k) = (gd / 3, gd % 3);
            self.f_frozen[f] = self.sys.fext[i][k] - self.sys.fbed[i][k];
        }
        self.merit_noise = self.merit_round_off();
        self.r_x.copy_from_slice(&self.r);
    }

    /// Round-off level of a merit change from the iterate [J] (after `freeze`): a length is
    /// computed from coordinates to about ε_mach·(max(|x_a|, |x_b|) + l), so a strain energy
    /// difference is exact only to T times that, plus ε_mach·W; the frozen work's terms
    /// f·(x_t − x) to ε_mach·|f|·|x| (×8 margin).
    fn merit_round_off(&self) -> f64 {
        let mut sum = self.bend_x.abs();
        for ((e, c), &l) in self
            .model
            .elements()
            .iter()
            .zip(&self.sys.cable)
            .zip(&self.len_x)
        {
            let xa = self.x[e.a].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let xb = self.x[e.b].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            sum += c.tension.abs() * (xa.max(xb) + l) + cable::strain_energy(e, (l - e.l0) / e.l0);
        }
        for (t, ev) in self.model.net_triangles().iter().zip(&self.sys.net) {
            let xm = t
                .nodes
                .iter()
                .flat_map(|&nd| self.x[nd])
                .fold(0.0f64, |m, c| m.max(c.abs()));
            let (gu, gv) = t.shape_gradients();
            let su: f64 = gu.iter().map(|g| g.abs()).sum();
            let sv: f64 = gv.iter().map(|g| g.abs()).sum();
            sum += t.uv_area()
                * (ev.u.tension.abs() * (xm * su + ev.u.length)
                    + ev.v.tension.abs() * (xm * sv + ev.v.length));
        }
        for (l, ev) in self.model.links.iter().zip(&self.sys.link) {
            let xm = [self.x[l.node], self.x[l.centre]]
                .iter()
                .flatten()
                .fold(0.0f64, |m, c| m.max(c.abs()));
            let p = l.offset.iter().map(|c| c * c).sum::<f64>().sqrt();
            sum += l.stiffness * ev.stretch * (xm + p);
        }
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            sum += self.f_frozen[f].abs() * self.x[gd / 3][gd % 3].abs();
        }
        8.0 * f64::EPSILON * sum
    }

    /// Decrease of the merit from `self.x` to `self.x_trial` (evaluated): strain (axial and
    /// bending, docs/theory/fem.md#bending) and seabed energy exactly, the work of the other
    /// external forces by the trapezoidal rule between `self.x` and the trial, so that its
    /// gradient at `self.x` is the residual (docs/theory/fem.md#static-solver). Positive when
    /// the trial is better.
    fn merit_decrease(&self) -> f64 {
        self.merit_decrease_from(&self.x, &self.len_x, self.bend_x, &self.f_frozen)
    }

    /// Merit decrease from a base point (positions, element lengths, bending energy and
    /// external force there) to `self.x_trial` (evaluated).
    fn merit_decrease_from(&self, x0: &[[f64; 3]], len0: &[f64], bend0: f64, f0: &[f64]) -> f64 {
        let mut dw = self.sys.element_energy() - bend0;
        for ((e, c), &l_x) in self.model.elements().iter().zip(&self.sys.cable).zip(len0) {
            dw += cable::strain_energy(e, (c.length - e.l0) / e.l0)
                - cable::strain_energy(e, (l_x - e.l0) / e.l0);
        }
        if self.model.env.seabed.is_some() {
            let bed = BedLaw::new(self.model, false);
            for i in 0..self.model.n_nodes() {
                dw += bed.energy_change(self.model, i, x0[i][2], self.x_trial[i][2]);
            }
        }
        // Work of the other external forces by the trapezoidal rule between the base point and
        // the trial: their change along the step counts to first order, as in the quadratic
        // model, whose tangent holds the water loads' ∂f/∂x.
        let mut work = 0.0;
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            let (i, k) = (gd / 3, gd % 3);
            let f_trial = self.sys.fext[i][k] - self.sys.fbed[i][k];
            work += 0.5 * (f0[f] + f_trial) * (self.x_trial[i][k] - x0[i][k]);
        }
        work - dw
    }

    /// Reports the iterate to the observer and records ‖r‖/F_ref; `Err` when told to stop.
    fn observe(
        &mut self,
        rn: f64,
        mu: f64,
        hist: &mut Vec<f64>,
    ) -> std::result::Result<(), NewtonFail> {
        hist.push(rn / self.f_ref);
        self.history.push(rn / self.f_ref);
        self.progress.iteration = self.iterations;
        self.progress.relative_residual = rn / self.f_ref;
        self.progress.damping = mu;
        if (self.observer)(&self.progress) == StaticControl::Stop {
            return Err(NewtonFail {
                reason: FailureReason::Interrupted,
                history: hist.clone(),
                stopped: true,
                fatal: None,
            });
        }
        Ok(())
    }

    /// Solves (J + μD)Δx = −r at the iterate into `self.dx`, raising the μ on the diagonal
    /// from `mu_in`. Returns (r·Δx, ΔxᵀJΔx, step scale) or `None` if the matrix is singular.
    fn damped_step(&mut self, mu: f64, mu_in: f64) -> Option<(f64, f64, f64)> {
        let dmu = mu - mu_in;
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            let p = self.sys.diag_pos[f];
            self.sys.values[p] += dmu * self.d_node[gd / 3];
        }
        // With `stretch_damping`, the line elements' stretch: (EA/L0)·[I −I; −I I] on their
        // two nodes.
        let stretch = if self.st.stretch_damping {
            self.model.elements()
        } else {
            &[]
        };
        for (e, pos) in stretch.iter().zip(&self.sys.cable_pos) {
            if e.l0 <= 0.0 {
                continue;
            }
            let k = dmu * e.ea / e.l0;
            for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let kij = if i == j { k } else { -k };
                for c in 0..3 {
                    let q = pos[(3 * i + c) * 6 + 3 * j + c];
                    if q != NONE {
                        self.sys.values[q] += kij;
                    }
                }
            }
        }
        self.iterations += 1;
        if self.sys.factorize().is_err() {
            return None;
        }
        for (d, r) in self.dx.iter_mut().zip(&self.r_x) {
            *d = -r;
        }
        if self.sys.solve(&mut self.dx).is_err() || self.dx.iter().any(|d| !d.is_finite()) {
            return None;
        }
        let mut a = 0.0;
        let mut ddd = 0.0;
        let mut dmax: f64 = 0.0;
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            a += self.r_x[f] * self.dx[f];
            ddd += self.d_node[gd / 3] * self.dx[f] * self.dx[f];
            dmax = dmax.max(self.dx[f].abs());
        }
        let free = &self.sys.free_of_dof;
        let dx = &self.dx;
        let move_of = |node: usize, c: usize| match free[3 * node + c] {
            NONE => 0.0,
            f => dx[f],
        };
        for e in stretch.iter().filter(|e| e.l0 > 0.0) {
            for c in 0..3 {
                ddd += e.ea / e.l0 * (move_of(e.a, c) - move_of(e.b, c)).powi(2);
            }
        }
        // (J + μD)Δx = −r ⇒ ΔxᵀJΔx = −r·Δx − μ·ΔxᵀDΔx. Step cap: no DOF moves more than L_ref.
        let sc = if dmax > self.l_ref {
            self.l_ref / dmax
        } else {
            1.0
        };
        Some((a, -a - mu * ddd, sc))
    }

    /// Tries x + λ·Δx for λ = 1, ½, ¼, … from λ = 2^-first (only λ = 1 without
    /// `line_search`). Accepts the first point whose merit decrease is at least `RHO_ACCEPT` of
    /// the quadratic model's, or whose residual fell tenfold. With `watch`, a full step that
    /// the merit rejects is taken on trial instead (`Trial::Watch`, see `levenberg_marquardt`).
    /// `Trial::Accept` carries the ratio to steer μ by (½ after backtracking: keep μ), with
    /// `self.x_trial`, `self.r` evaluated there.
    fn try_step(
        &mut self,
        s: f64,
        rn: f64,
        (a, b, sc): (f64, f64, f64),
        first: usize,
        watch: bool,
    ) -> Trial {
        let tries = if self.st.line_search && !self.no_backtracking {
            BACKTRACKS + 1
        } else {
            1
        };
        let mut lam = sc * 0.5f64.powi(first as i32);
        for k in first..tries {
            self.x_trial.copy_from_slice(&self.x);
            for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
                self.x_trial[gd / 3][gd % 3] += lam * self.dx[f];
            }
            if self.eval(s, true, false).is_ok() {
                let rt = self.residual(true);
                let pred = -lam * a - 0.5 * lam * lam * b;
                let rho = self.merit_decrease() / pred;
                // A predicted change below the merit's round-off cannot be judged by the
                // merit (very stiff taut members: W ≫ r·Δx); the residual judges it then.
                let noisy = pred.abs() <= self.merit_noise;
                let merit_ok = if noisy {
                    rt < rn
                } else {
                    pred > 0.0 && rho > RHO_ACCEPT
                };
                if rt.is_finite() && (merit_ok || rt <= 0.1 * rn) {
                    if k > 0 {
                        self.backtracked_steps += 1;
                        return Trial::Accept(0.5);
                    }
                    return Trial::Accept(if noisy {
                        1.0
                    } else if pred > 0.0 && rho.is_finite() && rho > 0.0 {
                        rho
                    } else {
                        0.5
                    });
                }
                if k == 0 && watch && pred > 0.0 && rt.is_finite() && rt <= WATCH_GROWTH * rn {
                    return Trial::Watch(pred);
                }
            }
            lam *= 0.5;
        }
        Trial::Reject
    }

    /// Levenberg–Marquardt Newton at load factor s from `self.x` (docs/theory/fem.md#static-solver):
    /// (J + μD)Δx = −r with D = Σ EA/L0 per node; a step is accepted on the energy merit,
    /// μ follows Nielsen's rule (μ·max(⅓, 1 − (2ρ − 1)³) after success, ×ν, ν doubling, after
    /// a rejection), so μ → 0 and the steps become Newton's near the solution. Returns
    /// (iterations, ‖r‖/F_ref history).
    /// With `follow`, the loads see the iterate once on the way (`follow_loads`).
    fn levenberg_marquardt(
        &mut self,
        s: f64,
        mu: &mut f64,
        follow: bool,
    ) -> std::result::Result<(usize, Vec<f64>), NewtonFail> {
        let mut hist = Vec::new();
        let fail = |reason: FailureReason, hist: &Vec<f64>| NewtonFail {
            reason,
            history: hist.clone(),
            stopped: false,
            fatal: None,
        };
        if let Err(e) = self.eval(s, false, true) {
            return Err(fail(e.into(), &hist));
        }
        let xtol = 1e-6 * self.l_ref;
        let start = self.iterations;
        let mut dx_last = f64::INFINITY;
        let mut rn = self.residual(false);
        let mut watched: Option<Watched> = None;
        let mut watch_ok = self.st.watchdog;
        // The loads' discontinuous data follow the iterate once, near the equilibrium.
        let mut followed = !follow;
        loop {
            if let Err(stop) = self.observe(rn, *mu, &mut hist) {
                // A watched step is on trial, not accepted: stop at the iterate it left.
                if let Some(w) = watched.take() {
                    self.x = w.x;
                }
                return Err(stop);
            }
            if !rn.is_finite() {
                return Err(fail(FailureReason::NonFiniteResidual, &hist));
            }
            let tol = self.st.tol * self.f_ref;
            if watched.is_none() && ((rn <= tol && dx_last <= xtol) || rn <= self.f_noise) {
                return Ok((self.iterations - start, hist));
            }
            if !followed && watched.is_none() && rn <= FOLLOW_LOADS_RESIDUAL * self.f_ref {
                followed = true;
                if self.follow_loads(s, &hist)? {
                    rn = self.residual(false);
                    dx_last = f64::INFINITY;
                    continue;
                }
            }
            self.freeze();
            let mut nu = 2.0;
            let mut mu_in = 0.0;
            let verdict = loop {
                if self.iterations - start >= self.st.max_iter {
                    return Err(fail(
                        FailureReason::NoConvergence {
                            iterations: self.st.max_iter,
                        },
                        &hist,
                    ));
                }
                let step = self.damped_step(*mu, mu_in);
                mu_in = *mu;
                if let Some(step) = step {
                    let allow = watch_ok
                        && watched.is_none()
                        && *mu <= WATCH_MAX_MU
                        && rn >= WATCH_MIN_RESIDUAL * self.f_ref;
                    match self.try_step(s, rn, step, 0, allow) {
                        Trial::Reject => {}
                        Trial::Accept(rho) => break Some(rho),
                        Trial::Watch(pred) => {
                            watched = Some(Watched {
                                x: self.x.clone(),
                                len: self.len_x.clone(),
                                bend: self.bend_x,
                                f_frozen: self.f_frozen.clone(),
                                r_x: self.r_x.clone(),
                                dx: self.dx.clone(),
                                step,
                                rn,
                                pred,
                                merit_noise: self.merit_noise,
                            });
                            break None;
                        }
                    }
                }
                if let Some(w) = watched.take() {
                    // The step after a watched one failed: undo the watched step.
                    break self.undo_watched(s, w);
                }
                self.rejected_steps += 1;
                *mu = (*mu * nu).max(MU_RESTART);
                nu *= 2.0;
                if *mu > MU_MAX {
                    return Err(fail(FailureReason::DampingExhausted, &hist));
                }
            };
            let verdict = match (verdict, watched.take()) {
                (Some(rho), Some(w)) => self.judge_watched(s, rho, w),
                (v, w) => {
                    watched = w;
                    v
                }
            };
            match verdict {
                Some(rho) => {
                    *mu = (*mu * (1.0f64 / 3.0).max(1.0 - (2.0 * rho.min(1.0) - 1.0).powi(3)))
                        .max(MU_MIN);
                    watch_ok = self.st.watchdog;
                }
                None if watched.is_some() => {}
                None => {
                    // Undone and nothing along the step acceptable: raise μ and start again
                    // from the iterate, without a watched step.
                    self.rejected_steps += 1;
                    *mu = (*mu * 2.0).max(MU_RESTART);
                    watch_ok = false;
                    if let Err(e) = self.eval(s, false, true) {
                        return Err(fail(e.into(), &hist));
                    }
                    rn = self.residual(false);
                    dx_last = f64::INFINITY;
                    continue;
                }
            }
            dx_last = 0.0;
            for (xt, x) in self.x_trial.iter().zip(&self.x) {
                for k in 0..3 {
                    dx_last = dx_last.max((xt[k] - x[k]).abs());
                }
            }
            std::mem::swap(&mut self.x, &mut self.x_trial);
            if let Err(e) = self.eval(s, false, true) {
                return Err(fail(e.into(), &hist));
            }
            rn = self.residual(false);
        }
    }

    /// Hands the iterate to the loads (`LoadProvider::accept_state`) before convergence, so
    /// that their discontinuous data (wake membership) are those of a shape near the
    /// equilibrium (docs/theory/fem.md#static-solver). Returns whether they changed; the
    /// forces and tangent at the iterate are then evaluated anew.
    fn follow_loads(&mut self, s: f64, hist: &[f64]) -> std::result::Result<bool, NewtonFail> {
        let fatal = |e: FemError| NewtonFail {
            reason: e.clone().into(),
            history: hist.to_vec(),
            stopped: false,
            fatal: Some(Box::new(e)),
        };
        if !crate::loads::accept_state(&mut *self.prov, self.st.time, &self.x).map_err(fatal)? {
            return Ok(false);
        }
        self.eval(s, false, true).map_err(fatal)?;
        Ok(true)
    }

    /// The step after a watched one was accepted at `self.x_trial`: keeps both if together
    /// they lower the merit frozen at the iterate the watched step left from (or its residual
    /// tenfold), else undoes the watched step.
    fn judge_watched(&mut self, s: f64, rho: f64, w: Watched) -> Option<f64> {
        let rt = self.residual(true);
        let dec = self.merit_decrease_from(&w.x, &w.len, w.bend, &w.f_frozen);
        // Below the merit's round-off the residual judges the pair (see `try_step`).
        let merit_ok = if w.pred.abs() <= w.merit_noise {
            rt < w.rn
        } else {
            dec >= RHO_ACCEPT * w.pred
        };
        if merit_ok || rt <= 0.1 * w.rn {
            Some(rho)
        } else {
            self.undo_watched(s, w)
        }
    }

    /// Undoes a watched step: puts the iterate it left from back, with its frozen merit data
    /// and step, and backtracks along that step from ½ (evaluations only). Returns the ratio to
    /// steer μ by, or `None` (with `self.x` at that iterate) if nothing along it is acceptable.
    fn undo_watched(&mut self, s: f64, w: Watched) -> Option<f64> {
        self.x = w.x;
        self.len_x = w.len;
        self.bend_x = w.bend;
        self.f_frozen = w.f_frozen;
        self.r_x = w.r_x;
        self.dx = w.dx;
        self.merit_noise = w.merit_noise;
        match self.try_step(s, w.rn, w.step, 1, false) {
            Trial::Accept(rho) => Some(rho),
            _ => None,
        }
    }

    fn failure(&mut self, s: f64, ds: f64, f: NewtonFail) -> FemError {
        // Worst node from the current residual.
        let _ = self.eval(s, false, false);
        let _ = self.residual(false);
        let mut worst = (0usize, 0.0f64);
        let mut node_r = vec![0.0; self.model.n_nodes()];
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            node_r[gd / 3] += self.r[f] * self.r[f];
        }
        for (i, r) in node_r.iter().enumerate() {
            if r.sqrt() > worst.1 || !r.is_finite() {
                worst = (i, r.sqrt());
            }
        }
        FemError::StaticFailed(Box::new(crate::error::StaticFailure {
            load_factor: s,
            increment: ds,
            min_increment: self.st.min_load_step,
            reason: f.reason,
            worst_node: worst.0,
            worst_position: self.x[worst.0],
            worst_residual: worst.1,
            f_ref: self.f_ref,
            history: f.history,
        }))
    }
}
