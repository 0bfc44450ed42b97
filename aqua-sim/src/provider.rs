//! The bridge between the water loads (aqua-hydro) and the structural solver (aqua-fem):
//! [`WaterLoads`] implements aqua-fem's `LoadProvider` with an aqua-hydro `LoadAssembly`.
//!
//! Neither crate knows the other; this is the one place that joins them.

use aqua_env::Phase;
use aqua_fem::{ElementLoad, LoadError, LoadProvider, Want};
use aqua_hydro::assembly::{ElementOutput, Elements, LoadAssembly};
use std::cell::RefCell;

thread_local! {
    /// The hydro side's element output, one per thread: 2.7 kB that a fresh value per element
    /// and evaluation would zero each time (the assembly overwrites what it reports).
    static LOCAL: RefCell<ElementOutput> = RefCell::new(ElementOutput::default());
}

/// Water loads for the structural solver: static phase (full current, no waves) or dynamic.
#[derive(Debug)]
pub struct WaterLoads {
    /// The load assembly (sea, elements, wake, buffers).
    pub assembly: LoadAssembly,
    /// Which sea the solver sees.
    pub phase: Phase,
    /// Nodes that carry buoyancy (lines with a volume, point bodies with a volume).
    buoyant: Vec<usize>,
    /// Per node: its buoyancy with every member fully submerged [N].
    max_lift: Vec<f64>,
}

impl WaterLoads {
    /// Wraps an assembly for the given phase; `elements` are the ones it was built from.
    pub fn new(assembly: LoadAssembly, phase: Phase, elements: &Elements) -> Self {
        let mut buoyant: Vec<usize> = elements
            .lines
            .iter()
            .filter(|l| l.props.volume_diameter > 0.0)
            .flat_map(|l| l.nodes)
            .chain(
                elements
                    .points
                    .iter()
                    .filter(|p| p.props.volume > 0.0)
                    .map(|p| p.node),
            )
            .collect();
        buoyant.sort_unstable();
        buoyant.dedup();
        // Fully submerged buoyancy: ρ·g·(π/4)·d_v²·L0 of a line (half to each end), ρ·g·V of
        // a point body (docs/theory/hydrodynamics.md).
        let rho_g = assembly.sea().density() * assembly.sea().gravity();
        let n = elements
            .lines
            .iter()
            .flat_map(|l| l.nodes)
            .chain(elements.points.iter().map(|p| p.node))
            .max()
            .map_or(0, |i| i + 1);
        let mut max_lift = vec![0.0; n];
        for l in &elements.lines {
            let d = l.props.volume_diameter;
            let f = rho_g * std::f64::consts::FRAC_PI_4 * d * d * l.props.rest_length;
            for &i in &l.nodes {
                max_lift[i] += 0.5 * f;
            }
        }
        for p in &elements.points {
            max_lift[p.node] += rho_g * p.props.volume;
        }
        Self {
            assembly,
            phase,
            buoyant,
            max_lift,
        }
    }
}

impl LoadProvider for WaterLoads {
    fn n_elements(&self) -> usize {
        self.assembly.n_elements()
    }

    fn element_nodes(&self, e: usize) -> &[usize] {
        self.assembly.element_nodes(e)
    }

    fn prepare(&mut self, t: f64, x: &[[f64; 3]], _v: &[[f64; 3]]) -> Result<(), LoadError> {
        self.assembly
            .prepare(t, self.phase, x)
            .map_err(LoadError::new)
    }

    fn accept_state(&mut self, t: f64, x: &[[f64; 3]]) -> Result<bool, LoadError> {
        self.assembly.update_wake(t, x).map_err(LoadError::new)
    }

    fn element_load(
        &self,
        e: usize,
        _t: f64,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        want: Want,
        out: &mut ElementLoad,
    ) -> Result<(), LoadError> {
        let hw = aqua_hydro::Want {
            dfdv: want.dfdv,
            dfdx: want.dfdx,
        };
        // The reused output holds only what the assembly wrote for this element's nodes.
        debug_assert_eq!(x.len(), self.assembly.element_nodes(e).len());
        LOCAL.with_borrow_mut(|local| {
            self.assembly.element_load(e, x, v, hw, local);
            let n = x.len();
            let dofs = 3 * n;
            out.force[..n].copy_from_slice(&local.force[..n]);
            out.added_mass[..n].copy_from_slice(&local.added_mass[..n]);
            if want.dfdv {
                for r in 0..dofs {
                    out.dfdv[r][..dofs].copy_from_slice(&local.dfdv[r][..dofs]);
                }
                out.has_dfdv = true;
            }
            if want.dfdx {
                for r in 0..dofs {
                    out.dfdx[r][..dofs].copy_from_slice(&local.dfdx[r][..dofs]);
                }
                out.has_dfdx = true;
            }
        });
        Ok(())
    }

    fn max_buoyancy(&self, lift: &mut [f64]) -> bool {
        for (l, m) in lift.iter_mut().zip(&self.max_lift) {
            *l += m;
        }
        true
    }

    fn mark_restoring_nodes(&self, held: &mut [bool]) {
        for &n in &self.buoyant {
            if let Some(h) = held.get_mut(n) {
                *h = true;
            }
        }
    }
}
