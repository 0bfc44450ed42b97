//! Symmetric factorisation of a nearly symmetric tangent with iterative refinement on the
//! non-symmetric remainder (docs/theory/fem.md#sparse-linear-algebra).
//!
//! S⁻¹ is applied by one L·D·Lᵀ of the whole, or, for a partitioned model (the cages of a
//! farm), by the [block solve](crate::system::schur) with an L·D·Lᵀ per part, the parts
//! factorised in parallel (docs/theory/fem.md#block-solve).
//!
//! The dynamic tangent J = m·M + c·C + k·K is symmetric except for the water loads'
//! velocity and position derivatives. Writing J = S + A with S = ½(J + Jᵀ) and A = ½(J − Jᵀ),
//! S is factorised as L·D·Lᵀ (AMD ordering, simplicial or supernodal by the fill of the
//! factor, the symbolic analysis reused) and J·y = b is solved by the stationary iteration
//!
//! ```text
//! y₀ = S⁻¹·b,    y_{k+1} = y_k + S⁻¹·(b − J·y_k)
//! ```
//!
//! whose error contracts by the spectral radius of S⁻¹A per sweep. It stops when
//! ‖b − J·y‖₂ ≤ `REFINE_TOL`·‖b‖₂, so the Newton step is that of J to round-off and Newton's
//! convergence is unchanged. When a sweep shrinks the residual by less than 10 %, or after
//! `MAX_SWEEPS`, a fresh factor hands the solve to restarted GMRES right-preconditioned by
//! S⁻¹ (a few eigenvalues of S⁻¹J outside |1 − λ| < 1 are what stalls the sweeps,
//! docs/theory/fem.md#gmres-rescue); when that fails too, or the L·D·Lᵀ has a zero pivot, the
//! caller falls back to the sparse LU of J.
//!
//! Since the sweeps solve with J itself, the factor may be that of an earlier, nearby matrix
//! ([`set_matrix`](SymmetricSolver::set_matrix)): it then only costs more sweeps. The caller
//! (`System`) keeps a factor across Newton iterations and steps until it grows too stale.

use crate::error::{FemError, Result};
use crate::system::schur::{PartFactor, SchurSolver};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LdltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// Refinement stops at ‖b − J·y‖₂ ≤ REFINE_TOL·‖b‖₂ (far below the Newton tolerances, so
/// the inexact solve does not change Newton's iterates beyond round-off of the tolerance).
const REFINE_TOL: f64 = 1e-10;
/// Refinement sweeps before giving up on the symmetric factor.
const MAX_SWEEPS: usize = 30;
/// A sweep must shrink the residual by at least this factor.
const MIN_CONTRACTION: f64 = 0.9;
/// Krylov dimension of the GMRES rescue before a restart.
const GMRES_RESTART: usize = 20;
/// GMRES cycles (of `GMRES_RESTART` applications of S⁻¹ each) before the LU takes over.
const GMRES_CYCLES: usize = 3;

/// Largest fill nnz(L)/n of the simplicial L·D·Lᵀ for which it is kept; denser factors are
/// supernodal. Measured (release, this 2-core machine): the 160-segment chain (fill 5.0)
/// 0.46–0.63 s simplicial against 0.76–0.83 s supernodal for its 60 s run, the 2 × 3 farm
/// (14.7) 2.9 against 3.4 s for 3 s, the reference cage (40) 7.2 ms per step simplicial
/// against 5.7–6.0 ms supernodal.
const SIMPLICIAL_MAX_FILL: f64 = 24.0;

/// Early ends of the refinement besides ‖b − J·y‖₂ ≤ `REFINE_TOL`·‖b‖₂.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct RefineStop {
    /// Stop, as solved, once ‖b − J·y‖₂ is at most this (0: never). A Newton caller
    /// passes a fraction of its own residual tolerance (inexact Newton).
    pub floor: f64,
    /// Stop, as settled, once ‖y‖∞ ≤ bound is certain: ‖y‖∞ + 2‖δ‖∞ ≤ bound.
    pub bound: Option<f64>,
}

