//! Static equilibrium: Newton with load continuation, pseudo-viscous stabilisation, an
//! optional line search (off by default) and a round-off convergence floor
//! (docs/theory/fem.md#static-solver).

use crate::error::{FemError, Result, invalid};
use crate::loads::LoadProvider;
use crate::model::Model;
use crate::state::{Outputs, State};
use crate::system::{Coef, EvalOptions, NONE, System};
use serde::{Deserialize, Serialize};

/// Settings of the static solver (scene keys of `[analysis.static]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StaticSettings {
    /// Relative force tolerance ε_r (‖r‖₂ ≤ ε_r·F_ref). Default 1e-6.
    pub tol: f64,
    /// Newton iterations per increment. Default 30.
    pub max_iter: usize,
    /// Initial number of load increments (Δs0 = 1/load_steps). Default 4.
    pub load_steps: usize,
    /// Smallest load increment before failing. Default 1e-4.
    pub min_load_step: f64,
    /// Pseudo-viscous stabilisation ε_s (0 disables). Default 1e-3.
    pub stabilisation: f64,
    /// Backtracking line search on ‖r‖₂. Default false: the norm is dominated by stiff axial
    /// residuals, and cutting steps on it tripled the iterations of the reference cage (6297
    /// with, 2242 without, same equilibrium; docs/theory/fem.md#static-solver).
    pub line_search: bool,
    /// Most pseudo-steps after full load. Default 2000.
    pub max_pseudo_steps: usize,
    /// Time at which loads and prescribed offsets are evaluated [s]. Default 0.
    pub time: f64,
    /// Form missing water-load position derivatives by finite differences. Default true.
    pub fd_position_jacobian: bool,
}

impl Default for StaticSettings {
    fn default() -> Self {
        Self {
            tol: 1e-6,
            max_iter: 30,
            load_steps: 4,
            min_load_step: 1e-4,
            stabilisation: 1e-3,
            line_search: false,
            max_pseudo_steps: 2000,
            time: 0.0,
            fd_position_jacobian: true,
        }
    }
}

impl StaticSettings {
    fn validate(&self) -> Result<()> {
        if !(self.tol.is_finite() && self.tol > 0.0 && self.tol < 1.0) {
            return Err(invalid("static tol", self.tol, "0 < tol < 1"));
        }
        if self.max_iter == 0 {
            return Err(invalid("static max_iter", 0.0, ">= 1"));
        }
        if self.load_steps == 0 {
            return Err(invalid("static load_steps", 0.0, ">= 1"));
        }
        if !(self.min_load_step > 0.0 && self.min_load_step <= 1.0) {
            return Err(invalid(
                "static min_load_step",
                self.min_load_step,
                "0 < value <= 1",
            ));
        }
        if !(self.stabilisation.is_finite() && self.stabilisation >= 0.0) {
            return Err(invalid("static stabilisation", self.stabilisation, ">= 0"));
        }
        if !self.time.is_finite() {
            return Err(invalid("static time [s]", self.time, "finite"));
        }
        Ok(())
    }
}

/// What the static solve did.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct StaticReport {
    /// Accepted load increments.
    pub increments: usize,
    /// Rejected (halved) increments.
    pub rejected_increments: usize,
    /// Total Newton iterations (factorisations).
    pub iterations: usize,
    /// Pseudo-steps after full load.
    pub pseudo_steps: usize,
    /// ‖r‖/F_ref per iteration of the last Newton solve.
    pub last_residual_history: Vec<f64>,
    /// Final ‖r‖/F_ref.
    pub relative_residual: f64,
    /// Round-off level of ‖r‖ relative to F_ref at the solution: the solver stops there even
    /// if `tol` asks for less.
    pub noise_level: f64,
    /// Reference force F_ref [N].
    pub f_ref: f64,
    /// ‖r‖/F_ref at every Newton iterate of every increment and pseudo-step, in order.
    pub residual_history: Vec<f64>,
    /// The observer stopped the solve: the state is the last accepted one, not an equilibrium.
    pub interrupted: bool,
    /// Warnings (logged by the caller).
    pub warnings: Vec<String>,
}

