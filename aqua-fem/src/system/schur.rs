//! Block solve of a partitioned Jacobian by the Schur complement of its interface: each
//! part's interior is eliminated by its own sparse factor (symbolic analysis once, the parts
//! factorised in parallel, each sequentially), the interface through the dense
//! S = A_bb − Σ_p A_bp·A_pp⁻¹·A_pb summed in part order, so the bits do not depend on the
//! number of threads (docs/theory/fem.md#block-solve). The parts' factor is an LU, or for a
//! symmetric matrix (the dynamic tangent's symmetric part) an L·D·Lᵀ of half the work.

use crate::error::{FemError, Result};
use crate::symmetric::{analyse_ldlt, factorize_ldlt};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor as dense_lu, solve as dense_solve};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{LdltRef, SymbolicCholesky};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, MatMut, Par};
use rayon::prelude::*;

const NONE: usize = usize::MAX;

/// The block solve is used only while the dense interface stays small next to the system:
/// at most this many interface DOFs (a dense S of 8·n_b² bytes, n_b³/3 flops per
/// factorisation)…
const MAX_INTERFACE: usize = 3000;
/// …and at most this fraction of the free DOFs.
const MAX_INTERFACE_FRACTION: f64 = 0.25;

/// How the parts' interior blocks are factorised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PartFactor {
    /// Sparse LU with partial pivoting (any matrix).
    Lu,
    /// Sparse L·D·Lᵀ of the upper triangle (the matrix must be symmetric).
    Ldlt,
}

/// A part's factor of A_pp.
enum Factor {
    Lu {
        symbolic: SymbolicLu<usize>,
        numeric: NumericLu<usize, f64>,
    },
    Ldlt {
        symbolic: SymbolicCholesky<usize>,
        l_values: Vec<f64>,
        /// The upper triangle of A_pp (CSC) and the position of each entry in the part's
        /// `vals`.
        up_col_ptr: Vec<usize>,
        up_row_idx: Vec<usize>,
        up_pos: Vec<usize>,
        up_vals: Vec<f64>,
    },
}

impl Factor {
    /// The symbolic analysis of A_pp (n × n, CSC `col_ptr`/`row_idx`, rows sorted) and the
    /// scratch its factorisation and a solve of `rhs_cols` columns need.
    fn analyse(
        kind: PartFactor,
        n: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        rhs_cols: usize,
    ) -> Result<(Self, faer::dyn_stack::StackReq)> {
        match kind {
            PartFactor::Lu => {
                let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
                let symbolic = factorize_symbolic_lu(sym, Default::default())
                    .map_err(|e| FemError::Linear(format!("symbolic LU of a part: {e:?}")))?;
                let req = symbolic
                    .factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default())
                    .or(symbolic.solve_in_place_scratch::<f64>(rhs_cols, Par::Seq));
                let numeric = NumericLu::new();
                Ok((Factor::Lu { symbolic, numeric }, req))
            }
            PartFactor::Ldlt => {
                let (mut up_col_ptr, mut up_row_idx, mut up_pos) =
                    (vec![0], Vec::new(), Vec::new());
                for c in 0..n {
                    for (k, &r) in row_idx[col_ptr[c]..col_ptr[c + 1]].iter().enumerate() {
                        if r <= c {
                            up_row_idx.push(r);
                            up_pos.push(col_ptr[c] + k);
                        }
                    }
                    up_col_ptr.push(up_row_idx.len());
                }
                let symbolic = analyse_ldlt(n, &up_col_ptr, &up_row_idx)?;
                let req = symbolic
                    .factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default())
                    .or(symbolic.solve_in_place_scratch::<f64>(rhs_cols, Par::Seq));
                let f = Factor::Ldlt {
                    l_values: vec![0.0; symbolic.len_val()],
                    symbolic,
                    up_vals: vec![0.0; up_pos.len()],
                    up_col_ptr,
                    up_row_idx,
                    up_pos,
                };
                Ok((f, req))
            }
        }
    }

    /// Numeric factorisation of A_pp with values `vals` (its CSC `col_ptr`/`row_idx`).
    fn factorize(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        vals: &[f64],
        mem: &mut MemBuffer,
    ) -> Result<()> {
        let n = col_ptr.len() - 1;
        let singular = |e: &dyn std::fmt::Debug| {
            FemError::Linear(format!("singular Jacobian ({e:?}); check supports"))
        };
        match self {
            Factor::Lu { symbolic, numeric } => {
                let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
                symbolic
                    .factorize_numeric_lu(
                        numeric,
                        SparseColMatRef::new(sym, vals),
                        Par::Seq,
                        MemStack::new(mem),
                        Default::default(),
                    )
                    .map(|_| ())
                    .map_err(|e| singular(&e))
            }
            Factor::Ldlt {
                symbolic,
                l_values,
                up_col_ptr,
                up_row_idx,
                up_pos,
                up_vals,
            } => {
                for (u, &p) in up_vals.iter_mut().zip(up_pos.iter()) {
                    *u = vals[p];
                }
                let upper = (&up_col_ptr[..], &up_row_idx[..], &up_vals[..]);
                factorize_ldlt(symbolic, l_values, upper, mem)
                    .map_err(|_| singular(&"zero pivot in L·D·Lᵀ"))
            }
        }
    }

    /// Solves A_pp·Y = B in place for the columns of `b`.
    fn solve(&self, b: MatMut<'_, f64>, mem: &mut MemBuffer) {
        match self {
            Factor::Lu { symbolic, numeric } => LuRef::new_unchecked(symbolic, numeric)
                .solve_in_place_with_conj(Conj::No, b, Par::Seq, MemStack::new(mem)),
            Factor::Ldlt {
                symbolic, l_values, ..
            } => LdltRef::new(symbolic, l_values).solve_in_place_with_conj(
                Conj::No,
                b,
                Par::Seq,
                MemStack::new(mem),
            ),
        }
    }
}

