//! The implicit midpoint rule (docs/theory/fem.md#energy-consistent-midpoint,
//! #energy-decaying-midpoint): the equations at the midpoint x_m = ½(x_n + x_{n+1}),
//! a_m = (v_{n+1} − v_n)/h, with cable and seabed elastic forces the discrete gradient of their
//! energy between the step's ends, and the end velocity from
//! x_{n+1} − x_n = h·((1 − θ)·v_n + θ·v_{n+1}).

use super::scheme::Nodal;
use crate::error::Result;
use crate::loads::LoadProvider;
use crate::model::Model;
use crate::system::{Coef, EvalOptions, NONE, StepEnds, System};

/// The midpoint rule's weight θ and the state it evaluates at.
#[derive(Debug)]
pub(crate) struct Midpoint {
    /// θ ∈ [½, 1] (½ conserves the energy).
    pub theta: f64,
    /// The state the equations are evaluated at: x_m, v_m, a_m.
    pub xm: Vec<[f64; 3]>,
    pub vm: Vec<[f64; 3]>,
    pub am: Vec<[f64; 3]>,
    /// Storage of the step's end positions for the discrete gradient, between evaluations.
    secant_buf: Option<StepEnds>,
}

impl Midpoint {
    pub(crate) fn new(theta: f64, n: usize) -> Self {
        Self {
            theta,
            xm: vec![[0.0; 3]; n],
            vm: vec![[0.0; 3]; n],
            am: vec![[0.0; 3]; n],
            secant_buf: None,
        }
    }

    /// Spectral radius ρ(Ω) of the rule on an undamped linear oscillator at Ω = ωΔt:
    /// x1 − x0 = Δt·((1 − θ)·v0 + θ·v1), v1 − v0 = −Δt·ω²·(x0 + x1)/2; 1 for θ = ½ and for
    /// Ω → ∞ (docs/theory/fem.md#energy-decaying-midpoint).
    pub(crate) fn spectral_radius(&self, omega_dt: f64) -> f64 {
        let th = self.theta;
        let w2 = omega_dt * omega_dt;
        // Columns: the step from (x, Δt·v) = e_j.
        let col = |x0: f64, v0: f64| {
            let v1 = (v0 - w2 * x0 - 0.5 * w2 * (1.0 - th) * v0) / (1.0 + 0.5 * w2 * th);
            (x0 + (1.0 - th) * v0 + th * v1, v1)
        };
        let (a, c) = col(1.0, 0.0);
        let (b, d) = col(0.0, 1.0);
        let (tr, det) = (a + d, a * d - b * c);
        let disc = tr * tr - 4.0 * det;
        if disc < 0.0 {
            det.abs().sqrt()
        } else {
            0.5 * (tr.abs() + disc.sqrt())
        }
    }

    /// ∂r/∂x_{n+1}: m = 1/(θh²), k = ½, c = 1/h.
    pub(crate) fn coef(&self, h: f64) -> Coef {
        Coef {
            m: 1.0 / (self.theta * h * h),
            k: 0.5,
            c: 1.0 / h,
        }
    }

    /// The evaluation state (x_m, v_m) of one free DOF with end position `x1`: v_m is
    /// (x_{n+1} − x_n)/h for every θ (½ for the plain rule).
    #[inline]
    pub(crate) fn evaluation_point(xn: f64, x1: f64, h: f64) -> (f64, f64) {
        (0.5 * (xn + x1), (x1 - xn) / h)
    }

    /// v1 on the free DOFs from x1, and the midpoint state (x_m, v_m, a_m) on all DOFs (the
    /// constrained ones follow their motion at t_n and t_{n+1}); `start` is (x_n, v_n). With
    /// the weight θ (½ for the plain rule): v1 = (x1 − x_n)/(θ·h) − (1 − θ)/θ·v_n and
    /// v_m = (1 − θ)·v_n + θ·v1, which is (x1 − x_n)/h on the free DOFs for every θ; on a
    /// constrained DOF v_m = ½(v_n + v1), its velocity at the midpoint time.
    pub(crate) fn kinematics(
        &mut self,
        h: f64,
        model: &Model,
        sys: &System,
        start: (&[[f64; 3]], &[[f64; 3]]),
        x1: &[[f64; 3]],
        v1: &mut [[f64; 3]],
    ) {
        let (x, v) = start;
        let th = self.theta;
        let lag = (1.0 - th) / th;
        for &gd in &sys.dof_of_free {
            let (i, k) = (gd / 3, gd % 3);
            v1[i][k] = (x1[i][k] - x[i][k]) / (th * h) - lag * v[i][k];
        }
        for i in 0..model.n_nodes() {
            for k in 0..3 {
                let (x0, v0) = (x[i][k], v[i][k]);
                self.xm[i][k] = 0.5 * (x0 + x1[i][k]);
                // Free DOFs: (x1 − x_n)/h. A prescribed DOF moves as its motion says, so its
                // velocity at t_n + h/2, where the forces are evaluated, is the mean of its ends
                // whatever θ (docs/theory/fem.md#energy-decaying-midpoint).
                let w = if sys.free_of_dof[3 * i + k] == NONE {
                    0.5
                } else {
                    th
                };
                self.vm[i][k] = (1.0 - w) * v0 + w * v1[i][k];
                self.am[i][k] = (v1[i][k] - v0) / h;
            }
        }
    }

    /// Evaluates the step's equations at the midpoint, with discrete-gradient cable and seabed
    /// forces between x_n and x1.
    pub(crate) fn evaluate<P: LoadProvider + ?Sized>(
        &mut self,
        sys: &mut System,
        model: &Model,
        provider: &mut P,
        xn: &[[f64; 3]],
        x1: &[[f64; 3]],
        o: &EvalOptions,
    ) -> Result<()> {
        let mut ends = self.secant_buf.take().unwrap_or_default();
        ends.0.clear();
        ends.0.extend_from_slice(xn);
        ends.1.clear();
        ends.1.extend_from_slice(x1);
        sys.secant = Some(ends);
        let r = sys.evaluate(model, provider, &self.xm, &self.vm, &self.am, o);
        // Later evaluations (outputs, guards) are of states, not of steps.
        self.secant_buf = sys.secant.take();
        r
    }

    /// A converged step: the end state's acceleration is the midpoint's (which the next
    /// predictor uses), and one evaluation at the end state (x1, v1, a1) so that outputs,
    /// guards and the energy balance see x_{n+1}.
    pub(crate) fn finish<P: LoadProvider + ?Sized>(
        &mut self,
        sys: &mut System,
        model: &Model,
        provider: &mut P,
        end: (Nodal<'_>, Nodal<'_>, &mut [[f64; 3]]),
        o_end: &EvalOptions,
    ) -> Result<()> {
        let (x1, v1, a1) = end;
        for &gd in &sys.dof_of_free {
            a1[gd / 3][gd % 3] = self.am[gd / 3][gd % 3];
        }
        sys.evaluate(model, provider, x1, v1, a1, o_end)
    }
}
