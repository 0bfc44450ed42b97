//! The wall-time model behind `aqua check`'s cost estimate: Newton iterations expected for the
//! statics and the dynamics, times the cost of one iteration, from the counts of the model.
//! Measured constants of this code, release build on the 2-core development machine; the
//! measurements that set them, and how far each example's estimate is from its measured wall,
//! are in docs/notes/check-estimate.md.
//!
//! One Newton iteration costs a part proportional to the elements (evaluation and assembly of
//! the cables and water loads; in dynamics also the sea at every node and wave component, a
//! fixed part and a part per rigid body) and a part for the sparse factorisation, which grows
//! faster than the unknowns: each net is a 2-D mesh whose factor fills in, measured as growing
//! with the square of the net's free DOFs (the cages of a farm are separate nets joined by a few
//! bridle DOFs, so a farm of 8 cages costs 8 cages, not one net of 8 times the DOFs). The static solver needs more iterations
//! the finer the net (docs/theory/fem.md#static-solver): 76 / 108 / 333 iterations on the
//! reference cage at 5 / 2.5 / 1.25 m elements.

/// How the dynamic phase is driven, which sets its Newton iterations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Driving {
    /// No dynamic phase.
    #[default]
    None,
    /// Something floats on slack lines in waves (collars, buoys): the step is halved to
    /// milliseconds and grows back only partly.
    FloatingInWaves,
    /// A prescribed motion drives a stiff line.
    Prescribed,
    /// Anything else (current, waves on fixed structures).
    Steady,
}

/// The counts the estimate depends on.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Workload {
    /// Free DOFs.
    pub free_dofs: usize,
    /// Cable elements plus water-load elements (panels, lines, points).
    pub elements: usize,
    /// Σ over the nets (cages, panels, imported meshes) of their free DOFs squared.
    pub net_dofs_squared: f64,
    /// Wave components × nodes (the sea is evaluated at every node in dynamics).
    pub wave_points: usize,
    /// Nothing but lines (no net, nothing floating): the statics start from the stretched
    /// touchdown shape.
    pub lines_only: bool,
    /// A static solve is part of the run.
    pub statics: bool,
    /// Coarser levels solved first (`analysis.static.mesh_sequence`).
    pub mesh_sequence: usize,
    /// The dynamic phase.
    pub driving: Driving,
    /// The dynamic phase runs the midpoint rule (more Newton iterations a step than HHT-α).
    pub midpoint: bool,
    /// Rigid bodies (`[[body]]`).
    pub bodies: usize,
    /// Dynamic steps at the nominal step.
    pub steps: usize,
    /// Simulated time of the dynamic phase [s].
    pub t_end: f64,
}

/// Seconds per static iteration and element (cables and water loads, the water-load
/// Jacobian by finite differences, trial evaluations of the line search).
pub const STATIC_PER_ELEMENT: f64 = 2.7e-6;
/// Seconds per static iteration and squared free DOF of a net (its factorisation).
pub const STATIC_PER_NET_DOF2: f64 = 8.0e-10;
/// Seconds per dynamic iteration whatever the model (the step's bookkeeping, guards and
/// trackers; what a line of a few elements costs).
pub const DYNAMIC_PER_ITERATION: f64 = 75e-6;
/// Seconds per dynamic iteration and element.
pub const DYNAMIC_PER_ELEMENT: f64 = 0.75e-6;
/// Seconds per dynamic iteration, node and wave component.
pub const DYNAMIC_PER_WAVE_POINT: f64 = 57e-9;
/// Seconds per dynamic iteration and rigid body (its hull's loads and the links of its
/// fairleads, differentiated with dual numbers; the feed barge).
pub const DYNAMIC_PER_BODY: f64 = 0.5e-3;
/// Seconds per dynamic iteration and squared free DOF of a net (the factor is reused across
/// iterations while it preconditions well, so less than in statics).
pub const DYNAMIC_PER_NET_DOF2: f64 = 1.1e-10;
/// Newton iterations per simulated second when something floats on slack lines in waves
/// (halvings included; the bundled farm 224 with HHT-α), at [`FLOATING_REFERENCE_DOFS`].
pub const FLOATING_ITERATIONS_PER_SECOND: f64 = 220.0;
/// Free DOFs (the bundled farm's) at which the floating iterations per second are
/// [`FLOATING_ITERATIONS_PER_SECOND`]; above, they grow as (free DOFs /
/// this)^[`FLOATING_SIZE_EXPONENT`], below they fall as (free DOFs /
/// this)^[`FLOATING_SMALL_EXPONENT`].
pub const FLOATING_REFERENCE_DOFS: f64 = 4605.0;
/// How the floating iterations per second fall below the bundled farm's size: the moored cage
/// (1 287 free DOFs, HHT-α) takes 122 per second against the farm's 224,
/// ln(224/122)/ln(4 701/1 287) = 0.47.
pub const FLOATING_SMALL_EXPONENT: f64 = 0.47;
/// Newton iterations per step of a line driven by a prescribed motion with HHT-α (line and
/// seabed relaxation; the mooring chain 2.05 at dt 0.1 s, 1.9 at 0.01 s).
pub const PRESCRIBED_ITERATIONS_PER_STEP_HHT: f64 = 2.05;
/// Newton iterations per step of a line driven by a prescribed motion with the midpoint rule,
/// a + b·Δt: the mooring chain takes 3.29 / 2.61 / 2.12 / 1.94 / 1.92 at
/// Δt = 0.1 / 0.05 / 0.025 / 0.0125 / 0.01 s.
pub const PRESCRIBED_ITERATIONS_PER_STEP_MIDPOINT: (f64, f64) = (1.9, 14.0);
/// How the floating iterations per second grow with the model: a larger farm has more slack
/// members, and a step fails Newton when any of them does, so its step is halved further
/// (the full-scale farm, 103 013 free DOFs: 424 per second over its first 12 s against the
/// bundled farm's 189, ln(424/189)/ln(103 013/4 605) = 0.26; on the base of 220 the model gives
/// it 493, 16 % above its count, while its cost per iteration is 29 % above the model's).
pub const FLOATING_SIZE_EXPONENT: f64 = 0.26;

