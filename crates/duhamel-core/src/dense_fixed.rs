//! [`DenseLu::solve_transpose_many`](crate::dense::DenseLu::solve_transpose_many) for a few
//! right-hand sides known at compile time: each update of a row of `X` is one `[f64; K]`
//! operation instead of a loop of unknown length (the element-space step solves for its
//! `n_d` element dofs every step under a mass law; measured: 3x faster at `n = 20`,
//! `K = 4`). The same operations in the same order as the general loop: bit for bit its
//! results. And the four partial sums of [`dot3`](crate::dense::dot3), one register of
//! four lanes per product on AVX.

/// `a^T X = B` for `K` right-hand sides from the factors `P a = L U` (`lu` row-major
/// `n x n`, `piv` the row permutation); `b` is `n x K` row-major, `perm` scratch of the same
/// size. False if the solution is not finite.
pub(crate) fn solve_transpose_fixed<const K: usize>(
    lu: &[f64],
    piv: &[usize],
    n: usize,
    b: &mut [f64],
    perm: &mut [f64],
) -> bool {
    let (b, perm) = (&mut b[..n * K], &mut perm[..n * K]);
    // U^T Y = B, row by row.
    for (j, row) in lu.chunks_exact(n).enumerate() {
        let (head, tail) = b.split_at_mut((j + 1) * K);
        let yj: &mut [f64; K] = (&mut head[j * K..]).try_into().expect("K entries");
        let inv = 1.0 / row[j];
        for y in yj.iter_mut() {
            *y *= inv;
        }
        let yj = *yj;
        for (bi, &u) in tail.chunks_exact_mut(K).zip(&row[j + 1..]) {
            if u != 0.0 {
                for (x, y) in bi.iter_mut().zip(yj) {
                    *x -= u * y;
                }
            }
        }
    }
    // L^T W = Y (unit diagonal), from the last row up.
    for (j, row) in lu.chunks_exact(n).enumerate().rev() {
        let (head, tail) = b.split_at_mut(j * K);
        let wj: [f64; K] = tail[..K].try_into().expect("K entries");
        for (bi, &l) in head.chunks_exact_mut(K).zip(&row[..j]) {
            if l != 0.0 {
                for (x, w) in bi.iter_mut().zip(wj) {
                    *x -= l * w;
                }
            }
        }
    }
    for (i, &p) in piv.iter().enumerate() {
        perm[p * K..(p + 1) * K].copy_from_slice(&b[i * K..(i + 1) * K]);
    }
    b.copy_from_slice(perm);
    b.iter().all(|v| v.is_finite())
}

/// [`eliminate`](crate::dense::eliminate) for an `N x N` system known at compile time (the
/// few-mode Newton's): the same operations in the same order (partial pivoting, the
/// elimination, the back substitution and its sums), bit for bit its results, unrolled.
/// `m` is overwritten by the factors and `b` by the solution; false when the matrix is
/// numerically singular or the solution not finite.
#[inline(always)]
pub(crate) fn eliminate_fixed<const N: usize>(m: &mut [[f64; N]; N], b: &mut [f64; N]) -> bool {
    for k in 0..N {
        let (p, pivot) = (k..N)
            .map(|i| (i, m[i][k].abs()))
            .fold((k, -1.0), |best, c| if c.1 > best.1 { c } else { best });
        if !(pivot.is_finite() && pivot > 0.0) {
            return false;
        }
        if p != k {
            m.swap(k, p);
            b.swap(k, p);
        }
        let inv = 1.0 / m[k][k];
        for i in k + 1..N {
            let f = m[i][k] * inv;
            if f != 0.0 {
                let (above, below) = m.split_at_mut(i);
                for (x, y) in below[0][k..].iter_mut().zip(&above[k][k..]) {
                    *x -= f * y;
                }
                b[i] -= f * b[k];
            }
        }
    }
    for k in (0..N).rev() {
        let s: f64 = (k + 1..N).map(|j| m[k][j] * b[j]).sum();
        b[k] = (b[k] - s) / m[k][k];
    }
    b.iter().all(|v| v.is_finite())
}

