//! Exact transition and load-transfer matrices of one modal oscillator.
//!
//! The oscillator is `x'' + c x' + k x = p(t)` per unit modal mass (`c = 2 zeta omega`,
//! `k = omega^2`). Over a step `dt` the state `y = (x, x')` obeys Duhamel's integral
//!
//! ```text
//! y(dt) = A y(0) + integral_0^dt A(dt - tau) (0, p(tau)) dtau
//! ```
//!
//! [`Transfer`] holds `A` and the moments `M_k = integral_0^dt A(dt - tau) e2 (tau/dt)^k dtau`
//! for `k = 0..=3`, so that any load that is a cubic polynomial in time over the step is
//! integrated exactly. The paper's load-transfer matrix `B` for the basis
//! `(p0, Dp, DDp)` (parabola through start, middle and end values) is built from them.
//!
//! # Evaluation
//!
//! In the time unit `dt` the oscillator is `X'' + 2a X' + h^2 X = s^k`, with `h^2 = k dt^2`
//! and `a = c dt / 2`; its eigenvalues are `z = -a +- sqrt(a^2 - h^2)`. Every entry is a
//! divided difference over the two eigenvalues of the exponential-integrator functions
//! `phi_j(z) = sum_n z^n / (n + j)!`:
//!
//! * `A = [[M0 + a D0, D0], [-h^2 D0, M0 - a D0]]`, with `D0 = phi_0[z1, z2]` and
//!   `M0 = (e^z1 + e^z2) / 2`;
//! * the displacement moment of `s^k` is `k! phi_{k+1}[z1, z2]`, the velocity moment is
//!   `phi_0[z1, z2]` for `k = 0` and `k` times the displacement moment of `s^(k-1)` otherwise
//!   (integration by parts).
//!
//! Three evaluations keep the error at round-off in every regime (negative, zero, light,
//! critical, heavy damping; rigid-body modes `k = 0`; `h` from 1e-8 to 1e3):
//!
//! 1. both `|z| <= 1.5`: Taylor series in real arithmetic (power sums and complete symmetric
//!    polynomials of the eigenvalues, so complex and coincident eigenvalues need no special
//!    case); exact at `k = 0`;
//! 2. both `|z| >= 1`: upward recurrence `z phi_{j+1} = phi_j - 1/j!` written on the pair
//!    (mean, divided difference) in real arithmetic — stable for large `|z|`, and free of
//!    `0/0` at critical damping;
//! 3. otherwise (real, well separated eigenvalues: one small, one large) each `phi_j` is
//!    evaluated on its own (series or recurrence) and the divided difference is formed
//!    directly; the eigenvalues differ by more than 0.5, so nothing cancels.
//!
//! `a^2 - h^2` is formed with a fused multiply-add and the small real eigenvalue as
//! `h^2 / z_big`, which removes the cancellations near critical and heavy damping.

use super::far::far;

/// `1/n!` for `n = 0..40`.
const INV_FACT: [f64; 40] = inv_factorials();

const fn inv_factorials() -> [f64; 40] {
    let mut out = [0.0; 40];
    let mut f = 1.0;
    let mut n = 0;
    while n < 40 {
        if n > 0 {
            f *= n as f64;
        }
        out[n] = 1.0 / f;
        n += 1;
    }
    out
}

/// Largest eigenvalue modulus for which the Taylor series is used.
const R_SERIES: f64 = 1.5;
/// Smallest eigenvalue modulus for which the upward recurrence is used.
const R_UPWARD: f64 = 1.0;
/// Number of Taylor terms; `1.5^34 / 34!` is far below the unit round-off.
const N_TERMS: usize = 34;
/// Number of moments (`s^0 .. s^3`).
pub const N_MOMENTS: usize = 4;

/// Exact step matrices of one modal oscillator for one step length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transfer {
    /// Transition matrix `A(dt)`, acting on `(x, x')`.
    pub a: [[f64; 2]; 2],
    /// `m[r][k]`: row `r` (0 displacement, 1 velocity) of the response at `dt` to the load
    /// `(tau/dt)^k`, `k = 0..=3`, from rest.
    pub m: [[f64; N_MOMENTS]; 2],
    /// `A[0][0] - 1` and `A[1][1] - 1`, each to round-off of its own size (the steps take
    /// the state's increment from them: `x + ((A00 - 1) x + A01 x' + ...)` rounds at the
    /// increment's scale, where `A00 x + ...` rounds at the state's on every step and, with
    /// many short steps, drifts: `pseudo::rows`).
    pub a_less_one: [f64; 2],
}

