//! Small dense linear solves for the Newton step equations (faer, partial pivoting LU).

use crate::dense_fixed as fixed;

/// `a . b` over the shorter length, in four interleaved partial sums (which the compiler
/// can keep in SIMD registers: a plain sequential sum cannot be reordered, and vectorised).
#[inline]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

/// `(r . x_0, r . x_1, r . x_2)` in one pass over `r` (each in four partial sums, as
/// [`dot`]).
#[inline]
pub fn dot3(r: &[f64], x: [&[f64]; 3]) -> (f64, f64, f64) {
    let n = r.len().min(x[0].len()).min(x[1].len()).min(x[2].len());
    let (r, a, b, c) = (&r[..n], &x[0][..n], &x[1][..n], &x[2][..n]);
    let full = n - n % 4;
    let acc = fixed::partial_sums3(full, r, [a, b, c]);
    let mut out = [0.0; 3];
    for (o, (acc, v)) in out.iter_mut().zip(acc.iter().zip([a, b, c])) {
        let tail: f64 = (full..n).map(|j| r[j] * v[j]).sum();
        *o = (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail;
    }
    (out[0], out[1], out[2])
}

/// Largest system solved by the in-place elimination below; faer above.
pub(crate) const SMALL: usize = 32;

/// Solves `a x = b` in place of `b` for a row-major `n x n` matrix `a`. Returns `false` when
/// the matrix is numerically singular (a zero or non-finite pivot).
///
/// Newton's step equations are often tiny (a few retained modes): there an allocation-free
/// Gaussian elimination with partial pivoting on a stack copy is several times faster than
/// building faer matrices and a factorisation object each iteration (measured: allocation
/// and setup were 40 % of a 5-mode nonlinear step). Larger systems use faer's LU.
pub fn solve_in_place(n: usize, a: &[f64], b: &mut [f64]) -> bool {
    debug_assert_eq!(a.len(), n * n);
    debug_assert_eq!(b.len(), n);
    // The stack copy sized to the system: zeroing a 32 x 32 buffer for a one-mode step
    // was 15 % of a one-dof hysteretic step (perf, issue 23).
    if n <= 4 {
        let mut m = [0.0; 16];
        m[..n * n].copy_from_slice(a);
        return eliminate(n, &mut m[..n * n], b);
    }
    if n <= SMALL {
        let mut m = [0.0; SMALL * SMALL];
        m[..n * n].copy_from_slice(a);
        return eliminate(n, &mut m[..n * n], b);
    }
    lu_solve(n, a, b)
}

/// [`solve_in_place`] for a caller that rebuilds `a` before its next solve: the small
/// systems are eliminated in `a` itself (no copy); `a` is left overwritten by the factors.
pub fn solve_overwriting(n: usize, a: &mut [f64], b: &mut [f64]) -> bool {
    debug_assert_eq!(a.len(), n * n);
    debug_assert_eq!(b.len(), n);
    if n <= SMALL {
        return eliminate(n, a, b);
    }
    lu_solve(n, a, b)
}

/// faer's LU with partial pivoting, for the systems above [`SMALL`].
fn lu_solve(n: usize, a: &[f64], b: &mut [f64]) -> bool {
    crate::dense_kept::KeptLu::factor(n, a).solve(b)
}

/// Gaussian elimination with partial pivoting, in place: `m` (row-major `n x n`) is
/// overwritten by its factors and `b` by the solution. Returns `false` when the matrix is
/// numerically singular or the solution not finite. For callers that rebuild `m` anyway (no
/// copy needed).
pub fn eliminate(n: usize, m: &mut [f64], b: &mut [f64]) -> bool {
    // the same code for each small size, its loops then of known length (unrolled, no
    // bounds checks): the same operations in the same order
    match n {
        1 => eliminate_sized(1, m, b),
        2 => eliminate_sized(2, m, b),
        3 => eliminate_sized(3, m, b),
        4 => eliminate_sized(4, m, b),
        _ => eliminate_sized(n, m, b),
    }
}

/// [`eliminate`]'s body, inlined where `n` is a constant.
#[inline(always)]
fn eliminate_sized(n: usize, m: &mut [f64], b: &mut [f64]) -> bool {
    let (m, b) = (&mut m[..n * n], &mut b[..n]);
    for k in 0..n {
        let Some(p) = pivot_row(m, n, k) else {
            return false;
        };
        if p != k {
            for j in 0..n {
                m.swap(k * n + j, p * n + j);
            }
            b.swap(k, p);
        }
        let inv = 1.0 / m[k * n + k];
        for i in k + 1..n {
            let f = m[i * n + k] * inv;
            if f != 0.0 {
                for j in k..n {
                    m[i * n + j] -= f * m[k * n + j];
                }
                b[i] -= f * b[k];
            }
        }
    }
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|j| m[k * n + j] * b[j]).sum();
        b[k] = (b[k] - s) / m[k * n + k];
    }
    b.iter().all(|v| v.is_finite())
}

