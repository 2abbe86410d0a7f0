//! A bearing whose stiffness and damping are tables against the spin speed, following a
//! speed law in time (a run-up through a fluid-film bearing's speed range):
//!
//! ```text
//! r = K(omega(t)) (x, y) + C(omega(t)) (x', y'),
//! ```
//!
//! each of the eight coefficients `kxx, kxy, kyx, kyy, cxx, cxy, cyx, cyy` a piecewise cubic
//! Hermite interpolant of its table (the knot slopes given: PCHIP's, computed by the caller)
//! or the broken line through it, held at its end values outside the table. Linear in the
//! state: the tangents are `K` and `C` themselves.

use super::definition::Definition;
use super::element::{distinct, Element, Tangent};
use super::shifted::Shifted;
use crate::error::CoreError;
use crate::speed::SpeedLaw;
use serde::{Deserialize, Serialize};

/// Coefficients per table: `kxx, kxy, kyx, kyy, cxx, cxy, cyx, cyy`.
pub const COEFFICIENTS: usize = 8;

/// A speed-tabulated linear bearing on two dofs.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedTableBearing {
    dofs: [usize; 2],
    speeds: Vec<f64>,
    /// Per coefficient, its values at `speeds`.
    values: Vec<Vec<f64>>,
    /// Per coefficient, the slopes at `speeds` (Hermite), or None (linear).
    slopes: Option<Vec<Vec<f64>>>,
    law: SpeedLaw,
}

fn invalid(name: &'static str, problem: String) -> CoreError {
    CoreError::InvalidInput { name, problem }
}

impl SpeedTableBearing {
    /// The bearing on `(dof_x, dof_y)` with `values[c][i]` of coefficient `c` at
    /// `speeds[i]` (strictly ascending), Hermite `slopes` (same shape) or linear, at `law`.
    pub fn new(
        dof_x: usize,
        dof_y: usize,
        speeds: Vec<f64>,
        values: Vec<Vec<f64>>,
        slopes: Option<Vec<Vec<f64>>>,
        law: SpeedLaw,
    ) -> Result<Self, CoreError> {
        distinct(dof_x, dof_y)?;
        if speeds.is_empty() || speeds.windows(2).any(|w| w[1] <= w[0] || !w[1].is_finite()) {
            return Err(invalid(
                "speeds",
                "must be finite and strictly ascending".into(),
            ));
        }
        let shaped = |t: &Vec<Vec<f64>>| {
            t.len() == COEFFICIENTS
                && t.iter()
                    .all(|c| c.len() == speeds.len() && c.iter().all(|v| v.is_finite()))
        };
        if !shaped(&values) {
            return Err(invalid(
                "values",
                format!("must be {COEFFICIENTS} finite tables of len(speeds)"),
            ));
        }
        if let Some(s) = &slopes {
            if !shaped(s) {
                return Err(invalid(
                    "slopes",
                    format!("must be {COEFFICIENTS} finite tables of len(speeds)"),
                ));
            }
        }
        law.validate()?;
        Ok(Self {
            dofs: [dof_x, dof_y],
            speeds,
            values,
            slopes,
            law,
        })
    }

    /// The eight coefficients at spin speed `w`.
    pub fn coefficients(&self, w: f64) -> [f64; COEFFICIENTS] {
        let s = &self.speeds;
        let n = s.len();
        let mut out = [0.0; COEFFICIENTS];
        if n == 1 || w <= s[0] || w >= s[n - 1] {
            let i = if n == 1 || w <= s[0] { 0 } else { n - 1 };
            for (c, o) in out.iter_mut().enumerate() {
                *o = self.values[c][i];
            }
            return out;
        }
        let i = s.partition_point(|&v| v <= w) - 1; // s[i] <= w < s[i + 1]
        let h = s[i + 1] - s[i];
        let u = (w - s[i]) / h;
        for (c, o) in out.iter_mut().enumerate() {
            let (y0, y1) = (self.values[c][i], self.values[c][i + 1]);
            *o = match &self.slopes {
                None => y0 + u * (y1 - y0),
                Some(d) => {
                    let (d0, d1) = (d[c][i] * h, d[c][i + 1] * h);
                    let (u2, u3) = (u * u, u * u * u);
                    (2.0 * u3 - 3.0 * u2 + 1.0) * y0
                        + (u3 - 2.0 * u2 + u) * d0
                        + (-2.0 * u3 + 3.0 * u2) * y1
                        + (u3 - u2) * d1
                }
            };
        }
        out
    }
}

impl Element for SpeedTableBearing {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn eval(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let c = self.coefficients(self.law.omega(t));
        r[0] += c[0] * x[0] + c[1] * x[1] + c[4] * v[0] + c[5] * v[1];
        r[1] += c[2] * x[0] + c[3] * x[1] + c[6] * v[0] + c[7] * v[1];
        if let Some(tg) = tangent {
            for k in 0..4 {
                tg.kx[k] += c[k];
                tg.cv[k] += c[4 + k];
            }
        }
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        true
    }
}