/// One part: its interior block A_pp with its own factor, and its couplings to the interface.
struct Part {
    /// Free DOFs of the interior, ascending (local index = position).
    dofs: Vec<usize>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Position in the global `values` of each entry of A_pp.
    val_pos: Vec<usize>,
    vals: Vec<f64>,
    factor: Factor,
    mem: MemBuffer,
    /// The interface DOFs this part couples to (indices into the interface list, ascending).
    iface: Vec<usize>,
    /// A_pb by columns: per local interface column, (interior row, position in `values`).
    a_pb: Vec<Vec<(usize, usize)>>,
    /// A_bp by interior columns: per interior column, (local interface row, position).
    a_bp: Vec<Vec<(usize, usize)>>,
    /// The values of `a_bp` at the last factorisation, in the same order.
    a_bp_vals: Vec<f64>,
    /// X = A_pp⁻¹·A_pb, interior × local interface, column-major.
    x: Vec<f64>,
    /// A_bp·X, local interface × local interface, column-major.
    c: Vec<f64>,
    /// The interior solution of the last solve (A_pp⁻¹·b_p, then the final x_p).
    y: Vec<f64>,
    /// A_bp·y of the last solve.
    g: Vec<f64>,
}

/// The Schur-complement block solver of a partitioned sparse matrix.
pub(crate) struct SchurSolver {
    n: usize,
    parts: Vec<Part>,
    /// The interface: free DOFs that couple to a DOF of another part, ascending.
    iface: Vec<usize>,
    /// A_bb: (position in `values`, interface row, interface column).
    a_bb: Vec<(usize, usize, usize)>,
    /// S, then its LU in place.
    s: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    dense_mem: MemBuffer,
    rb: Vec<f64>,
}

impl std::fmt::Debug for SchurSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SchurSolver")
            .field("n", &self.n)
            .field("parts", &self.parts.len())
            .field("interface", &self.iface.len())
            .finish_non_exhaustive()
    }
}