/// The row at or below `k` with the largest entry in column `k` (partial pivoting), or None
/// when that entry is zero or not finite (a numerically singular matrix).
#[inline(always)]
pub(crate) fn pivot_row(m: &[f64], n: usize, k: usize) -> Option<usize> {
    let (p, pivot) = (k..n)
        .map(|i| (i, m[i * n + k].abs()))
        .fold((k, -1.0), |best, c| if c.1 > best.1 { c } else { best });
    (pivot.is_finite() && pivot > 0.0).then_some(p)
}

/// An LU factorisation with partial pivoting of a row-major `n x n` matrix, kept to solve
/// with it again (a modified Newton iteration reuses it over iterations and steps).
#[derive(Debug, Clone, Default)]
pub struct DenseLu {
    n: usize,
    lu: Vec<f64>,
    piv: Vec<usize>,
}

impl DenseLu {
    /// Factorises `a`; `None` when it is numerically singular.
    pub fn factor(n: usize, a: &[f64]) -> Option<Self> {
        let mut lu = DenseLu::default();
        lu.refactor(n, a).then_some(lu)
    }

    /// Factorises `a` into this object's buffers (no allocation after the first time);
    /// `false` when it is numerically singular (the factors are then meaningless).
    pub fn refactor(&mut self, n: usize, a: &[f64]) -> bool {
        self.refactor_with(n, a, true)
    }

    /// [`DenseLu::refactor`], without searching for pivots when `a` is strictly column
    /// diagonally dominant (with a margin): partial pivoting then keeps every diagonal pivot
    /// (dominance is inherited by each Schur complement), so the factors are the same, bit
    /// for bit, for about `n^2` comparisons instead of the column scans (a fifth of the
    /// factorisation at `n = 20`; the mass-law step refactorises every step).
    pub fn refactor_dominant(&mut self, n: usize, a: &[f64]) -> bool {
        let search = !fixed::column_dominant(n, a);
        if !search && n <= 32 {
            // dominant: every entry finite, no row exchanged
            self.n = n;
            self.lu.resize(n * n, 0.0);
            self.piv.clear();
            self.piv.extend(0..n);
            return fixed::lu_unpivoted(n, a, &mut self.lu);
        }
        self.refactor_with(n, a, search)
    }

    fn refactor_with(&mut self, n: usize, a: &[f64], search: bool) -> bool {
        debug_assert_eq!(a.len(), n * n);
        self.n = n;
        self.lu.clear();
        self.lu.extend_from_slice(a);
        self.piv.clear();
        self.piv.extend(0..n);
        let lu = &mut self.lu;
        for k in 0..n {
            let p = if search {
                let Some(p) = pivot_row(lu, n, k) else {
                    return false;
                };
                p
            } else {
                let d = lu[k * n + k].abs();
                if !(d.is_finite() && d > 0.0) {
                    return false;
                }
                k
            };
            if p != k {
                let (top, bottom) = lu.split_at_mut(p * n);
                top[k * n..(k + 1) * n].swap_with_slice(&mut bottom[..n]);
                self.piv.swap(k, p);
            }
            // Rows below k minus multiples of row k: contiguous slices (vectorised).
            let (head, tail) = lu.split_at_mut((k + 1) * n);
            let row_k = &head[k * n..];
            let inv = 1.0 / row_k[k];
            for row in tail.chunks_exact_mut(n) {
                let f = row[k] * inv;
                row[k] = f;
                if f != 0.0 {
                    for (x, &y) in row[k + 1..].iter_mut().zip(&row_k[k + 1..]) {
                        *x -= f * y;
                    }
                }
            }
        }
        true
    }

