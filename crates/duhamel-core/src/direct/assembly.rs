//! Physical matrices (dense or CSR), the assembly of iteration matrices from them and from
//! the elements' tangents, and their LU factorisation (faer: dense partial pivoting, or
//! sparse LU with the symbolic analysis done once per run).
//!
//! An iteration matrix has `nb x nb` blocks of size `n` (one block for the generalized-alpha
//! methods, two by two for the cubic Hermite time element, whose unknowns are `(x1, h v1)`).
//! In sparse mode every block has the same pattern: the union of the patterns of the constant
//! matrices, of the element couplings and of the diagonal.

use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Mat, MatMut};

use crate::error::CoreError;

/// A square matrix as given: dense (row-major) or compressed sparse rows.
#[derive(Debug, Clone, PartialEq)]
pub enum Matrix {
    /// `data[i * n + j]` is entry `(i, j)`.
    Dense { n: usize, data: Vec<f64> },
    /// Row `i` holds `data[indptr[i]..indptr[i + 1]]` in columns `indices[..]`.
    Csr {
        n: usize,
        indptr: Vec<usize>,
        indices: Vec<usize>,
        data: Vec<f64>,
    },
}

impl Matrix {
    /// Order of the matrix.
    pub fn n(&self) -> usize {
        match self {
            Matrix::Dense { n, .. } | Matrix::Csr { n, .. } => *n,
        }
    }

    /// Whether the matrix is stored sparse.
    pub fn is_sparse(&self) -> bool {
        matches!(self, Matrix::Csr { .. })
    }

    /// Checks the storage against the order `n`; `name` is the Python-side name.
    pub fn validate(&self, name: &'static str, n: usize) -> Result<(), CoreError> {
        let bad = |problem: String| Err(CoreError::InvalidInput { name, problem });
        if self.n() != n {
            return bad(format!("has order {}, expected {n}", self.n()));
        }
        match self {
            Matrix::Dense { n, data } => {
                if data.len() != n.saturating_mul(*n) {
                    return bad(format!("has {} entries, expected {n} x {n}", data.len()));
                }
                if data.iter().any(|v| !v.is_finite()) {
                    return bad("contains NaN or inf".into());
                }
            }
            Matrix::Csr {
                n,
                indptr,
                indices,
                data,
            } => {
                if indptr.len() != n + 1 || indptr[0] != 0 || indptr.windows(2).any(|w| w[1] < w[0])
                {
                    return bad("has an invalid CSR row pointer".into());
                }
                if indices.len() != indptr[*n] || data.len() != indptr[*n] {
                    return bad("has CSR arrays of inconsistent lengths".into());
                }
                if indices.iter().any(|&j| j >= *n) {
                    return bad("has a CSR column index out of range".into());
                }
                if data.iter().any(|v| !v.is_finite()) {
                    return bad("contains NaN or inf".into());
                }
            }
        }
        Ok(())
    }

    /// `y += alpha A x`.
    pub fn mul_add(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        if alpha == 0.0 {
            return;
        }
        match self {
            Matrix::Dense { n, data } => {
                for (row, yi) in data.chunks_exact(*n).zip(y.iter_mut()) {
                    let s: f64 = row.iter().zip(x).map(|(a, b)| a * b).sum();
                    *yi += alpha * s;
                }
            }
            Matrix::Csr {
                indptr,
                indices,
                data,
                ..
            } => {
                for (i, yi) in y.iter_mut().enumerate() {
                    let r = indptr[i]..indptr[i + 1];
                    let s: f64 = indices[r.clone()]
                        .iter()
                        .zip(&data[r])
                        .map(|(&j, a)| a * x[j])
                        .sum();
                    *yi += alpha * s;
                }
            }
        }
    }

    /// Calls `f(row, col, value)` for every stored entry, in storage order.
    fn for_each(&self, mut f: impl FnMut(usize, usize, f64)) {
        match self {
            Matrix::Dense { n, data } => {
                for (k, &v) in data.iter().enumerate() {
                    f(k / n, k % n, v);
                }
            }
            Matrix::Csr {
                indptr,
                indices,
                data,
                ..
            } => {
                for i in 0..indptr.len() - 1 {
                    for k in indptr[i]..indptr[i + 1] {
                        f(i, indices[k], data[k]);
                    }
                }
            }
        }
    }
}