impl Workload {
    /// Expected Newton iterations of the static solve: 2 evaluations when nothing is free,
    /// 13.5 for lines alone, else 80 + 0.022 per free DOF (the reference-cage ladder 76 /
    /// 108 / 333 at 795 / 3 027 / 12 387 DOFs, the farm 156 and 211 at 4 605 and 10 113).
    pub fn static_iterations(&self) -> f64 {
        if self.free_dofs == 0 {
            2.0
        } else if self.lines_only {
            13.5
        } else {
            80.0 + 0.022 * self.free_dofs as f64
        }
    }

    /// Seconds per static Newton iteration.
    pub fn static_iteration_seconds(&self) -> f64 {
        STATIC_PER_ELEMENT * self.elements as f64 + STATIC_PER_NET_DOF2 * self.net_dofs_squared
    }

    /// Estimated static solve [s] (0 without one). With a mesh sequence, level k (the nets'
    /// element length 2^k times the scene's) has 1/4^k of the DOFs and elements and 1/16^k of
    /// the factorisation, and every level, started from the level below, needs about the
    /// iterations of the coarsest level solved alone (measured on the full-scale farm:
    /// 149 / 129 / 208 iterations at 6.4 / 3.2 / 1.6 m with `stretch_damping`, 196 / 178 / 291
    /// without, the model 221 each;
    /// docs/theory/fem.md#mesh-sequencing).
    pub fn static_seconds(&self) -> f64 {
        if !self.statics {
            return 0.0;
        }
        if self.mesh_sequence == 0 || self.lines_only || self.free_dofs == 0 {
            return self.static_iterations() * self.static_iteration_seconds();
        }
        let level = |k: usize| {
            let f = 4f64.powi(k as i32);
            Workload {
                free_dofs: (self.free_dofs as f64 / f) as usize,
                elements: (self.elements as f64 / f) as usize,
                net_dofs_squared: self.net_dofs_squared / (f * f),
                ..*self
            }
        };
        let n = self.mesh_sequence;
        (0..=n)
            .map(|k| level(n).static_iterations() * level(k).static_iteration_seconds())
            .sum()
    }

    /// Expected Newton iterations of the dynamic phase, step halvings included.
    pub fn dynamic_iterations(&self) -> f64 {
        match self.driving {
            Driving::None => 0.0,
            // At least one iteration a nominal step (the feed barge at dt 2.5 ms: 1.03).
            Driving::FloatingInWaves => {
                let size = self.free_dofs as f64 / FLOATING_REFERENCE_DOFS;
                let exponent = if size >= 1.0 {
                    FLOATING_SIZE_EXPONENT
                } else {
                    FLOATING_SMALL_EXPONENT
                };
                let per_second = FLOATING_ITERATIONS_PER_SECOND * size.powf(exponent);
                (per_second * self.t_end).max(1.03 * self.steps as f64)
            }
            Driving::Prescribed => {
                let per_step = if self.midpoint {
                    let (a, b) = PRESCRIBED_ITERATIONS_PER_STEP_MIDPOINT;
                    a + b * self.t_end / (self.steps.max(1) as f64)
                } else {
                    PRESCRIBED_ITERATIONS_PER_STEP_HHT
                };
                per_step * self.steps as f64
            }
            // Reference cage and buoy mooring in a current: 1.0 per step.
            Driving::Steady => 1.2 * self.steps as f64,
        }
    }

