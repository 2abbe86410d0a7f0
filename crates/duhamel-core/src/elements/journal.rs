//! Short (Ocvirk) plain journal bearing with half-film (Gumbel) cavitation.
//!
//! The journal centre `p = (x, y)` moves in a bearing of radius `R`, length `L`, radial
//! clearance `c`, lubricant viscosity `mu`, the journal spinning at `omega(t)`. At the angle
//! `theta` from +x (towards +y, the sense of a positive spin) the film is
//! `h = c - x cos(theta) - y sin(theta)`. The short-bearing Reynolds equation
//! `d/dz (h^3 / (12 mu) dp/dz) = (omega / 2) dh/dtheta + dh/dt` with `p(+-L/2) = 0` gives
//! `p = (6 mu / h^3) (z^2 - L^2 / 4) G`; integrated over the length, `int p dz = mu L^3 g /
//! h^3` with
//!
//! ```text
//! g(theta) = -G = a cos(theta) + b sin(theta),   a = x' + (omega / 2) y,   b = y' - (omega / 2) x.
//! ```
//!
//! Gumbel's condition keeps the positive pressures only: the film carries load where
//! `g > 0`, the half circle `|theta - beta| < pi / 2` around `beta = atan2(b, a)`. The
//! restoring force (left-hand side; the film pushes the journal with `-r`) is
//!
//! ```text
//! r = R mu L^3 int_{beta - pi/2}^{beta + pi/2} g / h^3 (cos(theta), sin(theta)) dtheta.
//! ```
//!
//! Tangents are exact: the integrand vanishes at both ends of the film, so differentiating
//! the integral is differentiating the integrand (`dg/dx = -(omega/2) sin`, `dg/dy =
//! (omega/2) cos`, `dh/dx = -cos`, `dh/dy = -sin`, `dg/dx' = cos`, `dg/dy' = sin`).
//!
//! The integrals are evaluated by composite Gauss-Legendre quadrature (8 points on each of
//! [`PANELS`] panels of the half circle): the integrand is analytic on the film, so the error
//! falls geometrically with the panels; 1e-13 relative against the closed-form static forces
//! up to an eccentricity ratio of 0.9 (tests below). The film force is singular at the wall:
//! a journal at or beyond the clearance (`|p| >= c`) is an error naming the bearing.
//! Where `a = b = 0` (a centred journal at rest, or pure spin at the centre) the film
//! carries nothing and the half circle is taken at `beta = 0` for the tangents.

use super::definition::Definition;
use super::element::{check, distinct, Element, Tangent};
use super::shifted::Shifted;
use crate::error::CoreError;
use crate::speed::SpeedLaw;
use serde::{Deserialize, Serialize};

/// Panels of the quadrature over the half circle.
pub const PANELS: usize = 48;

/// 8-point Gauss-Legendre nodes and weights on [-1, 1] (positive half; symmetric).
const GL8: [(f64, f64); 4] = [
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
];

/// A short journal bearing on the two lateral dofs of a journal.
#[derive(Debug, Clone, PartialEq)]
pub struct ShortJournalBearing {
    dofs: [usize; 2],
    radius: f64,
    length: f64,
    clearance: f64,
    viscosity: f64,
    law: SpeedLaw,
    /// Per quadrature point: offset from `beta - pi/2` as (cos, sin), and weight.
    points: Vec<(f64, f64, f64)>,
}

/// Force and tangents at one state: `(r, dr/dx, dr/dx')`, row-major 2 x 2.
pub type JournalForce = ([f64; 2], [f64; 4], [f64; 4]);

impl ShortJournalBearing {
    /// The bearing on `(dof_x, dof_y)` of `radius`, `length`, radial `clearance` and
    /// `viscosity` (all `> 0`), the journal spinning at `law`.
    pub fn new(
        dof_x: usize,
        dof_y: usize,
        radius: f64,
        length: f64,
        clearance: f64,
        viscosity: f64,
        law: SpeedLaw,
    ) -> Result<Self, CoreError> {
        distinct(dof_x, dof_y)?;
        check("radius", radius, true)?;
        check("length", length, true)?;
        check("clearance", clearance, true)?;
        check("viscosity", viscosity, true)?;
        law.validate()?;
        let width = std::f64::consts::PI / PANELS as f64;
        let mut points = Vec::with_capacity(8 * PANELS);
        for p in 0..PANELS {
            let mid = (p as f64 + 0.5) * width;
            for &(node, weight) in &GL8 {
                for s in [-1.0, 1.0] {
                    let off = mid + s * node * width / 2.0;
                    points.push((off.cos(), off.sin(), weight * width / 2.0));
                }
            }
        }
        Ok(Self {
            dofs: [dof_x, dof_y],
            radius,
            length,
            clearance,
            viscosity,
            law,
            points,
        })
    }