/// One Newton iteration of the static solve, as reported to an observer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticProgress {
    /// Load factor being solved for (1 = full load).
    pub load_factor: f64,
    /// Pseudo-steps after full load so far.
    pub pseudo_steps: usize,
    /// Newton iterations so far.
    pub iteration: usize,
    /// ‖r‖/F_ref at this iterate.
    pub relative_residual: f64,
}

/// What an observer tells the static solver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StaticControl {
    /// Go on.
    Continue,
    /// Stop now and return the last accepted state with `report.interrupted`.
    Stop,
}

/// Result of a static solve.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    /// Equilibrium state (v = a = 0).
    pub state: State,
    /// Tensions, strains, reactions, ...
    pub outputs: Outputs,
    /// Solver statistics.
    pub report: StaticReport,
}

/// Failure of one Newton solve.
struct NewtonFail {
    reason: String,
    history: Vec<f64>,
    /// The observer asked to stop (not a failure of the method).
    stopped: bool,
}

struct Ctx<'m, 'p, 'o, P: LoadProvider + ?Sized> {
    model: &'m Model,
    prov: &'p mut P,
    sys: System,
    st: StaticSettings,
    x: Vec<[f64; 3]>,
    zero: Vec<[f64; 3]>,
    x_ref: Vec<[f64; 3]>,
    dstab: Vec<f64>,
    r: Vec<f64>,
    dx: Vec<f64>,
    x_trial: Vec<[f64; 3]>,
    f_ref: f64,
    f_floor: f64,
    /// Round-off level of ‖r‖₂ at the current iterate [N] (see `noise_floor`).
    f_noise: f64,
    noise_buf: Vec<f64>,
    l_ref: f64,
    iterations: usize,
    /// Progress reported so far (load factor, pseudo-steps).
    progress: StaticProgress,
    history: Vec<f64>,
    observer: &'o mut dyn FnMut(&StaticProgress) -> StaticControl,
}

