//! Cubic polynomials in one variable, for the closed-form single-mode step.

use crate::elements::ModalCubic;

/// `c[0] + c[1] u + c[2] u^2 + c[3] u^3`.
pub type CubicPoly = [f64; 4];

/// Product of two cubics, truncated at degree 3 (exact when the true degree is <= 3).
fn mul(a: &CubicPoly, b: &CubicPoly) -> CubicPoly {
    let mut c = [0.0; 4];
    for i in 0..4 {
        for j in 0..4 - i {
            c[i + j] += a[i] * b[j];
        }
    }
    c
}

/// `rho(q(u), v(u))` for `rho = sum a[i][j] q^i v^j` and affine `q = qa + qb u`,
/// `v = va + vb u`; only the powers that non-zero coefficients need are formed.
pub fn compose(a: &ModalCubic, q: [f64; 2], v: [f64; 2]) -> CubicPoly {
    let (qi_max, vj_max) = degrees(a);
    let mut qp = [[1.0, 0.0, 0.0, 0.0]; 4];
    let mut vp = [[1.0, 0.0, 0.0, 0.0]; 4];
    let (q1, v1) = ([q[0], q[1], 0.0, 0.0], [v[0], v[1], 0.0, 0.0]);
    for k in 1..=qi_max {
        qp[k] = mul(&qp[k - 1], &q1);
    }
    for k in 1..=vj_max {
        vp[k] = mul(&vp[k - 1], &v1);
    }
    let mut out = [0.0; 4];
    for (i, row) in a.iter().enumerate() {
        for (j, &aij) in row.iter().enumerate().take(4 - i) {
            if aij != 0.0 {
                let term = if j == 0 {
                    qp[i]
                } else if i == 0 {
                    vp[j]
                } else {
                    mul(&qp[i], &vp[j])
                };
                for (o, t) in out.iter_mut().zip(&term) {
                    *o += aij * t;
                }
            }
        }
    }
    out
}

/// Highest powers of `q` and of `v` with a non-zero coefficient.
fn degrees(a: &ModalCubic) -> (usize, usize) {
    let mut d = (0, 0);
    for (i, row) in a.iter().enumerate() {
        for (j, &aij) in row.iter().enumerate().take(4 - i) {
            if aij != 0.0 {
                d = (d.0.max(i), d.1.max(j));
            }
        }
    }
    d
}

/// Value at `u` (Horner).
pub fn eval(c: &CubicPoly, u: f64) -> f64 {
    ((c[3] * u + c[2]) * u + c[1]) * u + c[0]
}

/// The cubic in `d` of `c(u0 + h d)` (Taylor shift), so that roots near `u0` are found on a
/// well-scaled polynomial.
pub fn shift(c: &CubicPoly, u0: f64, h: f64) -> CubicPoly {
    let d1 = (3.0 * c[3] * u0 + 2.0 * c[2]) * u0 + c[1];
    let d2 = 3.0 * c[3] * u0 + c[2];
    [eval(c, u0), d1 * h, d2 * h * h, c[3] * h * h * h]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn composition_and_shift() {
        // rho = 2 q^3 + 0.5 q v - v, q = 1 + 2u, v = -1 + u
        let mut a = [[0.0; 4]; 4];
        a[3][0] = 2.0;
        a[1][1] = 0.5;
        a[0][1] = -1.0;
        let c = compose(&a, [1.0, 2.0], [-1.0, 1.0]);
        for u in [-1.3, 0.0, 0.4, 2.0] {
            let (q, v) = (1.0 + 2.0 * u, -1.0 + u);
            let want = 2.0 * q * q * q + 0.5 * q * v - v;
            assert!((eval(&c, u) - want).abs() < 1e-12 * (1.0 + want.abs()));
            let s = shift(&c, 0.3, 0.7);
            let d = (u - 0.3) / 0.7;
            assert!((eval(&s, d) - want).abs() < 1e-12 * (1.0 + want.abs()));
        }
    }
}
