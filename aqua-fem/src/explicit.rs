//! Explicit lumped mass-spring integrator: semi-implicit Euler or RK4 with an automatic
//! stable step (docs/theory/fem.md#explicit-schemes).

use crate::dynamics::{Energies, StepReport};
use crate::error::{FemError, Result, invalid};
use crate::loads::LoadProvider;
use crate::model::Model;
use crate::seabed::BedLaw;
use crate::state::{Outputs, State};
use crate::system::{Coef, EvalOptions, System};
use serde::{Deserialize, Serialize};

/// Explicit scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum ExplicitScheme {
    /// Symplectic Euler: v ← v + Δt·a(x, v, t); x ← x + Δt·v.
    #[default]
    SemiImplicitEuler,
    /// Classic fourth-order Runge–Kutta on (x, v).
    Rk4,
}

/// Settings of the explicit integrator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExplicitSettings {
    /// Scheme.
    pub scheme: ExplicitScheme,
    /// Safety factor on the stable-step estimate. Default 0.5.
    pub cfl: f64,
    /// User step [s]; `None` = the estimate. A larger value is reduced (with a warning) unless
    /// `dt_fixed`, which makes it an error.
    pub dt: Option<f64>,
    /// Refuse to reduce a user `dt`.
    pub dt_fixed: bool,
    /// End time [s].
    pub t_end: f64,
    /// Output interval [s]: steps land on its multiples and the stable step is re-estimated.
    pub output_interval: Option<f64>,
}

impl ExplicitSettings {
    /// Defaults (semi-implicit Euler, cfl 0.5, automatic step) up to `t_end` [s].
    pub fn new(t_end: f64) -> Self {
        Self {
            scheme: ExplicitScheme::SemiImplicitEuler,
            cfl: 0.5,
            dt: None,
            dt_fixed: false,
            t_end,
            output_interval: None,
        }
    }
}

/// Explicit lumped mass-spring integrator.
#[derive(Debug)]
pub struct ExplicitSolver<'m> {
    model: &'m Model,
    st: ExplicitSettings,
    sys: System,
    state: State,
    outputs: Outputs,
    dt: f64,
    warnings: Vec<String>,
    xs: Vec<[f64; 3]>,
    vs: Vec<[f64; 3]>,
    acc: [Vec<[f64; 3]>; 4],
    vel: [Vec<[f64; 3]>; 4],
    fext_prev: Vec<[f64; 3]>,
    reac_prev: Vec<[f64; 3]>,
    x_prev: Vec<[f64; 3]>,
    power_prev: f64,
    energies: Energies,
    e0: f64,
    n_steps: usize,
    scratch: Vec<[f64; 3]>,
}

fn solve3(m: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if !(det.abs() > 0.0) || !det.is_finite() {
        return None;
    }
    let mut out = [0.0; 3];
    for c in 0..3 {
        let mut mc = m;
        for r in 0..3 {
            mc[r][c] = b[r];
        }
        out[c] = (mc[0][0] * (mc[1][1] * mc[2][2] - mc[1][2] * mc[2][1])
            - mc[0][1] * (mc[1][0] * mc[2][2] - mc[1][2] * mc[2][0])
            + mc[0][2] * (mc[1][0] * mc[2][1] - mc[1][1] * mc[2][0]))
            / det;
    }
    Some(out)
}

