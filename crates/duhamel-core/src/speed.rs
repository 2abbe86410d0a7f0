//! Scalar speed laws `omega(t)` of a rotor: the spin speed, its derivative and the rotation
//! angle `theta(t) = integral_0^t omega`, all in closed form.
//!
//! They drive the time-scaled linear couplings (the gyroscopic `omega(t) G`) and the unbalance
//! load ([`crate::loads::TimeFunction::Unbalance`]). Before `t = 0` a law keeps its initial
//! speed.

use crate::error::CoreError;

/// A spin-speed law (rad/s).
/// Coupling matrices multiplied by a speed law `s(t)`: the force `s(t) (K x + C x')`
/// (`LinearCoupling(K, C, scale=...)`, e.g. the gyroscopic `omega(t) G` of a run-up). The
/// matrices are modal (`Phi^T K Phi`, `n_modes x n_modes` row-major: `M = [f64]`, the modal
/// routes) or physical (`M = direct::assembly::Matrix`, the direct integrators).
#[derive(Debug)]
pub struct ScaledCoupling<'a, M: ?Sized = [f64]> {
    /// The stiffness part, if any.
    pub k: Option<&'a M>,
    /// The damping part, if any.
    pub c: Option<&'a M>,
    /// The time scale `s(t)`.
    pub law: SpeedLaw,
}

impl<M: ?Sized> Clone for ScaledCoupling<'_, M> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<M: ?Sized> Copy for ScaledCoupling<'_, M> {}

/// Serialised as a number (a constant speed) or `{"omega0", "omega1", "t1"}` (a run-up).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum SpeedLaw {
    /// `omega(t) = omega`.
    Constant(f64),
    /// Linear from `omega0` at `t = 0` to `omega1` at `t1 > 0`, constant `omega1` after.
    LinearRunUp { omega0: f64, omega1: f64, t1: f64 },
}

impl SpeedLaw {
    /// Checks the parameters; errors name the Python-side parameter.
    pub fn validate(&self) -> Result<(), CoreError> {
        let bad =
            |name: &'static str, problem: String| Err(CoreError::InvalidInput { name, problem });
        match *self {
            SpeedLaw::Constant(omega) if !omega.is_finite() => {
                bad("omega", format!("must be finite, got {omega}"))
            }
            SpeedLaw::LinearRunUp { omega0, omega1, t1 } => {
                if !omega0.is_finite() {
                    return bad("omega0", format!("must be finite, got {omega0}"));
                }
                if !omega1.is_finite() {
                    return bad("omega1", format!("must be finite, got {omega1}"));
                }
                if !(t1.is_finite() && t1 > 0.0) {
                    return bad("t1", format!("must be a positive finite time, got {t1}"));
                }
                Ok(())
            }
            SpeedLaw::Constant(_) => Ok(()),
        }
    }

    /// The speed when it does not depend on time.
    pub fn constant_value(&self) -> Option<f64> {
        match *self {
            SpeedLaw::Constant(omega) => Some(omega),
            SpeedLaw::LinearRunUp { omega0, omega1, .. } => (omega0 == omega1).then_some(omega0),
        }
    }

    /// Angular acceleration of the run-up (0 for a constant speed).
    fn rate(&self) -> f64 {
        match *self {
            SpeedLaw::Constant(_) => 0.0,
            SpeedLaw::LinearRunUp { omega0, omega1, t1 } => (omega1 - omega0) / t1,
        }
    }

    /// `omega(t)`.
    pub fn omega(&self, t: f64) -> f64 {
        match *self {
            SpeedLaw::Constant(omega) => omega,
            SpeedLaw::LinearRunUp { omega0, omega1, t1 } => {
                if t <= 0.0 {
                    omega0
                } else if t >= t1 {
                    omega1
                } else {
                    omega0 + self.rate() * t
                }
            }
        }
    }

    /// `omega'(t)`, from the right (`left = false`) or from the left where it jumps (`t = 0`
    /// and `t = t1` of a run-up).
    pub fn domega_side(&self, t: f64, left: bool) -> f64 {
        match *self {
            SpeedLaw::Constant(_) => 0.0,
            SpeedLaw::LinearRunUp { t1, .. } => {
                let inside = if left {
                    t > 0.0 && t <= t1
                } else {
                    t >= 0.0 && t < t1
                };
                if inside {
                    self.rate()
                } else {
                    0.0
                }
            }
        }
    }

    /// `omega'(t)`, right-continuous.
    pub fn domega(&self, t: f64) -> f64 {
        self.domega_side(t, false)
    }

