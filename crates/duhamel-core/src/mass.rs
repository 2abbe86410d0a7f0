//! Time-varying mass `M(t) = M0 mu(t)` for a scalar law `mu`.

use crate::error::CoreError;

/// The scalar mass law `mu(t)`. Serialised (a stored run's mass) as `{"exponential": {"rate":
/// ..., "scale": ...}}`, `{"harmonic": {...}}`, `{"table": {"t": [...], "mu": [...]}}`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MassLaw {
    /// `mu = scale * exp(rate t)`.
    Exponential { rate: f64, scale: f64 },
    /// `mu = 1 + amplitude * sin(frequency t)` (the rotor's `M0 [1 + xi sin(nu t)]`).
    Harmonic { amplitude: f64, frequency: f64 },
    /// Piecewise-linear `mu` through `(t, mu)` samples, held constant outside them.
    Table { t: Vec<f64>, mu: Vec<f64> },
}

/// How the mass enters the equation of motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MassForm {
    /// `M(t) x''`.
    Acceleration,
    /// `d/dt (M(t) x') = M x'' + M' x'` (the paper's eqs. 28 and 35).
    Momentum,
}

/// How the mass change becomes a pseudo-force.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MassTreatment {
    /// Divide the equation of motion by `mu` and move the rest to the right-hand side
    /// (no acceleration needed; NOTES.md section 3).
    Eliminate,
    /// Keep `-(mu - 1) M0 x''` as a pseudo-force with `x''` estimated as `(v1 - v0)/dt`.
    Estimate,
}

/// A mass law attached to a model.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeVaryingMass {
    /// The law.
    pub law: MassLaw,
    /// Acceleration or momentum form.
    pub form: MassForm,
    /// Whether the stiffness scales with the mass (gravity stiffness, e.g. `m g / l`).
    pub scale_stiffness: bool,
    /// Pseudo-force treatment.
    pub treatment: MassTreatment,
}

/// The smallest value a mass law may take relative to its largest over a run.
pub const MU_FLOOR: f64 = 1e-8;

impl MassLaw {
    /// Checks the parameters (a law must stay positive on `[0, t_end]`).
    pub fn validate(&self, t_end: f64) -> Result<(), CoreError> {
        let bad =
            |name: &'static str, problem: String| Err(CoreError::InvalidInput { name, problem });
        match self {
            MassLaw::Exponential { rate, scale } => {
                if !(rate.is_finite() && scale.is_finite() && *scale > 0.0) {
                    return bad("scale", format!("must be positive and `rate` finite, got scale = {scale}, rate = {rate}"));
                }
            }
            MassLaw::Harmonic {
                amplitude,
                frequency,
            } => {
                if !(amplitude.is_finite() && frequency.is_finite()) {
                    return bad("amplitude", "and `frequency` must be finite".into());
                }
                if amplitude.abs() >= 1.0 {
                    return bad(
                        "amplitude",
                        format!("must be below 1 in magnitude, or the mass 1 + amplitude sin(frequency t) reaches zero; got {amplitude}"),
                    );
                }
            }
            MassLaw::Table { t, mu } => {
                if t.len() != mu.len() || t.len() < 2 {
                    return bad(
                        "mu",
                        format!(
                            "needs at least two samples, one per `t` (got {} and {})",
                            mu.len(),
                            t.len()
                        ),
                    );
                }
                if t.iter().chain(mu).any(|v| !v.is_finite()) || t.windows(2).any(|w| w[1] <= w[0])
                {
                    return bad(
                        "t",
                        "must be finite and strictly increasing (and `mu` finite)".into(),
                    );
                }
                if let Some(i) = mu.iter().position(|&m| m <= 0.0) {
                    return bad(
                        "mu",
                        format!("must stay positive; mu[{i}] = {} at t = {}", mu[i], t[i]),
                    );
                }
            }
        }
        let worst = self.min_on(t_end);
        if worst.is_nan() || worst <= 0.0 {
            return bad(
                "mass law",
                format!("reaches {worst} (<= 0) before t_end = {t_end}; a mass must stay positive"),
            );
        }
        let most = self.max_on(t_end);
        if !most.is_finite() {
            return bad(
                "mass law",
                format!("overflows (reaches {most}) before t_end = {t_end}"),
            );
        }
        if worst < MU_FLOOR * most {
            return bad(
                "mass law",
                format!(
                    "falls to {:.3e} of its largest value before t_end = {t_end} (from {most:e} \
                     to {worst:e}); a mass law must stay above {MU_FLOOR:e} of its maximum, or \
                     the divided equation of motion overflows",
                    worst / most
                ),
            );
        }
        Ok(())
    }

    /// Largest value on `[0, t_end]` (exact for these laws).
    fn max_on(&self, t_end: f64) -> f64 {
        match self {
            MassLaw::Exponential { rate, scale } => scale * (rate * t_end).exp().max(1.0),
            MassLaw::Harmonic { amplitude, .. } => 1.0 + amplitude.abs(),
            MassLaw::Table { mu, .. } => mu.iter().copied().fold(0.0, f64::max),
        }
    }

