//! The sea a structure sits in: constants, current and waves, evaluated at many points at one
//! time (docs/theory/environment.md#flow-at-a-point).

use crate::airy::{LinearSum, RawKinematics, SumScratch};
use crate::constants::{Constants, Depth};
use crate::current::Current;
use crate::ramp::Ramp;
use crate::stokes::Stokes2;
use crate::stretching::Stretching;
use rayon::prelude::*;
use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};

/// What the water does at one point and time.
///
/// Current and wave parts are separate because a wake factor multiplies the current only.
/// Dry points (above the instantaneous surface) have zero velocities, accelerations and
/// pressure; a point below the seabed plane has the flow at the bed right above it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlowPoint {
    /// Surface elevation η(x, y, t) [m] (wave ramp applied).
    pub eta: f64,
    /// Submergence ζ = η − z [m], positive under water.
    pub submergence: f64,
    /// Current velocity U_c [m/s] (ramp applied, no wake).
    pub current: [f64; 3],
    /// ∂U_c/∂t [m/s²] (non-zero only while a ramp or schedule blend runs).
    pub current_acc: [f64; 3],
    /// Wave orbital velocity [m/s].
    pub wave_vel: [f64; 3],
    /// Local wave acceleration ∂u/∂t [m/s²].
    pub wave_acc: [f64; 3],
    /// Wave dynamic pressure p_d [Pa].
    pub p_dyn: f64,
}

impl FlowPoint {
    /// Total fluid velocity U_c + u_w [m/s].
    pub fn velocity(&self) -> [f64; 3] {
        [
            self.current[0] + self.wave_vel[0],
            self.current[1] + self.wave_vel[1],
            self.current[2] + self.wave_vel[2],
        ]
    }

    /// True if the point is under the instantaneous surface.
    pub fn is_wet(&self) -> bool {
        self.submergence >= 0.0
    }
}

/// Which solve asks: statics use the full current (if `in_static`) and no waves; dynamics use
/// the ramps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Static equilibrium: R = 1 for the current, no waves.
    Static,
    /// Dynamic run at time t.
    Dynamic,
}

/// The waves of a sea.
// Built once per run and read at every point: the size of the variants does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub enum Waves {
    /// Still water.
    None,
    /// A sum of linear components (a regular Airy wave, listed components, or an irregular sea).
    Linear {
        /// The components.
        sum: LinearSum,
        /// How kinematics are evaluated near the surface.
        stretching: Stretching,
        /// The wave ramp.
        ramp: Ramp,
    },
    /// A Stokes second-order regular wave.
    Stokes2 {
        /// The wave.
        wave: Stokes2,
        /// How kinematics are evaluated near the surface.
        stretching: Stretching,
        /// The wave ramp.
        ramp: Ramp,
    },
}

impl Waves {
    /// True unless still water.
    pub fn is_active(&self) -> bool {
        !matches!(self, Waves::None)
    }

    fn ramp(&self) -> Ramp {
        match self {
            Waves::None => Ramp::off(),
            Waves::Linear { ramp, .. } | Waves::Stokes2 { ramp, .. } => *ramp,
        }
    }
}

thread_local! {
    /// Per-thread scratch of the wave sums: grows once, then no allocation per call.
    static SCRATCH: RefCell<Option<SumScratch>> = const { RefCell::new(None) };
}

/// Points × components above which [`Sea::eval`] splits the work over threads.
const PARALLEL_WORK: usize = 40_000;

/// An immutable sea state: `Send + Sync`, evaluation is a pure function of (x, t).
#[derive(Debug)]
pub struct Sea {
    constants: Constants,
    current: Current,
    waves: Waves,
    current_ramp: bool,
    below_seabed: AtomicBool,
}

impl Clone for Sea {
    fn clone(&self) -> Self {
        Self {
            constants: self.constants,
            current: self.current.clone(),
            waves: self.waves.clone(),
            current_ramp: self.current_ramp,
            below_seabed: AtomicBool::new(self.below_seabed.load(Ordering::Relaxed)),
        }
    }
}