impl SchurSolver {
    /// The block solver of the n×n pattern (`col_ptr`, `row_idx`, rows sorted) under
    /// `part_of` (a part number per DOF) with the parts' factor `kind` (`Ldlt` only for
    /// symmetric values on a structurally symmetric pattern), or `None` where it does not
    /// pay: fewer than two parts with interior DOFs, or an interface above `MAX_INTERFACE` or
    /// `MAX_INTERFACE_FRACTION` of the DOFs.
    pub(crate) fn new(
        col_ptr: &[usize],
        row_idx: &[usize],
        part_of: &[usize],
        kind: PartFactor,
    ) -> Result<Option<Self>> {
        let n = part_of.len();
        let mut is_iface = vec![false; n];
        for c in 0..n {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                if part_of[r] != part_of[c] {
                    is_iface[r] = true;
                    is_iface[c] = true;
                }
            }
        }
        let iface: Vec<usize> = (0..n).filter(|&d| is_iface[d]).collect();
        let nb = iface.len();
        if nb > MAX_INTERFACE || nb as f64 > MAX_INTERFACE_FRACTION * n as f64 {
            return Ok(None);
        }
        let mut iface_of = vec![NONE; n];
        for (b, &d) in iface.iter().enumerate() {
            iface_of[d] = b;
        }
        // Interior DOFs per part, in part order; local index within the part.
        let n_parts = part_of.iter().map(|&p| p + 1).max().unwrap_or(0);
        let mut interior: Vec<Vec<usize>> = vec![Vec::new(); n_parts];
        let mut local = vec![NONE; n];
        for d in 0..n {
            if !is_iface[d] {
                local[d] = interior[part_of[d]].len();
                interior[part_of[d]].push(d);
            }
        }
        let part_ids: Vec<usize> = (0..n_parts).filter(|&p| !interior[p].is_empty()).collect();
        if part_ids.len() < 2 {
            return Ok(None);
        }
        let mut slot = vec![NONE; n_parts];
        for (k, &p) in part_ids.iter().enumerate() {
            slot[p] = k;
        }
        // The interface DOFs each part couples to: from its interior columns (A_bp) and the
        // interface columns' interior rows (A_pb).
        let mut touched: Vec<Vec<usize>> = vec![Vec::new(); part_ids.len()];
        for c in 0..n {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                match (is_iface[r], is_iface[c]) {
                    (true, false) => touched[slot[part_of[c]]].push(iface_of[r]),
                    (false, true) => touched[slot[part_of[r]]].push(iface_of[c]),
                    _ => {}
                }
            }
        }
        let mut a_bb = Vec::new();
        for &c in &iface {
            for (k, &r) in row_idx[col_ptr[c]..col_ptr[c + 1]].iter().enumerate() {
                if is_iface[r] {
                    a_bb.push((col_ptr[c] + k, iface_of[r], iface_of[c]));
                }
            }
        }
        let mut parts = Vec::with_capacity(part_ids.len());
        for (k, &p) in part_ids.iter().enumerate() {
            let dofs = std::mem::take(&mut interior[p]);
            let mut pi = std::mem::take(&mut touched[k]);
            pi.sort_unstable();
            pi.dedup();
            let mut pi_local = vec![NONE; nb];
            for (j, &b) in pi.iter().enumerate() {
                pi_local[b] = j;
            }
            let ni = dofs.len();
            let mut pcol = Vec::with_capacity(ni + 1);
            let mut prow = Vec::new();
            let mut ppos = Vec::new();
            let mut a_bp = vec![Vec::new(); ni];
            pcol.push(0);
            for (lc, &c) in dofs.iter().enumerate() {
                for (kk, &r) in row_idx[col_ptr[c]..col_ptr[c + 1]].iter().enumerate() {
                    if is_iface[r] {
                        a_bp[lc].push((pi_local[iface_of[r]], col_ptr[c] + kk));
                    } else {
                        // Not an interface row, so of this part: rows stay sorted locally.
                        prow.push(local[r]);
                        ppos.push(col_ptr[c] + kk);
                    }
                }
                pcol.push(prow.len());
            }
            let mut a_pb = vec![Vec::new(); pi.len()];
            for (j, &b) in pi.iter().enumerate() {
                let c = iface[b];
                for (kk, &r) in row_idx[col_ptr[c]..col_ptr[c + 1]].iter().enumerate() {
                    if !is_iface[r] && part_of[r] == p {
                        a_pb[j].push((local[r], col_ptr[c] + kk));
                    }
                }
            }
            let (factor, req) = Factor::analyse(kind, ni, &pcol, &prow, pi.len().max(1))?;
            let mem = MemBuffer::try_new(req)
                .map_err(|_| FemError::Linear("out of memory for a part's factor".into()))?;
            let kp = pi.len();
            let n_bp = a_bp.iter().map(Vec::len).sum();
            parts.push(Part {
                a_bp_vals: vec![0.0; n_bp],
                vals: vec![0.0; ppos.len()],
                col_ptr: pcol,
                row_idx: prow,
                val_pos: ppos,
                factor,
                mem,
                x: vec![0.0; ni * kp],
                c: vec![0.0; kp * kp],
                y: vec![0.0; ni],
                g: vec![0.0; kp],
                iface: pi,
                a_pb,
                a_bp,
                dofs,
            });
        }
        let req =
            dense_lu::lu_in_place_scratch::<usize, f64>(nb, nb, Par::Seq, Default::default()).or(
                dense_solve::solve_in_place_scratch::<usize, f64>(nb, 1, Par::Seq),
            );
        Ok(Some(Self {
            n,
            parts,
            a_bb,
            s: Mat::zeros(nb, nb),
            perm: vec![0; nb],
            perm_inv: vec![0; nb],
            dense_mem: MemBuffer::try_new(req)
                .map_err(|_| FemError::Linear("out of memory for the interface LU".into()))?,
            rb: vec![0.0; nb],
            iface,
        }))
    }

    /// Number of parts and of interface DOFs.
    pub(crate) fn shape(&self) -> (usize, usize) {
        (self.parts.len(), self.iface.len())
    }

    /// Factorises the matrix of `values` (same pattern as at construction).
    pub(crate) fn factorize(&mut self, values: &[f64]) -> Result<()> {
        let done: Vec<Result<()>> = self
            .parts
            .par_iter_mut()
            .map(|p| p.factorize(values))
            .collect();
        done.into_iter().collect::<Result<()>>()?;
        // S = A_bb − Σ_p A_bp·X_p, summed in part order.
        self.s.fill(0.0);
        for &(pos, r, c) in &self.a_bb {
            self.s[(r, c)] += values[pos];
        }
        for p in &self.parts {
            let kp = p.iface.len();
            for m in 0..kp {
                let col = p.iface[m];
                for j in 0..kp {
                    self.s[(p.iface[j], col)] -= p.c[j + m * kp];
                }
            }
        }
        let nb = self.iface.len();
        dense_lu::lu_in_place(
            self.s.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.dense_mem),
            Default::default(),
        );
        if (0..nb).any(|k| self.s[(k, k)] == 0.0 || !self.s[(k, k)].is_finite()) {
            return Err(FemError::Linear(
                "singular interface (Schur complement) of the partitioned Jacobian".into(),
            ));
        }
        Ok(())
    }

    /// Solves A·x = rhs in place with the last factorisation.
    pub(crate) fn solve(&mut self, rhs: &mut [f64]) {
        debug_assert_eq!(rhs.len(), self.n);
        let b: &[f64] = rhs;
        self.parts.par_iter_mut().for_each(|p| p.solve_interior(b));
        // r_b = b_b − Σ_p A_bp·A_pp⁻¹·b_p, then x_b = S⁻¹·r_b.
        for (rb, &d) in self.rb.iter_mut().zip(&self.iface) {
            *rb = rhs[d];
        }
        for p in &self.parts {
            for (j, &b) in p.iface.iter().enumerate() {
                self.rb[b] -= p.g[j];
            }
        }
        let nb = self.iface.len();
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, nb);
        let s = self.s.as_ref();
        dense_solve::solve_in_place_with_conj(
            s,
            s,
            perm,
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut self.rb, nb, 1),
            Par::Seq,
            MemStack::new(&mut self.dense_mem),
        );
        let xb: &[f64] = &self.rb;
        self.parts
            .par_iter_mut()
            .for_each(|p| p.back_substitute(xb));
        for p in &self.parts {
            for (&d, &v) in p.dofs.iter().zip(&p.y) {
                rhs[d] = v;
            }
        }
        for (&d, &v) in self.iface.iter().zip(&self.rb) {
            rhs[d] = v;
        }
    }
}

