//! Nonlinear (power-law) fluid viscous damper.
//!
//! With the relative velocity `v = v_i - v_j` (`v_i` when grounded) the element force
//! (`r_i = +F`, `r_j = -F`) is
//!
//! ```text
//! F = c |v|^a sgn(v)                                    for |v| >= v0,
//! F = c v0^a [ (3 - a)/2 (v / v0) + (a - 1)/2 (v / v0)^3 ]  for |v| < v0   (a < 1 only),
//! ```
//!
//! `a > 0` the velocity exponent (`a = 1` linear, `0.2 <= a <= 0.5` typical of seismic
//! dampers). For `a < 1` the power law has an infinite slope `c a |v|^(a-1)` at `v = 0`,
//! which stops Newton iterations; below the regularisation velocity `v0` it is replaced by
//! the odd cubic that matches the force and its slope at `|v| = v0` (so `F` is `C^1`,
//! monotone, with slope `c v0^(a-1) (3 - a)/2` at rest, and differs from the power law only
//! for `|v| < v0`, by less than `c v0^a`). For `a >= 1` the power law is used everywhere.
//! The default `v0` is [`DEFAULT_V0`] (1e-4, i.e. 0.1 mm/s in SI units), far below the
//! velocities at which such dampers are specified.
//!
//! Stateless (a function of the current velocity): `dr/dx = 0`,
//! `dr/dv = dF/dv [[1, -1], [-1, 1]]`.

use super::common::{check, finite, local_dofs, relative, scatter};
use crate::elements::element::{Element, Tangent};
use crate::error::CoreError;

/// The default regularisation velocity `v0` (0.1 mm/s in SI units).
pub const DEFAULT_V0: f64 = 1e-4;

/// Power-law viscous damper between dofs `i` and `j` (or `i` and ground).
#[derive(Debug, Clone, PartialEq)]
pub struct ViscousDamper {
    dofs: Vec<usize>,
    c: f64,
    exponent: f64,
    v0: f64,
}

impl ViscousDamper {
    /// Damper from dof `i` to dof `j` (`None`: to ground) with coefficient `c >= 0` and
    /// velocity exponent `exponent > 0`, regularised below [`DEFAULT_V0`] when
    /// `exponent < 1`. Errors name the parameter (`"j"` when `j == Some(i)`).
    pub fn new(i: usize, j: Option<usize>, c: f64, exponent: f64) -> Result<Self, CoreError> {
        check("c", c, false)?;
        check("exponent", exponent, true)?;
        Ok(Self {
            dofs: local_dofs(i, j)?,
            c,
            exponent,
            v0: DEFAULT_V0,
        })
    }

    /// The same damper with the regularisation velocity `v0 > 0` (named `"v0"`).
    pub fn with_v0(mut self, v0: f64) -> Result<Self, CoreError> {
        check("v0", v0, true)?;
        self.v0 = v0;
        Ok(self)
    }

    /// Damping coefficient `c`.
    pub fn c(&self) -> f64 {
        self.c
    }

    /// Velocity exponent `a`.
    pub fn exponent(&self) -> f64 {
        self.exponent
    }

    /// Regularisation velocity `v0` (used only when `a < 1`).
    pub fn v0(&self) -> f64 {
        self.v0
    }

    /// The force and its derivative `(F, dF/dv)` at relative velocity `v`.
    pub fn force(&self, v: f64) -> (f64, f64) {
        let (c, a) = (self.c, self.exponent);
        if a < 1.0 && v.abs() < self.v0 {
            let s = v / self.v0;
            let scale = c * self.v0.powf(a);
            let (p, q) = (0.5 * (3.0 - a), 0.5 * (a - 1.0));
            (
                scale * s * (p + q * s * s),
                scale / self.v0 * (p + 3.0 * q * s * s),
            )
        } else if v == 0.0 {
            // a >= 1: F = 0, slope c (a = 1) or 0
            (0.0, if a == 1.0 { c } else { 0.0 })
        } else {
            let m = c * self.power(v.abs());
            (m.copysign(v), a * m / v.abs())
        }
    }

    /// `s^a` for `s > 0`: the square root for the usual `a = 1/2` (correctly rounded and
    /// about ten times cheaper than `powf`, which it equals but in the last bit of about
    /// one value in 1,400), `powf` otherwise.
    #[inline(always)]
    fn power(&self, s: f64) -> f64 {
        if self.exponent == 0.5 {
            s.sqrt()
        } else {
            s.powf(self.exponent)
        }
    }
}

impl Element for ViscousDamper {
    fn path_reads(&self) -> Option<(bool, bool)> {
        Some((true, true))
    }

    fn restarts_exactly(&self) -> bool {
        false
    }

    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn eval(
        &self,
        _x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let (f, df) = self.force(relative(v));
        finite(t, &[f, df])?;
        scatter(f, df, r, tangent.map(|tg| tg.cv));
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_exponent_is_a_linear_damper() {
        let d = ViscousDamper::new(0, None, 3.0, 1.0).unwrap();
        for v in [-2.0, -1e-6, 0.0, 1e-9, 0.5] {
            let (f, df) = d.force(v);
            assert!((f - 3.0 * v).abs() <= 1e-15 * (1.0 + v.abs()) && (df - 3.0).abs() < 1e-14);
        }
    }

    #[test]
    fn square_root_law_is_the_power_law() {
        let d = ViscousDamper::new(0, None, 3.0, 0.5).unwrap();
        for v in [-2.0, -1e-3, 1.5e-4, 0.25, 7.0] {
            let (f, df) = d.force(v);
            let want = 3.0 * v.abs().powf(0.5);
            assert!((f.abs() - want).abs() <= 2.0 * f64::EPSILON * want && f * v > 0.0);
            assert!((df - 0.5 * want / v.abs()).abs() <= 4.0 * f64::EPSILON * df);
        }
    }

    #[test]
    fn validates_parameters() {
        let name = |e: CoreError| match e {
            CoreError::InvalidInput { name, .. } => name,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            name(ViscousDamper::new(0, None, -1.0, 0.5).unwrap_err()),
            "c"
        );
        assert_eq!(
            name(ViscousDamper::new(0, None, 1.0, 0.0).unwrap_err()),
            "exponent"
        );
        assert_eq!(
            name(ViscousDamper::new(0, Some(0), 1.0, 0.5).unwrap_err()),
            "j"
        );
        let d = ViscousDamper::new(0, None, 1.0, 0.5).unwrap();
        assert_eq!(name(d.with_v0(f64::INFINITY).unwrap_err()), "v0");
    }
}