/// The L·D·Lᵀ of the symmetric part of a structurally symmetric CSC matrix.
pub(crate) struct SymmetricSolver {
    n: usize,
    /// Upper-triangle pattern (CSC, rows sorted).
    up_col_ptr: Vec<usize>,
    up_row_idx: Vec<usize>,
    /// For each upper entry (r, c): positions of (r, c) and (c, r) in the full values.
    pairs: Vec<(usize, usize)>,
    up_values: Vec<f64>,
    /// How S⁻¹ is applied.
    factor: SymmetricFactor,
    /// The full matrix at the last factorisation (refinement residuals use it).
    pub(crate) factored: Vec<f64>,
    b: Vec<f64>,
    y: Vec<f64>,
    res: Vec<f64>,
    /// Refinement sweeps of the last solve (GMRES steps included).
    pub last_sweeps: usize,
    /// Solves that the sweeps did not finish and GMRES did.
    pub gmres_rescues: usize,
    /// GMRES basis V (m + 1 vectors) and preconditioned directions Z = S⁻¹V (m vectors),
    /// allocated at the first rescue.
    krylov: Vec<f64>,
    /// `factored` is the matrix whose symmetric part was factorised.
    fresh: bool,
}

impl std::fmt::Debug for SymmetricSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SymmetricSolver")
            .field("n", &self.n)
            .finish_non_exhaustive()
    }
}

/// The factor of S: one L·D·Lᵀ of the whole, or the block solve of a partition with an
/// L·D·Lᵀ per part.
enum SymmetricFactor {
    Whole {
        symbolic: Box<SymbolicCholesky<usize>>,
        l_values: Vec<f64>,
        mem: MemBuffer,
    },
    Blocks {
        schur: Box<SchurSolver>,
        /// S in the full pattern (both triangles), the block solve's input.
        full: Vec<f64>,
    },
}

/// The symbolic L·D·Lᵀ analysis (AMD ordering) of the n × n upper-triangle pattern
/// `col_ptr`/`row_idx`: simplicial for thin factors (lines, grids of lines), supernodal for
/// nets, decided by the fill nnz(L)/n of the simplicial factor, so the choice (and every
/// result bit) depends on the model alone (docs/theory/fem.md#sparse-linear-algebra).
pub(crate) fn analyse_ldlt(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Result<SymbolicCholesky<usize>> {
    let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let analyse = |threshold| {
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: threshold,
            ..Default::default()
        };
        factorize_symbolic_cholesky(sym, Side::Upper, SymmetricOrdering::Amd, params)
            .map_err(|e| FemError::Linear(format!("symbolic LDLt: {e:?}")))
    };
    let symbolic = analyse(SupernodalThreshold::FORCE_SIMPLICIAL)?;
    if symbolic.len_val() as f64 > SIMPLICIAL_MAX_FILL * n as f64 {
        return analyse(SupernodalThreshold::FORCE_SUPERNODAL);
    }
    Ok(symbolic)
}

/// The numeric L·D·Lᵀ of the n × n symmetric matrix given by its upper triangle
/// (`col_ptr`/`row_idx`/`values`, the pattern `symbolic` was analysed on) into `l_values`;
/// `Err` on a zero pivot.
pub(crate) fn factorize_ldlt(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &mut [f64],
    upper: (&[usize], &[usize], &[f64]),
    mem: &mut MemBuffer,
) -> std::result::Result<(), ()> {
    let (col_ptr, row_idx, values) = upper;
    let n = col_ptr.len() - 1;
    let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    symbolic
        .factorize_numeric_ldlt(
            l_values,
            SparseColMatRef::new(sym, values),
            Side::Upper,
            LdltRegularization::default(),
            Par::Seq,
            MemStack::new(mem),
            Default::default(),
        )
        .map(|_| ())
        .map_err(|_| ())
}