impl Part {
    /// The factor of A_pp, X = A_pp⁻¹·A_pb and C = A_bp·X.
    fn factorize(&mut self, values: &[f64]) -> Result<()> {
        for (v, &pos) in self.vals.iter_mut().zip(&self.val_pos) {
            *v = values[pos];
        }
        let ni = self.dofs.len();
        self.factor
            .factorize(&self.col_ptr, &self.row_idx, &self.vals, &mut self.mem)?;
        let kp = self.iface.len();
        if kp == 0 {
            return Ok(());
        }
        self.x.fill(0.0);
        for (j, col) in self.a_pb.iter().enumerate() {
            for &(r, pos) in col {
                self.x[r + j * ni] = values[pos];
            }
        }
        self.factor.solve(
            MatMut::from_column_major_slice_mut(&mut self.x, ni, kp),
            &mut self.mem,
        );
        self.c.fill(0.0);
        let mut k = 0;
        for (lc, col) in self.a_bp.iter().enumerate() {
            for &(j, pos) in col {
                let a = values[pos];
                self.a_bp_vals[k] = a;
                k += 1;
                for m in 0..kp {
                    self.c[j + m * kp] += a * self.x[lc + m * ni];
                }
            }
        }
        Ok(())
    }

    /// y = A_pp⁻¹·b_p and g = A_bp·y.
    fn solve_interior(&mut self, b: &[f64]) {
        for (y, &d) in self.y.iter_mut().zip(&self.dofs) {
            *y = b[d];
        }
        let ni = self.dofs.len();
        self.factor.solve(
            MatMut::from_column_major_slice_mut(&mut self.y, ni, 1),
            &mut self.mem,
        );
        self.g.fill(0.0);
        let mut k = 0;
        for (col, &y) in self.a_bp.iter().zip(&self.y) {
            for &(j, _) in col {
                self.g[j] += self.a_bp_vals[k] * y;
                k += 1;
            }
        }
    }