    /// Seconds per dynamic Newton iteration.
    pub fn dynamic_iteration_seconds(&self) -> f64 {
        DYNAMIC_PER_ITERATION
            + DYNAMIC_PER_BODY * self.bodies as f64
            + DYNAMIC_PER_ELEMENT * self.elements as f64
            + DYNAMIC_PER_WAVE_POINT * self.wave_points as f64
            + DYNAMIC_PER_NET_DOF2 * self.net_dofs_squared
    }

    /// Estimated dynamic phase [s] (0 without one).
    pub fn dynamic_seconds(&self) -> f64 {
        self.dynamic_iterations() * self.dynamic_iteration_seconds()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cage net refined by `r` halvings of its element length from a 5 m cage: 4× the
    /// elements and free DOFs per halving, one net.
    fn cage(r: i32) -> Workload {
        let f = 4f64.powi(r);
        let dofs = (795.0 * f) as usize;
        Workload {
            free_dofs: dofs,
            elements: (1176.0 * f) as usize,
            net_dofs_squared: (dofs as f64).powi(2),
            statics: true,
            driving: Driving::Steady,
            steps: 100,
            t_end: 10.0,
            ..Default::default()
        }
    }

    #[test]
    fn estimate_grows_with_every_count() {
        let base = cage(1);
        let total = |w: &Workload| w.static_seconds() + w.dynamic_seconds();
        let more = [
            Workload {
                free_dofs: base.free_dofs + 1000,
                ..base
            },
            Workload {
                elements: base.elements + 1000,
                ..base
            },
            Workload {
                net_dofs_squared: base.net_dofs_squared * 2.0,
                ..base
            },
            Workload {
                wave_points: 10_000,
                ..base
            },
            Workload {
                steps: base.steps * 2,
                ..base
            },
            Workload { bodies: 1, ..base },
        ];
        for (k, w) in more.iter().enumerate() {
            assert!(total(w) > total(&base), "count {k}: {w:?}");
        }
        // Monotone along the refinement ladder, in both phases.
        for r in 0..4 {
            let (a, b) = (cage(r), cage(r + 1));
            assert!(b.static_seconds() > a.static_seconds(), "{r}");
            assert!(b.dynamic_seconds() > a.dynamic_seconds(), "{r}");
        }
    }

    /// The statics of a net cost more than its DOFs: more iterations and dearer ones at every
    /// halving of the element length (docs/theory/fem.md#static-solver). Each halving
    /// quadruples the DOFs; the estimate must grow by more than 4^1.3 (the target
    /// slope, which today's solver does not meet), while the cost of a dynamic step, at the
    /// same number of steps, grows at least linearly.
    #[test]
    fn statics_grow_super_linearly_with_refinement() {
        for r in 0..3 {
            let (a, b) = (cage(r), cage(r + 1));
            let dofs = b.free_dofs as f64 / a.free_dofs as f64;
            let stat = b.static_seconds() / a.static_seconds();
            assert!(
                stat > dofs.powf(1.3),
                "halving {r}: statics × {stat:.2} for DOFs × {dofs:.2}"
            );
            assert!(b.static_iterations() > a.static_iterations());
            let dynamic = b.dynamic_seconds() / a.dynamic_seconds();
            assert!(
                dynamic >= 0.99 * dofs,
                "halving {r}: dynamics × {dynamic:.2}"
            );
        }
    }

    /// A farm of n separate nets costs n nets, not one net of n times the DOFs: the
    /// factorisation term adds over the nets.
    #[test]
    fn separate_nets_cost_their_sum() {
        let one = cage(2);
        let eight = Workload {
            free_dofs: 8 * one.free_dofs,
            elements: 8 * one.elements,
            net_dofs_squared: 8.0 * one.net_dofs_squared,
            ..one
        };
        let per = |w: &Workload| w.static_iteration_seconds();
        assert!((per(&eight) / per(&one) - 8.0).abs() < 1e-9);
        let merged = Workload {
            net_dofs_squared: (8.0 * one.free_dofs as f64).powi(2),
            ..eight
        };
        assert!(per(&merged) > 2.0 * per(&eight));
    }

    /// A mesh sequence costs the coarser solves but saves fine iterations: on a farm-sized
    /// net the estimate falls (measured on the full-scale farm: no convergence in an hour
    /// without, 346 s with two levels), and each level is cheaper than the one above.
    #[test]
    fn a_mesh_sequence_lowers_the_estimate_of_a_large_net() {
        let fine = Workload {
            mesh_sequence: 0,
            ..cage(4)
        };
        let one = Workload {
            mesh_sequence: 1,
            ..fine
        };
        let two = Workload {
            mesh_sequence: 2,
            ..fine
        };
        assert!(one.static_seconds() < 0.5 * fine.static_seconds());
        assert!(two.static_seconds() < one.static_seconds());
        // The coarser levels add to the fine level's cost: more than the fine level alone at
        // the coarser level's iteration count.
        let fine_alone = cage(3).static_iterations() * fine.static_iteration_seconds();
        assert!(one.static_seconds() > fine_alone);
    }

    #[test]
    fn nothing_free_or_lines_alone_take_few_iterations() {
        let none = Workload {
            statics: true,
            elements: 500,
            ..Default::default()
        };
        assert_eq!(none.static_iterations(), 2.0);
        let lines = Workload {
            free_dofs: 3000,
            lines_only: true,
            ..none
        };
        assert!(lines.static_iterations() < 20.0);
        assert_eq!(none.dynamic_seconds(), 0.0);
        let floating = Workload {
            free_dofs: 4605,
            driving: Driving::FloatingInWaves,
            t_end: 30.0,
            steps: 300,
            ..none
        };
        assert_eq!(floating.dynamic_iterations(), 220.0 * 30.0);
    }

    /// A dynamic phase takes at least one Newton iteration a step: a floating model run at a
    /// small step (the feed barge at dt 2.5 ms: 24 708 iterations for 24 004 steps, where the
    /// rate per simulated second gives 5 800) is estimated from its steps.
    #[test]
    fn a_small_step_costs_at_least_an_iteration_a_step() {
        let barge = Workload {
            free_dofs: 810,
            driving: Driving::FloatingInWaves,
            t_end: 60.0,
            steps: 24_000,
            ..Default::default()
        };
        assert!(barge.dynamic_iterations() >= 24_000.0);
        let coarse = Workload {
            steps: 600,
            ..barge
        };
        assert!(coarse.dynamic_iterations() < 0.5 * barge.dynamic_iterations());
    }

    /// The midpoint rule takes more Newton iterations a step than HHT-α on a line driven by a
    /// prescribed motion (the mooring chain at dt 0.1 s: 3.3 against 2.05), fewer at smaller
    /// steps (2.1 at 0.025 s).
    #[test]
    fn the_midpoint_rule_costs_more_iterations_on_a_driven_line() {
        let hht = Workload {
            free_dofs: 237,
            elements: 160,
            driving: Driving::Prescribed,
            steps: 600,
            t_end: 60.0,
            ..Default::default()
        };
        let mid = Workload {
            midpoint: true,
            ..hht
        };
        let ratio = mid.dynamic_seconds() / hht.dynamic_seconds();
        assert!((ratio - 3.3 / 2.05).abs() < 1e-9, "{ratio}");
        let fine = Workload { steps: 2400, ..mid };
        let per_step = fine.dynamic_iterations() / 2400.0;
        assert!((per_step - 2.25).abs() < 1e-9, "{per_step}");
    }

    /// A larger floating model halves its step further, so it takes more iterations per
    /// simulated second, though fewer than in proportion to its size; a smaller one fewer
    /// (the moored cage, 1 287 free DOFs: 122 per second).
    #[test]
    fn a_larger_floating_farm_takes_more_iterations_per_second() {
        let floating = |free_dofs| Workload {
            free_dofs,
            driving: Driving::FloatingInWaves,
            t_end: 12.0,
            ..Default::default()
        };
        let cage = floating(1287).dynamic_iterations() / 12.0;
        assert!((cage - 122.0).abs() < 3.0, "{cage}");
        assert_eq!(floating(4605).dynamic_iterations(), 220.0 * 12.0);
        let (a, b) = (
            floating(50_000).dynamic_iterations(),
            floating(100_000).dynamic_iterations(),
        );
        assert!(a > 220.0 * 12.0 && b > a && b < 2.0 * a, "{a} {b}");
    }
}