/// Why the symmetric path could not give the solution; the caller then uses the LU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SymmetricFallback {
    /// The L·D·Lᵀ met a zero pivot.
    ZeroPivot,
    /// Refinement did not contract (the non-symmetric part is too large).
    NoContraction,
    /// Refinement gave a non-finite iterate.
    NonFinite,
}

impl SymmetricSolver {
    /// Symbolic analysis of the symmetric part of the pattern `col_ptr`/`row_idx` (n × n),
    /// by blocks where `part_of` (a part per DOF) gives a partition the block solve takes;
    /// `None` if the pattern is not structurally symmetric.
    pub(crate) fn new(
        n: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        part_of: Option<&[usize]>,
    ) -> Result<Option<Self>> {
        let pos = |r: usize, c: usize| -> Option<usize> {
            let s = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            s.binary_search(&r).ok().map(|k| col_ptr[c] + k)
        };
        let mut up_col_ptr = Vec::with_capacity(n + 1);
        let mut up_row_idx = Vec::new();
        let mut pairs = Vec::new();
        up_col_ptr.push(0);
        for c in 0..n {
            for p in col_ptr[c]..col_ptr[c + 1] {
                let r = row_idx[p];
                let Some(q) = pos(c, r) else {
                    return Ok(None);
                };
                if r <= c {
                    up_row_idx.push(r);
                    pairs.push((p, q));
                }
            }
            up_col_ptr.push(up_row_idx.len());
        }
        let blocks = match part_of {
            Some(parts) => SchurSolver::new(col_ptr, row_idx, parts, PartFactor::Ldlt)?,
            None => None,
        };
        let factor = match blocks {
            Some(schur) => SymmetricFactor::Blocks {
                schur: Box::new(schur),
                full: vec![0.0; col_ptr[n]],
            },
            None => {
                let symbolic = analyse_ldlt(n, &up_col_ptr, &up_row_idx)?;
                let req = symbolic
                    .factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default())
                    .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
                let mem = MemBuffer::try_new(req)
                    .map_err(|_| FemError::Linear("out of memory for LDLt workspace".into()))?;
                SymmetricFactor::Whole {
                    l_values: vec![0.0; symbolic.len_val()],
                    symbolic: Box::new(symbolic),
                    mem,
                }
            }
        };
        let nnz_up = up_row_idx.len();
        Ok(Some(Self {
            n,
            factor,
            up_col_ptr,
            up_row_idx,
            pairs,
            up_values: vec![0.0; nnz_up],
            factored: vec![0.0; col_ptr[n]],
            b: vec![0.0; n],
            y: vec![0.0; n],
            res: vec![0.0; n],
            last_sweeps: 0,
            gmres_rescues: 0,
            krylov: Vec::new(),
            fresh: false,
        }))
    }

    /// Factorises S = ½(J + Jᵀ) of the full values `values` (same pattern as at `new`).
    pub(crate) fn factorize(
        &mut self,
        values: &[f64],
    ) -> std::result::Result<(), SymmetricFallback> {
        self.factored.copy_from_slice(values);
        self.refactor()
    }

    /// Factorises the symmetric part of the matrix held for the refinement (`factored`).
    pub(crate) fn refactor(&mut self) -> std::result::Result<(), SymmetricFallback> {
        for (u, &(p, q)) in self.up_values.iter_mut().zip(&self.pairs) {
            *u = 0.5 * (self.factored[p] + self.factored[q]);
        }
        self.fresh = true;
        match &mut self.factor {
            SymmetricFactor::Whole {
                symbolic,
                l_values,
                mem,
            } => {
                let upper = (
                    &self.up_col_ptr[..],
                    &self.up_row_idx[..],
                    &self.up_values[..],
                );
                factorize_ldlt(symbolic, l_values, upper, mem)
                    .map_err(|_| SymmetricFallback::ZeroPivot)
            }
            SymmetricFactor::Blocks { schur, full } => {
                for (&u, &(p, q)) in self.up_values.iter().zip(&self.pairs) {
                    full[p] = u;
                    full[q] = u;
                }
                schur
                    .factorize(full)
                    .map_err(|_| SymmetricFallback::ZeroPivot)
            }
        }
    }

    /// The parts and interface DOFs of the block solve, if S⁻¹ is applied by blocks.
    pub(crate) fn block_shape(&self) -> Option<(usize, usize)> {
        match &self.factor {
            SymmetricFactor::Blocks { schur, .. } => Some(schur.shape()),
            SymmetricFactor::Whole { .. } => None,
        }
    }

    /// Takes J's current `values` for the refinement and keeps the factor of an earlier
    /// matrix's symmetric part as the preconditioner (docs/theory/fem.md#sparse-linear-algebra).
    pub(crate) fn set_matrix(&mut self, values: &[f64]) {
        self.factored.copy_from_slice(values);
        self.fresh = false;
    }

    /// The factor was made from the matrix now being solved.
    pub(crate) fn is_fresh(&self) -> bool {
        self.fresh
    }

    fn solve_s(&mut self, rhs: &mut [f64]) {
        match &mut self.factor {
            SymmetricFactor::Whole {
                symbolic,
                l_values,
                mem,
            } => {
                let ldlt = LdltRef::new(symbolic, l_values);
                let m = MatMut::from_column_major_slice_mut(rhs, self.n, 1);
                ldlt.solve_in_place_with_conj(Conj::No, m, Par::Seq, MemStack::new(mem));
            }
            SymmetricFactor::Blocks { schur, .. } => schur.solve(rhs),
        }
    }

    /// Solves J·y = rhs in place (J as at the last `factorize`, in the CSC pattern
    /// `col_ptr`/`row_idx`). On `Err` `rhs` is left unchanged.
    #[cfg(test)]
    pub(crate) fn solve(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        rhs: &mut [f64],
    ) -> std::result::Result<(), SymmetricFallback> {
        let stop = RefineStop::default();
        self.solve_within(col_ptr, row_idx, rhs, stop).map(|_| ())
    }

    /// As `solve`, with the early stops of `stop`: `Ok(true)` when the bound settled it
    /// (`rhs` then holds that inexact y), `Ok(false)` for the solution (to `REFINE_TOL` or
    /// to `stop.floor`).
    pub(crate) fn solve_within(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        rhs: &mut [f64],
        stop: RefineStop,
    ) -> std::result::Result<bool, SymmetricFallback> {
        self.b.copy_from_slice(rhs);
        let bn = norm(&self.b);
        let mut y = std::mem::take(&mut self.y);
        let mut res = std::mem::take(&mut self.res);
        y.copy_from_slice(rhs);
        self.solve_s(&mut y);
        let mut out = self.refine(col_ptr, row_idx, &mut y, &mut res, bn, stop);
        // A fresh factor whose sweeps stall: a few eigenvalues of S⁻¹J lie outside the disk
        // |1 − λ| < 1, which GMRES removes in a few steps (a stale factor is refreshed first).
        if out == Err(SymmetricFallback::NoContraction)
            && self.fresh
            && self.gmres(col_ptr, row_idx, &mut y, &mut res, bn, stop.floor)
        {
            self.gmres_rescues += 1;
            out = Ok(false);
        }
        if out.is_ok() {
            rhs.copy_from_slice(&y);
        }
        self.y = y;
        self.res = res;
        out
    }

    /// The refinement sweeps on `y` (initially S⁻¹·b); `res` is scratch. `Ok(true)`: stopped
    /// early on `stop.bound`.
    fn refine(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        y: &mut [f64],
        res: &mut [f64],
        bn: f64,
        stop: RefineStop,
    ) -> std::result::Result<bool, SymmetricFallback> {
        let mut last = f64::INFINITY;
        let mut correction = f64::INFINITY;
        self.last_sweeps = 0;
        loop {
            self.residual(col_ptr, row_idx, y, res);
            let rn = norm(res);

            if !rn.is_finite() {
                return Err(SymmetricFallback::NonFinite);
            }
            if rn <= REFINE_TOL * bn || rn <= stop.floor {
                return Ok(false);
            }
            // After a sweep that contracted the residual by q ≤ ½, the remaining error is
            // at most q/(1 − q)·‖δ‖ ≤ ‖δ‖ (δ that sweep's correction).
            if let Some(d) = stop.bound
                && rn <= 0.5 * last
                && inf_norm(y) + 2.0 * correction <= d
            {
                return Ok(true);
            }
            if rn > MIN_CONTRACTION * last || self.last_sweeps == MAX_SWEEPS {
                return Err(SymmetricFallback::NoContraction);
            }
            last = rn;
            self.solve_s(res);
            for (yi, d) in y.iter_mut().zip(res.iter()) {
                *yi += d;
            }
            correction = inf_norm(res);
            self.last_sweeps += 1;
        }
    }
}

