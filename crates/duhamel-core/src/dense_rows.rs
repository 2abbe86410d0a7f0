//! Products and substitutions four rows at a time, each row's sum [`dot`]'s bit for bit:
//! the rows' partial sums side by side ([`crate::dense_fixed::partial_sums_rows4`]), four
//! independent chains of additions where one row's `dot` waits on its own.

use crate::dense::dot;
use crate::dense_fixed as fixed;

/// `out = m x` for a row-major `m` of `out.len()` rows of `x.len()` columns, each entry
/// [`dot`]`(row, x)` bit for bit.
pub(crate) fn matvec(m: &[f64], x: &[f64], out: &mut [f64]) {
    if x.is_empty() {
        out.fill(0.0);
        return;
    }
    row_dots(m, x, out.len(), |i, s| out[i] = s);
}

/// `y -= m x` (`m` row-major, `y.len()` rows of `x.len()` columns), each row's product
/// [`dot`]`(row, x)` bit for bit: `y_i - dot(row_i, x)`.
pub(crate) fn sub_matvec(y: &mut [f64], m: &[f64], x: &[f64]) {
    if x.is_empty() {
        return;
    }
    row_dots(m, x, y.len(), |i, s| y[i] -= s);
}

/// `y += m x` as [`sub_matvec`]: `y_i + dot(row_i, x)`.
pub(crate) fn add_matvec(y: &mut [f64], m: &[f64], x: &[f64]) {
    if x.is_empty() {
        return;
    }
    row_dots(m, x, y.len(), |i, s| y[i] += s);
}

/// `put(i, dot(row_i, x))` for the `rows` rows of the row-major `m` (`x.len() > 0`
/// columns), four rows at a time.
#[inline(always)]
fn row_dots(m: &[f64], x: &[f64], rows: usize, mut put: impl FnMut(usize, f64)) {
    let n = x.len();
    let m = &m[..rows * n];
    let full = n - n % 4;
    let mut blocks = m.chunks_exact(4 * n);
    let mut i = 0;
    for block in &mut blocks {
        let r: [&[f64]; 4] = std::array::from_fn(|i| &block[i * n..(i + 1) * n]);
        let acc = fixed::partial_sums_rows4(full, r, x);
        for (acc, row) in acc.iter().zip(r) {
            let tail: f64 = row[full..].iter().zip(&x[full..]).map(|(a, b)| a * b).sum();
            put(i, (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail);
            i += 1;
        }
    }
    for row in blocks.remainder().chunks_exact(n) {
        put(i, dot(row, x));
        i += 1;
    }
}

/// The forward substitution `L y = b` in place of `work` (`L` the unit lower triangle of the
/// row-major `n x n` factors `lu`), each row `work[i] -= dot(&lu_i[..i], &work[..i])` bit
/// for bit: rows `i0 .. i0 + 4` (`i0` a multiple of four) share their `dot`'s full chunks
/// (the columns before `i0`, all known), summed side by side; then each row's tail in order.
pub(crate) fn forward(lu: &[f64], n: usize, work: &mut [f64]) {
    let blocks = n / 4;
    for b in 0..blocks {
        let i0 = 4 * b;
        let r: [&[f64]; 4] = std::array::from_fn(|k| &lu[(i0 + k) * n..(i0 + k) * n + i0]);
        let acc = fixed::partial_sums_rows4(i0, r, &work[..i0]);
        for (k, acc) in acc.iter().enumerate() {
            let i = i0 + k;
            let row = &lu[i * n + i0..i * n + i];
            let tail: f64 = row.iter().zip(&work[i0..i]).map(|(x, y)| x * y).sum();
            work[i] -= (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail;
        }
    }
    for i in 4 * blocks..n {
        let s = dot(&lu[i * n..i * n + i], &work[..i]);
        work[i] -= s;
    }
}

#[cfg(test)]
mod tests {
    use super::{add_matvec, dot, forward, matvec, sub_matvec};
    use crate::dense::DenseLu;

    fn value(i: usize, s: f64) -> f64 {
        ((i as f64 + s) * 0.7).sin() * 10f64.powi((i % 7) as i32 - 3)
    }

    #[test]
    fn sub_and_add_matvec_are_row_dots_bit_for_bit() {
        for rows in 0..11 {
            for n in 0..23 {
                let m: Vec<f64> = (0..rows * n).map(|i| value(i, 0.3)).collect();
                let x: Vec<f64> = (0..n).map(|i| value(i, 1.1)).collect();
                let y0: Vec<f64> = (0..rows).map(|i| value(i, 4.2)).collect();
                let (mut sub, mut add) = (y0.clone(), y0.clone());
                sub_matvec(&mut sub, &m, &x);
                add_matvec(&mut add, &m, &x);
                for i in 0..rows {
                    let (want_sub, want_add) = if n == 0 {
                        (y0[i], y0[i])
                    } else {
                        let d = dot(&m[i * n..(i + 1) * n], &x);
                        (y0[i] - d, y0[i] + d)
                    };
                    assert_eq!(sub[i].to_bits(), want_sub.to_bits(), "rows {rows}, n {n}");
                    assert_eq!(add[i].to_bits(), want_add.to_bits(), "rows {rows}, n {n}");
                }
            }
        }
    }

    #[test]
    fn matvec_is_row_dots_bit_for_bit() {
        for rows in 0..11 {
            for n in 0..23 {
                let m: Vec<f64> = (0..rows * n).map(|i| value(i, 0.1)).collect();
                let x: Vec<f64> = (0..n).map(|i| value(i, 2.9)).collect();
                let mut out = vec![f64::NAN; rows];
                matvec(&m, &x, &mut out);
                for (i, got) in out.iter().enumerate() {
                    let want = if n == 0 {
                        0.0
                    } else {
                        dot(&m[i * n..(i + 1) * n], &x)
                    };
                    assert_eq!(got.to_bits(), want.to_bits(), "rows {rows}, n {n}, row {i}");
                }
            }
        }
    }

    #[test]
    fn forward_is_row_dots_bit_for_bit() {
        for n in 0..40 {
            let lu: Vec<f64> = (0..n * n).map(|i| value(i, 0.4)).collect();
            let b: Vec<f64> = (0..n).map(|i| value(i, 1.7)).collect();
            let mut got = b.clone();
            forward(&lu, n, &mut got);
            let mut want = b;
            for i in 0..n {
                let s = dot(&lu[i * n..i * n + i], &want[..i]);
                want[i] -= s;
            }
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&got), bits(&want), "n = {n}");
        }
    }

    #[test]
    fn lu_solve_solves() {
        for n in [1, 4, 7, 33] {
            let mut a: Vec<f64> = (0..n * n).map(|k| value(k, 0.2)).collect();
            for i in 0..n {
                let row: f64 = a[i * n..(i + 1) * n].iter().map(|v| v.abs()).sum();
                a[i * n + i] = row + 1.0; // diagonally dominant: well conditioned
            }
            let mut lu = DenseLu::default();
            assert!(lu.refactor(n, &a));
            let b: Vec<f64> = (0..n).map(|i| value(i, 2.3)).collect();
            let (mut x, mut work) = (b.clone(), vec![0.0; n]);
            assert!(lu.solve(&mut x, &mut work));
            for (i, bi) in b.iter().enumerate() {
                let r: f64 = (0..n).map(|j| a[i * n + j] * x[j]).sum();
                assert!(
                    (r - bi).abs() <= 1e-12 * (1.0 + bi.abs()),
                    "n = {n}, row {i}"
                );
            }
        }
    }
}