/// The pattern of one block and where each source entry lands in it.
struct SparsePattern {
    /// Column pointers of the block pattern (CSC, sorted rows).
    col_ptr: Vec<usize>,
    /// Column of each pattern entry.
    col_of: Vec<usize>,
    /// Per constant matrix: the pattern index of each stored entry (storage order).
    matrix_maps: Vec<Vec<usize>>,
    /// Per element: the pattern index of each local pair `(a, b)`, row-major.
    element_maps: Vec<Vec<usize>>,
    /// Pattern of the whole `nb n x nb n` matrix.
    symbolic: SymbolicSparseColMat<usize>,
    /// Its symbolic LU (fill-reducing ordering and elimination structure), computed once.
    lu: SymbolicLu<usize>,
}

/// An iteration matrix being assembled.
pub struct IterationMatrix<'a> {
    n: usize,
    nb: usize,
    matrices: Vec<&'a Matrix>,
    sparse: Option<SparsePattern>,
    dense: Mat<f64>,
    values: Vec<f64>,
}

/// A factorised iteration matrix.
pub enum Factorization {
    /// A 1 x 1 matrix.
    Scalar(f64),
    /// Dense LU with partial pivoting.
    Dense(PartialPivLu<f64>),
    /// Sparse LU.
    Sparse(Lu<usize, f64>),
}

impl Factorization {
    /// Solves `A x = b` in place of `b`; `false` if the result is not finite (singular).
    pub fn solve_in_place(&self, b: &mut [f64]) -> bool {
        match self {
            Factorization::Scalar(a) => {
                b[0] /= a;
            }
            Factorization::Dense(lu) => {
                let n = b.len();
                lu.solve_in_place(MatMut::from_column_major_slice_mut(b, n, 1));
            }
            Factorization::Sparse(lu) => {
                let n = b.len();
                lu.solve_in_place(MatMut::from_column_major_slice_mut(b, n, 1));
            }
        }
        b.iter().all(|v| v.is_finite())
    }
}

pub(crate) fn singular() -> CoreError {
    CoreError::InvalidInput {
        name: "dt",
        problem: "gives a singular iteration matrix (check M, C, K and the element tangents)"
            .into(),
    }
}

