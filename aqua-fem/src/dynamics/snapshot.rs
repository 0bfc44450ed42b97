//! A saved state of the implicit integrator (a coupling's save and restore): everything the
//! next step reads — the state, the previous step's internal forces and loads (the scheme's
//! residual and the energy ledger use them), the step control, the rods' and the rigid
//! bodies' reference frames, the members' memory of the energy-consistent HHT-α —
//! so that restore → step repeats save → step bit for bit (docs/theory/fem.md#coupling).
//! Factorisations are not saved: both save and restore ask for a fresh one, so the step after
//! either starts from the same linear algebra. A checkpoint ([`DynamicSolver::checkpoint`]) is
//! the same snapshot without that request (a coupling's revert of a failed call). The history
//! of peak tensions (the step's resolution indicator) is cut back to the saved length, not
//! copied.

use super::{DynamicSolver, Energies, HhtForces, StepControl};
use crate::error::{FemError, Result};
use crate::rigid_body::BodyFrame;
use crate::rod::EdgeFrame;
use crate::state::{Outputs, State};

/// What [`DynamicSolver::save`] keeps; see the module docs.
#[derive(Debug, Clone)]
pub struct Snapshot {
    state: State,
    q_prev: Vec<[f64; 3]>,
    fext_prev: Vec<[f64; 3]>,
    power_prev: f64,
    outputs: Outputs,
    dt_cur: f64,
    good_steps: usize,
    energies: Energies,
    n_steps: usize,
    total_iterations: usize,
    last_reaction: Vec<[f64; 3]>,
    first_contraction: f64,
    control: StepControl,
    peak_len: usize,
    kinetic_free: f64,
    rod_frames: Vec<EdgeFrame>,
    body_frames: Vec<BodyFrame>,
    hht: Option<HhtForces>,
    t_end: f64,
    extremes: Option<super::extreme_control::ExtremeControl>,
}

impl Snapshot {
    /// The time of the saved state [s].
    pub fn time(&self) -> f64 {
        self.state.t
    }
}

impl DynamicSolver<'_> {
    /// Saves the integrator's state; the next step factorises afresh.
    pub fn save(&mut self) -> Snapshot {
        self.fresh_factor();
        self.checkpoint()
    }

    /// The integrator's state, leaving the kept factorisation in use.
    pub fn checkpoint(&self) -> Snapshot {
        Snapshot {
            state: self.state.clone(),
            q_prev: self.q_prev.clone(),
            fext_prev: self.fext_prev.clone(),
            power_prev: self.power_prev,
            outputs: self.outputs.clone(),
            dt_cur: self.dt_cur,
            good_steps: self.good_steps,
            energies: self.energies,
            n_steps: self.n_steps,
            total_iterations: self.total_iterations,
            last_reaction: self.last_reaction.clone(),
            first_contraction: self.first_contraction,
            control: StepControl {
                peak_tensions: Vec::new(),
                peak_elements: Vec::new(),
                ..self.control.clone()
            },
            peak_len: self.control.peak_tensions.len(),
            kinetic_free: self.kinetic_free,
            rod_frames: self.sys.rod_frames.clone(),
            body_frames: self.sys.body_frames().to_vec(),
            hht: self.scheme.hht_forces().cloned(),
            t_end: self.st.t_end,
            extremes: self.extremes.clone(),
        }
    }

    /// Puts back a state saved by [`DynamicSolver::save`] of this solver (same model).
    pub fn restore(&mut self, s: &Snapshot) -> Result<()> {
        if s.state.x.len() != self.state.x.len()
            || s.rod_frames.len() != self.sys.rod_frames.len()
            || s.body_frames.len() != self.sys.body_frames().len()
        {
            return Err(FemError::InvalidModel(format!(
                "a snapshot of {} nodes restored into a solver of {}",
                s.state.x.len(),
                self.state.x.len()
            )));
        }
        self.state.clone_from(&s.state);
        self.q_prev.clone_from(&s.q_prev);
        self.fext_prev.clone_from(&s.fext_prev);
        self.power_prev = s.power_prev;
        self.outputs.clone_from(&s.outputs);
        self.dt_cur = s.dt_cur;
        self.good_steps = s.good_steps;
        self.energies = s.energies;
        self.n_steps = s.n_steps;
        self.total_iterations = s.total_iterations;
        self.last_reaction.clone_from(&s.last_reaction);
        self.first_contraction = s.first_contraction;
        let mut peaks = std::mem::take(&mut self.control.peak_tensions);
        let mut elements = std::mem::take(&mut self.control.peak_elements);
        peaks.truncate(s.peak_len);
        elements.truncate(s.peak_len);
        self.control.clone_from(&s.control);
        self.control.peak_tensions = peaks;
        self.control.peak_elements = elements;
        self.kinetic_free = s.kinetic_free;
        self.sys.rod_frames.clone_from(&s.rod_frames);
        self.sys.set_body_frames(&s.body_frames);
        if let Some(f) = &s.hht {
            self.scheme.restore_hht_forces(f);
        }
        self.st.t_end = s.t_end;
        self.extremes.clone_from(&s.extremes);
        self.clamp = false;
        self.full_newton = false;
        self.guarded = None;
        self.fresh_factor();
        Ok(())
    }

    /// The next Newton iteration forms and factorises its Jacobian afresh.
    fn fresh_factor(&mut self) {
        self.lu_valid = false;
        self.sys.restart_factor();
    }
}
