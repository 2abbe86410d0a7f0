//! Small dense linear solves for the Newton step equations (faer, partial pivoting LU).

use faer::linalg::solvers::Solve;
use faer::Mat;

/// Solves `a x = b` in place of `b` for a row-major `n x n` matrix `a`. Returns `false` when
/// the matrix is numerically singular (a zero or non-finite pivot).
pub fn solve_in_place(n: usize, a: &[f64], b: &mut [f64]) -> bool {
    debug_assert_eq!(a.len(), n * n);
    debug_assert_eq!(b.len(), n);
    if n == 1 {
        if a[0] == 0.0 || !a[0].is_finite() {
            return false;
        }
        b[0] /= a[0];
        return b[0].is_finite();
    }
    let m = Mat::from_fn(n, n, |i, j| a[i * n + j]);
    let lu = m.partial_piv_lu();
    let rhs = Mat::from_fn(n, 1, |i, _| b[i]);
    let x = lu.solve(&rhs);
    for (i, bi) in b.iter_mut().enumerate() {
        *bi = x[(i, 0)];
    }
    b.iter().all(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