/// Whether the row-major `n x n` matrix `a` is strictly column diagonally dominant with a
/// margin: `|a_jj| > (1 + 1e-6) sum_{i != j} |a_ij|` for every column `j` (Gaussian
/// elimination with partial pivoting then never exchanges rows, whatever the rounding).
pub(crate) fn column_dominant(n: usize, a: &[f64]) -> bool {
    const SMALL: usize = 64;
    let mut sums = [0.0_f64; SMALL];
    if n > SMALL || a.len() != n * n {
        return false;
    }
    let sums = &mut sums[..n];
    for row in a.chunks_exact(n) {
        for (s, x) in sums.iter_mut().zip(row) {
            *s += x.abs();
        }
    }
    sums.iter().enumerate().all(|(j, &s)| {
        let d = a[j * n + j].abs();
        d.is_finite() && d > (1.0 + 1e-6) * (s - d)
    })
}

/// The LU factors without row exchanges of a row-major `n x n` matrix (`n <= 32`), into
/// `lu` (`U` on and above the diagonal, the multipliers below), for a column dominant `a`
/// ([`column_dominant`], which partial pivoting would not exchange rows of): the same
/// operations on every entry as [`DenseLu::refactor`](crate::dense::DenseLu::refactor), bit
/// for bit its factors. Each row update runs over the whole row padded to a multiple of
/// eight (whole vector registers, no remainder loop; the entries left of the diagonal are
/// zeros there, and stay zeros), with the multipliers kept apart: measured on the mass-law
/// element-space step (`n = 20`, one factorisation per step). False on a zero or non-finite
/// pivot.
pub(crate) fn lu_unpivoted(n: usize, a: &[f64], lu: &mut [f64]) -> bool {
    match n {
        0..=8 => lu_padded::<8>(n, a, lu),
        9..=16 => lu_padded::<16>(n, a, lu),
        17..=24 => lu_padded::<24>(n, a, lu),
        _ => lu_padded::<32>(n, a, lu),
    }
}

fn lu_padded<const P: usize>(n: usize, a: &[f64], lu: &mut [f64]) -> bool {
    if n > P || a.len() != n * n || lu.len() != n * n {
        return false;
    }
    let mut m = [[0.0_f64; P]; P];
    for (row, src) in m.iter_mut().zip(a.chunks_exact(n)) {
        row[..n].copy_from_slice(src);
    }
    for k in 0..n {
        let d = m[k][k];
        if !(d.abs().is_finite() && d.abs() > 0.0) {
            return false;
        }
        let inv = 1.0 / d;
        let row_k = m[k];
        for (i, row) in m.iter_mut().enumerate().take(n).skip(k + 1) {
            let f = row[k] * inv;
            // the multiplier straight into the factors
            lu[i * n + k] = f;
            if f != 0.0 {
                // columns < k: 0 - f * 0 (zeros stay zeros); k: replaced below; > k: the
                // factorisation's update
                for (x, &y) in row.iter_mut().zip(&row_k) {
                    *x -= f * y;
                }
            }
            row[k] = 0.0;
        }
    }
    for (i, (dst, row)) in lu.chunks_exact_mut(n).zip(&m).enumerate() {
        dst[i..].copy_from_slice(&row[i..n]);
    }
    true
}

/// [`dot3`](crate::dense::dot3)'s four partial sums of each product over the first `full` entries (a multiple
/// of four, within every slice): lane `k` sums the entries `k, k + 4, ...` in order.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
pub(crate) fn partial_sums3(full: usize, r: &[f64], x: [&[f64]; 3]) -> [[f64; 4]; 3] {
    let mut acc = [[0.0; 4]; 3];
    for j in (0..full).step_by(4) {
        for k in 0..4 {
            let p = r[j + k];
            for (acc, x) in acc.iter_mut().zip(x) {
                acc[k] += p * x[j + k];
            }
        }
    }
    acc
}