impl SymmetricSolver {
    /// res = b − J·y (J the matrix at the last `factorize`).
    fn residual(&self, col_ptr: &[usize], row_idx: &[usize], y: &[f64], res: &mut [f64]) {
        res.copy_from_slice(&self.b);
        for c in 0..self.n {
            let yc = y[c];
            for p in col_ptr[c]..col_ptr[c + 1] {
                res[row_idx[p]] -= self.factored[p] * yc;
            }
        }
    }

    /// Restarted GMRES(m) on J·y = b from the sweeps' y, right-preconditioned by S⁻¹ (Saad
    /// and Schultz 1986; Givens rotations on the Hessenberg matrix). True when it reached
    /// ‖b − J·y‖₂ ≤ max(REFINE_TOL·‖b‖₂, floor); y is then the solution. Hand-written because
    /// faer 0.24 has no GMRES (its BiCGStab does not minimise the residual, which is what
    /// a few outlying eigenvalues call for).
    fn gmres(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        y: &mut [f64],
        res: &mut [f64],
        bn: f64,
        floor: f64,
    ) -> bool {
        let (n, m) = (self.n, GMRES_RESTART);
        let target = (REFINE_TOL * bn).max(floor);
        let mut kry = std::mem::take(&mut self.krylov);
        kry.resize((2 * m + 1) * n, 0.0);
        let (vs, zs) = kry.split_at_mut((m + 1) * n);
        let mut h = [[0.0f64; GMRES_RESTART]; GMRES_RESTART + 1];
        let (mut cs, mut sn, mut g) = (
            [0.0; GMRES_RESTART],
            [0.0; GMRES_RESTART],
            [0.0; GMRES_RESTART + 1],
        );
        let mut done = false;
        for _ in 0..GMRES_CYCLES {
            self.residual(col_ptr, row_idx, y, res);
            let beta = norm(res);
            if !beta.is_finite() {
                break;
            }
            if beta <= target {
                done = true;
                break;
            }
            for (v, r) in vs[..n].iter_mut().zip(res.iter()) {
                *v = r / beta;
            }
            g.fill(0.0);
            g[0] = beta;
            let mut k_used = 0;
            for k in 0..m {
                let z = &mut zs[k * n..(k + 1) * n];
                z.copy_from_slice(&vs[k * n..(k + 1) * n]);
                self.solve_s(z);
                self.last_sweeps += 1;
                // w = J·z, orthogonalised against V (modified Gram–Schmidt).
                let (done_v, rest) = vs.split_at_mut((k + 1) * n);
                let w = &mut rest[..n];
                w.fill(0.0);
                for c in 0..n {
                    let zc = z[c];
                    for p in col_ptr[c]..col_ptr[c + 1] {
                        w[row_idx[p]] += self.factored[p] * zc;
                    }
                }
                for (j, hj) in h.iter_mut().take(k + 1).enumerate() {
                    let vj = &done_v[j * n..(j + 1) * n];
                    let d: f64 = w.iter().zip(vj).map(|(a, b)| a * b).sum();
                    hj[k] = d;
                    for (a, b) in w.iter_mut().zip(vj) {
                        *a -= d * b;
                    }
                }
                let hn = norm(w);
                h[k + 1][k] = hn;
                if hn > 0.0 {
                    for a in w.iter_mut() {
                        *a /= hn;
                    }
                }
                for j in 0..k {
                    let (a, b) = (h[j][k], h[j + 1][k]);
                    h[j][k] = cs[j] * a + sn[j] * b;
                    h[j + 1][k] = -sn[j] * a + cs[j] * b;
                }
                let r = h[k][k].hypot(h[k + 1][k]);
                if r == 0.0 || !r.is_finite() {
                    break;
                }
                (cs[k], sn[k]) = (h[k][k] / r, h[k + 1][k] / r);
                h[k][k] = r;
                h[k + 1][k] = 0.0;
                g[k + 1] = -sn[k] * g[k];
                g[k] *= cs[k];
                k_used = k + 1;
                if g[k + 1].abs() <= 0.5 * target || hn == 0.0 {
                    break;
                }
            }
            // y += Z·c with H·c = g (upper triangular).
            let mut c = [0.0f64; GMRES_RESTART];
            for i in (0..k_used).rev() {
                let s: f64 = (i + 1..k_used).map(|j| h[i][j] * c[j]).sum();
                c[i] = (g[i] - s) / h[i][i];
            }
            for (i, ci) in c.iter().take(k_used).enumerate() {
                for (a, b) in y.iter_mut().zip(&zs[i * n..(i + 1) * n]) {
                    *a += ci * b;
                }
            }
            if k_used == 0 {
                break;
            }
        }
        if !done {
            self.residual(col_ptr, row_idx, y, res);
            let rn = norm(res);
            done = rn.is_finite() && rn <= target;
        }
        self.krylov = kry;
        done
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;

    /// CSC of a dense n × n matrix keeping the entries where `keep(r, c)`.
    fn csc(a: &nalgebra::DMatrix<f64>, keep: impl Fn(usize, usize) -> bool) -> CscParts {
        let n = a.nrows();
        let (mut cp, mut ri, mut v) = (vec![0], Vec::new(), Vec::new());
        for c in 0..n {
            for r in 0..n {
                if keep(r, c) {
                    ri.push(r);
                    v.push(a[(r, c)]);
                }
            }
            cp.push(ri.len());
        }
        (cp, ri, v)
    }
    type CscParts = (Vec<usize>, Vec<usize>, Vec<f64>);

    /// A banded tangent like a chain's: SPD symmetric part (mass + stiffness) plus a
    /// skew part of relative size `skew` (drag-like), half-bandwidth 3.
    fn tangent(n: usize, skew: f64) -> nalgebra::DMatrix<f64> {
        banded(n, 3, skew)
    }

    /// As `tangent` with half-bandwidth `band`. Off-diagonals decay like 1/d (band 3) or
    /// 1/d² (wider), so a row's off-diagonal sum stays below 2 < 4 ≤ the diagonal: S is
    /// diagonally dominant, hence SPD.
    fn banded(n: usize, band: usize, skew: f64) -> nalgebra::DMatrix<f64> {
        let mut a = nalgebra::DMatrix::zeros(n, n);
        for i in 0..n {
            a[(i, i)] = 4.0 + (i % 5) as f64 * 0.3;
            for d in 1..=band {
                if i + d < n {
                    let s = if band == 3 {
                        -0.5 / d as f64
                    } else {
                        -0.5 / (d * d) as f64
                    };
                    let k = skew * (((i * 7 + d * 3) % 11) as f64 / 11.0 - 0.5);
                    a[(i, i + d)] = s + k;
                    a[(i + d, i)] = s - k;
                }
            }
        }
        a
    }

    fn solve_both(
        a: &nalgebra::DMatrix<f64>,
    ) -> (std::result::Result<(), SymmetricFallback>, f64, usize) {
        let (out, err, sweeps, _) = solve_banded(a, 3);
        (out, err, sweeps)
    }

    /// Solves with the symmetric solver on the band pattern and compares with a dense LU;
    /// also says whether the factor went supernodal.
    fn solve_banded(
        a: &nalgebra::DMatrix<f64>,
        band: usize,
    ) -> (std::result::Result<(), SymmetricFallback>, f64, usize, bool) {
        let n = a.nrows();
        let (cp, ri, v) = csc(a, |r, c| r.abs_diff(c) <= band);
        let mut s = SymmetricSolver::new(n, &cp, &ri, None).unwrap().unwrap();
        let supernodal = match &s.factor {
            SymmetricFactor::Whole { symbolic, .. } => {
                matches!(symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_))
            }
            SymmetricFactor::Blocks { .. } => unreachable!("no partition given"),
        };
        s.factorize(&v).unwrap();
        let b: Vec<f64> = (0..n).map(|i| ((i * 13 % 7) as f64) - 3.0).collect();
        let mut y = b.clone();
        let out = s.solve(&cp, &ri, &mut y);
        // Independent solution: nalgebra's dense LU.
        let exact = a
            .clone()
            .lu()
            .solve(&nalgebra::DVector::from_vec(b))
            .unwrap();
        let err = (nalgebra::DVector::from_vec(y) - &exact).norm() / exact.norm();
        (out, err, s.last_sweeps, supernodal)
    }