impl<'a> IterationMatrix<'a> {
    /// An iteration matrix of `nb x nb` blocks of order `n` fed by the constant `matrices`
    /// and by elements acting on `element_dofs`. Sparse when any matrix is sparse.
    pub fn new(
        n: usize,
        nb: usize,
        matrices: &[&'a Matrix],
        element_dofs: &[&[usize]],
    ) -> Result<Self, CoreError> {
        let sparse = if matrices.iter().any(|m| m.is_sparse()) {
            Some(SparsePattern::new(n, nb, matrices, element_dofs)?)
        } else {
            None
        };
        let size = n * nb;
        let (dense, values) = match &sparse {
            Some(p) => (Mat::zeros(0, 0), vec![0.0; p.symbolic.row_idx().len()]),
            None => (Mat::zeros(size, size), Vec::new()),
        };
        Ok(IterationMatrix {
            n,
            nb,
            matrices: matrices.to_vec(),
            sparse,
            dense,
            values,
        })
    }

    /// Whether the matrix is assembled sparse.
    pub fn is_sparse(&self) -> bool {
        self.sparse.is_some()
    }

    /// Sets every entry to zero.
    pub fn clear(&mut self) {
        if self.sparse.is_some() {
            self.values.fill(0.0);
        } else {
            self.dense.fill(0.0);
        }
    }

    /// Position of block-pattern entry `k` in block `(bi, bj)` of the sparse values.
    fn sparse_pos(p: &SparsePattern, nb: usize, k: usize, bi: usize, bj: usize) -> usize {
        let c = p.col_of[k];
        let (start, len) = (p.col_ptr[c], p.col_ptr[c + 1] - p.col_ptr[c]);
        let nnz = p.col_of.len();
        bj * nb * nnz + nb * start + bi * len + (k - start)
    }

    /// Adds `coef` times constant matrix `which` into block `(bi, bj)`.
    pub fn add_matrix(&mut self, which: usize, block: (usize, usize), coef: f64) {
        if coef == 0.0 {
            return;
        }
        let (n, nb) = (self.n, self.nb);
        let (bi, bj) = block;
        let m = self.matrices[which];
        match &self.sparse {
            Some(p) => {
                let map = &p.matrix_maps[which];
                let mut e = 0;
                m.for_each(|_, _, v| {
                    let pos = Self::sparse_pos(p, nb, map[e], bi, bj);
                    self.values[pos] += coef * v;
                    e += 1;
                });
            }
            None => {
                let dense = &mut self.dense;
                m.for_each(|i, j, v| {
                    dense[(bi * n + i, bj * n + j)] += coef * v;
                });
            }
        }
    }

    /// Adds `coef` times the row-major local matrix `local` of element `element` (acting on
    /// `dofs`) into block `(bi, bj)`.
    pub fn add_local(
        &mut self,
        element: usize,
        dofs: &[usize],
        local: &[f64],
        block: (usize, usize),
        coef: f64,
    ) {
        if coef == 0.0 {
            return;
        }
        let (n, nb) = (self.n, self.nb);
        let (bi, bj) = block;
        let nl = dofs.len();
        match &self.sparse {
            Some(p) => {
                let map = &p.element_maps[element];
                for (&k, &v) in map.iter().zip(local) {
                    if v != 0.0 {
                        let pos = Self::sparse_pos(p, nb, k, bi, bj);
                        self.values[pos] += coef * v;
                    }
                }
            }
            None => {
                for a in 0..nl {
                    for b in 0..nl {
                        let v = local[a * nl + b];
                        if v != 0.0 {
                            self.dense[(bi * n + dofs[a], bj * n + dofs[b])] += coef * v;
                        }
                    }
                }
            }
        }
    }

    /// LU factorisation of the assembled matrix.
    pub fn factorize(&self) -> Result<Factorization, CoreError> {
        match &self.sparse {
            Some(p) => {
                let mat = SparseColMatRef::new(p.symbolic.as_ref(), &self.values);
                let lu = Lu::try_new_with_symbolic(p.lu.clone(), mat).map_err(|_| singular())?;
                Ok(Factorization::Sparse(lu))
            }
            None if self.n * self.nb == 1 => {
                let a = self.dense[(0, 0)];
                if a == 0.0 || !a.is_finite() {
                    return Err(singular());
                }
                Ok(Factorization::Scalar(a))
            }
            None => Ok(Factorization::Dense(self.dense.partial_piv_lu())),
        }
    }
}

impl SparsePattern {
    fn new(
        n: usize,
        nb: usize,
        matrices: &[&Matrix],
        element_dofs: &[&[usize]],
    ) -> Result<Self, CoreError> {
        // (col, row) pairs of one block: every source entry and the diagonal.
        let mut pairs: Vec<(usize, usize)> = (0..n).map(|i| (i, i)).collect();
        for m in matrices {
            m.for_each(|i, j, _| pairs.push((j, i)));
        }
        for dofs in element_dofs {
            for &a in *dofs {
                for &b in *dofs {
                    pairs.push((b, a));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        let mut col_ptr = vec![0usize; n + 1];
        for &(c, _) in &pairs {
            col_ptr[c + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let col_of: Vec<usize> = pairs.iter().map(|&(c, _)| c).collect();
        let rows: Vec<usize> = pairs.iter().map(|&(_, r)| r).collect();
        let find = |i: usize, j: usize| -> usize {
            let r = col_ptr[j]..col_ptr[j + 1];
            col_ptr[j] + rows[r].binary_search(&i).expect("entry is in the pattern")
        };
        let matrix_maps = matrices
            .iter()
            .map(|m| {
                let mut map = Vec::new();
                m.for_each(|i, j, _| map.push(find(i, j)));
                map
            })
            .collect();
        let element_maps = element_dofs
            .iter()
            .map(|dofs| {
                dofs.iter()
                    .flat_map(|&a| dofs.iter().map(move |&b| (a, b)))
                    .map(|(a, b)| find(a, b))
                    .collect()
            })
            .collect();
        // The whole matrix: column (bj, c) holds, for bi = 0..nb, rows bi n + (rows of c).
        let nnz = pairs.len();
        let size = n * nb;
        let mut big_ptr = Vec::with_capacity(size + 1);
        let mut big_rows = Vec::with_capacity(nnz * nb * nb);
        big_ptr.push(0);
        for _bj in 0..nb {
            for c in 0..n {
                for bi in 0..nb {
                    big_rows.extend(rows[col_ptr[c]..col_ptr[c + 1]].iter().map(|&r| bi * n + r));
                }
                big_ptr.push(big_rows.len());
            }
        }
        let symbolic = SymbolicSparseColMat::new_checked(size, size, big_ptr, None, big_rows);
        let lu = SymbolicLu::try_new(symbolic.as_ref()).map_err(|e| CoreError::InvalidInput {
            name: "M",
            problem: format!("sparse symbolic factorisation failed: {e:?}"),
        })?;
        Ok(SparsePattern {
            col_ptr,
            col_of,
            matrix_maps,
            element_maps,
            symbolic,
            lu,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csr_of(n: usize, dense: &[f64]) -> Matrix {
        let (mut indptr, mut indices, mut data) = (vec![0], Vec::new(), Vec::new());
        for i in 0..n {
            for j in 0..n {
                if dense[i * n + j] != 0.0 {
                    indices.push(j);
                    data.push(dense[i * n + j]);
                }
            }
            indptr.push(indices.len());
        }
        Matrix::Csr {
            n,
            indptr,
            indices,
            data,
        }
    }

    /// Dense and sparse assembly of a 2 x 2 block matrix solve the same system.
    #[test]
    fn dense_and_sparse_agree() {
        let n = 3;
        let a = [4.0, -1.0, 0.0, -1.0, 4.0, -1.0, 0.0, -1.0, 4.0];
        let b = [1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0];
        let local = [0.5, -0.5, -0.5, 0.5];
        let dofs = [0usize, 2];
        let solve = |ma: &Matrix, mb: &Matrix| {
            let mut it = IterationMatrix::new(n, 2, &[ma, mb], &[&dofs]).unwrap();
            it.clear();
            it.add_matrix(0, (0, 0), 1.0);
            it.add_matrix(1, (0, 1), 0.3);
            it.add_matrix(1, (1, 0), -0.2);
            it.add_matrix(0, (1, 1), 2.0);
            it.add_local(0, &dofs, &local, (1, 1), 1.5);
            it.add_local(0, &dofs, &local, (0, 1), 0.7);
            let f = it.factorize().unwrap();
            let mut rhs = vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
            assert!(f.solve_in_place(&mut rhs));
            rhs
        };
        let dense = solve(
            &Matrix::Dense {
                n,
                data: a.to_vec(),
            },
            &Matrix::Dense {
                n,
                data: b.to_vec(),
            },
        );
        let sparse = solve(&csr_of(n, &a), &csr_of(n, &b));
        for (d, s) in dense.iter().zip(&sparse) {
            assert!((d - s).abs() < 1e-14, "{dense:?} vs {sparse:?}");
        }
        // the dense solution satisfies the assembled equations
        let mut full = [[0.0; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                full[i][j] += a[i * 3 + j];
                full[i][3 + j] += 0.3 * b[i * 3 + j];
                full[3 + i][j] -= 0.2 * b[i * 3 + j];
                full[3 + i][3 + j] += 2.0 * a[i * 3 + j];
            }
        }
        for (p, &da) in dofs.iter().enumerate() {
            for (q, &db) in dofs.iter().enumerate() {
                full[3 + da][3 + db] += 1.5 * local[p * 2 + q];
                full[da][3 + db] += 0.7 * local[p * 2 + q];
            }
        }
        for (i, row) in full.iter().enumerate() {
            let r: f64 = row.iter().zip(&dense).map(|(x, y)| x * y).sum();
            assert!((r - (i + 1) as f64).abs() < 1e-13);
        }
    }
}