impl<'m> ExplicitSolver<'m> {
    /// Prepares the integrator from `initial` or the as-built state at rest at t = 0.
    pub fn new<P: LoadProvider + ?Sized>(
        model: &'m Model,
        settings: ExplicitSettings,
        initial: Option<&State>,
        provider: &mut P,
    ) -> Result<Self> {
        if !(settings.cfl > 0.0 && settings.cfl <= 1.0) {
            return Err(invalid("cfl", settings.cfl, "0 < cfl <= 1"));
        }
        if let Some(dt) = settings.dt
            && !(dt.is_finite() && dt > 0.0)
        {
            return Err(invalid("dt [s]", dt, "> 0"));
        }
        if let Some(o) = settings.output_interval
            && !(o.is_finite() && o > 0.0)
        {
            return Err(invalid("output_interval [s]", o, "> 0"));
        }
        if let Some(b) = model.rigid_bodies().first() {
            return Err(FemError::RigidBodyNeedsImplicit {
                body: b.name.clone(),
            });
        }
        let n = model.n_nodes();
        for i in 0..n {
            let free = (0..3).any(|k| !model.is_constrained(i, k));
            if free && model.lumped_mass[i] <= 0.0 {
                return Err(FemError::InvalidModel(format!(
                    "node {i} has free DOFs but no mass (give it an element or a point mass)"
                )));
            }
        }
        let mut state = match initial {
            Some(s) if s.x.len() == n => s.clone(),
            Some(s) => {
                return Err(FemError::InvalidModel(format!(
                    "initial state has {} nodes, the model {n}",
                    s.x.len()
                )));
            }
            None => State::as_built(model, 0.0),
        };
        if !(settings.t_end.is_finite() && settings.t_end >= state.t) {
            return Err(invalid(
                "t_end [s]",
                settings.t_end,
                format!(">= start time {}", state.t),
            ));
        }
        {
            let State { t, x, v, a } = &mut state;
            model.apply_constraints(*t, 1.0, x, v, a);
        }
        let sys = System::new(model, &*provider)?;
        let z = vec![[0.0; 3]; n];
        let mut s = Self {
            model,
            sys,
            outputs: Outputs::new(model),
            dt: 0.0,
            warnings: Vec::new(),
            xs: z.clone(),
            vs: z.clone(),
            acc: [z.clone(), z.clone(), z.clone(), z.clone()],
            vel: [z.clone(), z.clone(), z.clone(), z.clone()],
            fext_prev: z.clone(),
            scratch: z.clone(),
            reac_prev: z.clone(),
            x_prev: z,
            power_prev: 0.0,
            energies: Energies::default(),
            e0: 0.0,
            n_steps: 0,
            state,
            st: settings,
        };
        s.update_dt(provider)?;
        let (x, v) = (s.state.x.clone(), s.state.v.clone());
        let t = s.state.t;
        s.accel(provider, t, &x, &v, 0)?;
        s.state.a = s.acc[0].clone();
        s.bookkeeping(0.0, true);
        s.e0 = s.energies.kinetic + s.energies.strain;
        Ok(s)
    }

    /// Current state.
    pub fn state(&self) -> &State {
        &self.state
    }
    /// Outputs of the current state.
    pub fn outputs(&self) -> &Outputs {
        &self.outputs
    }
    /// Current step [s].
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// Warnings (e.g. a user dt reduced to the stable step).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
    /// Whether t_end has been reached.
    pub fn is_finished(&self) -> bool {
        self.state.t >= self.st.t_end - 1e-9 * self.dt.max(1e-12)
    }
    /// Moves the end time to `t_end` [s], not before the current time (a coupling's call).
    pub fn extend_to(&mut self, t_end: f64) -> Result<()> {
        if !(t_end.is_finite() && t_end >= self.state.t) {
            return Err(invalid(
                "t_end [s]",
                t_end,
                format!("finite and not before the current time {} s", self.state.t),
            ));
        }
        self.st.t_end = t_end;
        Ok(())
    }
    /// Accepted steps.
    pub fn n_steps(&self) -> usize {
        self.n_steps
    }

    /// Stable step estimate Δt_est = cfl·min_i min(2/ω_i, 2m_i/c_i) at the current state [s].
    pub fn stable_step<P: LoadProvider + ?Sized>(&mut self, provider: &mut P) -> Result<f64> {
        let model = self.model;
        let o = EvalOptions {
            t: self.state.t,
            load_scale: 1.0,
            dynamic: true,
            jacobian: Some(Coef {
                m: 0.0,
                k: 0.0,
                c: 1.0,
            }),
            inertia: false,
            consistent_mass: false,
            rayleigh: (0.0, 0.0),
            fd_dfdx: false,
            clamp_geometric: false,
        };
        self.sys.evaluate(
            model,
            provider,
            &self.state.x,
            &self.state.v,
            &self.state.a,
            &o,
        )?;
        let n = model.n_nodes();
        let mut k_sum = vec![0.0; n];
        for (e, c) in model.elements().iter().zip(&self.sys.cable) {
            // Full EA/L0 even when slack: the element may tighten before the next estimate.
            let k = e.ea / e.l0 + c.tension.abs() / c.length;
            k_sum[e.a] += k;
            k_sum[e.b] += k;
        }
        // Bending: Gershgorin row sums of the hinge tangents (docs/theory/fem.md#stable-step);
        // 2·Σk bounds the cable rows, ω² ≤ max row sum/m bounds the hinge part.
        let mut k_bend = vec![0.0; n];
        self.sys.add_hinge_row_sums(model, &mut k_bend);
        self.sys.add_rod_row_sums(model, &mut k_bend);
        self.sys.add_net_row_sums(model, &mut k_bend);
        let c_rows = self.sys.row_abs_sums();
        let bed = BedLaw::new(model, true);
        let mut dt = f64::INFINITY;
        for i in 0..n {
            if (0..3).all(|k| model.is_constrained(i, k)) {
                continue;
            }
            let m = model.lumped_mass[i];
            // The seabed's contact stiffness (docs/theory/fem.md#seabed-contact).
            let (k_line, k_point) = bed.stiffness_parts(model, i);
            let w2 = (2.0 * k_sum[i] + k_bend[i] + k_line + k_point) / m;
            if w2 > 0.0 {
                dt = dt.min(2.0 / w2.sqrt());
            }
            let c = (0..3)
                .filter_map(|k| {
                    let f = self.sys.free_of_dof[3 * i + k];
                    (f != crate::system::NONE).then(|| c_rows[f])
                })
                .fold(0.0, f64::max)
                + self.sys.friction_spare_damping(i);
            if c > 0.0 {
                dt = dt.min(2.0 * m / c);
            }
        }
        if !dt.is_finite() {
            return Err(FemError::InvalidModel(
                "no stiffness or damping found to estimate a stable explicit step".into(),
            ));
        }
        Ok(self.st.cfl * dt)
    }