    #[test]
    fn bound_and_floor_stop_the_refinement_early_and_only_when_safe() {
        let a = tangent(60, 0.05);
        let n = a.nrows();
        let (cp, ri, v) = csc(&a, |r, c| r.abs_diff(c) <= 3);
        let mut s = SymmetricSolver::new(n, &cp, &ri, None).unwrap().unwrap();
        s.factorize(&v).unwrap();
        let b: Vec<f64> = (0..n).map(|i| ((i * 13 % 7) as f64) - 3.0).collect();
        let exact = a
            .clone()
            .lu()
            .solve(&nalgebra::DVector::from_vec(b.clone()))
            .unwrap();
        let ymax = exact.amax();
        let mut full = b.clone();
        s.solve(&cp, &ri, &mut full).unwrap();
        let full_sweeps = s.last_sweeps;
        let solve = |s: &mut SymmetricSolver, stop: RefineStop| {
            let mut y = b.clone();
            let out = s.solve_within(&cp, &ri, &mut y, stop).unwrap();
            (out, y, s.last_sweeps)
        };
        // A bound twice the solution's size is settled early; the inexact y obeys it.
        let (out, y, sweeps) = solve(
            &mut s,
            RefineStop {
                floor: 0.0,
                bound: Some(2.0 * ymax),
            },
        );
        assert!(
            out && sweeps < full_sweeps,
            "{out} after {sweeps} of {full_sweeps}"
        );
        assert!(y.iter().all(|v| v.abs() <= 2.0 * ymax));
        // A bound below the solution's size is never settled: the full solution.
        let (out, y, _) = solve(
            &mut s,
            RefineStop {
                floor: 0.0,
                bound: Some(0.9 * ymax),
            },
        );
        assert!(!out);
        let err = (nalgebra::DVector::from_vec(y) - &exact).norm() / exact.norm();
        assert!(err < 1e-10, "{err}");
        // A residual floor of 1e-4·‖b‖ stops before 1e-10 with that residual.
        let bn = norm(&b);
        let (out, y, sweeps) = solve(
            &mut s,
            RefineStop {
                floor: 1e-4 * bn,
                bound: None,
            },
        );
        assert!(!out && sweeps < full_sweeps, "{sweeps} of {full_sweeps}");
        let r = nalgebra::DVector::from_vec(b.clone()) - &a * nalgebra::DVector::from_vec(y);
        assert!(r.norm() <= 1e-4 * bn, "{}", r.norm() / bn);
    }

