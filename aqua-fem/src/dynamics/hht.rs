//! The HHT-α scheme (docs/theory/fem.md#hht-alpha): Newmark kinematics with
//! β = (1 + α)²/4, γ = ½ + α, the residual M·a_{n+1} + (1 − α)·q_{n+1} + α·q_n = 0 and the
//! Jacobian M/(βΔt²) + (1 − α)·[K + γ/(βΔt)·C].

use super::scheme::Nodal;
use crate::system::{Coef, System};

/// HHT-α with line relaxation: a step in which one line's relaxation took more local
/// iterations than this while an element of it that was slack ended taut (a tightening front
/// crossing about as many elements) is halved (docs/theory/fem.md#line-relaxation-hht).
pub(crate) const HHT_FRONT_ELEMENTS: usize = 10;

/// HHT-α's parameters.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Hht {
    /// α ∈ [0, 1/3].
    pub alpha: f64,
    /// β = (1 + α)²/4.
    pub beta: f64,
    /// γ = ½ + α.
    pub gamma: f64,
}

impl Hht {
    pub(crate) fn new(alpha: f64) -> Self {
        Self {
            alpha,
            beta: 0.25 * (1.0 + alpha) * (1.0 + alpha),
            gamma: 0.5 + alpha,
        }
    }

    /// m = 1/(βh²), k = 1 − α, c = (1 − α)·γ/(βh).
    pub(crate) fn coef(&self, h: f64) -> Coef {
        let (alpha, beta, gamma) = (self.alpha, self.beta, self.gamma);
        Coef {
            m: 1.0 / (beta * h * h),
            k: 1.0 - alpha,
            c: (1.0 - alpha) * gamma / (beta * h),
        }
    }

    /// Newmark's a_{n+1} = (x_{n+1} − x_n − h·v_n)/(βh²) − (1/(2β) − 1)·a_n and
    /// v_{n+1} = v_n + h·[(1 − γ)·a_n + γ·a_{n+1}] of one DOF.
    #[inline]
    pub(crate) fn newmark(&self, xn: f64, vn: f64, an: f64, x1: f64, h: f64) -> (f64, f64) {
        let (beta, gamma) = (self.beta, self.gamma);
        let a = (x1 - xn - h * vn) / (beta * h * h) - (1.0 / (2.0 * beta) - 1.0) * an;
        (a, vn + h * ((1.0 - gamma) * an + gamma * a))
    }

    /// Newmark kinematics of the iterate on the free DOFs; `start` is (x_n, v_n, a_n).
    pub(crate) fn kinematics(
        &self,
        h: f64,
        sys: &System,
        start: (Nodal<'_>, Nodal<'_>, Nodal<'_>),
        x1: &[[f64; 3]],
        v1: &mut [[f64; 3]],
        a1: &mut [[f64; 3]],
    ) {
        let (x, v, acc) = start;
        for &gd in &sys.dof_of_free {
            let (i, k) = (gd / 3, gd % 3);
            let (a, vel) = self.newmark(x[i][k], v[i][k], acc[i][k], x1[i][k], h);
            a1[i][k] = a;
            v1[i][k] = vel;
        }
    }
}