    /// Solves `a x = b` in place of `b` (`work`: scratch of length `n`); false if the
    /// solution is not finite.
    pub fn solve(&self, b: &mut [f64], work: &mut [f64]) -> bool {
        let n = self.n;
        let (b, work) = (&mut b[..n], &mut work[..n]);
        for (w, &p) in work.iter_mut().zip(&self.piv) {
            *w = b[p];
        }
        crate::dense_rows::forward(&self.lu, n, work);
        for (i, row) in self.lu.chunks_exact(n).enumerate().rev() {
            let s = dot(&row[i + 1..], &work[i + 1..]);
            work[i] = (work[i] - s) / row[i];
        }
        b.copy_from_slice(work);
        b.iter().all(|v| v.is_finite())
    }
}

impl DenseLu {
    /// Solves `a^T x = b` in place of `b` with the same factors (`P a = L U`, so
    /// `a^T = U^T L^T P`); false if the solution is not finite. Row-oriented: every update
    /// runs along a contiguous row of the factors.
    pub fn solve_transpose(&self, b: &mut [f64], work: &mut [f64]) -> bool {
        let n = self.n;
        let (b, work) = (&mut b[..n], &mut work[..n]);
        work.copy_from_slice(b);
        // U^T y = b: y_j final once the rows above are subtracted.
        for (j, row) in self.lu.chunks_exact(n).enumerate() {
            let yj = work[j] / row[j];
            work[j] = yj;
            if yj != 0.0 {
                for (w, u) in work[j + 1..].iter_mut().zip(&row[j + 1..]) {
                    *w -= u * yj;
                }
            }
        }
        // L^T w = y (unit diagonal), from the last row up.
        for (j, row) in self.lu.chunks_exact(n).enumerate().rev() {
            let wj = work[j];
            if wj != 0.0 {
                for (w, l) in work[..j].iter_mut().zip(&row[..j]) {
                    *w -= l * wj;
                }
            }
        }
        for (i, &p) in self.piv.iter().enumerate() {
            b[p] = work[i];
        }
        b.iter().all(|v| v.is_finite())
    }
}

impl DenseLu {
    /// Solves `a^T X = B` in place of `B` for `k` right-hand sides at once: `b` is `n x k`
    /// row-major (row `m` holds component `m` of every right-hand side, so each update is a
    /// `k`-wide vector operation); `perm` is scratch of the same size. False if the
    /// solution is not finite.
    pub fn solve_transpose_many(&self, b: &mut [f64], k: usize, perm: &mut [f64]) -> bool {
        let n = self.n;
        let (lu, piv) = (&self.lu[..], &self.piv[..]);
        match k {
            1 => return fixed::solve_transpose_fixed::<1>(lu, piv, n, b, perm),
            2 => return fixed::solve_transpose_fixed::<2>(lu, piv, n, b, perm),
            3 => return fixed::solve_transpose_fixed::<3>(lu, piv, n, b, perm),
            4 => return fixed::solve_transpose_fixed::<4>(lu, piv, n, b, perm),
            6 => return fixed::solve_transpose_fixed::<6>(lu, piv, n, b, perm),
            8 => return fixed::solve_transpose_fixed::<8>(lu, piv, n, b, perm),
            _ => {}
        }
        self.solve_transpose_general(b, k, perm)
    }