    /// The film force `r` and its tangents at position `p`, velocity `v` and spin `omega`.
    pub fn force(&self, p: [f64; 2], v: [f64; 2], omega: f64) -> Result<JournalForce, CoreError> {
        let [x, y] = p;
        let rho = x.hypot(y);
        let inside = rho.is_finite() && rho < self.clearance;
        if !inside || !v[0].is_finite() || !v[1].is_finite() {
            return Err(CoreError::OutOfDomain {
                time: 0.0,
                step: 0,
                last_good_time: None,
                message: format!(
                    "ShortJournalBearing: the journal on dofs ({}, {}) reached eccentricity \
                     ratio {:.6} of the clearance {:e} m (velocity ({:e}, {:e}) m/s); the film \
                     force is singular at the wall (ratio 1): the motion is beyond what the \
                     bearing can carry, or the step is too large",
                    self.dofs[0],
                    self.dofs[1],
                    rho / self.clearance,
                    self.clearance,
                    v[0],
                    v[1]
                ),
            });
        }
        let half = 0.5 * omega;
        let a = v[0] + half * y;
        let b = v[1] - half * x;
        let beta = if a == 0.0 && b == 0.0 {
            0.0
        } else {
            b.atan2(a)
        };
        // theta = beta - pi/2 + off: cos = sin(beta) cos(off) ... rotated by beta - pi/2
        let (sb, cb) = beta.sin_cos();
        let (c0, s0) = (sb, -cb); // cos and sin of beta - pi/2
        let mut r = [0.0; 2];
        let mut kx = [0.0; 4];
        let mut cv = [0.0; 4];
        for &(co, so, w) in &self.points {
            let ct = c0 * co - s0 * so;
            let st = s0 * co + c0 * so;
            let h = self.clearance - x * ct - y * st;
            let inv3 = 1.0 / (h * h * h);
            let g = (a * ct + b * st).max(0.0);
            let n = [ct, st];
            let f = w * g * inv3;
            let dgx = [-half * st, half * ct]; // dg/dx, dg/dy
            let three = 3.0 * g * inv3 / h;
            let dx = [dgx[0] * inv3 + three * ct, dgx[1] * inv3 + three * st];
            let dv = [ct * inv3, st * inv3];
            for i in 0..2 {
                r[i] += f * n[i];
                for j in 0..2 {
                    kx[2 * i + j] += w * dx[j] * n[i];
                    cv[2 * i + j] += w * dv[j] * n[i];
                }
            }
        }
        let scale = self.radius * self.viscosity * self.length.powi(3);
        for value in r.iter_mut().chain(kx.iter_mut()).chain(cv.iter_mut()) {
            *value *= scale;
        }
        Ok((r, kx, cv))
    }
}

impl Element for ShortJournalBearing {
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
        let (f, kx, cv) = self.force([x[0], x[1]], [v[0], v[1]], self.law.omega(t))?;
        r[0] += f[0];
        r[1] += f[1];
        if let Some(tg) = tangent {
            for k in 0..4 {
                tg.kx[k] += kx[k];
                tg.cv[k] += cv[k];
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

/// `duhamel.rotor.journal.JournalElement`: the definition of a [`ShortJournalBearing`],
/// with a linear part `k0 x + c0 x'` taken out when given.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JournalElementDef {
    pub dofs: (usize, usize),
    pub radius: f64,
    pub length: f64,
    pub clearance: f64,
    pub viscosity: f64,
    #[serde(default = "at_rest")]
    pub speed: SpeedLaw,
    #[serde(default)]
    pub k0: Option<[[f64; 2]; 2]>,
    #[serde(default)]
    pub c0: Option<[[f64; 2]; 2]>,
}

fn at_rest() -> SpeedLaw {
    SpeedLaw::Constant(0.0)
}

crate::element_variants! {
    /// A journal bearing's film force, whole or less a linear part.
    pub enum JournalFilm {
        Whole(ShortJournalBearing),
        Less(Shifted<ShortJournalBearing>),
    }
}

impl Definition for JournalElementDef {
    const NAME: &'static str = "JournalElement";
    const SIGNATURE: &'static str =
        "(dofs, *, radius, length, clearance, viscosity, speed=0.0, k0=None, c0=None)";
    const DOC: &'static str = r#"A short (Ocvirk) journal bearing as an element on the journal's dofs ``dofs=(x, y)``
(to the ground): the film force of a plain journal of `radius`, `length`, radial
`clearance` and oil `viscosity` (Pa s) turning at `speed` (rad/s, or a :mod:`duhamel.speed`
law), with half-film (Guembel) cavitation, integrated over the film; exact tangents. With
`k0`, `c0` (2 x 2) the element is the film force minus ``k0 x + c0 x'`` (a linear part
carried by the background instead); :meth:`evaluate` always gives the element's force.

Parameters
----------
dofs : pair of int or dof labels
    The journal centre's dofs ``(x, y)``.
radius, length, clearance : float
    The bearing's geometry (m), > 0.
viscosity : float
    Oil viscosity (Pa s), > 0.
speed : float or speed law
    The journal's speed (rad/s) or a :mod:`duhamel.speed` law.
k0, c0 : 2 x 2 matrices, optional
    A linear part taken out.

Examples
--------
>>> from duhamel.rotor.journal import JournalElement
>>> e = JournalElement((0, 1), radius=0.025, length=0.02, clearance=5e-5, viscosity=0.02,
...                    speed=300.0)
>>> r, K, C = e.evaluate([2e-5, -1e-5], [0.0, 0.0])
>>> K.shape, bool(r[0] > 0)
((2, 2), True)
"#;
    const LEGACY: &'static [&'static str] = &[
        "dof_x",
        "dof_y",
        "radius",
        "length",
        "clearance",
        "viscosity",
        "speed",
        "k0",
        "c0",
    ];
    type Runtime = JournalFilm;