impl Transfer {
    /// Whether every entry is finite (the evaluation can overflow for extreme `k dt^2` or
    /// `c dt`, e.g. a strongly negative damping whose growth over the step overflows).
    pub fn is_finite(&self) -> bool {
        let a = self.a.iter().flatten();
        a.chain(self.m.iter().flatten()).all(|x| x.is_finite())
    }

    /// Exact matrices of `x'' + c x' + k x = p(t)` over a step `dt`.
    ///
    /// `k >= 0` is the modal stiffness `omega^2`, `c` the modal damping `2 zeta omega` (any
    /// sign), both per unit modal mass; `dt > 0`. `a^2 - h^2` is formed from error-free
    /// products, so near-critical damping loses nothing to the rounding of `k dt^2`.
    ///
    /// `k = +inf` marks a coordinate without modal mass (a massless dof's static or
    /// first-order coordinate, unit stiffness): `c x' + x = p(t)`, `c >= 0` its time constant
    /// ([`super::relaxation`]).
    pub fn new(k: f64, c: f64, dt: f64) -> Self {
        if k == f64::INFINITY {
            return super::relaxation::transfer(c, dt);
        }
        if k > 0.0 {
            let omega = k.sqrt();
            if let Some(far) = far(omega, c / (2.0 * omega), dt) {
                return Transfer::far(far.a, far.m);
            }
        }
        // a = c dt / 2 and hh = k dt^2 as unevaluated sums (hi + lo).
        let (a, a_lo) = two_prod(0.5 * c, dt);
        let (p, p_lo) = two_prod(k, dt);
        let (hh, hh_lo) = two_prod(p, dt);
        let hh_lo = hh_lo + p_lo * dt;
        let (aa, aa_lo) = two_prod(a, a);
        let delta = (aa - hh) + (aa_lo + 2.0 * a * a_lo - hh_lo);
        Self::from_scaled(hh, a, delta, dt)
    }

    /// Exact matrices for a natural frequency `omega >= 0` (rad/s) and damping ratio `zeta`.
    ///
    /// `a^2 - h^2 = (zeta - 1)(zeta + 1) h^2` is exact to a few roundings near `zeta = 1`.
    pub fn from_omega_zeta(omega: f64, zeta: f64, dt: f64) -> Self {
        if let Some(far) = far(omega, zeta, dt) {
            return Transfer::far(far.a, far.m);
        }
        let h = omega * dt;
        let hh = h * h;
        Self::from_scaled(hh, zeta * h, (zeta - 1.0) * (zeta + 1.0) * hh, dt)
    }

    /// From the dimensionless `h^2`, `a` and `delta = a^2 - h^2`.
    fn from_scaled(hh: f64, a: f64, delta: f64, dt: f64) -> Self {
        let Kernel { a11, a22, d } = kernel(hh, a, delta);
        let d0 = d[0];
        let mut disp = [0.0; N_MOMENTS];
        let mut fact = 1.0;
        for (kk, slot) in disp.iter_mut().enumerate() {
            if kk > 0 {
                fact *= kk as f64;
            }
            *slot = fact * d[kk + 1];
        }
        let mut vel = [0.0; N_MOMENTS];
        vel[0] = d0;
        for kk in 1..N_MOMENTS {
            vel[kk] = kk as f64 * disp[kk - 1];
        }
        let dt2 = dt * dt;
        // From rest under the constant load `h^2`, `1 - x_free` with `x_free(0) = 1`:
        // `A00 - 1 = -h^2 M00`; and `A11 = x''(1)` of the response to `v(0) = 1`, which is the
        // derivative of the constant load's response: `A11 - 1 = -h^2 M00 - 2 a M10`.
        let less00 = -hh * d[1];
        Transfer {
            a: [[a11, d0 * dt], [-hh * d0 / dt, a22]],
            m: [disp.map(|v| v * dt2), vel.map(|v| v * dt)],
            a_less_one: [less00, less00 - 2.0 * a * d0],
        }
    }

