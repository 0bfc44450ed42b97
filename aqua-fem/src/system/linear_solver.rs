//! The linear solver of the Newton systems: the symmetric part's L·D·Lᵀ refined on the rest,
//! kept across iterations while it stays a good preconditioner, with the sparse LU (symbolic
//! analysis once) as fallback and for statics (docs/theory/fem.md#sparse-linear-algebra).

use super::schur::PartFactor;
use super::{SchurSolver, System};
use crate::error::{FemError, Result};
use crate::symmetric::{RefineStop, SymmetricSolver};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};

/// Factorisations on the LU after the symmetric path failed before it is tried again.
const SYMMETRIC_PAUSE: usize = 64;
/// A stale L·D·Lᵀ is replaced when a solve with it needs more than this many refinement
/// sweeps beyond the last solve with a fresh one (a numeric factorisation of the reference
/// cage costs about as much as 7 sweeps).
const STALE_EXTRA_SWEEPS: usize = 4;
/// Longest pause, in factorisations, before a kept L·D·Lᵀ is tried again after kept factors
/// failed in a row (docs/theory/fem.md#sparse-linear-algebra).
const MAX_STALE_PAUSE: usize = 8;

/// Sparse LU with a symbolic factorisation computed once.
pub(super) struct LinearSolver {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    mem: MemBuffer,
}

impl std::fmt::Debug for LinearSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LinearSolver").finish_non_exhaustive()
    }
}

impl System {
    /// Factorises the current `values`: the symmetric L·D·Lᵀ with refinement when `symmetric`
    /// is set and it applies, else the sparse LU (symbolic analyses on first use).
    pub fn factorize(&mut self) -> Result<()> {
        let nf = self.n_free();
        if nf == 0 {
            return Ok(());
        }
        if let Some(v) = self.values.iter().find(|v| !v.is_finite()) {
            return Err(FemError::NonFinite(format!("Jacobian entry {v}")));
        }
        self.sym_active = false;
        if self.symmetric && !self.sym_unusable {
            if self.sym_pause > 0 {
                self.sym_pause -= 1;
            } else {
                if self.sym.is_none() {
                    // A failed symbolic analysis leaves the LU, which has its own errors.
                    let parts = self.part_of_free.as_deref();
                    self.sym = SymmetricSolver::new(nf, &self.col_ptr, &self.row_idx, parts)
                        .unwrap_or(None);
                    self.sym_unusable = self.sym.is_none();
                }
                if let Some(s) = self.sym.as_mut() {
                    // After a kept factor failed, the next ones are skipped for a pause that
                    // doubles with each failure in a row: their failed solve is the cost of a
                    // factorisation on a scene whose tangent changes much between iterations.
                    let skip = !self.sym_refactor && self.sym_skip > 0;
                    if skip {
                        self.sym_skip -= 1;
                    }
                    if !self.sym_refactor && !skip {
                        // The last L·D·Lᵀ stays the preconditioner; the refinement solves
                        // with this J (docs/theory/fem.md#sparse-linear-algebra).
                        s.set_matrix(&self.values);
                        self.sym_active = true;
                        self.n_factor_reuses += 1;
                        return Ok(());
                    }
                    if s.factorize(&self.values).is_ok() {
                        self.sym_active = true;
                        self.sym_refactor = false;
                        self.n_factorisations += 1;
                        return Ok(());
                    }
                    self.symmetric_fallback();
                }
            }
        }
        self.factorize_lu(None)
    }

    /// The next `factorize` factorises afresh instead of keeping an earlier L·D·Lᵀ.
    pub fn require_fresh_factor(&mut self) {
        self.sym_refactor = true;
    }

    /// As `require_fresh_factor`, and the pause after failed kept factors ends: a run
    /// restored to a saved state repeats its steps bit for bit.
    pub fn restart_factor(&mut self) {
        self.sym_refactor = true;
        self.sym_skip = 0;
        self.sym_backoff = 0;
    }

    /// After the symmetric path failed: LU for the next `SYMMETRIC_PAUSE` factorisations.
    fn symmetric_fallback(&mut self) {
        self.n_symmetric_fallbacks += 1;
        self.sym_pause = SYMMETRIC_PAUSE;
        self.sym_active = false;
        self.sym_refactor = true;
    }

    /// The symmetric solve of `rhs` with the current factor; a stale factor that does not
    /// contract is replaced by a fresh one of this J and the solve repeated. `Err` leaves `rhs`
    /// untouched (the caller falls back to the LU).
    /// `floor` and `bound` as in `solve_within`; `Ok(true)` is an early stop on `bound`,
    /// whose sweep count says nothing of the factor's quality and is left out of the
    /// refactor rule.
    fn solve_symmetric(
        &mut self,
        rhs: &mut [f64],
        floor: f64,
        bound: Option<f64>,
    ) -> std::result::Result<bool, ()> {
        let sym = self.sym.as_mut().expect("symmetric factor");
        for _ in 0..2 {
            let fresh = sym.is_fresh();
            let stop = RefineStop { floor, bound };
            let out = sym.solve_within(&self.col_ptr, &self.row_idx, rhs, stop);
            self.n_refinement_sweeps += sym.last_sweeps;
            match (out, fresh) {
                (Ok(true), _) => return Ok(true),
                (Ok(false), true) => {
                    self.sym_fresh_sweeps = sym.last_sweeps;
                    return Ok(false);
                }
                (Ok(false), false) => {
                    self.sym_backoff = 0;
                    // Refactorise once the stale factor costs more sweeps than a new one.
                    if sym.last_sweeps > self.sym_fresh_sweeps + STALE_EXTRA_SWEEPS {
                        self.sym_refactor = true;
                    }
                    return Ok(false);
                }
                (Err(_), true) => return Err(()),
                (Err(_), false) => {
                    self.n_factor_reuses -= 1;
                    self.n_stale_failures += 1;
                    self.sym_backoff = (2 * self.sym_backoff).clamp(1, MAX_STALE_PAUSE);
                    self.sym_skip = self.sym_backoff;
                    if sym.refactor().is_err() {
                        return Err(());
                    }
                    self.n_factorisations += 1;
                    self.sym_refactor = false;
                }
            }
        }
        Err(())
    }