/// Connected components (cable and load elements) held by nothing.
pub(crate) fn check_supported<P: LoadProvider + ?Sized>(model: &Model, provider: &P) -> Result<()> {
    let n = model.n_nodes();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let union = |p: &mut Vec<usize>, a: usize, b: usize| {
        let (ra, rb) = (find(p, a), find(p, b));
        if ra != rb {
            p[ra.max(rb)] = ra.min(rb);
        }
    };
    for e in model.elements() {
        union(&mut parent, e.a, e.b);
    }
    for e in 0..provider.n_elements() {
        let nodes = provider.element_nodes(e);
        for w in nodes.windows(2) {
            if w[0] < n && w[1] < n {
                union(&mut parent, w[0], w[1]);
            }
        }
    }
    let mut held = vec![false; n];
    provider.mark_restoring_nodes(&mut held);
    let seabed = model.env.seabed.is_some();
    let mut comp_held = vec![false; n];
    let mut comp_size = vec![0usize; n];
    for i in 0..n {
        let r = find(&mut parent, i);
        comp_size[r] += 1;
        let c = (0..3).any(|k| model.is_constrained(i, k))
            || held[i]
            || (seabed && (model.bed_coef[i] > 0.0 || model.bed_point[i] > 0.0));
        comp_held[r] |= c;
    }
    for i in 0..n {
        if find(&mut parent, i) == i && !comp_held[i] {
            return Err(FemError::Unconstrained {
                first_node: i,
                n_nodes: comp_size[i],
            });
        }
    }
    Ok(())
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
    settings.validate()?;
    check_supported(model, &*provider)?;
    let sys = System::new(model, &*provider)?;
    let n = model.n_nodes();
    let nf = sys.n_free();
    let max_ea = model.elements().iter().map(|e| e.ea).fold(0.0, f64::max);
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
        x: model.nodes().to_vec(),
        zero: vec![[0.0; 3]; n],
        x_ref: model.nodes().to_vec(),
        dstab: vec![0.0; n],
        r: vec![0.0; nf],
        dx: vec![0.0; nf],
        x_trial: vec![[0.0; 3]; n],
        f_ref: 1.0,
        f_floor: (1e-6 * wsum).max(1e-9 * max_ea).max(1e-12),
        f_noise: 0.0,
        noise_buf: vec![0.0; n],
        l_ref: model.mean_length,
        iterations: 0,
        progress: StaticProgress {
            load_factor: 0.0,
            pseudo_steps: 0,
            iteration: 0,
            relative_residual: f64::NAN,
        },
        history: Vec::new(),
        observer,
    };
    let mut report = StaticReport::default();
    let t = settings.time;
    let eps0 = settings.stabilisation;
    let mut eps = eps0;
    let mut s_acc = 0.0;
    let mut ds = 1.0 / settings.load_steps as f64;
    let mut x_acc = ctx.x.clone();
    loop {
        let s = if s_acc >= 1.0 || s_acc + ds > 1.0 - 1e-12 {
            1.0
        } else {
            s_acc + ds
        };
        ctx.x.copy_from_slice(&x_acc);
        apply_constraints(model, t, s, &mut ctx.x);
        ctx.x_ref.copy_from_slice(&x_acc);
        ctx.update_stabilisation(eps);
        ctx.progress.load_factor = s;
        ctx.progress.pseudo_steps = report.pseudo_steps;
        let res = ctx.newton(s);
        match res {
            Ok((iters, hist)) => {
                report.last_residual_history = hist;
                let fs = ctx.stabilisation_force_norm();
                x_acc.copy_from_slice(&ctx.x);
                if s_acc >= 1.0 {
                    report.pseudo_steps += 1;
                } else {
                    report.increments += 1;
                }
                s_acc = s;
                if s >= 1.0 && fs <= (settings.tol * ctx.f_ref).max(ctx.f_noise) {
                    break;
                }
                if report.pseudo_steps >= settings.max_pseudo_steps {
                    return Err(ctx.failure(
                        1.0,
                        0.0,
                        NewtonFail {
                            reason: format!(
                                "stabilisation force {fs:.3e} N still above tolerance after {} \
                                 pseudo-steps (a part of the structure may be unsupported or \
                                 have no lateral stiffness)",
                                settings.max_pseudo_steps
                            ),
                            history: vec![],
                            stopped: false,
                        },
                    ));
                }
                if iters <= 5 {
                    if s_acc < 1.0 {
                        ds = (2.0 * ds).min(1.0 - s_acc);
                    }
                    // Easy step: trust the model more (pseudo-transient continuation).
                    eps = (0.25 * eps).max(1e-12 * eps0);
                }
            }
            Err(f) if f.stopped => {
                report.interrupted = true;
                ctx.x.copy_from_slice(&x_acc);
                ctx.eval_at_x(s_acc, false)?;
                break;
            }
            Err(f) => {
                report.rejected_increments += 1;
                let give_up = if s_acc < 1.0 {
                    ds *= 0.5;
                    ds < settings.min_load_step
                } else {
                    eps0 == 0.0 || eps > 1e3 * eps0
                };
                if give_up {
                    return Err(ctx.failure(s, ds, f));
                }
                eps = if eps0 > 0.0 {
                    (4.0 * eps).max(eps0)
                } else {
                    0.0
                };
                ctx.x.copy_from_slice(&x_acc);
                ctx.eval_at_x(s_acc, false)?;
            }
        }
    }
    // Final evaluation for outputs at the equilibrium (or last accepted) state.
    let s_out = if report.interrupted { s_acc } else { 1.0 };
    ctx.eval_at_x(s_out, false)?;
    let mut outputs = Outputs::new(model);
    outputs.update(model, &ctx.sys, false);
    let rn = ctx.residual_norm(s_out);
    report.iterations = ctx.iterations;
    report.residual_history = std::mem::take(&mut ctx.history);
    report.f_ref = ctx.f_ref;
    report.relative_residual = rn / ctx.f_ref;
    report.noise_level = ctx.f_noise / ctx.f_ref;
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