    /// `theta(t) = integral_0^t omega(s) ds`, exact.
    pub fn theta(&self, t: f64) -> f64 {
        match *self {
            SpeedLaw::Constant(omega) => omega * t,
            SpeedLaw::LinearRunUp { omega0, omega1, t1 } => {
                if t <= 0.0 {
                    omega0 * t
                } else if t <= t1 {
                    t * (omega0 + 0.5 * self.rate() * t)
                } else {
                    0.5 * (omega0 + omega1) * t1 + omega1 * (t - t1)
                }
            }
        }
    }

    /// The time in `(t0, t1)` at which the angle is `angle` (`theta(t0) < angle <
    /// theta(t1)`), when the speed is positive at both ends (so `theta` rises through the
    /// interval, `omega` being linear on each side of a run-up's end): Newton's method on
    /// `theta`, kept inside a shrinking bracket. `None` otherwise.
    pub fn time_at_angle(&self, angle: f64, t0: f64, t1: f64) -> Option<f64> {
        let (mut lo, mut hi) = (t0, t1);
        let (a0, a1) = (self.theta(lo), self.theta(hi));
        if !(self.omega(lo) > 0.0 && self.omega(hi) > 0.0 && a0 < angle && angle < a1) {
            return None;
        }
        let mut t = lo + (hi - lo) * (angle - a0) / (a1 - a0);
        for _ in 0..60 {
            let f = self.theta(t) - angle;
            if f == 0.0 {
                break;
            }
            if f > 0.0 {
                hi = t;
            } else {
                lo = t;
            }
            let next = t - f / self.omega(t);
            let next = if next > lo && next < hi {
                next
            } else {
                0.5 * (lo + hi)
            };
            if next == t || hi - lo <= 4.0 * f64::EPSILON * hi.abs().max(lo.abs()) {
                t = next;
                break;
            }
            t = next;
        }
        Some(t)
    }

    /// The time inside `(t, t + dt)` where `omega'` jumps (the end of a run-up), if any.
    pub fn breakpoint_in(&self, t: f64, dt: f64) -> Option<f64> {
        match *self {
            SpeedLaw::LinearRunUp { t1, .. } if t1 > t && t1 < t + dt => Some(t1),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Composite Gauss-Legendre (3 points, exact for quintics) on `[a, b]` split at `t1`.
    fn quad(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let x = (0.6f64).sqrt();
        let (nodes, weights) = ([-x, 0.0, x], [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0]);
        let h = (b - a) / n as f64;
        (0..n)
            .map(|i| {
                let c = a + (i as f64 + 0.5) * h;
                nodes
                    .iter()
                    .zip(&weights)
                    .map(|(z, w)| w * f(c + 0.5 * h * z))
                    .sum::<f64>()
                    * 0.5
                    * h
            })
            .sum()
    }

    #[test]
    fn theta_is_the_integral_of_omega() {
        let law = SpeedLaw::LinearRunUp {
            omega0: 10.0,
            omega1: 150.0,
            t1: 1.3,
        };
        for t in [0.0, 0.2, 1.0, 1.3, 1.7, 5.0] {
            let exact = if t <= 1.3 {
                quad(|s| law.omega(s), 0.0, t, 7)
            } else {
                quad(|s| law.omega(s), 0.0, 1.3, 7) + quad(|s| law.omega(s), 1.3, t, 7)
            };
            assert!(
                (law.theta(t) - exact).abs() <= 1e-13 * exact.abs().max(1.0),
                "t = {t}: {} vs {exact}",
                law.theta(t)
            );
        }
        assert_eq!(SpeedLaw::Constant(3.0).theta(2.0), 6.0);
    }

    #[test]
    fn derivative_sides_and_validation() {
        let law = SpeedLaw::LinearRunUp {
            omega0: 0.0,
            omega1: 20.0,
            t1: 2.0,
        };
        assert_eq!(law.domega(1.0), 10.0);
        assert_eq!(law.domega(2.0), 0.0);
        assert_eq!(law.domega_side(2.0, true), 10.0);
        assert_eq!(law.domega_side(0.0, true), 0.0);
        assert_eq!(law.domega(0.0), 10.0);
        assert_eq!(law.omega(3.0), 20.0);
        assert_eq!(law.breakpoint_in(1.5, 1.0), Some(2.0));
        assert_eq!(law.breakpoint_in(2.0, 1.0), None);
        let bad = SpeedLaw::LinearRunUp {
            omega0: 0.0,
            omega1: 1.0,
            t1: -1.0,
        };
        assert!(matches!(
            bad.validate(),
            Err(CoreError::InvalidInput { name: "t1", .. })
        ));
        assert!(matches!(
            SpeedLaw::Constant(f64::NAN).validate(),
            Err(CoreError::InvalidInput { name: "omega", .. })
        ));
    }
}