    /// Smallest value on `[0, t_end]` (exact for these laws).
    fn min_on(&self, t_end: f64) -> f64 {
        match self {
            MassLaw::Exponential { rate, scale } => scale * (rate * t_end).exp().min(1.0),
            MassLaw::Harmonic { amplitude, .. } => 1.0 - amplitude.abs(),
            MassLaw::Table { mu, .. } => mu.iter().copied().fold(f64::INFINITY, f64::min),
        }
    }

    /// `(mu(t), mu'(t))`; where `mu'` jumps (a table's breakpoint), the derivative from the
    /// right.
    pub fn eval(&self, t: f64) -> (f64, f64) {
        self.eval_side(t, false)
    }

    /// `(mu(t), mu'(t))` with the derivative from the left when `left` (the end of a step
    /// that ends on a breakpoint belongs to the segment before it).
    pub fn eval_side(&self, t: f64, left: bool) -> (f64, f64) {
        match self {
            MassLaw::Exponential { rate, scale } => {
                let m = scale * (rate * t).exp();
                (m, rate * m)
            }
            MassLaw::Harmonic {
                amplitude,
                frequency,
            } => {
                let (s, c) = (frequency * t).sin_cos();
                (1.0 + amplitude * s, amplitude * frequency * c)
            }
            MassLaw::Table { t: ts, mu } => {
                let last = ts.len() - 1;
                // The segment (i - 1, i) that t belongs to on the requested side; a time within
                // rounding of a breakpoint (a grid time n * dt) counts as on it.
                let tol = 1e-12 * t.abs().max(ts[last].abs()).max(f64::MIN_POSITIVE);
                let i = if left {
                    ts.partition_point(|&x| x < t - tol)
                } else {
                    ts.partition_point(|&x| x <= t + tol)
                };
                if i == 0 {
                    return (mu[0], 0.0);
                }
                if i > last {
                    return (mu[last], 0.0);
                }
                let slope = (mu[i] - mu[i - 1]) / (ts[i] - ts[i - 1]);
                (mu[i - 1] + slope * (t - ts[i - 1]), slope)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stored run keeps its mass law as this JSON: read back bit for bit.
    #[test]
    fn serde_round_trip_is_exact() {
        let laws = [
            MassLaw::Exponential {
                rate: -(0.1 + 0.2),
                scale: 1.0 / 3.0,
            },
            MassLaw::Harmonic {
                amplitude: 0.1,
                frequency: 157.07963267948966,
            },
            MassLaw::Table {
                t: vec![0.0, 0.1 + 0.2, 1.0],
                mu: vec![1.0, 2.0 / 3.0, 5e-324],
            },
        ];
        for law in laws {
            let text = serde_json::to_string(&law).unwrap();
            let back: MassLaw = serde_json::from_str(&text).unwrap();
            assert_eq!(format!("{back:?}"), format!("{law:?}"), "{text}");
        }
    }

    #[test]
    fn laws_and_derivatives() {
        let e = MassLaw::Exponential {
            rate: -0.5,
            scale: 2.0,
        };
        let (m, dm) = e.eval(1.0);
        assert!((m - 2.0 * (-0.5f64).exp()).abs() < 1e-15 && (dm + 0.5 * m).abs() < 1e-15);
        let h = MassLaw::Harmonic {
            amplitude: 0.2,
            frequency: 3.0,
        };
        let (m, dm) = h.eval(0.0);
        assert!(m == 1.0 && (dm - 0.6).abs() < 1e-15);
        let t = MassLaw::Table {
            t: vec![0.0, 1.0],
            mu: vec![1.0, 0.5],
        };
        assert_eq!(t.eval(0.5), (0.75, -0.5));
        assert_eq!(t.eval(2.0), (0.5, 0.0));
        // at a breakpoint the slope depends on the side
        let v = MassLaw::Table {
            t: vec![0.0, 1.0, 2.0],
            mu: vec![1.0, 0.5, 1.5],
        };
        assert_eq!(v.eval_side(1.0, true), (0.5, -0.5));
        assert_eq!(v.eval_side(1.0, false), (0.5, 1.0));
        assert_eq!(v.eval_side(0.0, false).1, -0.5);
        assert_eq!(v.eval_side(2.0, true).1, 1.0);
    }

    #[test]
    fn a_law_that_reaches_zero_is_rejected() {
        let h = MassLaw::Harmonic {
            amplitude: 1.0,
            frequency: 1.0,
        };
        assert!(h.validate(10.0).is_err());
        let t = MassLaw::Table {
            t: vec![0.0, 1.0],
            mu: vec![1.0, 0.0],
        };
        assert!(t.validate(1.0).is_err());
        let e = MassLaw::Exponential {
            rate: -1.0,
            scale: 1.0,
        };
        assert!(e.validate(5.0).is_ok());
    }
}