impl Sea {
    /// A sea from its parts. The current's start-up ramp is off until
    /// [`Sea::with_current_ramp`] switches it on.
    pub fn new(constants: Constants, current: Current, waves: Waves) -> Self {
        Self {
            constants,
            current,
            waves,
            current_ramp: false,
            below_seabed: AtomicBool::new(false),
        }
    }

    /// Still water with the given constants.
    pub fn still(constants: Constants) -> Self {
        Self::new(constants, Current::none(), Waves::None)
    }

    /// Use the current's start-up ramp in dynamics: for runs that do not start from a static
    /// state which already contains the current
    /// (docs/theory/environment.md#when-the-current-ramps).
    pub fn with_current_ramp(mut self, on: bool) -> Self {
        self.current_ramp = on;
        self
    }

    /// True if the current ramps up in dynamics.
    pub fn current_ramps(&self) -> bool {
        self.current_ramp && self.current.ramp.duration > 0.0
    }

    /// g, ρ_w, ν and the depth.
    pub fn constants(&self) -> &Constants {
        &self.constants
    }

    /// Gravity g [m/s²].
    pub fn gravity(&self) -> f64 {
        self.constants.gravity
    }

    /// Water density ρ_w [kg/m³].
    pub fn density(&self) -> f64 {
        self.constants.density
    }

    /// Kinematic viscosity ν [m²/s].
    pub fn kinematic_viscosity(&self) -> f64 {
        self.constants.kinematic_viscosity
    }

    /// Water depth.
    pub fn depth(&self) -> Depth {
        self.constants.depth
    }

    /// The current.
    pub fn current(&self) -> &Current {
        &self.current
    }

    /// The waves.
    pub fn waves(&self) -> &Waves {
        &self.waves
    }

    /// True if the sea has waves (a current-only sea costs nothing for waves).
    pub fn has_waves(&self) -> bool {
        self.waves.is_active()
    }

    /// True if the sea has a current.
    pub fn has_current(&self) -> bool {
        self.current.is_active()
    }

    /// True once any evaluated point was below the seabed plane (and took the flow at the
    /// bed): a body resting on the penalty seabed does so by its contact overlap.
    pub fn saw_point_below_seabed(&self) -> bool {
        self.below_seabed.load(Ordering::Relaxed)
    }

    /// Surface elevation η [m] at (x, y) and t (zero in statics).
    pub fn elevation(&self, x: f64, y: f64, t: f64, phase: Phase) -> f64 {
        if phase == Phase::Static {
            return 0.0;
        }
        let r = self.waves.ramp().value(t);
        match &self.waves {
            Waves::None => 0.0,
            Waves::Linear { sum, .. } => r * sum.elevation_only(x, y, t),
            Waves::Stokes2 { wave, .. } => r * wave.elevation(x, y, t),
        }
    }

    /// Everything at one point p = (x, y, z) [m] and time t [s].
    pub fn at(&self, p: [f64; 3], t: f64, phase: Phase) -> FlowPoint {
        match &self.waves {
            Waves::Linear { sum, .. } if phase == Phase::Dynamic => SCRATCH.with(|cell| {
                let mut sc = cell.borrow_mut();
                let sc = sc.get_or_insert_with(SumScratch::default);
                sc.fit(sum.len());
                self.at_with(p, t, phase, sc)
            }),
            _ => self.at_with(p, t, phase, &mut SumScratch::default()),
        }
    }