    fn update_dt<P: LoadProvider + ?Sized>(&mut self, provider: &mut P) -> Result<()> {
        let est = self.stable_step(provider)?;
        self.dt = match self.st.dt {
            None => est,
            Some(user) if user <= est => user,
            Some(user) => {
                if self.st.dt_fixed {
                    return Err(invalid(
                        "explicit dt [s]",
                        user,
                        format!("<= the stable step estimate {est:.4e} s (dt_fixed = true)"),
                    ));
                }
                let w = format!(
                    "t = {:.3} s: explicit dt {user:.4e} s reduced to the stable step {est:.4e} s",
                    self.state.t
                );
                if !self.warnings.contains(&w) {
                    self.warnings.push(w);
                }
                est
            }
        };
        Ok(())
    }

    /// Accelerations a(x, v, t) into `self.acc[slot]` (constrained DOFs from their motion).
    fn accel<P: LoadProvider + ?Sized>(
        &mut self,
        provider: &mut P,
        t: f64,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        slot: usize,
    ) -> Result<()> {
        let model = self.model;
        let o = EvalOptions {
            t,
            load_scale: 1.0,
            dynamic: true,
            jacobian: None,
            inertia: false,
            consistent_mass: false,
            rayleigh: (0.0, 0.0),
            fd_dfdx: false,
            clamp_geometric: false,
        };
        self.sys
            .evaluate(model, provider, x, v, &self.acc[slot], &o)?;
        for i in 0..model.n_nodes() {
            let presc = model.prescribed(i, t, 1.0);
            let mut m = self.sys.added[i];
            let mut b = [0.0; 3];
            for k in 0..3 {
                m[k][k] += model.lumped_mass[i];
                b[k] = -self.sys.q[i][k];
            }
            for k in 0..3 {
                if model.is_constrained(i, k) {
                    let ak = presc.map(|p| p.2[k]).unwrap_or(0.0);
                    for l in 0..3 {
                        b[l] -= m[l][k] * ak;
                        m[k][l] = 0.0;
                        m[l][k] = 0.0;
                    }
                    m[k][k] = 1.0;
                    b[k] = ak;
                }
            }
            let a = solve3(m, b).ok_or_else(|| {
                FemError::InvalidModel(format!("node {i}: singular nodal mass matrix"))
            })?;
            if a.iter().any(|c| !c.is_finite()) {
                return Err(FemError::NonFinite(format!(
                    "acceleration of node {i} at t = {t}"
                )));
            }
            self.acc[slot][i] = a;
        }
        Ok(())
    }

    fn bookkeeping(&mut self, h: f64, first: bool) {
        let model = self.model;
        self.outputs.update(model, &self.sys, false);
        let n = model.n_nodes();
        let mut ek = 0.0;
        for i in 0..n {
            let a = self.state.a[i];
            let v = self.state.v[i];
            for k in 0..3 {
                let mut ma = model.lumped_mass[i] * a[k];
                let mut mv = model.lumped_mass[i] * v[k];
                for l in 0..3 {
                    ma += self.sys.added[i][k][l] * a[l];
                    mv += self.sys.added[i][k][l] * v[l];
                }
                if model.is_constrained(i, k) {
                    self.outputs.reaction[i][k] += ma;
                }
                ek += 0.5 * v[k] * mv;
            }
        }
        let u = self.outputs.strain_energy(model) + self.sys.element_energy();
        let mut power = self.sys.net_damping_power(model);
        for (e, c) in model.elements().iter().zip(&self.sys.cable) {
            power += c.damping_force * c.strain_rate * e.l0;
        }
        if !first {
            for i in 0..n {
                for k in 0..3 {
                    let dx = self.state.x[i][k] - self.x_prev[i][k];
                    self.energies.external_work +=
                        0.5 * (self.fext_prev[i][k] + self.sys.fext[i][k]) * dx;
                    self.energies.support_work +=
                        0.5 * (self.reac_prev[i][k] + self.outputs.reaction[i][k]) * dx;
                }
            }
            self.energies.damping_dissipation += 0.5 * (self.power_prev + power) * h;
        }
        self.energies.kinetic = ek;
        self.energies.strain = u;
        self.energies.numerical_dissipation = self.energies.external_work
            + self.energies.support_work
            - (ek + u - self.e0)
            - self.energies.damping_dissipation;
        self.power_prev = power;
        self.fext_prev.copy_from_slice(&self.sys.fext);
        self.reac_prev.copy_from_slice(&self.outputs.reaction);
    }

