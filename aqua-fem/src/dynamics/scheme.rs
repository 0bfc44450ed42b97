//! The implicit time schemes behind one interface for the Newton loop: each supplies its
//! kinematics (a_{n+1}, v_{n+1} and the evaluation state from the iterate x_{n+1}), its
//! Jacobian coefficients, its evaluation time and residual weight, and how the step's forces
//! are evaluated (docs/theory/fem.md#hht-alpha, #energy-consistent-midpoint). Enum dispatch:
//! the load provider is generic, which a trait object cannot carry.

use super::hht::Hht;
use super::midpoint::Midpoint;
use super::settings::DynamicSettings;
use crate::cable::CableEval;
use crate::error::Result;
use crate::failure::SchemeKind;
use crate::loads::LoadProvider;
use crate::model::Model;
use crate::system::{Coef, EvalOptions, System};

/// A nodal vector (positions [m], velocities [m/s] or accelerations [m/s²]).
pub(super) type Nodal<'a> = &'a [[f64; 3]];

/// How a scheme evaluates the forces of a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ForceEvaluation {
    /// All forces at the evaluation state (x_{n+1} for HHT-α).
    EndPoint,
    /// Cable and seabed elastic forces as the discrete gradient of their energy between the
    /// step's ends, the rest at the midpoint (docs/theory/fem.md#energy-consistent-midpoint).
    DiscreteGradient,
}

/// The implicit time scheme of a run.
#[derive(Debug)]
pub(crate) enum Scheme {
    /// HHT-α (docs/theory/fem.md#hht-alpha).
    Hht(Hht),
    /// The energy-consistent (θ = ½) or energy-decaying implicit midpoint rule
    /// (docs/theory/fem.md#energy-consistent-midpoint, #energy-decaying-midpoint).
    Midpoint(Midpoint),
}

impl Scheme {
    /// The scheme the settings ask for, for a model of `n` nodes.
    pub(crate) fn new(st: &DynamicSettings, n: usize) -> Self {
        if st.midpoint {
            Self::Midpoint(Midpoint::new(st.theta, n))
        } else {
            Self::Hht(Hht::new(st.alpha))
        }
    }

    /// Which scheme this is, for the hints of its failures.
    pub(crate) fn kind(&self) -> SchemeKind {
        match self {
            Self::Hht(_) => SchemeKind::Hht,
            Self::Midpoint(_) => SchemeKind::Midpoint,
        }
    }

    /// Coefficients of ∂r/∂x_{n+1} = m·M + k·K + c·C for a step h [s].
    pub(crate) fn coef(&self, h: f64) -> Coef {
        match self {
            Self::Hht(s) => s.coef(h),
            Self::Midpoint(s) => s.coef(h),
        }
    }

    /// Time at which the step's equations are evaluated [s].
    pub(crate) fn eval_time(&self, t: f64, h: f64) -> f64 {
        match self {
            Self::Hht(_) => t + h,
            Self::Midpoint(_) => t + 0.5 * h,
        }
    }

    /// Weight w of q_{n+1} in the residual M·a + w·q_{n+1} + (1 − w)·q_n.
    pub(crate) fn residual_weight(&self) -> f64 {
        match self {
            Self::Hht(s) => 1.0 - s.alpha,
            Self::Midpoint(_) => 1.0,
        }
    }

    /// How the step's forces are evaluated.
    pub(crate) fn force_evaluation(&self) -> ForceEvaluation {
        match self {
            Self::Hht(_) => ForceEvaluation::EndPoint,
            Self::Midpoint(_) => ForceEvaluation::DiscreteGradient,
        }
    }

    /// The kinematics of the iterate x1 on the free DOFs (v1, a1) and the scheme's own
    /// evaluation state; `start` is (x_n, v_n, a_n).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn kinematics(
        &mut self,
        h: f64,
        model: &Model,
        sys: &System,
        start: (Nodal<'_>, Nodal<'_>, Nodal<'_>),
        x1: &[[f64; 3]],
        v1: &mut [[f64; 3]],
        a1: &mut [[f64; 3]],
    ) {
        match self {
            Self::Hht(s) => s.kinematics(h, sys, start, x1, v1, a1),
            Self::Midpoint(s) => s.kinematics(h, model, sys, (start.0, start.1), x1, v1),
        }
    }

    /// Evaluates the step's equations; `step` is (x_n, x1, v1, a1).
    pub(crate) fn evaluate<P: LoadProvider + ?Sized>(
        &mut self,
        sys: &mut System,
        model: &Model,
        provider: &mut P,
        step: (Nodal<'_>, Nodal<'_>, Nodal<'_>, Nodal<'_>),
        o: &EvalOptions,
    ) -> Result<()> {
        let (xn, x1, v1, a1) = step;
        match self {
            Self::Hht(s) => s.evaluate(sys, model, provider, x1, v1, a1, o),
            Self::Midpoint(s) => s.evaluate(sys, model, provider, xn, x1, o),
        }
    }

