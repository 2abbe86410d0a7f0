//! The reaction force of a misaligned flexible coupling, a function of the rotor's angle
//! only: ROSS's `MisalignmentFlex` (ross-rotordynamics 2.3.0, `ross/faults/misalignment.py`,
//! after Xia et al. 2019, the hexangular flexible coupling), driven here by the exact angle
//! `theta(t)` of a speed law, so a run-up sees the force at the angle the rotor has turned.
//!
//! Parallel offset `(dx, dy)`, `d = |(dx, dy)|`, shaft radius `r`, the coupling's radial
//! stiffness `k_d`, `psi = theta + atan2(dx, dy)` and `g(u) = |r + d e^(i u)| - r`
//! (`sqrt(r^2 + d^2 + 2 r d cos u) - r`, the stretch of a bolt at the coupling's rim):
//!
//! ```text
//! F_x = k_d [ g(psi - pi/2) sin(theta) + g(psi + pi/6) sin(theta + 2 pi/3)
//!             - g(psi + 5 pi/6) sin(theta + 4 pi/3) ]
//! F_y = the same with cos in place of the sin of theta + ...
//! ```
//!
//! (ROSS's `sqrt(aux1 + aux2 sin(phi))`, `sqrt(aux1 + aux2 cos(phi + pi/6))` and
//! `sqrt(aux1 - aux2 sin(phi + pi/3))` written as `g`). Angular misalignment `alpha` with the
//! bending stiffness `k_b`: `a = k_b r 2 |sin(alpha / 2)| |sin(alpha)|` and, with
//! `u_j = theta + 2 pi j / 3`,
//!
//! ```text
//! F_x = -a sum_j |sin u_j| cos u_j,    F_y = -a sum_j |sin u_j| sin u_j
//! ```
//!
//! (ROSS's `|aux sin(ang + 4 a)| cos(ang + pi + 4 a)`; `sqrt(2 - 2 cos alpha) = 2 |sin(alpha
//! / 2)|`). The force acts with `+` on the coupling's first node and `-` on its second (the
//! caller's load pattern). The angular force has kinks at the multiples of `pi / 3`
//! ([`Coupling::kink_in`], [`Coupling::kink_jumps`]), which the load's step integrates
//! exactly (`TimeFunction::jump_in`).

use std::cmp::Ordering;

use crate::error::CoreError;

/// A flexible coupling's misalignment: geometry and stiffnesses.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Coupling {
    /// Shaft radius at the coupling (m), `> 0`.
    pub radius: f64,
    /// Parallel offset along x and y (m).
    pub delta: [f64; 2],
    /// Radial stiffness of the coupling (N/m), `>= 0`.
    pub radial_stiffness: f64,
    /// Angular misalignment (rad).
    pub angle: f64,
    /// Bending stiffness of the coupling, `>= 0`.
    pub bending_stiffness: f64,
}

const THIRD: f64 = 2.0 * std::f64::consts::PI / 3.0;
const HALF_PI: f64 = std::f64::consts::FRAC_PI_2;
const SIXTH_PI: f64 = std::f64::consts::FRAC_PI_6;