    /// x_p = y − X·x_b (the interior solution, into `y`).
    fn back_substitute(&mut self, xb: &[f64]) {
        let ni = self.dofs.len();
        for (m, &b) in self.iface.iter().enumerate() {
            let v = xb[b];
            for (y, &xv) in self.y.iter_mut().zip(&self.x[m * ni..(m + 1) * ni]) {
                *y -= xv * v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense solve by Gaussian elimination with partial pivoting (the oracle).
    fn dense_solve(a: &[Vec<f64>], b: &[f64]) -> Vec<f64> {
        let n = b.len();
        let mut m: Vec<Vec<f64>> = a
            .iter()
            .zip(b)
            .map(|(r, &bi)| {
                let mut r = r.clone();
                r.push(bi);
                r
            })
            .collect();
        for k in 0..n {
            let p = (k..n)
                .max_by(|&i, &j| m[i][k].abs().total_cmp(&m[j][k].abs()))
                .unwrap();
            m.swap(k, p);
            for i in k + 1..n {
                let f = m[i][k] / m[k][k];
                for j in k..=n {
                    m[i][j] -= f * m[k][j];
                }
            }
        }
        let mut x = vec![0.0; n];
        for k in (0..n).rev() {
            let s: f64 = (k + 1..n).map(|j| m[k][j] * x[j]).sum();
            x[k] = (m[k][n] - s) / m[k][k];
        }
        x
    }

    /// A test matrix: CSC pattern (column pointers, row indices), values, the dense matrix
    /// and the part of each DOF.
    type Partitioned = (Vec<usize>, Vec<usize>, Vec<f64>, Vec<Vec<f64>>, Vec<usize>);

    /// Three chains of 8 DOFs (parts 0, 1, 2; unsymmetric tridiagonal blocks with a few
    /// long-range entries inside a part), joined by entries 7–8, 15–17 and 3–20: the pattern
    /// in CSC with sorted rows, its values, the dense matrix and the parts.
    fn partitioned() -> Partitioned {
        let n = 24;
        let part: Vec<usize> = (0..n).map(|i| i / 8).collect();
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            a[i][i] = 4.0 + 0.1 * i as f64;
            if i + 1 < n && part[i + 1] == part[i] {
                a[i][i + 1] = -1.0 - 0.03 * i as f64;
                a[i + 1][i] = -0.7 + 0.02 * i as f64;
            }
        }
        for (i, j, v) in [
            (0, 5, 0.3),
            (10, 14, -0.4),
            (18, 23, 0.25),
            (7, 8, -1.1),
            (8, 7, -0.9),
            (15, 17, 0.6),
            (17, 16, -0.5),
            (3, 20, 0.35),
            (20, 3, -0.45),
        ] {
            a[i][j] = v;
        }
        let (col_ptr, row_idx, vals) = csc(&a);
        (col_ptr, row_idx, vals, a, part)
    }

    /// The CSC form (column pointers, sorted row indices, values) of the nonzeros of `a`.
    fn csc(a: &[Vec<f64>]) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut vals = Vec::new();
        for j in 0..a.len() {
            for (i, row) in a.iter().enumerate() {
                if row[j] != 0.0 {
                    row_idx.push(i);
                    vals.push(row[j]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        (col_ptr, row_idx, vals)
    }

    /// Each part's L·D·Lᵀ solves a symmetric matrix as the LU path and a dense elimination
    /// do, including an indefinite one (negative pivots, as the dynamic tangent's slack
    /// members and water loads can give); the symmetric part of the test matrix, with every
    /// other diagonal entry negated.
    #[test]
    fn the_ldlt_block_solve_matches_a_dense_solve_of_a_symmetric_matrix() {
        let (_, _, _, a, part) = partitioned();
        let n = a.len();
        let mut sym = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in 0..n {
                sym[i][j] = 0.5 * (a[i][j] + a[j][i]);
            }
            if i % 2 == 1 {
                sym[i][i] = -sym[i][i];
            }
        }
        let (col_ptr, row_idx, vals) = csc(&sym);
        let b: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).cos() - 0.2).collect();
        let want = dense_solve(&sym, &b);
        for kind in [PartFactor::Ldlt, PartFactor::Lu] {
            let mut s = SchurSolver::new(&col_ptr, &row_idx, &part, kind)
                .unwrap()
                .expect("three parts with interiors");
            s.factorize(&vals).unwrap();
            let mut x = b.clone();
            s.solve(&mut x);
            for (i, (x, w)) in x.iter().zip(&want).enumerate() {
                assert!(
                    (x - w).abs() <= 1e-12 * (1.0 + w.abs()),
                    "{kind:?}, DOF {i}: {x} against {w}"
                );
            }
        }
    }

    #[test]
    fn the_block_solve_matches_a_dense_solve() {
        let (col_ptr, row_idx, vals, a, part) = partitioned();
        let mut s = SchurSolver::new(&col_ptr, &row_idx, &part, PartFactor::Lu)
            .unwrap()
            .expect("three parts with interiors");
        // Interface: every DOF with an entry in another part's row or column.
        assert_eq!(s.iface, vec![3, 7, 8, 15, 17, 20]);
        assert_eq!(s.shape(), (3, 6));
        let b: Vec<f64> = (0..a.len()).map(|i| (0.7 * i as f64).sin() + 0.5).collect();
        let want = dense_solve(&a, &b);
        s.factorize(&vals).unwrap();
        let mut x = b.clone();
        s.solve(&mut x);
        for (i, (x, w)) in x.iter().zip(&want).enumerate() {
            assert!(
                (x - w).abs() <= 1e-13 * (1.0 + w.abs()),
                "DOF {i}: {x} against {w}"
            );
        }
        // A second factorisation with other values (same pattern) is solved afresh.
        let vals2: Vec<f64> = vals.iter().map(|v| v * 1.5).collect();
        s.factorize(&vals2).unwrap();
        let mut x = b.clone();
        s.solve(&mut x);
        for (x, w) in x.iter().zip(&want) {
            assert!((x - w / 1.5).abs() <= 1e-13 * (1.0 + w.abs()));
        }
    }

    #[test]
    fn one_part_or_a_large_interface_is_left_to_the_lu() {
        let (col_ptr, row_idx, _, a, _) = partitioned();
        let one = vec![0; a.len()];
        assert!(
            SchurSolver::new(&col_ptr, &row_idx, &one, PartFactor::Lu)
                .unwrap()
                .is_none()
        );
        // Every DOF its own part: all DOFs are interface.
        let each: Vec<usize> = (0..a.len()).collect();
        assert!(
            SchurSolver::new(&col_ptr, &row_idx, &each, PartFactor::Lu)
                .unwrap()
                .is_none()
        );
    }
}