    /// A far step's matrices (no cancellation in `A - 1` there: `A` is not near `1`).
    fn far(a: [[f64; 2]; 2], m: [[f64; N_MOMENTS]; 2]) -> Self {
        Transfer {
            a,
            m,
            a_less_one: [a[0][0] - 1.0, a[1][1] - 1.0],
        }
    }

    /// Load-transfer matrix `B` for the paper's basis `(p0, Dp, DDp)`, with the load over the
    /// step `p(s dt) = p0 + Dp s + 4 DDp s (1 - s)`.
    pub fn b(&self) -> [[f64; 3]; 2] {
        let row = |r: usize| {
            let m = &self.m[r];
            [m[0], m[1], 4.0 * (m[1] - m[2])]
        };
        [row(0), row(1)]
    }
}

/// `x * y` as `hi + lo` exactly (fused multiply-add).
fn two_prod(x: f64, y: f64) -> (f64, f64) {
    let hi = x * y;
    (hi, x.mul_add(y, -hi))
}

/// Dimensionless step quantities: the diagonal of `A` and `D[j] = phi_j[z1, z2]`, `j = 0..=4`.
struct Kernel {
    a11: f64,
    a22: f64,
    d: [f64; 5],
}

impl Kernel {
    /// Diagonal of `A` from `mean0 = (e^z1 + e^z2)/2`: `mean0 +- a D0`.
    fn from_mean(mean0: f64, a: f64, d: [f64; 5]) -> Self {
        Kernel {
            a11: mean0 + a * d[0],
            a22: mean0 - a * d[0],
            d,
        }
    }

    /// Diagonal of `A` for distinct real eigenvalues, in the eigen form that does not cancel
    /// when one exponential is negligible (`mean0 - a D0` would).
    fn from_real(z1: f64, z2: f64, d: [f64; 5]) -> Self {
        let (e1, e2) = (z1.exp(), z2.exp());
        let dz = z1 - z2;
        Kernel {
            a11: (z1 * e2 - z2 * e1) / dz,
            a22: (z1 * e1 - z2 * e2) / dz,
            d,
        }
    }
}

/// The kernel for `X'' + 2a X' + hh X`, with `delta = a^2 - hh` supplied accurately.
fn kernel(hh: f64, a: f64, delta: f64) -> Kernel {
    // `a^2` overflowed while `hh` did not: the eigenvalues are real and far apart, and
    // `sqrt(delta) = |a| sqrt((1 - h/|a|)(1 + h/|a|))` is still a number.
    let (delta, root) = if delta.is_finite() || !(a.is_finite() && hh.is_finite()) {
        (delta, delta.sqrt())
    } else {
        let r = hh.sqrt() / a.abs();
        (f64::INFINITY, a.abs() * ((1.0 - r) * (1.0 + r)).sqrt())
    };
    if delta > 0.0 {
        // Real eigenvalues; a != 0 here since hh >= 0.
        let d = root;
        let z_big = -a - a.signum() * d;
        let z_small = hh / z_big;
        let (big, small) = (z_big.abs(), z_small.abs());
        if big <= R_SERIES {
            let (mean0, dd) = series(hh, a);
            Kernel::from_mean(mean0, a, dd)
        } else if small >= R_UPWARD {
            let (mean0, dd) = upward(hh, a, delta, Some((z_big, z_small)));
            if delta >= 1.0 {
                Kernel::from_real(z_big, z_small, dd)
            } else {
                Kernel::from_mean(mean0, a, dd)
            }
        } else {
            Kernel::from_real(z_big, z_small, separated(z_big, z_small))
        }
    } else {
        // Complex (or coincident) eigenvalues of modulus h.
        let (mean0, dd) = if hh.sqrt() <= R_SERIES {
            series(hh, a)
        } else {
            upward(hh, a, delta, None)
        };
        Kernel::from_mean(mean0, a, dd)
    }
}