    #[test]
    fn thin_factor_is_simplicial_and_wide_band_supernodal_both_exact() {
        // Half-bandwidth 3: fill ≈ 4 ≤ 24, simplicial (the path lines take).
        let (out, err, _, supernodal) = solve_banded(&banded(100, 3, 0.05), 3);
        assert_eq!(out, Ok(()));
        assert!(err < 1e-10, "{err}");
        assert!(!supernodal);
        // Half-bandwidth 40: fill ≈ 40 > 24, supernodal (the path nets take).
        let (out, err, sweeps, supernodal) = solve_banded(&banded(100, 40, 0.05), 40);
        assert_eq!(out, Ok(()));
        assert!(err < 1e-10, "{err}");
        assert!(supernodal);
        assert!((1..=8).contains(&sweeps), "{sweeps} sweeps");
    }

    #[test]
    fn symmetric_matrix_needs_no_refinement() {
        let (out, err, sweeps) = solve_both(&tangent(60, 0.0));
        assert_eq!(out, Ok(()));
        assert!(err < 1e-13, "{err}");
        assert_eq!(sweeps, 0);
    }

    #[test]
    fn small_skew_part_is_refined_to_the_exact_solution() {
        let (out, err, sweeps) = solve_both(&tangent(60, 0.05));
        assert_eq!(out, Ok(()));
        assert!(err < 1e-10, "{err}");
        // Contraction ≈ ‖S⁻¹A‖ ≈ 1e-2 per sweep: a handful of sweeps, not the maximum.
        assert!((1..=6).contains(&sweeps), "{sweeps} sweeps");
    }