    /// [`DenseLu::solve_transpose_many`] for any `k` (a loop of length `k` per update).
    pub(crate) fn solve_transpose_general(
        &self,
        b: &mut [f64],
        k: usize,
        perm: &mut [f64],
    ) -> bool {
        let n = self.n;
        let (b, perm) = (&mut b[..n * k], &mut perm[..n * k]);
        // U^T Y = B, row by row.
        for (j, row) in self.lu.chunks_exact(n).enumerate() {
            let (head, tail) = b.split_at_mut((j + 1) * k);
            let yj = &mut head[j * k..];
            let inv = 1.0 / row[j];
            for y in yj.iter_mut() {
                *y *= inv;
            }
            for (bi, &u) in tail.chunks_exact_mut(k).zip(&row[j + 1..]) {
                if u != 0.0 {
                    for (x, y) in bi.iter_mut().zip(yj.iter()) {
                        *x -= u * y;
                    }
                }
            }
        }
        // L^T W = Y (unit diagonal), from the last row up.
        for (j, row) in self.lu.chunks_exact(n).enumerate().rev() {
            let (head, tail) = b.split_at_mut(j * k);
            let wj = &tail[..k];
            for (bi, &l) in head.chunks_exact_mut(k).zip(&row[..j]) {
                if l != 0.0 {
                    for (x, w) in bi.iter_mut().zip(wj) {
                        *x -= l * w;
                    }
                }
            }
        }
        for (i, &p) in self.piv.iter().enumerate() {
            perm[p * k..(p + 1) * k].copy_from_slice(&b[i * k..(i + 1) * k]);
        }
        b.copy_from_slice(perm);
        b.iter().all(|v| v.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dot3_is_three_dots_bit_for_bit() {
        // every length's chunks and tail, values of mixed sign and magnitude
        let value =
            |i: usize, s: f64| ((i as f64 + s) * 0.7).sin() * 10f64.powi((i % 7) as i32 - 3);
        for n in 0..40 {
            let r: Vec<f64> = (0..n).map(|i| value(i, 0.1)).collect();
            let x: Vec<Vec<f64>> = (0..3)
                .map(|k| (0..n).map(|i| value(i, 1.3 + k as f64)).collect())
                .collect();
            let (a, b, c) = dot3(&r, [&x[0], &x[1], &x[2]]);
            for (got, xk) in [a, b, c].iter().zip(&x) {
                assert_eq!(got.to_bits(), dot(&r, xk).to_bits(), "n = {n}");
            }
        }
    }

    #[test]
    fn small_eliminations_are_the_general_loop_bit_for_bit() {
        for n in 1..=5 {
            let a: Vec<f64> = (0..n * n)
                .map(|i| ((i as f64) * 1.7).cos() + if i % (n + 1) == 0 { 3.0 } else { 0.0 })
                .collect();
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).sin() + 1.0).collect();
            let (mut m1, mut b1) = (a.clone(), b.clone());
            let (mut m2, mut b2) = (a.clone(), b.clone());
            assert!(eliminate(n, &mut m1, &mut b1));
            assert!(eliminate_sized(n, &mut m2, &mut b2));
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&b1), bits(&b2));
            assert_eq!(bits(&m1), bits(&m2));
        }
    }

    #[test]
    fn padded_factors_are_the_factorisations_bit_for_bit() {
        for n in 1..=32 {
            // column dominant, entries of mixed sign and magnitude, some zeros
            let mut a: Vec<f64> = (0..n * n)
                .map(|k| {
                    let v = ((k * 37 % 23) as f64 - 11.0) * 0.013 * (1.0 + (k % 7) as f64);
                    v * f64::from(k % 5 != 3)
                })
                .collect();
            for j in 0..n {
                let col: f64 = (0..n).map(|i| a[i * n + j].abs()).sum();
                a[j * n + j] = if j % 2 == 0 { 1.5 } else { -1.5 } * (col + 0.1);
            }
            assert!(crate::dense_fixed::column_dominant(n, &a), "n = {n}");
            let (mut fast, mut slow) = (DenseLu::default(), DenseLu::default());
            assert!(fast.refactor_dominant(n, &a));
            assert!(slow.refactor_with(n, &a, false));
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fast.lu), bits(&slow.lu), "n = {n}");
            assert_eq!(fast.piv, slow.piv);
        }
    }

    #[test]
    fn solves_a_small_system() {
        let a = [4.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 2.0];
        let mut b = [1.0, 2.0, 3.0];
        assert!(solve_in_place(3, &a, &mut b));
        let r: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| a[i * 3 + j] * b[j]).sum::<f64>())
            .collect();
        for (ri, bi) in r.iter().zip([1.0, 2.0, 3.0]) {
            assert!((ri - bi).abs() < 1e-14);
        }
        assert!(!solve_in_place(2, &[1.0, 2.0, 2.0, 4.0], &mut [1.0, 1.0]));
    }

    #[test]
    fn many_transposed_solves_are_the_single_ones() {
        let n = 7;
        let a: Vec<f64> = (0..n * n)
            .map(|k| ((k * 17 % 11) as f64 - 5.0) + if k % (n + 1) == 0 { 0.3 } else { 0.0 })
            .collect();
        let lu = DenseLu::factor(n, &a).expect("regular");
        let k = 3;
        let rhs: Vec<Vec<f64>> = (0..k)
            .map(|c| (0..n).map(|i| ((i * 3 + c) as f64 * 0.37).sin()).collect())
            .collect();
        let mut many: Vec<f64> = (0..n * k).map(|x| rhs[x % k][x / k]).collect();
        let mut perm = vec![0.0; n * k];
        assert!(lu.solve_transpose_many(&mut many, k, &mut perm));
        let mut work = vec![0.0; n];
        for (c, r) in rhs.iter().enumerate() {
            let mut one = r.clone();
            assert!(lu.solve_transpose(&mut one, &mut work));
            for i in 0..n {
                assert!((one[i] - many[i * k + c]).abs() < 1e-13 * (1.0 + one[i].abs()));
            }
        }
    }

    #[test]
    fn kept_factorisation_solves_like_elimination() {
        let n = 6;
        let a: Vec<f64> = (0..n * n)
            .map(|k| ((k * 13 % 7) as f64 - 3.0) + if k % (n + 1) == 0 { 0.5 } else { 0.0 })
            .collect();
        let lu = DenseLu::factor(n, &a).expect("regular");
        let mut work = vec![0.0; n];
        for seed in 0..3 {
            let rhs: Vec<f64> = (0..n).map(|i| ((i + seed) as f64).cos()).collect();
            let (mut x, mut y) = (rhs.clone(), rhs.clone());
            assert!(lu.solve(&mut x, &mut work));
            assert!(solve_in_place(n, &a, &mut y));
            for (xi, yi) in x.iter().zip(&y) {
                assert!((xi - yi).abs() < 1e-12 * (1.0 + yi.abs()));
            }
        }
        assert!(DenseLu::factor(2, &[1.0, 2.0, 2.0, 4.0]).is_none());
        // the transpose with the same factors
        let at: Vec<f64> = (0..n * n).map(|k| a[(k % n) * n + k / n]).collect();
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin() + 0.1).collect();
        let (mut x, mut y) = (rhs.clone(), rhs.clone());
        assert!(lu.solve_transpose(&mut x, &mut work));
        assert!(solve_in_place(n, &at, &mut y));
        for (xi, yi) in x.iter().zip(&y) {
            assert!((xi - yi).abs() < 1e-12 * (1.0 + yi.abs()));
        }
    }

    #[test]
    fn small_and_large_paths_agree() {
        for n in [5, 40] {
            // diagonally weighted but pivoting-relevant matrix
            let a: Vec<f64> = (0..n * n)
                .map(|k| {
                    let (i, j) = (k / n, k % n);
                    ((i * 7 + j * 3) % 11) as f64 - 5.0 + if i == j { 20.0 } else { 0.0 }
                })
                .collect();
            let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
            let mut b: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| a[i * n + j] * x[j]).sum())
                .collect();
            assert!(solve_in_place(n, &a, &mut b));
            for (bi, xi) in b.iter().zip(&x) {
                assert!((bi - xi).abs() < 1e-12, "n = {n}");
            }
        }
    }
}
