//! Exponential-integrator functions of a complex argument, for first-order (complex) modes.
//!
//! `phi_0(z) = e^z`, `phi_{j+1}(z) = (phi_j(z) - 1/j!) / z`, i.e.
//! `phi_j(z) = sum_n z^n / (n + j)!`. A first-order mode `eta' = lambda eta + u(t)` over a
//! step `h` responds to the load `u = (s/h)^k` (`s` the time into the step) from rest with
//! `h k! phi_{k+1}(lambda h)`.

use num_complex::Complex64;

/// Below this modulus the Taylor series is summed; above it the upward recurrence (which
/// then loses at most a few units of round-off per level) is used.
const TAYLOR_BELOW: f64 = 1.5;
/// Taylor terms: `1.5^32 / 32!` is far below the unit round-off.
const TERMS: usize = 32;

/// `1/n!` for `n = 0..TERMS + 4`.
fn inv_factorial(n: usize) -> f64 {
    (1..=n).fold(1.0, |acc, k| acc / k as f64)
}

/// `phi_0(z) .. phi_3(z)`.
pub fn phis(z: Complex64) -> [Complex64; 4] {
    let e = z.exp();
    if z.norm() < TAYLOR_BELOW {
        let mut out = [e; 4];
        for (j, slot) in out.iter_mut().enumerate().skip(1) {
            // Horner on sum_n z^n / (n + j)!.
            let mut acc = Complex64::new(inv_factorial(TERMS + j), 0.0);
            for n in (0..TERMS).rev() {
                acc = acc * z + inv_factorial(n + j);
            }
            *slot = acc;
        }
        out
    } else {
        let p1 = (e - 1.0) / z;
        let p2 = (p1 - 1.0) / z;
        let p3 = (p2 - 0.5) / z;
        [e, p1, p2, p3]
    }
}

/// Response at the end of a step `h` of `eta' = lambda eta + u` from rest to the load
/// `u(s) = (s/h)^k`, `k = 0, 1, 2`: `h k! phi_{k+1}(lambda h)`.
pub fn moments(lambda: Complex64, h: f64) -> [Complex64; 3] {
    let p = phis(lambda * h);
    [p[1] * h, p[2] * h, p[3] * (2.0 * h)]
}

/// Response at the end of a step `h` to the load `p0 + Dp s + 4 DDp s (1 - s)`, `s = t/h`
/// (the paper's basis, see `Transfer::b`): the weights of `(p0, Dp, DDp)`.
pub fn basis_weights(lambda: Complex64, h: f64) -> [Complex64; 3] {
    let m = moments(lambda, h);
    [m[0], m[1], (m[1] - m[2]) * 4.0]
}

/// Response at the end of an interval `rest` to the load `j0 + j1 s + j2 s^2` started at its
/// beginning (`s` the time since then): `sum_k j_k rest^k (response to (s/rest)^k)`.
pub fn polynomial_response(lambda: Complex64, rest: f64, j: [f64; 3]) -> Complex64 {
    let m = moments(lambda, rest);
    m[0] * j[0] + m[1] * (j[1] * rest) + m[2] * (j[2] * rest * rest)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `phi_j` by the integral `int_0^1 e^{z (1 - s)} s^(j-1) / (j-1)! ds`, Gauss–Legendre on
    /// many panels (smooth integrand: converged to round-off).
    fn phi_quadrature(z: Complex64, j: usize) -> Complex64 {
        let nodes = [
            (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
            (-0.538_469_310_105_683, 0.478_628_670_499_366_5),
            (0.0, 0.568_888_888_888_888_9),
            (0.538_469_310_105_683, 0.478_628_670_499_366_5),
            (0.906_179_845_938_664, 0.236_926_885_056_189_1),
        ];
        let panels = 400 * (z.norm() as usize / 10).max(1);
        let mut acc = Complex64::new(0.0, 0.0);
        for p in 0..panels {
            let (a, b) = (p as f64 / panels as f64, (p + 1) as f64 / panels as f64);
            for &(x, w) in &nodes {
                let s = 0.5 * (a + b) + 0.5 * (b - a) * x;
                let f = (z * (1.0 - s)).exp() * s.powi(j as i32 - 1) * inv_factorial(j - 1);
                acc += f * (0.5 * (b - a) * w);
            }
        }
        acc
    }

    #[test]
    fn phis_match_their_integrals_across_the_switch() {
        let zs = [
            Complex64::new(1e-9, 0.0),
            Complex64::new(-0.3, 1.1),
            Complex64::new(1.49, 0.0),
            Complex64::new(1.51, 0.0),
            Complex64::new(-1.2, -0.9),
            Complex64::new(0.0, 2.0),
            Complex64::new(-8.0, 30.0),
            Complex64::new(-400.0, 0.0),
            Complex64::new(3.0, -5.0),
        ];
        for z in zs {
            let p = phis(z);
            for (j, pj) in p.iter().enumerate().skip(1) {
                let q = phi_quadrature(z, j);
                let err = (pj - q).norm() / q.norm();
                assert!(err < 2e-14, "phi_{j}({z}) = {pj} vs {q}: {err:e}");
            }
        }
    }

    #[test]
    fn recurrence_holds() {
        for z in [Complex64::new(0.7, -0.2), Complex64::new(5.0, 5.0)] {
            let p = phis(z);
            assert!((p[0] - (1.0 + z * p[1])).norm() < 1e-14 * p[0].norm().max(1.0));
            assert!((p[1] - (1.0 + z * p[2])).norm() < 1e-14 * p[1].norm().max(1.0));
            assert!((p[2] - (0.5 + z * p[3])).norm() < 1e-14 * p[2].norm().max(1.0));
        }
    }
}