    /// A strong skew coupling between two unknowns only (a rank-2 A in J = S + A) puts two
    /// eigenvalues of S⁻¹J far outside |1 − λ| < 1: the sweeps stall, GMRES, for which
    /// S⁻¹J is the identity plus rank 2, finishes in a few steps; the answer is the dense LU's.
    #[test]
    fn few_outlying_eigenvalues_are_rescued_by_gmres() {
        let mut a = tangent(60, 0.1);
        a[(20, 21)] += 8.0;
        a[(21, 20)] -= 8.0;
        let n = a.nrows();
        let (cp, ri, v) = csc(&a, |r, c| r.abs_diff(c) <= 3);
        let mut s = SymmetricSolver::new(n, &cp, &ri, None).unwrap().unwrap();
        s.factorize(&v).unwrap();
        let b: Vec<f64> = (0..n).map(|i| ((i * 13 % 7) as f64) - 3.0).collect();
        let mut y = b.clone();
        let out = s.solve(&cp, &ri, &mut y);
        assert_eq!(out, Ok(()));
        assert_eq!(s.gmres_rescues, 1, "the sweeps alone did it");
        let exact = a
            .clone()
            .lu()
            .solve(&nalgebra::DVector::from_vec(b))
            .unwrap();
        let err = (nalgebra::DVector::from_vec(y) - &exact).norm() / exact.norm();
        assert!(err < 1e-9, "{err}");
        assert!(
            s.last_sweeps <= 40,
            "{} sweeps and GMRES steps",
            s.last_sweeps
        );
    }

    #[test]
    fn large_skew_part_falls_back_and_leaves_the_rhs() {
        let a = tangent(60, 12.0);
        let n = a.nrows();
        let (cp, ri, v) = csc(&a, |r, c| r.abs_diff(c) <= 3);
        let mut s = SymmetricSolver::new(n, &cp, &ri, None).unwrap().unwrap();
        s.factorize(&v).unwrap();
        let b = vec![1.0; n];
        let mut y = b.clone();
        let out = s.solve(&cp, &ri, &mut y);
        assert!(out.is_err(), "{out:?}");
        assert_eq!(y, b);
    }

    #[test]
    fn unsymmetric_pattern_is_refused() {
        let a = tangent(10, 0.0);
        let (cp, ri, _) = csc(&a, |r, c| r == c || r == c + 1);
        assert!(SymmetricSolver::new(10, &cp, &ri, None).unwrap().is_none());
    }
}
