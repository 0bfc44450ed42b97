//! The energy ledger of a run, W_ext + W_sup = ΔE_k + ΔU + D + E_num, and the guard that
//! rejects a step which created energy or turned an element over
//! (docs/theory/fem.md#energy-balance, #step-control).

use super::DynamicSolver;
use super::settings::MassMatrix;
use crate::failure::FailureReason;
use crate::state::Outputs;
use serde::{Deserialize, Serialize};

/// Energy balance since the start of the run [J]:
/// W_ext + W_sup = ΔE_k + ΔU + D + E_num.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Energies {
    /// Kinetic energy ½vᵀ(M + M_added)v now.
    pub kinetic: f64,
    /// Strain energy ΣU_e now.
    pub strain: f64,
    /// Work of external forces (gravity, point, water, seabed) since the start.
    pub external_work: f64,
    /// Work of the support reactions since the start.
    pub support_work: f64,
    /// Energy dissipated by axial and Rayleigh damping since the start.
    pub damping_dissipation: f64,
    /// Numerical dissipation E_num (≈ 0 for α = 0).
    pub numerical_dissipation: f64,
}

/// Relative energy a step may create before it is rejected (docs/theory/fem.md#step-control):
/// HHT-α (α ≥ 0) only dissipates in linear problems; growth beyond round-off and the
/// trapezoidal work of state-dependent loads means the step left the physics.
pub const ENERGY_GROWTH_TOL: f64 = 0.01;

/// The energy terms of one step (see `DynamicSolver::balance`).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Balance {
    kinetic: f64,
    strain: f64,
    power: f64,
    external_work: f64,
    support_work: f64,
    /// Σ|work| over the DOFs: the scale of the trapezoidal work's own error.
    work_magnitude: f64,
    /// Kinetic energy of the free DOFs.
    kinetic_free: f64,
    /// Work of the supports without the inertia of the supported DOFs (what they pass on to
    /// the rest of the structure, whatever the prescribed velocity does).
    support_work_static: f64,
}

