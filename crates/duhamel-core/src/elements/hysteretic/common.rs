//! What the device elements share: parameter checks, the two-node kinematics (relative
//! deformation, equal and opposite forces) and the non-finite guard.

use crate::error::CoreError;

pub(crate) use crate::elements::element::check;

/// The post-yield stiffness ratio: finite and `<= 1` (negative: softening).
pub(crate) fn check_alpha(alpha: f64) -> Result<(), CoreError> {
    if alpha.is_finite() && alpha <= 1.0 {
        Ok(())
    } else {
        Err(CoreError::InvalidInput {
            name: "alpha",
            problem: format!("must be finite and <= 1, got {alpha}"),
        })
    }
}

/// The local dofs `[i]` (grounded) or `[i, j]`.
pub(crate) fn local_dofs(i: usize, j: Option<usize>) -> Result<Vec<usize>, CoreError> {
    match j {
        None => Ok(vec![i]),
        Some(j) if j == i => Err(CoreError::InvalidInput {
            name: "j",
            problem: format!("must differ from i (both are {i}); use j=None to connect to ground"),
        }),
        Some(j) => Ok(vec![i, j]),
    }
}

/// `x_i - x_j` (`x_i` when grounded).
#[inline]
pub(crate) fn relative(x: &[f64]) -> f64 {
    x[0] - x.get(1).copied().unwrap_or(0.0)
}

/// Adds the element force `s` (`+s` on `i`, `-s` on `j`) into `r` and its derivative `ds`
/// with respect to the relative coordinate into the `n x n` matrix `m` (`n = 1` or `2`).
#[inline]
pub(crate) fn scatter(s: f64, ds: f64, r: &mut [f64], m: Option<&mut [f64]>) {
    let n = r.len();
    r[0] += s;
    if n == 2 {
        r[1] -= s;
    }
    if let Some(m) = m {
        m[0] += ds;
        if n == 2 {
            m[1] -= ds;
            m[2] -= ds;
            m[3] += ds;
        }
    }
}

/// `Ok` when all `values` are finite, else the run failure the driver locates.
#[inline]
pub(crate) fn finite(t: f64, values: &[f64]) -> Result<(), CoreError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(CoreError::NonFinite {
            time: t,
            step: 0,
            last_good_time: None,
        })
    }
}

/// The 4 x 4 system `a x = b` by Gaussian elimination with partial pivoting (`a`
/// nonsingular: the triple pendulum's symmetric positive definite Hessian).
pub(crate) fn solve4(mut a: [[f64; 4]; 4], mut b: [f64; 4]) -> [f64; 4] {
    for col in 0..4 {
        let p = (col..4)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap_or(col);
        a.swap(col, p);
        b.swap(col, p);
        let pivot = a[col];
        for row in col + 1..4 {
            let m = a[row][col] / pivot[col];
            for (v, p) in a[row][col..].iter_mut().zip(&pivot[col..]) {
                *v -= m * p;
            }
            b[row] -= m * b[col];
        }
    }
    let mut x = [0.0; 4];
    for row in (0..4).rev() {
        let s: f64 = (row + 1..4).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / a[row][row];
    }
    x
}