    /// Takes one explicit step (landing on output times and t_end).
    pub fn step<P: LoadProvider + ?Sized>(&mut self, provider: &mut P) -> Result<StepReport> {
        if self.is_finished() {
            return Err(FemError::InvalidModel(format!(
                "step requested after t_end = {}",
                self.st.t_end
            )));
        }
        let model = self.model;
        let t = self.state.t;
        crate::loads::accept_state(provider, t, &self.state.x)?;
        self.sys.accept_rod_frames(model, &self.state.x);
        let mut h = self.dt;
        let mut target = self.st.t_end;
        if let Some(oi) = self.st.output_interval {
            let k = ((t + 1e-9 * h) / oi).floor() + 1.0;
            target = target.min(k * oi);
        }
        let mut landed = false;
        if t + h >= target - 1e-9 * h {
            h = target - t;
            landed = true;
        }
        let t1 = if landed { target } else { t + h };
        self.x_prev.copy_from_slice(&self.state.x);
        let n = model.n_nodes();
        match self.st.scheme {
            ExplicitScheme::SemiImplicitEuler => {
                // acc[0] holds a(x_n, v_n, t_n).
                for i in 0..n {
                    for k in 0..3 {
                        self.state.v[i][k] += h * self.acc[0][i][k];
                        self.state.x[i][k] += h * self.state.v[i][k];
                    }
                }
            }
            ExplicitScheme::Rk4 => {
                self.vel[0].copy_from_slice(&self.state.v);
                for stage in 1..4 {
                    let c = if stage == 3 { 1.0 } else { 0.5 };
                    for i in 0..n {
                        for k in 0..3 {
                            self.xs[i][k] = self.state.x[i][k] + c * h * self.vel[stage - 1][i][k];
                            self.vs[i][k] = self.state.v[i][k] + c * h * self.acc[stage - 1][i][k];
                        }
                    }
                    let ts = t + c * h;
                    let (mut xs, mut vs) =
                        (std::mem::take(&mut self.xs), std::mem::take(&mut self.vs));
                    let mut scratch = std::mem::take(&mut self.scratch);
                    model.apply_constraints(ts, 1.0, &mut xs, &mut vs, &mut scratch);
                    self.scratch = scratch;
                    let r = self.accel(provider, ts, &xs, &vs, stage);
                    self.vel[stage].copy_from_slice(&vs);
                    self.xs = xs;
                    self.vs = vs;
                    r?;
                }
                for i in 0..n {
                    for k in 0..3 {
                        self.state.x[i][k] += h / 6.0
                            * (self.vel[0][i][k]
                                + 2.0 * self.vel[1][i][k]
                                + 2.0 * self.vel[2][i][k]
                                + self.vel[3][i][k]);
                        self.state.v[i][k] += h / 6.0
                            * (self.acc[0][i][k]
                                + 2.0 * self.acc[1][i][k]
                                + 2.0 * self.acc[2][i][k]
                                + self.acc[3][i][k]);
                    }
                }
            }
        }
        self.state.t = t1;
        {
            let State { t, x, v, a } = &mut self.state;
            model.apply_constraints(*t, 1.0, x, v, a);
        }
        if self
            .state
            .x
            .iter()
            .chain(&self.state.v)
            .flatten()
            .any(|c| !c.is_finite())
        {
            return Err(FemError::NonFinite(format!(
                "explicit state at t = {t1} (step {h:.3e} s too large?)"
            )));
        }
        let (x, v) = (
            std::mem::take(&mut self.state.x),
            std::mem::take(&mut self.state.v),
        );
        let r = self.accel(provider, t1, &x, &v, 0);
        self.state.x = x;
        self.state.v = v;
        r?;
        self.state.a.copy_from_slice(&self.acc[0]);
        self.bookkeeping(h, false);
        self.n_steps += 1;
        if landed && self.st.output_interval.is_some() && !self.is_finished() {
            self.update_dt(provider)?;
            // Restore the evaluation at the current state for consistency of acc[0].
            let (x, v) = (
                std::mem::take(&mut self.state.x),
                std::mem::take(&mut self.state.v),
            );
            let r = self.accel(provider, t1, &x, &v, 0);
            self.state.x = x;
            self.state.v = v;
            r?;
        }
        Ok(StepReport {
            t: t1,
            dt: h,
            iterations: 0,
            retries: 0,
            residual_history: Vec::new(),
            convergence_order: None,
            output_time: self.st.output_interval.is_none() || landed,
            energies: self.energies,
        })
    }
}