/// [`dot3`](crate::dense::dot3)'s four partial sums on AVX: one 4-lane register per product, each lane the
/// scalar loop's partial sum (the same multiplications and additions in the same order:
/// no fused multiply-add), where the compiler's own vectorisation used half-width
/// registers and shuffles.
#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
#[inline(always)]
pub(crate) fn partial_sums3(full: usize, r: &[f64], x: [&[f64]; 3]) -> [[f64; 4]; 3] {
    use std::arch::x86_64::{__m256d, _mm256_storeu_pd};
    use std::arch::x86_64::{_mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_setzero_pd};
    assert!(full % 4 == 0 && full <= r.len() && x.iter().all(|v| full <= v.len()));
    // SAFETY: AVX is enabled at compile time (the cfg above); the intrinsic touches no
    // memory.
    let mut acc: [__m256d; 3] = [unsafe { _mm256_setzero_pd() }; 3];
    for j in (0..full).step_by(4) {
        // SAFETY: AVX is enabled at compile time (the cfg above); `j + 4 <= full` and
        // `full` is within `r` and every `x[i]` (asserted), so each unaligned load reads
        // four `f64` inside its slice.
        unsafe {
            let p = _mm256_loadu_pd(r.as_ptr().add(j));
            for (acc, x) in acc.iter_mut().zip(x) {
                let y = _mm256_loadu_pd(x.as_ptr().add(j));
                *acc = _mm256_add_pd(*acc, _mm256_mul_pd(p, y));
            }
        }
    }
    let mut out = [[0.0; 4]; 3];
    for (o, a) in out.iter_mut().zip(acc) {
        // SAFETY: `o` is four writable `f64`; the store is unaligned.
        unsafe { _mm256_storeu_pd(o.as_mut_ptr(), a) };
    }
    out
}

/// [`matvec`](crate::dense_rows::matvec)'s four partial sums of four rows `r` against one `x`
/// over the first `full` entries (a multiple of four, within every slice): lane `k` of row
/// `i` sums the entries `k, k + 4, ...` in order, as [`dot`](crate::dense::dot) does.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
pub(crate) fn partial_sums_rows4(full: usize, r: [&[f64]; 4], x: &[f64]) -> [[f64; 4]; 4] {
    let mut acc = [[0.0; 4]; 4];
    for j in (0..full).step_by(4) {
        for k in 0..4 {
            let y = x[j + k];
            for (acc, r) in acc.iter_mut().zip(r) {
                acc[k] += r[j + k] * y;
            }
        }
    }
    acc
}

/// [`partial_sums_rows4`] on AVX: one 4-lane register per row, each lane the scalar loop's
/// partial sum (the same multiplications and additions in the same order: no fused
/// multiply-add); four independent chains where one row's [`dot`](crate::dense::dot) waits
/// on its single register's additions.
#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
#[inline(always)]
pub(crate) fn partial_sums_rows4(full: usize, r: [&[f64]; 4], x: &[f64]) -> [[f64; 4]; 4] {
    use std::arch::x86_64::{__m256d, _mm256_storeu_pd};
    use std::arch::x86_64::{_mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_setzero_pd};
    assert!(full % 4 == 0 && full <= x.len() && r.iter().all(|v| full <= v.len()));
    // SAFETY: AVX is enabled at compile time (the cfg above); the intrinsic touches no
    // memory.
    let mut acc: [__m256d; 4] = [unsafe { _mm256_setzero_pd() }; 4];
    for j in (0..full).step_by(4) {
        // SAFETY: AVX is enabled at compile time (the cfg above); `j + 4 <= full` and
        // `full` is within `x` and every `r[i]` (asserted), so each unaligned load reads
        // four `f64` inside its slice.
        unsafe {
            let y = _mm256_loadu_pd(x.as_ptr().add(j));
            for (acc, r) in acc.iter_mut().zip(r) {
                let p = _mm256_loadu_pd(r.as_ptr().add(j));
                *acc = _mm256_add_pd(*acc, _mm256_mul_pd(p, y));
            }
        }
    }
    let mut out = [[0.0; 4]; 4];
    for (o, a) in out.iter_mut().zip(acc) {
        // SAFETY: `o` is four writable `f64`; the store is unaligned.
        unsafe { _mm256_storeu_pd(o.as_mut_ptr(), a) };
    }
    out
}

#[cfg(test)]
mod tests {
    use crate::dense::DenseLu;

