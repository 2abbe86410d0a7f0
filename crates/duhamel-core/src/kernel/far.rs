//! The oscillator's step matrices when the step spans an astronomically large number of
//! periods (`h = omega dt > 1e50`): closed forms in the physical variables.
//!
//! The dimensionless kernel of [`super::oscillator`] works with `h^2` and its powers, which
//! overflow or underflow there (`(1, 0.1, 1e300)` needs `h^2 = 1e600`) although the matrices
//! themselves are ordinary numbers (the displacement response to a unit load is `1/omega^2`).
//! Here:
//!
//! * `A` comes from the eigen form: `e^{-zeta h}` with `cos` and `sin` of the damped phase
//!   (`|zeta| < 1`), or the two real exponentials (`|zeta| >= 1`);
//! * the moments from the polynomial particular solution: for the load `s^n` (`s = t/dt`),
//!   `x_p = (1/k) sum_j (-L)^j s^n` with `L = r1 d/ds + r2 d^2/ds^2`, `r1 = 2 zeta / h`,
//!   `r2 = 1/h^2`, and `M_n = y_p(dt) - A y_p(0)`.
//!
//! Both are well conditioned when `|zeta| < 1e-3 h` (then `r1`, `r2` are small and the slow
//! real eigenvalue, if any, decays by more than `e^-500` over the step); outside it the
//! dimensionless kernel is used.

/// Number of moments (`s^0 .. s^3`), as in [`super::oscillator::N_MOMENTS`].
const N_MOMENTS: usize = 4;

/// Smallest `h = omega dt` for the far evaluation.
const H_FAR: f64 = 1e50;

/// `A` and the moments (`m[r][n]`, row `r` of the response to `(t/dt)^n`), or None when the
/// step is not in the far regime.
pub(super) fn far(omega: f64, zeta: f64, dt: f64) -> Option<FarMatrices> {
    let h = omega * dt;
    // Written to be false for NaN as well.
    if !(h > H_FAR && zeta.abs() < 1e-3 * h) {
        return None;
    }
    let a = transition(omega, zeta, dt, h);
    let inv_omega = 1.0 / omega;
    let inv_k = inv_omega * inv_omega;
    // 1 / (k dt) = (1/omega) / h, without forming k dt.
    let inv_kdt = inv_omega / h;
    let (r1, r2) = (2.0 * zeta / h, (1.0 / h) * (1.0 / h));
    let column = |n: usize| {
        let p = particular(n, r1, r2);
        let (x0, x1) = (inv_k * p[0], inv_k * (p[0] + p[1] + p[2] + p[3]));
        let (v0, v1) = (inv_kdt * p[1], inv_kdt * (p[1] + 2.0 * p[2] + 3.0 * p[3]));
        [
            x1 - (a[0][0] * x0 + a[0][1] * v0),
            v1 - (a[1][0] * x0 + a[1][1] * v0),
        ]
    };
    let cols: [[f64; 2]; N_MOMENTS] = std::array::from_fn(column);
    let m = [cols.map(|c| c[0]), cols.map(|c| c[1])];
    Some(FarMatrices { a, m })
}

/// The transition matrix and the moments of a far step.
pub(super) struct FarMatrices {
    pub a: [[f64; 2]; 2],
    pub m: [[f64; N_MOMENTS]; 2],
}

/// `A(dt)` from the eigen form.
fn transition(omega: f64, zeta: f64, dt: f64, h: f64) -> [[f64; 2]; 2] {
    if zeta.abs() < 1.0 {
        let q = ((1.0 - zeta) * (1.0 + zeta)).sqrt();
        let e = (-zeta * h).exp();
        let (sin, cos) = (h * q).sin_cos();
        let r = zeta / q;
        return [
            [e * (cos + r * sin), e * sin / q * (1.0 / omega)],
            [-(e * sin / q) * omega, e * (cos - r * sin)],
        ];
    }
    // Real eigenvalues z_big, z_small (per step) with z_big z_small = h^2.
    let s = zeta.abs() * ((1.0 - 1.0 / zeta.abs()) * (1.0 + 1.0 / zeta.abs())).sqrt();
    let sum = zeta + zeta.signum() * s;
    let (z_big, z_small) = (-h * sum, -h / sum);
    let (e_big, e_small) = (z_big.exp(), z_small.exp());
    if e_big == 0.0 && e_small == 0.0 {
        // Both decay below the double range (this includes critical damping, z_big = z_small).
        return [[0.0; 2]; 2];
    }
    let dz = z_big - z_small;
    [
        [
            (z_big * e_small - z_small * e_big) / dz,
            dt * ((e_big - e_small) / dz),
        ],
        [
            -omega * (h / dz) * (e_big - e_small),
            (z_big * e_big - z_small * e_small) / dz,
        ],
    ]
}

/// Coefficients (of `1, s, s^2, s^3`) of `sum_j (-L)^j s^n`, `L p = r1 p' + r2 p''`.
fn particular(n: usize, r1: f64, r2: f64) -> [f64; N_MOMENTS] {
    let mut term = [0.0; N_MOMENTS];
    term[n] = 1.0;
    let mut total = term;
    for _ in 0..n {
        let mut next = [0.0; N_MOMENTS];
        for (i, slot) in next.iter_mut().enumerate() {
            let d1 = if i + 1 < N_MOMENTS {
                (i + 1) as f64 * term[i + 1]
            } else {
                0.0
            };
            let d2 = if i + 2 < N_MOMENTS {
                ((i + 2) * (i + 1)) as f64 * term[i + 2]
            } else {
                0.0
            };
            *slot = -(r1 * d1 + r2 * d2);
        }
        term = next;
        for (t, x) in total.iter_mut().zip(term) {
            *t += x;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn particular_solution_satisfies_the_equation() {
        // (1 + L) P = s^n coefficient by coefficient, L P = r1 P' + r2 P''.
        let (r1, r2) = (0.3, 0.07);
        for n in 0..N_MOMENTS {
            let p = particular(n, r1, r2);
            for i in 0..N_MOMENTS {
                let d1 = if i + 1 < N_MOMENTS {
                    (i + 1) as f64 * p[i + 1]
                } else {
                    0.0
                };
                let d2 = if i + 2 < N_MOMENTS {
                    ((i + 2) * (i + 1)) as f64 * p[i + 2]
                } else {
                    0.0
                };
                let lhs = p[i] + r1 * d1 + r2 * d2;
                let rhs = if i == n { 1.0 } else { 0.0 };
                assert!((lhs - rhs).abs() < 1e-15, "n={n} i={i}: {lhs}");
            }
        }
    }

    #[test]
    fn undamped_far_step_is_the_closed_form() {
        let (omega, dt) = (1e60, 1.0);
        let f = far(omega, 0.0, dt).expect("far regime");
        let h: f64 = omega * dt;
        assert_eq!(f.a[0][0], h.cos());
        assert!((f.a[1][0] + omega * h.sin()).abs() <= 1e-15 * omega);
        // step response (1 - cos h) / omega^2
        let x = (1.0 - h.cos()) / (omega * omega);
        assert!((f.m[0][0] - x).abs() <= 1e-15 * x.abs());
        assert!(far(1.0, 0.0, 1.0).is_none() && far(1e60, 1e58, 1.0).is_none());
    }
}