fn apply_constraints(model: &Model, t: f64, s: f64, x: &mut [[f64; 3]]) {
    let n = x.len();
    let mut v = vec![[0.0; 3]; n];
    let mut a = vec![[0.0; 3]; n];
    model.apply_constraints(t, s, x, &mut v, &mut a);
}

impl<P: LoadProvider + ?Sized> Ctx<'_, '_, '_, P> {
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

    fn eval_at_x(&mut self, s: f64, jac: bool) -> Result<()> {
        self.eval(s, false, jac)
    }

    /// D_i = Σ s_e·EA/L0 over the node's elements, from the last evaluation.
    /// D_i = ε·Σ EA/L0 over the node's elements. The axial stiffness is used whether the
    /// element is taut or slack: s·EA/L0 would vanish on slack parts, exactly where the
    /// pseudo-viscous term is needed.
    fn update_stabilisation(&mut self, eps: f64) {
        self.dstab.iter_mut().for_each(|d| *d = 0.0);
        for e in self.model.elements() {
            let k = eps * e.ea / e.l0;
            self.dstab[e.a] += k;
            self.dstab[e.b] += k;
        }
    }

    fn stabilisation_force_norm(&self) -> f64 {
        let mut s = 0.0;
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            let _ = f;
            let i = gd / 3;
            let d = self.dstab[i] * (self.x[i][gd % 3] - self.x_ref[i][gd % 3]);
            s += d * d;
        }
        s.sqrt()
    }

    /// Fills `self.r` (free residual incl. stabilisation, at `x_or_trial`) and updates F_ref;
    /// returns ‖r‖₂.
    fn residual(&mut self, trial: bool) -> f64 {
        let x = if trial { &self.x_trial } else { &self.x };
        let mut rn = 0.0;
        for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
            let (i, k) = (gd / 3, gd % 3);
            let r = self.sys.q[i][k] + self.dstab[i] * (x[i][k] - self.x_ref[i][k]);
            self.r[f] = r;
            rn += r * r;
        }
        let mut fe = 0.0;
        let mut re = 0.0;
        for i in 0..self.model.n_nodes() {
            for k in 0..3 {
                fe += self.sys.fext[i][k].powi(2);
                if self.sys.free_of_dof[3 * i + k] == NONE {
                    re += self.sys.q[i][k].powi(2);
                }
            }
        }
        self.f_ref = fe.sqrt().max(re.sqrt()).max(self.f_floor);
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
        let mut s2 = 0.0;
        for &gd in &self.sys.dof_of_free {
            s2 += noise[gd / 3];
        }
        2.0 * s2.sqrt()
    }

    fn residual_norm(&mut self, _s: f64) -> f64 {
        self.residual(false)
    }

    /// Newton on g + f_s at load factor s from `self.x`. Returns (iterations, history).
    fn newton(&mut self, s: f64) -> std::result::Result<(usize, Vec<f64>), NewtonFail> {
        let mut hist = Vec::new();
        let fail = |reason: String, hist: &Vec<f64>| NewtonFail {
            reason,
            history: hist.clone(),
            stopped: false,
        };
        if let Err(e) = self.eval(s, false, true) {
            return Err(fail(e.to_string(), &hist));
        }
        let xtol = 1e-6 * self.l_ref;
        let mut dx_prev = f64::INFINITY;
        let mut rn = self.residual(false);
        for it in 0..self.st.max_iter {
            hist.push(rn / self.f_ref);
            self.history.push(rn / self.f_ref);
            self.progress.iteration = self.iterations + it;
            self.progress.relative_residual = rn / self.f_ref;
            if (self.observer)(&self.progress) == StaticControl::Stop {
                self.iterations += it;
                return Err(NewtonFail {
                    reason: "interrupted".into(),
                    history: hist,
                    stopped: true,
                });
            }
            if !rn.is_finite() {
                return Err(fail("non-finite residual".into(), &hist));
            }
            let tol = self.st.tol * self.f_ref;
            if it > 0 && ((rn <= tol && dx_prev <= xtol) || rn <= self.f_noise) {
                self.iterations += it;
                return Ok((it, hist));
            }
            // J = K + D_stab.
            for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
                let p = self.sys.diag_pos[f];
                self.sys.values[p] += self.dstab[gd / 3];
            }
            if let Err(e) = self.sys.factorize() {
                return Err(fail(e.to_string(), &hist));
            }
            for f in 0..self.r.len() {
                self.dx[f] = -self.r[f];
            }
            if let Err(e) = self.sys.solve(&mut self.dx) {
                return Err(fail(e.to_string(), &hist));
            }
            // Step cap: max nodal |Δx| ≤ L_ref.
            let mut dmax: f64 = 0.0;
            let mut nodal = 0.0;
            let mut last_node = usize::MAX;
            for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
                if gd / 3 != last_node {
                    dmax = dmax.max(nodal);
                    nodal = 0.0;
                    last_node = gd / 3;
                }
                nodal += self.dx[f] * self.dx[f];
            }
            let dmax = dmax.max(nodal).sqrt();
            if dmax > self.l_ref {
                let sc = self.l_ref / dmax;
                self.dx.iter_mut().for_each(|d| *d *= sc);
            }
            let dinf = self.dx.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            if (rn <= tol && dinf <= xtol) || rn <= self.f_noise {
                self.iterations += it + 1;
                return Ok((it + 1, hist));
            }
            // Backtracking line search (Armijo 1e-4, halving to 1/32).
            let mut lambda = 1.0;
            let mut best: Option<(f64, f64)> = None;
            let mut full_r: Option<f64> = None;
            let mut accepted = false;
            loop {
                self.x_trial.copy_from_slice(&self.x);
                for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
                    self.x_trial[gd / 3][gd % 3] += lambda * self.dx[f];
                }
                let ok = self.eval(s, true, true).is_ok();
                let rt = if ok {
                    self.residual(true)
                } else {
                    f64::INFINITY
                };
                if lambda == 1.0 && rt.is_finite() {
                    full_r = Some(rt);
                }
                if rt.is_finite() && best.is_none_or(|(_, b)| rt < b) {
                    best = Some((lambda, rt));
                }
                if rt <= (1.0 - 1e-4 * lambda) * rn || !self.st.line_search && rt.is_finite() {
                    accepted = true;
                    break;
                }
                lambda *= 0.5;
                if lambda < 1.0 / 32.0 {
                    break;
                }
            }
            if !accepted {
                // No Armijo point: accept the full (capped) step if it does not raise the
                // residual much (slack parts falling into place), else the best point.
                if let Some(r1) = full_r
                    && r1 <= 2.0 * rn
                {
                    best = Some((1.0, r1));
                }
                let Some((lb, _)) = best else {
                    return Err(fail(
                        "no finite residual along the Newton direction (degenerate element)".into(),
                        &hist,
                    ));
                };
                lambda = lb;
                self.x_trial.copy_from_slice(&self.x);
                for (f, &gd) in self.sys.dof_of_free.iter().enumerate() {
                    self.x_trial[gd / 3][gd % 3] += lambda * self.dx[f];
                }
                if let Err(e) = self.eval(s, true, true) {
                    return Err(fail(e.to_string(), &hist));
                }
            }
            std::mem::swap(&mut self.x, &mut self.x_trial);
            rn = self.residual(false);
            dx_prev = lambda * dinf;
        }
        hist.push(rn / self.f_ref);
        self.iterations += self.st.max_iter;
        Err(fail(
            format!("no convergence in {} iterations", self.st.max_iter),
            &hist,
        ))
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