/// Taylor series in real arithmetic: power sums `s_n = (z1^n + z2^n)/2` and complete
/// symmetric polynomials `p_n = sum_i z1^i z2^(n-i)` from `e1 = z1 + z2 = -2a`,
/// `e2 = z1 z2 = hh`.
fn series(hh: f64, a: f64) -> (f64, [f64; 5]) {
    let e1 = -2.0 * a;
    let (mut s_prev, mut s) = (1.0, -a); // s_0, s_1
    let (mut p_prev, mut p) = (0.0, 1.0); // p_{-1}, p_0
    let mut mean0 = 1.0 + s; // n = 0, 1
    let mut d = [0.0; 5];
    for n in 1..N_TERMS {
        // term p_{n-1} / (n + j)!
        for (j, dj) in d.iter_mut().enumerate() {
            *dj += p * INV_FACT[n + j];
        }
        let s_next = e1 * s - hh * s_prev;
        let p_next = e1 * p - hh * p_prev;
        (s_prev, s) = (s, s_next);
        (p_prev, p) = (p, p_next);
        if n + 1 < N_TERMS {
            mean0 += s * INV_FACT[n + 1];
        }
    }
    (mean0, d)
}

/// `C = cosh(sqrt(delta))`, `S = sinh(sqrt(delta))/sqrt(delta)`: entire functions of `delta`
/// (for `delta < 0` they are `cos` and `sin(b)/b` with `b = sqrt(-delta)`).
fn cosh_sinhc(delta: f64) -> (f64, f64) {
    if delta.abs() < 1e-2 {
        let (mut c, mut s, mut t) = (0.0, 0.0, 1.0);
        for n in 0..10 {
            c += t * INV_FACT[2 * n];
            s += t * INV_FACT[2 * n + 1];
            t *= delta;
        }
        (c, s)
    } else if delta > 0.0 {
        let d = delta.sqrt();
        (d.cosh(), d.sinh() / d)
    } else {
        let b = (-delta).sqrt();
        (b.cos(), b.sin() / b)
    }
}

/// Upward recurrence on (mean, divided difference), stable when both `|z| >= 1`.
fn upward(hh: f64, a: f64, delta: f64, real: Option<(f64, f64)>) -> (f64, [f64; 5]) {
    let (mean0, d0) = match real {
        Some((z_big, z_small)) if delta >= 1.0 => {
            // Separated real exponentials: no overflow of cosh/sinh, no cancellation.
            let (eb, es) = (z_big.exp(), z_small.exp());
            (0.5 * (eb + es), (eb - es) / (z_big - z_small))
        }
        _ => {
            let (c, s) = cosh_sinhc(delta);
            let e = (-a).exp();
            (e * c, e * s)
        }
    };
    let m = -a;
    let mut d = [d0, 0.0, 0.0, 0.0, 0.0];
    let mut mean = mean0;
    for j in 0..4 {
        // (mean_j, D_j) = [[m, delta], [1, m]] (mean_{j+1}, D_{j+1}) + (1/j!, 0)
        let x = mean - INV_FACT[j];
        let next_mean = (m * x - delta * d[j]) / hh;
        d[j + 1] = (m * d[j] - x) / hh;
        mean = next_mean;
    }
    (mean0, d)
}

/// `phi_0..phi_4` at one real point `z`, by series for `|z| < 1` and by the
/// upward recurrence otherwise.
pub(super) fn phi_point(z: f64) -> [f64; 5] {
    let mut out = [0.0; 5];
    if z.abs() < R_UPWARD {
        for (j, o) in out.iter_mut().enumerate() {
            let mut t = 1.0;
            let mut acc = 0.0;
            for n in 0..30 {
                acc += t * INV_FACT[n + j];
                t *= z;
            }
            *o = acc;
        }
    } else {
        out[0] = z.exp();
        out[1] = z.exp_m1() / z;
        for j in 1..4 {
            out[j + 1] = (out[j] - INV_FACT[j]) / z;
        }
    }
    out
}