    /// After convergence: the end state's acceleration and an evaluation of `sys` at the end
    /// state (x1, v1, a1) with `o_end`, where the scheme did not evaluate there.
    pub(crate) fn finish<P: LoadProvider + ?Sized>(
        &mut self,
        sys: &mut System,
        model: &Model,
        provider: &mut P,
        end: (Nodal<'_>, Nodal<'_>, &mut [[f64; 3]]),
        o_end: &EvalOptions,
    ) -> Result<()> {
        match self {
            Self::Hht(s) => {
                s.finish(sys, model);
                Ok(())
            }
            Self::Midpoint(s) => s.finish(sys, model, provider, end, o_end),
        }
    }

    /// The members' memory of the energy-consistent HHT-α (docs/theory/fem.md#energy-consistent-hht-alpha).
    pub(crate) fn hht_forces(&self) -> Option<&super::hht::HhtForces> {
        match self {
            Self::Hht(s) => s.forces(),
            Self::Midpoint(_) => None,
        }
    }

    /// The change of the scheme's own energy over the step of h to x1 (HHT-α; 0 for the
    /// midpoint rule, whose discrete gradient leaves none), given a_nᵀMa_n and
    /// a_{n+1}ᵀMa_{n+1} [J].
    pub(crate) fn algorithmic_energy_change(
        &self,
        model: &Model,
        x1: &[[f64; 3]],
        h: f64,
        ama: (f64, f64),
    ) -> f64 {
        match self {
            Self::Hht(s) => s.algorithmic_energy_change(model, x1, h, ama),
            Self::Midpoint(_) => 0.0,
        }
    }

    /// Puts back the members' memory of a snapshot (HHT-α).
    pub(crate) fn restore_hht_forces(&mut self, f: &super::hht::HhtForces) {
        if let Self::Hht(s) = self {
            s.restore_forces(f);
        }
    }

    /// Before the attempts of a step from the state (x_n, t_n).
    pub(crate) fn begin(&mut self, model: &Model, xn: &[[f64; 3]], t: f64) {
        if let Self::Hht(s) = self {
            s.begin(model, xn, t);
        }
    }

    /// After a step was accepted with the end state x1 at time t1.
    pub(crate) fn accept(&mut self, model: &Model, x1: &[[f64; 3]], t1: f64) {
        if let Self::Hht(s) = self {
            s.accept(model, x1, t1);
        }
    }

    /// The state of the last evaluation (positions, velocities) given the iterate before the
    /// last update `x_iter` and the velocities `v1` formed from it.
    pub(crate) fn evaluation_state<'a>(
        &'a self,
        x_iter: &'a [[f64; 3]],
        v1: &'a [[f64; 3]],
    ) -> (&'a [[f64; 3]], &'a [[f64; 3]]) {
        match self {
            Self::Hht(_) => (x_iter, v1),
            Self::Midpoint(s) => (&s.xm, &s.vm),
        }
    }

    /// The evaluation state (position, velocity) of one free DOF whose end position is `x1`,
    /// from its start (x_n, v_n, a_n): the line relaxation's view of the kinematics.
    pub(crate) fn evaluation_point(
        &self,
        xn: f64,
        vn: f64,
        an: f64,
        x1: f64,
        h: f64,
    ) -> (f64, f64) {
        match self {
            Self::Hht(s) => (x1, s.newmark(xn, vn, an, x1, h).1),
            Self::Midpoint(_) => Midpoint::evaluation_point(xn, x1, h),
        }
    }

    /// Spectral radius of the scheme on an undamped linear oscillator at Ω = ωΔt.
    pub(crate) fn spectral_radius(&self, omega_dt: f64) -> f64 {
        match self {
            Self::Hht(s) => s.spectral_radius(omega_dt),
            Self::Midpoint(s) => s.spectral_radius(omega_dt),
        }
    }

    /// β of the Newmark family's leading truncation term for the local error estimate.
    pub(crate) fn error_beta(&self) -> f64 {
        match self {
            Self::Hht(s) => s.beta,
            Self::Midpoint(_) => 0.25,
        }
    }

    /// A line relaxation that carried a tightening front across more elements than this
    /// fails the attempt (HHT-α only; docs/theory/fem.md#line-relaxation-hht).
    pub(crate) fn front_limit(&self) -> Option<usize> {
        match self {
            Self::Hht(_) => Some(super::hht::HHT_FRONT_ELEMENTS),
            Self::Midpoint(_) => None,
        }
    }

    /// Whether clamping the geometric stiffness to T ≥ 0 changes this element's tangent: a
    /// slack element pushes under HHT-α; under the midpoint rule a tension-only slack element
    /// carries at most its damping force, so only one in compression does.
    pub(crate) fn clamp_matters(&self, c: &CableEval) -> bool {
        match self {
            Self::Hht(_) => c.switch < 1.0,
            Self::Midpoint(_) => c.switch < 1.0 && c.tension < 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_step_names_the_damping_of_its_own_scheme() {
        let mut st = DynamicSettings::new(0.1, 1.0);
        let failed = crate::failure::FailureReason::NonFiniteResidual;
        let hht = failed.hint(Scheme::new(&st, 3).kind());
        st.midpoint = true;
        let mid = failed.hint(Scheme::new(&st, 3).kind());
        assert!(hht.contains("alpha") && !hht.contains("theta"), "{hht}");
        assert!(mid.contains("theta") && !mid.contains("alpha"), "{mid}");
    }
}
