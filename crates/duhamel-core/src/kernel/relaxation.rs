//! The exact step of a coordinate without mass: `c x' + x = p(t)` (unit stiffness).
//!
//! A massless dof that damping reaches is first-order (docs/basis.md, "Massless dofs"): in
//! its K-orthonormal coordinate it relaxes towards the load with the time constant `c > 0`;
//! `c = 0` is a static coordinate, `x = p` at every instant. The modal engine marks such a
//! coordinate with the modal stiffness `k = +inf` (no mass per unit stiffness) and steps it
//! with the same [`Transfer`] as an oscillator, on the state `(x, x')`:
//!
//! * `x(dt) = e^z x(0) + sum_k M0_k (load (s/dt)^k)`, `z = -dt/c`, with the Duhamel moments
//!   `M0_k = (dt/c) int_0^1 e^{z (1 - s)} s^k ds = -z k! phi_{k+1}(z)`;
//! * `x'` is no state of the equation (nothing depends on it) but is given exactly: it obeys
//!   the same equation with the load's derivative and starts at `(p(0) - x(0)) / c`, so
//!   `x'(dt) = -e^z x(0) / c + sum_k M1_k (...)`, `M1_0 = e^z / c`,
//!   `M1_k = (k/dt) M0_{k-1}` — no cancellation, also for `c << dt` (where `e^z`
//!   underflows and `x` is the load lagged by `c`);
//! * `c = 0`: `x(dt) = p(dt)` (`M0_k = 1`), `x'(dt) = p'(dt)` (`M1_k = k/dt`), `A = 0`.

use super::oscillator::{phi_point, Transfer, N_MOMENTS};

/// The step of `c x' + x = p(t)` over `dt` (see the module documentation); `c` of any sign
/// (negative: a growing coordinate, exact as well).
pub fn transfer(c: f64, dt: f64) -> Transfer {
    if c == 0.0 {
        let mut m = [[1.0; N_MOMENTS], [0.0; N_MOMENTS]];
        for (k, v) in m[1].iter_mut().enumerate() {
            *v = k as f64 / dt;
        }
        return Transfer {
            a: [[0.0; 2]; 2],
            m,
            a_less_one: [-1.0, -1.0],
        };
    }
    let z = -dt / c;
    let phi = phi_point(z);
    let e = phi[0];
    let mut m0 = [0.0; N_MOMENTS];
    let mut fact = 1.0;
    for (k, slot) in m0.iter_mut().enumerate() {
        if k > 0 {
            fact *= k as f64;
        }
        *slot = -z * fact * phi[k + 1];
    }
    let mut m1 = [0.0; N_MOMENTS];
    m1[0] = e / c;
    for k in 1..N_MOMENTS {
        m1[k] = k as f64 / dt * m0[k - 1];
    }
    Transfer {
        a: [[e, 0.0], [-e / c, 0.0]],
        m: [m0, m1],
        // e^z - 1 = z phi_1(z), without cancellation for short steps
        a_less_one: [z * phi[1], -1.0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `int_0^dt (1/c) e^{-(dt - t)/c} (t/dt)^k dt` by composite Gauss-Legendre.
    fn moment(c: f64, dt: f64, k: i32) -> f64 {
        let nodes = [
            (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
            (-0.538_469_310_105_683, 0.478_628_670_499_366_5),
            (0.0, 0.568_888_888_888_888_9),
            (0.538_469_310_105_683, 0.478_628_670_499_366_5),
            (0.906_179_845_938_664, 0.236_926_885_056_189_1),
        ];
        let panels = 4000;
        let mut acc = 0.0;
        for p in 0..panels {
            let (a, b) = (p as f64 / panels as f64, (p + 1) as f64 / panels as f64);
            for &(x, w) in &nodes {
                let s = 0.5 * (a + b) + 0.5 * (b - a) * x;
                acc += (dt / c) * (-(dt / c) * (1.0 - s)).exp() * s.powi(k) * 0.5 * (b - a) * w;
            }
        }
        acc
    }

    #[test]
    fn moments_are_the_duhamel_integrals() {
        for &(c, dt) in &[
            (1.0, 0.01),
            (0.002, 0.01),
            (0.5, 0.9),
            (1e-3, 1.0),
            (3.0, 40.0),
        ] {
            let t = transfer(c, dt);
            for k in 0..N_MOMENTS {
                let want = moment(c, dt, k as i32);
                let got = t.m[0][k];
                assert!(
                    (got - want).abs() <= 1e-13 * want.abs().max(1e-300),
                    "{c} {dt} {k}"
                );
            }
            assert_eq!(t.a[0][0], (-dt / c).exp());
        }
    }

    #[test]
    fn velocity_is_the_equation_at_the_end() {
        // c x'(dt) = p(dt) - x(dt) for every moment (p(dt) = 1) and from a free start
        for &(c, dt) in &[(1.0, 0.01), (0.002, 0.01), (0.5, 0.9), (1e-6, 1.0)] {
            let t = transfer(c, dt);
            for k in 0..N_MOMENTS {
                let lhs = c * t.m[1][k];
                let rhs = 1.0 - t.m[0][k];
                assert!(
                    (lhs - rhs).abs() <= 1e-12 * (1.0 + rhs.abs()),
                    "{c} {dt} {k}"
                );
            }
            assert!((c * t.a[1][0] + t.a[0][0]).abs() <= 1e-15);
        }
    }

    #[test]
    fn static_coordinate_follows_the_load() {
        let t = transfer(0.0, 0.25);
        assert_eq!(t.a, [[0.0; 2]; 2]);
        assert_eq!(t.m[0], [1.0; N_MOMENTS]);
        assert_eq!(t.m[1], [0.0, 4.0, 8.0, 12.0]);
        // a very short time constant converges to it
        let near = transfer(1e-12, 0.25);
        for k in 0..N_MOMENTS {
            assert!((near.m[0][k] - 1.0).abs() < 1e-10 && (near.m[1][k] - t.m[1][k]).abs() < 1e-8);
        }
        assert!(Transfer::new(f64::INFINITY, 0.0, 0.25) == t);
    }
}