/// Divided differences for real eigenvalues that are far apart (one small, one large).
fn separated(z_big: f64, z_small: f64) -> [f64; 5] {
    let pb = phi_point(z_big);
    let ps = phi_point(z_small);
    let dz = z_big - z_small;
    let mut d = [0.0; 5];
    for j in 0..5 {
        d[j] = (pb[j] - ps[j]) / dz;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    #[test]
    fn rigid_body_mode_is_exact() {
        let dt = 0.37;
        let t = Transfer::new(0.0, 0.0, dt);
        assert_eq!(t.a, [[1.0, dt], [0.0, 1.0]]);
        let b = t.b();
        let expect = [
            [dt * dt / 2.0, dt * dt / 6.0, dt * dt / 3.0],
            [dt, dt / 2.0, 2.0 * dt / 3.0],
        ];
        for r in 0..2 {
            for c in 0..3 {
                assert!(close(b[r][c], expect[r][c], 1e-15), "{r} {c}");
            }
        }
    }

    #[test]
    fn undamped_closed_form() {
        for &(w, dt) in &[(1.0, 0.1), (3.0, 0.9), (10.0, 7.3), (2.0, 400.0)] {
            let t = Transfer::from_omega_zeta(w, 0.0, dt);
            let h: f64 = w * dt;
            let tol = 1e-14 * (1.0 + h);
            assert!(close(t.a[0][0], h.cos(), tol));
            assert!(close(t.a[0][1] * w, h.sin(), tol));
            assert!(close(t.a[1][0] / w, -h.sin(), tol));
            // step response x = (1 - cos h)/w^2
            assert!(close(t.m[0][0] * w * w, 1.0 - h.cos(), tol));
        }
    }

    #[test]
    fn critical_damping_has_no_zero_over_zero() {
        for &h in &[1e-8, 1e-3, 0.5, 1.2, 3.0, 50.0, 700.0] {
            let t = Transfer::from_omega_zeta(1.0, 1.0, h);
            let e = (-h).exp();
            assert!(close(t.a[0][0], e * (1.0 + h), 1e-13), "h={h}");
            assert!(close(t.a[0][1], e * h, 1e-13), "h={h}");
            assert!(t.m.iter().flatten().all(|v| v.is_finite()));
        }
    }

    #[test]
    fn heavy_damping_matches_exponentials() {
        // zeta = 5/4 gives z = -0.5 h and -2 h exactly.
        for &h in &[0.01, 0.4, 0.9, 2.0, 40.0] {
            let t = Transfer::from_omega_zeta(1.0, 1.25, h);
            let (z1, z2): (f64, f64) = (-0.5 * h, -2.0 * h);
            let a11 = (z1 * z2.exp() - z2 * z1.exp()) / (z1 - z2);
            assert!(close(t.a[0][0], a11, 1e-14), "h={h}");
        }
    }

    /// `sum_{n >= n0} sign(n) coef(n) h^n / n!`, summed smallest first.
    fn series(h: f64, n0: i32, coef: impl Fn(i32) -> f64) -> f64 {
        let term = |n: i32| coef(n) * (-h).powi(n) / (1..=n).map(f64::from).product::<f64>();
        (n0..40).rev().map(term).sum()
    }

    #[test]
    fn diagonal_less_one_keeps_its_own_digits() {
        // undamped: A00 - 1 = A11 - 1 = cos h - 1 = -2 sin^2(h/2)
        for &h in &[1e-7, 1e-4, 1e-2, 0.3, 2.0, 40.0] {
            let t = Transfer::from_omega_zeta(1.0, 0.0, h);
            let want = -2.0 * (0.5 * h).sin().powi(2);
            for v in t.a_less_one {
                assert!((v - want).abs() <= 4e-15 * want.abs(), "h={h}: {v} {want}");
            }
        }
        // critical damping: A00 = e^-h (1 + h), A11 = e^-h (1 - h), by their series
        for &h in &[1e-6, 1e-3, 0.1, 0.9] {
            let t = Transfer::from_omega_zeta(1.0, 1.0, h);
            let want = [
                series(h, 2, |n| f64::from(1 - n)),
                series(h, 1, |n| f64::from(1 + n)),
            ];
            for (v, w) in t.a_less_one.iter().zip(want) {
                assert!((v - w).abs() <= 1e-14 * w.abs(), "h={h}: {v} {w}");
            }
        }
        // a step long enough that the subtraction loses nothing
        let t = Transfer::new(3.0, 0.4, 0.7);
        assert!((t.a_less_one[0] - (t.a[0][0] - 1.0)).abs() <= 1e-15);
        assert!((t.a_less_one[1] - (t.a[1][1] - 1.0)).abs() <= 1e-15);
        // a first-order coordinate: e^(-dt/c) - 1
        let t = Transfer::new(f64::INFINITY, 0.5, 1e-6);
        let want = (-2e-6f64).exp_m1();
        assert!((t.a_less_one[0] - want).abs() <= 1e-15 * want.abs());
    }
}