    fn at_with(&self, p: [f64; 3], t: f64, phase: Phase, cs: &mut SumScratch) -> FlowPoint {
        let [x, y, z_point] = p;
        let mut out = FlowPoint::default();
        // Below the seabed plane the flow is the flow at the bed
        // (docs/theory/environment.md#flow-at-a-point): a body resting on the penalty seabed
        // sinks into it by its contact overlap and must see what it would see lying on it.
        let z = match self.constants.depth {
            Depth::Finite(h) if z_point < -h => {
                self.below_seabed.store(true, Ordering::Relaxed);
                -h
            }
            _ => z_point,
        };
        // Waves first: they decide where the surface is.
        let mut wave = RawKinematics::default();
        if phase == Phase::Dynamic {
            let ramp = self.waves.ramp();
            let (r, rdot) = (ramp.value(t), ramp.rate(t));
            let raw = match &self.waves {
                Waves::None => None,
                Waves::Linear {
                    sum, stretching, ..
                } => {
                    let eta = r * sum.elevation(x, y, t, cs);
                    out.eta = eta;
                    (z <= eta).then(|| {
                        let zs = stretching.apply(z, eta, self.constants.depth);
                        sum.kinematics(zs, cs)
                    })
                }
                Waves::Stokes2 {
                    wave, stretching, ..
                } => {
                    let eta = r * wave.elevation(x, y, t);
                    out.eta = eta;
                    (z <= eta).then(|| {
                        let zs = stretching.apply(z, eta, self.constants.depth);
                        wave.kinematics(x, y, t, zs)
                    })
                }
            };
            if let Some(k) = raw {
                for c in 0..3 {
                    wave.vel[c] = r * k.vel[c];
                    wave.acc[c] = r * k.acc[c] + rdot * k.vel[c];
                }
                wave.p_over_rho = r * k.p_over_rho;
            }
        }
        out.submergence = out.eta - z_point;
        if z > out.eta {
            return out;
        }
        out.wave_vel = wave.vel;
        out.wave_acc = wave.acc;
        out.p_dyn = self.constants.density * wave.p_over_rho;
        if self.current.is_active() {
            let (r, rdot, tc) = match phase {
                Phase::Static => (if self.current.in_static { 1.0 } else { 0.0 }, 0.0, 0.0),
                Phase::Dynamic if self.current_ramp => {
                    (self.current.ramp.value(t), self.current.ramp.rate(t), t)
                }
                Phase::Dynamic => (1.0, 0.0, t),
            };
            if r != 0.0 || rdot != 0.0 {
                let (u, a) = self.current.eval(z, tc, r, rdot);
                out.current = u;
                out.current_acc = a;
            }
        }
        out
    }