/// `duhamel.elements.SpeedTableBearing`: the definition of a [`SpeedTableBearing`] less its
/// coefficients at the initial speed (`k0 x + c0 x'`, which the background carries).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedTableBearingDef {
    pub dofs: (usize, usize),
    pub speeds: Vec<f64>,
    pub values: Vec<Vec<f64>>,
    #[serde(default)]
    pub slopes: Option<Vec<Vec<f64>>>,
    pub speed: SpeedLaw,
    pub k0: [[f64; 2]; 2],
    pub c0: [[f64; 2]; 2],
}

impl Definition for SpeedTableBearingDef {
    const NAME: &'static str = "SpeedTableBearing";
    const SIGNATURE: &'static str = "(dofs, *, speeds, values, slopes=None, speed, k0, c0)";
    const DOC: &'static str = r#"A bearing whose stiffness and damping coefficients are tabulated against the spin speed,
following the speed law `speed` in time (the same PCHIP or linear interpolation as
:meth:`duhamel.rotor.Bearing.stiffness_at`, end values held), minus ``k0 x + c0 x'`` (its
matrices at the initial speed, which the background carries).

Parameters
----------
dofs : pair of int or dof labels
    The journal centre's dofs ``(x, y)``.
speeds : sequence of float
    The table's speeds, strictly ascending.
values : 8 sequences
    ``kxx, kxy, kyx, kyy, cxx, cxy, cyx, cyy`` at `speeds`.
slopes : 8 sequences, optional
    Their Hermite slopes (PCHIP); None: linear interpolation.
speed : float or speed law
    The rotor's speed law.
k0, c0 : 2 x 2 matrices
    The linear part the background carries.

Examples
--------
>>> import duhamel
>>> e = duhamel.elements.SpeedTableBearing((0, 1), speeds=[0.0, 100.0],
...     values=[[1e6, 2e6], [0, 0], [0, 0], [1e6, 2e6], [1e2, 1e2], [0, 0], [0, 0], [1e2, 1e2]],
...     speed=duhamel.speed.LinearRunUp(0.0, 100.0, 1.0), k0=[[1e6, 0], [0, 1e6]],
...     c0=[[1e2, 0], [0, 1e2]])
>>> r, K, C = e.evaluate([1e-3, 0.0], t=1.0)
>>> float(K[0, 0])
1000000.0
"#;
    type Runtime = Shifted<SpeedTableBearing>;

    fn build(&self) -> Result<Shifted<SpeedTableBearing>, CoreError> {
        let (x, y) = self.dofs;
        let table = SpeedTableBearing::new(
            x,
            y,
            self.speeds.clone(),
            self.values.clone(),
            self.slopes.clone(),
            self.speed,
        )?;
        Shifted::new(Box::new(table), self.k0.concat(), self.c0.concat())
    }

    fn tangent_bound(&self) -> Option<(f64, f64)> {
        // PCHIP and linear interpolation stay within each entry's tabulated values: the
        // entrywise largest difference bounds the Frobenius norm at any speed
        let worst = |rows: std::ops::Range<usize>, reference: [[f64; 2]; 2]| {
            let r = reference.concat();
            let sq: f64 = rows
                .enumerate()
                .map(|(k, c)| {
                    let w = self.values[c]
                        .iter()
                        .map(|v| (v - r[k]).abs())
                        .fold(0.0, f64::max);
                    w * w
                })
                .sum();
            sq.sqrt()
        };
        Some((worst(0..4, self.k0), worst(4..8, self.c0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_reproduces_a_cubic_and_holds_the_ends() {
        // y = w^3 with its exact slopes is reproduced exactly between knots
        let speeds = vec![0.0, 1.0, 3.0];
        let table = |f: fn(f64) -> f64| speeds.iter().map(|&w| f(w)).collect::<Vec<_>>();
        let values = vec![table(|w| w * w * w); COEFFICIENTS];
        let slopes = vec![table(|w| 3.0 * w * w); COEFFICIENTS];
        let b = SpeedTableBearing::new(0, 1, speeds, values, Some(slopes), SpeedLaw::Constant(0.0))
            .unwrap();
        for w in [0.25, 1.5, 2.9] {
            assert!((b.coefficients(w)[3] - w * w * w).abs() < 1e-12);
        }
        assert_eq!(b.coefficients(-1.0)[0], 0.0);
        assert_eq!(b.coefficients(5.0)[7], 27.0);
    }

    #[test]
    fn force_follows_the_speed_law() {
        let law = SpeedLaw::LinearRunUp {
            omega0: 0.0,
            omega1: 2.0,
            t1: 1.0,
        };
        let values = vec![vec![1.0, 3.0]; COEFFICIENTS];
        let b = SpeedTableBearing::new(0, 1, vec![0.0, 2.0], values, None, law).unwrap();
        let mut r = [0.0; 2];
        // at t = 0.5 the speed is 1: every coefficient 2
        b.eval(&[1.0, 0.0], &[0.0, 1.0], 0.5, &mut r, None).unwrap();
        assert_eq!(r, [4.0, 4.0]);
        assert!(
            SpeedTableBearing::new(0, 1, vec![1.0, 1.0], vec![vec![0.0; 2]; 8], None, law).is_err()
        );
    }
}