    /// Numeric LU of `values` (the current `self.values` if `None`): the block solve of the
    /// partition where there is one that pays, else the sparse LU of the whole.
    fn factorize_lu(&mut self, values: Option<&[f64]>) -> Result<()> {
        self.schur_active = false;
        if self.schur.is_none()
            && let Some(parts) = &self.part_of_free
        {
            self.schur = Some(SchurSolver::new(
                &self.col_ptr,
                &self.row_idx,
                parts,
                PartFactor::Lu,
            )?);
        }
        if let Some(Some(s)) = self.schur.as_mut() {
            s.factorize(values.unwrap_or(&self.values))?;
            self.schur_active = true;
            self.n_factorisations += 1;
            return Ok(());
        }
        let nf = self.n_free();
        // SAFETY-free: the pattern was built with sorted, in-range, unique row indices.
        let sym = SymbolicSparseColMatRef::new_checked(nf, nf, &self.col_ptr, None, &self.row_idx);
        if self.solver.is_none() {
            let symbolic = factorize_symbolic_lu(sym, Default::default())
                .map_err(|e| FemError::Linear(format!("symbolic LU: {e:?}")))?;
            let par = Par::Seq;
            let req = symbolic
                .factorize_numeric_lu_scratch::<f64>(par, Default::default())
                .or(symbolic.solve_in_place_scratch::<f64>(1, par));
            self.solver = Some(LinearSolver {
                symbolic,
                numeric: NumericLu::new(),
                mem: MemBuffer::try_new(req)
                    .map_err(|_| FemError::Linear("out of memory for LU workspace".into()))?,
            });
        }
        let s = self.solver.as_mut().expect("solver initialised");
        let mat = SparseColMatRef::new(sym, values.unwrap_or(&self.values));
        s.symbolic
            .factorize_numeric_lu(
                &mut s.numeric,
                mat,
                Par::Seq,
                MemStack::new(&mut s.mem),
                Default::default(),
            )
            .map_err(|e| FemError::Linear(format!("singular Jacobian ({e:?}); check supports")))?;
        self.n_factorisations += 1;
        Ok(())
    }

    /// Solves J·y = rhs in place with the last factorisation.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<()> {
        self.solve_within(rhs, 0.0, None).map(|_| ())
    }

    /// As `solve`, for a Newton caller that needs less than the full solution: the
    /// symmetric refinement also stops once ‖rhs − J·y‖₂ ≤ `floor`, and, with `bound`, once
    /// ‖y‖∞ ≤ bound is certain (a convergence check whose update is not applied; `Ok(true)`
    /// then, `rhs` holding the inexact y). `Ok(false)`: `rhs` holds y to 1e-10 or to
    /// `floor`. The LU solve is always exact.
    pub fn solve_within(
        &mut self,
        rhs: &mut [f64],
        floor: f64,
        bound: Option<f64>,
    ) -> Result<bool> {
        let nf = self.n_free();
        if nf == 0 {
            return Ok(false);
        }
        if self.sym_active {
            if let Ok(early) = self.solve_symmetric(rhs, floor, bound) {
                return Ok(early);
            }
            // The LU of the same matrix the symmetric factor was made of.
            let factored = std::mem::take(&mut self.sym.as_mut().expect("symmetric").factored);
            let lu = self.factorize_lu(Some(&factored));
            self.sym.as_mut().expect("symmetric").factored = factored;
            self.symmetric_fallback();
            lu?;
        }
        if self.schur_active {
            let s = self
                .schur
                .as_mut()
                .and_then(Option::as_mut)
                .expect("block solver");
            s.solve(rhs);
            return finite(rhs);
        }
        let s = self
            .solver
            .as_mut()
            .ok_or_else(|| FemError::Linear("solve before factorisation".into()))?;
        let lu = faer::sparse::linalg::lu::LuRef::new_unchecked(&s.symbolic, &s.numeric);
        let m = MatMut::from_column_major_slice_mut(rhs, nf, 1);
        lu.solve_in_place_with_conj(Conj::No, m, Par::Seq, MemStack::new(&mut s.mem));
        finite(rhs)
    }

    /// The block solver's number of parts and interface DOFs, if it serves the LU path.
    pub fn block_solve_shape(&self) -> Option<(usize, usize)> {
        self.schur
            .as_ref()
            .and_then(Option::as_ref)
            .map(SchurSolver::shape)
    }
}

/// `Ok(false)` if the solution is finite, else the singular-Jacobian error.
fn finite(rhs: &[f64]) -> Result<bool> {
    if rhs.iter().any(|v| !v.is_finite()) {
        return Err(FemError::Linear(
            "the Jacobian is singular (non-finite solution): a part of the structure may be \
             unsupported or massless"
                .into(),
        ));
    }
    Ok(false)
}