    /// Fills `out[i]` with the flow at `points[i]` [m] at time t [s].
    ///
    /// No allocation per call after the first on each thread; large batches run in parallel
    /// (the per-point summation order is fixed, so results do not depend on thread count).
    ///
    /// # Panics
    /// If `points` and `out` differ in length (a programming error, not user input).
    pub fn eval(&self, t: f64, phase: Phase, points: &[[f64; 3]], out: &mut [FlowPoint]) {
        assert_eq!(
            points.len(),
            out.len(),
            "points and out must have equal length"
        );
        let ncomp = match &self.waves {
            Waves::Linear { sum, .. } => sum.len().max(1),
            _ => 1,
        };
        if points.len() * ncomp < PARALLEL_WORK {
            for (p, o) in points.iter().zip(out.iter_mut()) {
                *o = self.at(*p, t, phase);
            }
        } else {
            // A few chunks per thread, so that the threads finish together.
            let per_thread = points.len().div_ceil(4 * rayon::current_num_threads());
            let chunk = per_thread.clamp(16, (PARALLEL_WORK / ncomp).max(16));
            points
                .par_chunks(chunk)
                .zip(out.par_chunks_mut(chunk))
                .for_each(|(ps, os)| {
                    for (p, o) in ps.iter().zip(os.iter_mut()) {
                        *o = self.at(*p, t, phase);
                    }
                });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airy::Component;
    use crate::current::CurrentProfile;

    fn airy_sea(h: f64, stretching: Stretching) -> Sea {
        let c = Constants {
            gravity: 9.81,
            ..Constants::with_depth(h)
        };
        let comp = Component::new(1.0, 8.0, 0.3, 0.2, c.depth, c.gravity).unwrap();
        Sea::new(
            c,
            Current::none(),
            Waves::Linear {
                sum: LinearSum::new(vec![comp], c.depth, c.gravity),
                stretching,
                ramp: Ramp::off(),
            },
        )
    }

    #[test]
    fn statics_see_no_waves_and_full_current() {
        let mut sea = airy_sea(50.0, Stretching::None);
        sea.current = Current {
            ramp: Ramp::new(10.0),
            ..Current::uniform([0.5, 0.0, 0.0])
        };
        let sea = sea.with_current_ramp(true);
        let f = sea.at([0.0, 0.0, -5.0], 0.0, Phase::Static);
        assert_eq!(f.wave_vel, [0.0; 3]);
        assert_eq!(f.current, [0.5, 0.0, 0.0]);
        let f = sea.at([0.0, 0.0, -5.0], 5.0, Phase::Dynamic);
        assert!((f.current[0] - 0.25).abs() < 1e-15 && f.current[1] == 0.0);
        assert!(f.current_acc[0] > 0.0);
    }

    #[test]
    fn zero_above_surface_every_stretching() {
        for st in [Stretching::None, Stretching::Vertical, Stretching::Wheeler] {
            let sea = airy_sea(40.0, st);
            for i in 0..50 {
                let t = i as f64 * 0.37;
                let eta = sea.elevation(3.0, -2.0, t, Phase::Dynamic);
                let f = sea.at([3.0, -2.0, eta + 1e-6], t, Phase::Dynamic);
                assert_eq!(f.wave_vel, [0.0; 3]);
                assert_eq!(f.wave_acc, [0.0; 3]);
                assert_eq!(f.p_dyn, 0.0);
                assert!(f.submergence < 0.0);
            }
        }
    }

    #[test]
    fn below_the_seabed_the_flow_is_the_flow_at_the_bed() {
        let h = 40.0;
        for stretching in [Stretching::None, Stretching::Wheeler] {
            let mut sea = airy_sea(h, stretching);
            sea.current = Current::uniform([0.5, 0.1, 0.0]);
            let at_bed = sea.at([3.0, 2.0, -h], 1.0, Phase::Dynamic);
            assert!(!sea.saw_point_below_seabed());
            for sink in [0.003, 1.0] {
                let below = sea.at([3.0, 2.0, -h - sink], 1.0, Phase::Dynamic);
                assert_eq!(below.current, [0.5, 0.1, 0.0]);
                assert_eq!(below.wave_vel, at_bed.wave_vel);
                assert_eq!(below.wave_acc, at_bed.wave_acc);
                assert_eq!(below.p_dyn, at_bed.p_dyn);
                assert_eq!(below.eta, at_bed.eta);
                // the point itself is that much deeper under the surface
                assert!((below.submergence - (at_bed.submergence + sink)).abs() < 1e-12);
            }
            assert!(sea.saw_point_below_seabed());
            // the orbits at a flat bed are horizontal, and they move there
            assert!(at_bed.wave_vel[2].abs() < 1e-12 && at_bed.wave_vel[0].abs() > 1e-3);
        }
        // A power-law profile vanishes at the bed, and so below it.
        let mut sea = airy_sea(h, Stretching::None);
        sea.current = Current::with_profile(CurrentProfile::PowerLaw {
            surface: [0.8, 0.0, 0.0],
            exponent: 1.0 / 7.0,
            depth: h,
        });
        let below = sea.at([0.0, 0.0, -h - 0.01], 0.0, Phase::Static);
        assert_eq!(below.current, [0.0; 3]);
    }

    #[test]
    fn eval_matches_at_serial_and_parallel() {
        let sea = airy_sea(40.0, Stretching::Wheeler);
        let pts: Vec<[f64; 3]> = (0..50_000)
            .map(|i| [i as f64 * 0.01, 0.0, -(i % 30) as f64])
            .collect();
        let mut out = vec![FlowPoint::default(); pts.len()];
        sea.eval(2.0, Phase::Dynamic, &pts, &mut out);
        for i in (0..pts.len()).step_by(997) {
            assert_eq!(out[i], sea.at(pts[i], 2.0, Phase::Dynamic));
        }
    }
}