    /// The fixed-width solves are the general loop's, bit for bit, for every width used.
    #[test]
    fn fixed_widths_are_the_general_loop_bit_for_bit() {
        let n = 9;
        let a: Vec<f64> = (0..n * n)
            .map(|k| ((k * 17 % 13) as f64 - 6.0) * 0.3 + if k % (n + 1) == 0 { 2.0 } else { 0.0 })
            .collect();
        let lu = DenseLu::factor(n, &a).expect("regular");
        for k in [1, 2, 3, 4, 6, 8] {
            let rhs: Vec<f64> = (0..n * k).map(|x| (x as f64 * 0.37).sin()).collect();
            let (mut fast, mut slow) = (rhs.clone(), rhs);
            let mut perm = vec![0.0; n * k];
            assert!(lu.solve_transpose_many(&mut fast, k, &mut perm));
            assert!(lu.solve_transpose_general(&mut slow, k, &mut perm));
            assert_eq!(fast, slow, "k = {k}");
        }
    }

    /// The fixed-size elimination is the general one's, bit for bit: pivoted, not pivoted,
    /// singular and tiny systems.
    #[test]
    fn fixed_elimination_is_the_general_one_bit_for_bit() {
        fn both<const N: usize>(a: [[f64; N]; N], b: [f64; N]) {
            let (mut m1, mut b1) = (a, b);
            let ok1 = super::eliminate_fixed(&mut m1, &mut b1);
            let (mut m2, mut b2) = (a.as_flattened().to_vec(), b.to_vec());
            let ok2 = crate::dense::eliminate(N, &mut m2, &mut b2);
            assert_eq!(ok1, ok2, "{a:?}");
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            if ok1 {
                assert_eq!(bits(m1.as_flattened()), bits(&m2), "{a:?}");
                assert_eq!(bits(&b1), bits(&b2), "{a:?}");
            }
        }
        for k in 0..200 {
            let x = |j: usize| {
                ((k * 31 + j * 17) as f64 * 0.731).sin() * 10f64.powi((j % 5) as i32 - 2)
            };
            both([[x(0), x(1)], [x(2), x(3)]], [x(4), -x(5)]);
            both([[1e-3 * x(0), x(1)], [x(2), x(3)]], [x(4), 0.0]);
            both(
                [[x(0), x(1), x(2)], [x(3), x(4), x(5)], [x(6), x(7), x(8)]],
                [x(9), x(10), -0.0],
            );
        }
        both([[0.0, 0.0], [0.0, 1.0]], [1.0, 1.0]);
        both([[1.0, 2.0], [2.0, 4.0]], [1.0, 1.0]);
        both([[f64::NAN, 1.0], [1.0, 1.0]], [1.0, 1.0]);
        both([[0.0, 1.0], [1.0, 0.0]], [-0.0, 0.0]);
    }

    /// On a column dominant matrix the factors without the pivot search are partial
    /// pivoting's, bit for bit; a matrix that is not dominant is still pivoted.
    #[test]
    fn dominant_matrices_skip_the_pivot_search_with_the_same_factors() {
        let n = 11;
        let mut a: Vec<f64> = (0..n * n)
            .map(|k| ((k * 29 % 17) as f64 - 8.0) * 0.05)
            .collect();
        for j in 0..n {
            a[j * n + j] = 3.0 + j as f64 * 0.1;
        }
        assert!(super::column_dominant(n, &a));
        let (mut pivoted, mut plain) = (DenseLu::default(), DenseLu::default());
        assert!(pivoted.refactor(n, &a) && plain.refactor_dominant(n, &a));
        let b: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
        let (mut x, mut y, mut work) = (b.clone(), b, vec![0.0; n]);
        assert!(pivoted.solve(&mut x, &mut work) && plain.solve(&mut y, &mut work));
        assert_eq!(x, y);
        // a zero diagonal: not dominant, pivoted, still solved
        a[0] = 0.0;
        assert!(!super::column_dominant(n, &a));
        assert!(plain.refactor_dominant(n, &a));
        let mut r = vec![1.0; n];
        assert!(plain.solve(&mut r, &mut work));
        let residual = (0..n)
            .map(|i| ((0..n).map(|j| a[i * n + j] * r[j]).sum::<f64>() - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(residual < 1e-12, "{residual}");
    }
}
