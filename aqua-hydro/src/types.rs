//! Types shared by every load module: vectors and matrices, what an evaluation is asked for, and
//! the speed below which a flow load is zero.

use nalgebra::{Matrix3, Vector3};

/// A 3-vector (position [m], velocity [m/s], force [N]).
pub(crate) type V3 = Vector3<f64>;
/// A 3×3 matrix (a Jacobian of a force).
pub(crate) type M3 = Matrix3<f64>;

/// Below this relative speed [m/s] drag, lift and their Jacobians are zero.
pub const ZERO_SPEED: f64 = 1e-12;

/// What is asked of a load evaluation besides the force.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Want {
    /// ∂F/∂U_r (gives ∂f/∂v).
    pub dfdv: bool,
    /// ∂F/∂p_j.
    pub dfdx: bool,
}