    fn build(&self) -> Result<JournalFilm, CoreError> {
        let (x, y) = self.dofs;
        let (r, l, c, mu) = (self.radius, self.length, self.clearance, self.viscosity);
        let film = ShortJournalBearing::new(x, y, r, l, c, mu, self.speed)?;
        let scale = r * mu * l.powi(3) / c.powi(3);
        if !(scale.is_finite() && scale < 1e250) {
            return Err(CoreError::InvalidInput {
                name: "clearance",
                problem: format!(
                    "with `radius` {r:e}, `length` {l:e} and `viscosity` {mu:e}: the film force's \
                     scale radius viscosity length^3 / clearance^3 = {scale:e} overflows the \
                     double range, beyond any physical bearing (check `clearance`)"
                ),
            });
        }
        if self.k0.is_none() && self.c0.is_none() {
            return Ok(JournalFilm::Whole(film));
        }
        let flat = |m: Option<[[f64; 2]; 2]>| m.unwrap_or_default().concat();
        let shifted = Shifted::new(Box::new(film), flat(self.k0), flat(self.c0))?;
        Ok(JournalFilm::Less(shifted))
    }

    fn rename(old: &str) -> Option<(&'static str, Option<usize>)> {
        super::hysteretic::rename_axes(old)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn bearing(omega: f64) -> ShortJournalBearing {
        ShortJournalBearing::new(0, 1, 0.05, 0.03, 1e-4, 0.02, SpeedLaw::Constant(omega)).unwrap()
    }

    /// Ocvirk's static forces at eccentricity ratio `e` along +x: radial (restoring, along
    /// +x) `K e^2 / (1 - e^2)^2`, tangential `-K pi e / (4 (1 - e^2)^(3/2))` along +y, with
    /// `K = mu omega R L^3 / c^2`.
    #[test]
    fn static_forces_are_ocvirks() {
        let omega = 300.0;
        let b = bearing(omega);
        let k = 0.02 * omega * 0.05 * 0.03f64.powi(3) / 1e-8;
        for e in [0.1, 0.3, 0.6, 0.8, 0.9] {
            let (f, _, _) = b.force([e * 1e-4, 0.0], [0.0, 0.0], omega).unwrap();
            let radial = k * e * e / (1.0 - e * e).powi(2);
            let tangential = -k * PI * e / (4.0 * (1.0 - e * e).powf(1.5));
            assert!(
                (f[0] / radial - 1.0).abs() < 1e-12,
                "{e}: {} {radial}",
                f[0]
            );
            assert!(
                (f[1] / tangential - 1.0).abs() < 1e-12,
                "{e}: {} {tangential}",
                f[1]
            );
        }
    }

    #[test]
    fn tangents_are_the_derivatives() {
        let b = bearing(250.0);
        let p = [3e-5, -4.5e-5];
        let v = [2e-3, -1e-3];
        let (_, kx, cv) = b.force(p, v, 250.0).unwrap();
        for j in 0..2 {
            let step = 1e-10;
            let (mut pp, mut pm, mut vp, mut vm) = (p, p, v, v);
            pp[j] += step;
            pm[j] -= step;
            vp[j] += 1e-7;
            vm[j] -= 1e-7;
            let (fp, _, _) = b.force(pp, v, 250.0).unwrap();
            let (fm, _, _) = b.force(pm, v, 250.0).unwrap();
            let (gp, _, _) = b.force(p, vp, 250.0).unwrap();
            let (gm, _, _) = b.force(p, vm, 250.0).unwrap();
            for i in 0..2 {
                let dk = (fp[i] - fm[i]) / (2.0 * step);
                let dc = (gp[i] - gm[i]) / 2e-7;
                assert!(
                    (dk - kx[2 * i + j]).abs()
                        < 1e-6 * kx.iter().map(|a| a.abs()).fold(0.0, f64::max)
                );
                assert!(
                    (dc - cv[2 * i + j]).abs()
                        < 1e-6 * cv.iter().map(|a| a.abs()).fold(0.0, f64::max)
                );
            }
        }
    }

    #[test]
    fn wall_and_bad_parameters_are_errors() {
        let b = bearing(100.0);
        let err = b.force([1e-4, 0.0], [0.0, 0.0], 100.0).unwrap_err();
        assert!(err.to_string().contains("eccentricity ratio 1.0"), "{err}");
        assert!(
            ShortJournalBearing::new(0, 1, -1.0, 0.03, 1e-4, 0.02, SpeedLaw::Constant(0.0))
                .is_err()
        );
        assert!(
            ShortJournalBearing::new(2, 2, 0.05, 0.03, 1e-4, 0.02, SpeedLaw::Constant(0.0))
                .is_err()
        );
    }
}
