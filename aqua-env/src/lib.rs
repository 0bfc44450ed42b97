//! aqua-env — the sea: fluid constants, current and waves (theory:
//! `docs/theory/environment.md`).
//!
//! Conventions: SI units, z up, z = 0 at still water, seabed at z = −h; directions β in radians
//! (degrees only in scene files), measured from +x towards +y, pointing where waves travel.
//!
//! Governing equations:
//! - Current: U_c(x, t) = R(t)·U_c(z) with a uniform, piecewise-linear or power-law profile
//!   U_s((z+h)/h)^p, and the C¹ ramp R(t) = ½(1 − cos πt/T_r).
//! - Linear waves: dispersion ω² = g k tanh kh (solved by Newton); per component
//!   η = a cos θ, θ = k(x cos β + y sin β) − ωt + φ, u_h = ωa C(z) cos θ, w = ωa S(z) sin θ,
//!   p_d = ρ g a K(z) cos θ, with C, S, K the cosh/sinh depth functions written overflow-free.
//! - Stokes 2nd order: η = a cos θ + (k a²/4) B_η cos 2θ and velocity corrections
//!   ¾ ω k a² cosh 2k(z+h)/sinh⁴ kh.
//! - Irregular seas: η = Σ a_i cos θ_i, a_i = √(2 S(ω_i) Δω), S JONSWAP/PM (DNV-RP-C205),
//!   cos-2s spreading, SplitMix64-seeded phases, Wheeler stretching z_s = h(z − η)/(h + η).
//!
//! [`Sea`] answers, for many points at one time, [`FlowPoint`]s (η, submergence, current and
//! wave velocity/acceleration, dynamic pressure) with no allocation per call.

pub mod airy;
pub mod config;
pub mod constants;
pub mod current;
pub mod dispersion;
pub mod error;
pub mod irregular;
pub mod ramp;
pub mod random;
pub mod record;
pub mod sea;
pub mod sea_params;
pub mod sea_summary_text;
pub mod spectrum;
pub mod spreading;
pub mod stokes;
pub mod stretching;
pub mod trig;

pub use airy::{Component, LinearSum};
pub use config::{BuildOptions, SeaSpec, SeaSummary};
pub use constants::{Constants, Depth};
pub use current::{Current, CurrentProfile, Schedule};
pub use dispersion::wave_number;
pub use error::EnvError;
pub use irregular::{Discretisation, IrregularSpec, Spacing};
pub use ramp::Ramp;
pub use sea::{FlowPoint, Phase, Sea, Waves};
pub use spectrum::Spectrum;
pub use stokes::Stokes2;
pub use stretching::Stretching;
