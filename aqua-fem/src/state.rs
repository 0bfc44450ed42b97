//! Solver state and per-step outputs (docs/theory/fem.md#outputs).

use crate::cable;
use crate::model::Model;
use crate::system::System;
use serde::{Deserialize, Serialize};

/// Kinematic state of all nodes at time t.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct State {
    /// Time [s].
    pub t: f64,
    /// Positions [m].
    pub x: Vec<[f64; 3]>,
    /// Velocities [m/s].
    pub v: Vec<[f64; 3]>,
    /// Accelerations [m/s²].
    pub a: Vec<[f64; 3]>,
}

impl State {
    /// As-built positions, at rest, at time t (constrained DOFs at their values at t).
    pub fn as_built(model: &Model, t: f64) -> Self {
        let n = model.n_nodes();
        let mut s = State {
            t,
            x: model.nodes().to_vec(),
            v: vec![[0.0; 3]; n],
            a: vec![[0.0; 3]; n],
        };
        model.apply_constraints(t, 1.0, &mut s.x, &mut s.v, &mut s.a);
        s
    }

    /// Displacements u = x − X [m].
    pub fn displacements(&self, model: &Model) -> Vec<[f64; 3]> {
        self.x
            .iter()
            .zip(model.nodes())
            .map(|(x, x0)| [x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]])
            .collect()
    }
}

/// Element and nodal results at one time.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Outputs {
    /// Axial force T per element [N] (signed, incl. axial damping).
    pub tension: Vec<f64>,
    /// Engineering strain per element.
    pub strain: Vec<f64>,
    /// Current length per element [m].
    pub length: Vec<f64>,
    /// Bending moment |M| per element that is a rod edge: the larger of its ends [N·m]
    /// (docs/theory/fem.md#rod); 0 elsewhere.
    #[serde(default)]
    pub bending_moment: Vec<f64>,
    /// Torque per element that is a rod edge: the mean of its ends [N·m]; 0 elsewhere.
    #[serde(default)]
    pub torque: Vec<f64>,
    /// Reaction per node [N]: the force the support applies to the structure (zero on free
    /// DOFs); R = M·a + f_int + f_bed − f_ext at constrained DOFs.
    pub reaction: Vec<[f64; 3]>,
    /// Seabed contact force per node [N].
    pub seabed_force: Vec<[f64; 3]>,
    /// Water load per node from the load provider [N].
    pub hydro_force: Vec<[f64; 3]>,
}

impl Outputs {
    pub(crate) fn new(model: &Model) -> Self {
        let (ne, n) = (model.elements().len(), model.n_nodes());
        Self {
            tension: vec![0.0; ne],
            strain: vec![0.0; ne],
            length: vec![0.0; ne],
            bending_moment: vec![0.0; ne],
            torque: vec![0.0; ne],
            reaction: vec![[0.0; 3]; n],
            seabed_force: vec![[0.0; 3]; n],
            hydro_force: vec![[0.0; 3]; n],
        }
    }

    /// Fills from the last evaluation of `sys` (which must include M·a in dynamics).
    pub(crate) fn update(&mut self, model: &Model, sys: &System, with_inertia: bool) {
        for (i, c) in sys.cable.iter().enumerate() {
            self.tension[i] = c.tension;
            self.strain[i] = c.strain;
            self.length[i] = c.length;
        }
        sys.rod_section_forces(model, &mut self.bending_moment, &mut self.torque);
        for i in 0..model.n_nodes() {
            for k in 0..3 {
                self.reaction[i][k] = if model.is_constrained(i, k) {
                    sys.q[i][k] + if with_inertia { sys.ma[i][k] } else { 0.0 }
                } else {
                    0.0
                };
            }
        }
        self.seabed_force.copy_from_slice(&sys.fbed);
        self.hydro_force.copy_from_slice(&sys.fhydro);
    }

    /// Total strain energy Σ ½·s·EA·ε²·L0 [J].
    pub fn strain_energy(&self, model: &Model) -> f64 {
        model
            .elements()
            .iter()
            .zip(&self.strain)
            .map(|(e, &s)| cable::strain_energy(e, s))
            .sum()
    }

    /// Number of slack elements (ε ≤ 0).
    pub fn n_slack(&self) -> usize {
        self.strain.iter().filter(|&&s| s <= 0.0).count()
    }
}