impl DynamicSolver<'_> {
    /// The energy terms of a step from `x_old` to the last evaluation (`self.sys`, with
    /// `out` its outputs) at (`x_new`, `v_new`); `mv` is scratch (docs/theory/fem.md#hht-alpha).
    fn balance(
        &self,
        x_old: &[[f64; 3]],
        x_new: &[[f64; 3]],
        v_new: &[[f64; 3]],
        out: &Outputs,
        mv: &mut [[f64; 3]],
    ) -> Balance {
        let model = self.model;
        let n = model.n_nodes();
        // Kinetic energy with structural + added mass.
        crate::system::mul_mass(
            model,
            self.st.mass_matrix == MassMatrix::Consistent,
            v_new,
            mv,
        );
        let mut b = Balance {
            // Axial, bending (docs/theory/fem.md#bending) and net triangle strain energy.
            strain: out.strain_energy(model) + self.sys.element_energy(),
            power: self.sys.net_damping_power(model),
            ..Balance::default()
        };
        for i in 0..n {
            for k in 0..3 {
                let mut m = mv[i][k];
                for l in 0..3 {
                    m += self.sys.added[i][k][l] * v_new[i][l];
                }
                b.kinetic += 0.5 * v_new[i][k] * m;
                if !model.is_constrained(i, k) {
                    b.kinetic_free += 0.5 * v_new[i][k] * m;
                }
            }
        }
        // Dissipated power: axial/Rayleigh-K damping and Rayleigh-M.
        for (e, c) in model.elements().iter().zip(&self.sys.cable) {
            b.power += c.damping_force * c.strain_rate * e.l0;
        }
        if self.st.rayleigh[0] > 0.0 {
            let mut ms = 0.0;
            for i in 0..n {
                for k in 0..3 {
                    ms += v_new[i][k] * mv[i][k];
                }
            }
            b.power += self.st.rayleigh[0] * ms;
        }
        for i in 0..n {
            for k in 0..3 {
                let dx = x_new[i][k] - x_old[i][k];
                let we = 0.5 * (self.fext_prev[i][k] + self.sys.fext[i][k]) * dx;
                let ws = 0.5 * (self.last_reaction[i][k] + out.reaction[i][k]) * dx;
                b.external_work += we;
                b.support_work += ws;
                b.work_magnitude += we.abs() + ws.abs();
                if model.is_constrained(i, k) {
                    b.support_work_static += 0.5 * (self.q_prev[i][k] + self.sys.q[i][k]) * dx;
                }
            }
        }
        b
    }

    /// Updates outputs and energies from the last evaluation (at the new state).
    pub(super) fn accept_bookkeeping(&mut self, h: f64, first: bool) {
        let b = match self.guarded.take() {
            // The guard already formed the new state's outputs and balance.
            Some(b) => {
                std::mem::swap(&mut self.outputs, &mut self.trial);
                b
            }
            None => {
                self.outputs.update(self.model, &self.sys, true);
                let mut mv = std::mem::take(&mut self.mv);
                // x1 holds x_n here (swapped in `step`).
                let b = self.balance(
                    &self.x1,
                    &self.state.x,
                    &self.state.v,
                    &self.outputs,
                    &mut mv,
                );
                self.mv = mv;
                b
            }
        };
        let (peak, element) =
            self.outputs
                .tension
                .iter()
                .enumerate()
                .fold(
                    (0.0f64, 0),
                    |(m, k), (e, &t)| if t > m { (t, e) } else { (m, k) },
                );
        self.control.peak_tensions.push(peak);
        self.control.peak_elements.push(element);
        if !first {
            self.energies.external_work += b.external_work;
            self.energies.support_work += b.support_work;
            self.energies.damping_dissipation += 0.5 * (self.power_prev + b.power) * h;
        }
        self.energies.kinetic = b.kinetic;
        self.energies.strain = b.strain;
        self.kinetic_free = b.kinetic_free;
        self.energies.numerical_dissipation = self.energies.external_work
            + self.energies.support_work
            - (b.kinetic + b.strain - self.e0)
            - self.energies.damping_dissipation;
        self.power_prev = b.power;
        self.q_prev.copy_from_slice(&self.sys.q);
        self.fext_prev.copy_from_slice(&self.sys.fext);
        self.last_reaction.copy_from_slice(&self.outputs.reaction);
    }

    /// The change of the scheme's own energy over the attempted step (x_n → x1, a_n → a1),
    /// which the step's equations trade with E (docs/theory/fem.md#energy-consistent-hht-alpha).
    fn algorithmic_energy_change(&mut self, h: f64) -> f64 {
        let model = self.model;
        let consistent = self.st.mass_matrix == MassMatrix::Consistent;
        let mut ama = [0.0; 2];
        for (k, a) in [&self.state.a, &self.a1].into_iter().enumerate() {
            crate::system::mul_mass(model, consistent, a, &mut self.mv);
            for &gd in &self.sys.dof_of_free {
                let (i, c) = (gd / 3, gd % 3);
                let mut m = self.mv[i][c];
                for l in 0..3 {
                    m += self.sys.added[i][c][l] * a[i][l];
                }
                ama[k] += a[i][c] * m;
            }
        }
        self.scheme
            .algorithmic_energy_change(model, &self.x1, h, (ama[0], ama[1]))
    }

    /// Why a converged attempt (x1, v1 with `self.sys` evaluated there) must still be
    /// rejected (docs/theory/fem.md#step-control): an element that resists compression or was
    /// taut turned over in one step (the true motion would pass through zero length), or the
    /// step created energy: ΔE_k,free + ΔU + D − W_ext − W_sup,q > ENERGY_GROWTH_TOL·E_scale, with
    /// E_scale = max(E_n, E_n+1) + Σ_dofs |W| (the trapezoidal work of loads that balance each
    /// other, e.g. weight and tension, is exact only to O(Δt³) per DOF).
    pub(super) fn guard(&mut self, h: f64) -> Option<FailureReason> {
        let model = self.model;
        self.guarded = None;
        for (e, (el, c)) in model.elements().iter().zip(&self.sys.cable).enumerate() {
            let (a, b) = (el.a, el.b);
            let d0 = crate::system::sub(self.state.x[b], self.state.x[a]);
            let d1 = crate::system::sub(self.x1[b], self.x1[a]);
            let dot = d0[0] * d1[0] + d0[1] * d1[1] + d0[2] * d1[2];
            let resisted = el.rc > 0.0 || c.strain > 0.0 || self.outputs.strain[e] > 0.0;
            if dot < 0.0 && resisted {
                return Some(FailureReason::ElementTurnedOver { element: e });
            }
        }
        for (i, t) in model.net_triangles().iter().enumerate() {
            if let Some(family) = t.turned_over(&self.state.x, &self.x1) {
                return Some(FailureReason::TwinesTurnedOver {
                    triangle: i,
                    family,
                });
            }
        }
        let mut trial = std::mem::take(&mut self.trial);
        trial.update(model, &self.sys, true);
        let mut mv = std::mem::take(&mut self.mv);
        let b = self.balance(&self.state.x, &self.x1, &self.v1, &trial, &mut mv);
        self.mv = mv;
        self.trial = trial;
        // The balance of the free DOFs: a prescribed node's own kinetic energy is the
        // support's business (a table motion may jump its velocity).
        let e_old = self.kinetic_free + self.energies.strain;
        let e_new = b.kinetic_free + b.strain;
        let alg = self.algorithmic_energy_change(h);
        let created = e_new - e_old + 0.5 * (self.power_prev + b.power) * h
            - b.external_work
            - b.support_work_static
            + alg;
        let scale = e_old.max(e_new) + b.work_magnitude + self.f_floor * model.mean_length;
        if created > ENERGY_GROWTH_TOL * scale {
            return Some(FailureReason::EnergyCreated { created, scale });
        }
        // Accepted: the bookkeeping reuses these outputs and this balance.
        self.guarded = Some(b);
        None
    }
}