impl Coupling {
    /// Checks the parameters (finite; radius positive; stiffnesses non-negative).
    pub fn validate(&self) -> Result<(), CoreError> {
        let bad =
            |name: &'static str, problem: String| Err(CoreError::InvalidInput { name, problem });
        let Coupling {
            radius,
            delta,
            radial_stiffness,
            angle,
            bending_stiffness,
        } = *self;
        if !(radius.is_finite() && radius > 0.0) {
            return bad("radius", format!("must be finite and > 0, got {radius}"));
        }
        for (name, v) in [
            ("mis_distance_x", delta[0]),
            ("mis_distance_y", delta[1]),
            ("mis_angle", angle),
        ] {
            if !v.is_finite() {
                return bad(name, format!("must be finite, got {v}"));
            }
        }
        for (name, v) in [
            ("radial_stiffness", radial_stiffness),
            ("bending_stiffness", bending_stiffness),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(name, format!("must be finite and >= 0, got {v}"));
            }
        }
        Ok(())
    }

    /// The reaction force `(F_x, F_y)` (N) at the rotor angle `theta`: parallel plus angular.
    pub fn force(&self, theta: f64) -> [f64; 2] {
        let p = self.parallel(theta);
        let a = self.angular(theta);
        [p[0] + a[0], p[1] + a[1]]
    }

    /// The parallel misalignment's force.
    fn parallel(&self, theta: f64) -> [f64; 2] {
        let [dx, dy] = self.delta;
        let d = dx.hypot(dy);
        if d == 0.0 || self.radial_stiffness == 0.0 {
            return [0.0, 0.0];
        }
        let r = self.radius;
        // g(u) = sqrt(r^2 + d^2 + 2 r d cos u) - r without the cancellation for d << r
        let g = |u: f64| {
            let s = d * (d + 2.0 * r * u.cos());
            s / ((r * r + s).max(0.0).sqrt() + r)
        };
        let psi = theta + dx.atan2(dy);
        let terms = [
            (g(psi - HALF_PI), 0.0, 1.0),
            (g(psi + SIXTH_PI), THIRD, 1.0),
            (g(psi + 5.0 * SIXTH_PI), 2.0 * THIRD, -1.0),
        ];
        let mut f = [0.0; 2];
        for (gk, beta, sign) in terms {
            let (s, c) = (theta + beta).sin_cos();
            f[0] += sign * gk * s;
            f[1] += sign * gk * c;
        }
        [self.radial_stiffness * f[0], self.radial_stiffness * f[1]]
    }

    /// The amplitude `a` of the angular force.
    fn angular_amplitude(&self) -> f64 {
        self.bending_stiffness
            * self.radius
            * 2.0
            * (0.5 * self.angle).sin().abs()
            * self.angle.sin().abs()
    }

    /// The angle of the one kink of the angular force strictly inside `(theta0, theta1)`
    /// (the kinks are at the multiples of `pi / 3`, where one of the `|sin u_j|` turns), or
    /// `None` when there is none, more than one, or no angular force.
    pub fn kink_in(&self, theta0: f64, theta1: f64) -> Option<f64> {
        if self.angular_amplitude() == 0.0 || theta1.partial_cmp(&theta0) != Some(Ordering::Greater)
        {
            return None;
        }
        let sixth = std::f64::consts::FRAC_PI_3;
        let first = (theta0 / sixth).floor() + 1.0;
        let last = (theta1 / sixth).ceil() - 1.0;
        (first == last).then_some(first * sixth)
    }

    /// The jumps of the first and second derivatives of `(F_x, F_y)` with respect to the
    /// angle at the kink `theta_k` (a multiple of `pi / 3`): `[[dF_x', dF_x''], [dF_y',
    /// dF_y'']]`. At `u_j = k pi`, `|sin u_j|` changes sign by `sigma = 2 (-1)^k`, so
    /// `-a |sin u| cos u` gains `-a sigma` in slope and `-a |sin u| sin u` gains `-2 a sigma`
    /// in curvature; the force itself is continuous.
    pub fn kink_jumps(&self, theta_k: f64) -> [[f64; 2]; 2] {
        let p = (theta_k / std::f64::consts::FRAC_PI_3).round() as i64;
        // the term j with p + 2 j = 0 (mod 3): u_j = (p + 2 j) pi / 3 = k pi
        let j = (0..3).find(|j| (p + 2 * j).rem_euclid(3) == 0).unwrap_or(0);
        let k = (p + 2 * j) / 3;
        let sigma = if k.rem_euclid(2) == 0 { 2.0 } else { -2.0 };
        let a = self.angular_amplitude();
        [[-a * sigma, 0.0], [0.0, -2.0 * a * sigma]]
    }

    /// The angular misalignment's force.
    fn angular(&self, theta: f64) -> [f64; 2] {
        let a = self.angular_amplitude();
        if a == 0.0 {
            return [0.0, 0.0];
        }
        let mut f = [0.0; 2];
        for j in 0..3 {
            let (s, c) = (theta + j as f64 * THIRD).sin_cos();
            f[0] -= s.abs() * c;
            f[1] -= s.abs() * s;
        }
        [a * f[0], a * f[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn coupling() -> Coupling {
        Coupling {
            radius: 0.0095,
            delta: [2e-4, 3e-4],
            radial_stiffness: 40e3,
            angle: 5f64.to_radians(),
            bending_stiffness: 38e3,
        }
    }

    /// ROSS's formulas as written there (`arctan(dx / dy)`, equal to `atan2` for `dy > 0`).
    #[test]
    fn equals_ross_formulas() {
        let c = coupling();
        let r = c.radius;
        let [dx, dy] = c.delta;
        let (aux1, aux2) = (r * r + dx * dx + dy * dy, 2.0 * r * dx.hypot(dy));
        let aux = c.bending_stiffness * r * (2.0 - 2.0 * c.angle.cos()).sqrt() * c.angle.sin();
        for k in 0..50 {
            let th = 0.37 * k as f64 - 3.0;
            let phi = (dx / dy).atan() + th;
            let fp = |v: f64| (aux1 + aux2 * v).sqrt() - r;
            let (f1, f2, f3) = (
                fp(phi.sin()),
                fp((phi + SIXTH_PI).cos()),
                fp(-(phi + 2.0 * SIXTH_PI).sin()),
            );
            let px = f1 * th.sin() + f2 * (th + THIRD).sin() - f3 * (th + 2.0 * THIRD).sin();
            let py = f1 * th.cos() + f2 * (th + THIRD).cos() - f3 * (th + 2.0 * THIRD).cos();
            let (mut ax, mut ay) = (0.0, 0.0);
            for j in 0..3 {
                let u = th + j as f64 * THIRD;
                ax += (aux * u.sin()).abs() * (u + std::f64::consts::PI).cos();
                ay += (aux * u.sin()).abs() * (u + std::f64::consts::PI).sin();
            }
            let want = [c.radial_stiffness * px + ax, c.radial_stiffness * py + ay];
            let got = c.force(th);
            for i in 0..2 {
                assert!(
                    (got[i] - want[i]).abs() < 1e-12 * 10.0,
                    "{th}: {got:?} vs {want:?}"
                );
            }
        }
    }

    /// One-sided finite differences across each kink of a turn agree with `kink_jumps`.
    #[test]
    fn kink_jumps_are_the_one_sided_differences() {
        let c = coupling();
        let h = 1e-4;
        for p in -7..8 {
            let tk = p as f64 * std::f64::consts::FRAC_PI_3;
            assert_eq!(c.kink_in(tk - 0.1, tk + 0.2), Some(tk));
            let f = |x: f64| c.force(x);
            for axis in 0..2 {
                let r = |m: f64| f(tk + m * h)[axis];
                let l = |m: f64| f(tk - m * h)[axis];
                let d1 = (-3.0 * r(0.0) + 4.0 * r(1.0) - r(2.0)) / (2.0 * h)
                    - (3.0 * l(0.0) - 4.0 * l(1.0) + l(2.0)) / (2.0 * h);
                let d2 = (2.0 * r(0.0) - 5.0 * r(1.0) + 4.0 * r(2.0) - r(3.0)) / (h * h)
                    - (2.0 * l(0.0) - 5.0 * l(1.0) + 4.0 * l(2.0) - l(3.0)) / (h * h);
                let want = c.kink_jumps(tk)[axis];
                let scale = c.angular_amplitude();
                assert!(
                    (d1 - want[0]).abs() < 1e-5 * scale,
                    "{p} {axis}: {d1} {want:?}"
                );
                assert!(
                    (d2 - want[1]).abs() < 1e-3 * scale,
                    "{p} {axis}: {d2} {want:?}"
                );
            }
        }
        // none, or two kinks in the interval
        assert_eq!(c.kink_in(0.1, 1.0), None);
        assert_eq!(c.kink_in(0.1, 2.5), None);
    }

    #[test]
    fn checks_and_zero_cases() {
        let mut c = coupling();
        assert!(c.validate().is_ok());
        c.radius = 0.0;
        assert!(c.validate().is_err());
        let mut c = coupling();
        c.bending_stiffness = -1.0;
        assert!(c.validate().is_err());
        let mut c = coupling();
        c.delta = [f64::NAN, 0.0];
        assert!(c.validate().is_err());
        let mut c = coupling();
        c.delta = [0.0, 0.0];
        c.angle = 0.0;
        assert_eq!(c.force(1.3), [0.0, 0.0]);
    }
}
