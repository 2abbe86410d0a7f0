//! Single friction pendulum isolator (bidirectional, coupled).
//!
//! On the two horizontal dofs `u = (x, y)` of the slider relative to the ground (or the
//! bearing's base), with a constant vertical load `W`, radius of curvature `R` and friction
//! coefficient `mu`, the restoring force (left-hand side) is
//!
//! ```text
//! r = (W / R) u + f,      |f| <= mu W,
//! ```
//!
//! the pendulum term (small-rotation approximation; period `2 pi sqrt(R / g)` when sliding
//! freely) plus the friction force `f`, elastoplastic with the circular interaction surface
//! `|f| = mu W` and the elastic pre-sliding stiffness `k0 = mu W / Y` (yield displacement `Y`;
//! the usual regularisation of Coulomb friction in isolator models, e.g. OpenSees'
//! `singleFPBearing` with `kInit = mu W / Y` or Constantinou et al.'s biaxial Bouc-Wen
//! friction model; values of `Y` in the literature are a few tenths of a millimetre). From
//! the committed `(u_c, f_c)`, radial return (backward Euler, exact for increments along a
//! straight line from a state on the surface when the direction does not change):
//!
//! ```text
//! f_trial = f_c + k0 (u - u_c);   f = f_trial  if |f_trial| <= mu W,
//!                                 f = mu W n,  n = f_trial / |f_trial|  otherwise,
//! ```
//!
//! with the consistent tangent `dr/du = (W/R) I + k0 I` (sticking) or
//! `(W/R) I + k0 (mu W / |f_trial|) (I - n n^T)` (sliding).
//!
//! `W` and `mu` are constant: no coupling with the vertical motion or the axial force, no
//! velocity or pressure dependence of the friction, no uplift. Internal variables:
//! `[u_c_x, u_c_y, f_c_x, f_c_y]`. **Initial state:** virgin (`f = 0`) at `u = 0` and loaded
//! along the straight line to the initial displacement (`f = k0 u` capped at `mu W` in its
//! direction); [`Element::eval`] (no history) is this virgin loading.

use super::common::{check, finite};
use crate::elements::element::distinct;
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;

/// The default yield (pre-sliding) displacement `Y`, in metres (0.25 mm).
pub const DEFAULT_YIELD_DISPLACEMENT: f64 = 2.5e-4;

/// Single friction pendulum bearing on the dofs `(dof_x, dof_y)`.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionPendulum {
    dofs: [usize; 2],
    radius: f64,
    mu: f64,
    weight: f64,
    yield_displacement: f64,
}

impl FrictionPendulum {
    /// Bearing on the dofs `(dof_x, dof_y)` (distinct) with radius of curvature `radius > 0`,
    /// friction coefficient `mu >= 0`, vertical load `weight > 0` and pre-sliding yield
    /// displacement `yield_displacement > 0` (e.g. [`DEFAULT_YIELD_DISPLACEMENT`] in metres).
    pub fn new(
        dof_x: usize,
        dof_y: usize,
        radius: f64,
        mu: f64,
        weight: f64,
        yield_displacement: f64,
    ) -> Result<Self, CoreError> {
        distinct(dof_x, dof_y)?;
        check("radius", radius, true)?;
        check("mu", mu, false)?;
        check("weight", weight, true)?;
        check("yield_displacement", yield_displacement, true)?;
        Ok(Self {
            dofs: [dof_x, dof_y],
            radius,
            mu,
            weight,
            yield_displacement,
        })
    }

    /// Radius of curvature `R`.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Friction coefficient `mu`.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// Vertical load `W`.
    pub fn weight(&self) -> f64 {
        self.weight
    }

    /// Pre-sliding yield displacement `Y`.
    pub fn yield_displacement(&self) -> f64 {
        self.yield_displacement
    }

    /// The friction force `f` at displacement `u` reached from the committed `(u_c, f_c)`,
    /// and its consistent tangent `df/du` (row-major 2 x 2).
    pub fn friction(&self, u_c: [f64; 2], f_c: [f64; 2], u: [f64; 2]) -> ([f64; 2], [f64; 4]) {
        let f_max = self.mu * self.weight;
        let k0 = f_max / self.yield_displacement;
        let trial = [f_c[0] + k0 * (u[0] - u_c[0]), f_c[1] + k0 * (u[1] - u_c[1])];
        let norm = trial[0].hypot(trial[1]);
        if norm <= f_max {
            (trial, [k0, 0.0, 0.0, k0])
        } else {
            let n = [trial[0] / norm, trial[1] / norm];
            let s = k0 * f_max / norm;
            let f = [f_max * n[0], f_max * n[1]];
            let kt = [
                s * (1.0 - n[0] * n[0]),
                -s * n[0] * n[1],
                -s * n[1] * n[0],
                s * (1.0 - n[1] * n[1]),
            ];
            (f, kt)
        }
    }

    fn add(
        &self,
        u: [f64; 2],
        (f, kf): ([f64; 2], [f64; 4]),
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let kp = self.weight / self.radius;
        let force = [kp * u[0] + f[0], kp * u[1] + f[1]];
        finite(t, &force)?;
        finite(t, &kf)?;
        r[0] += force[0];
        r[1] += force[1];
        if let Some(tg) = tangent {
            for (a, b) in tg.kx.iter_mut().zip(kf) {
                *a += b;
            }
            tg.kx[0] += kp;
            tg.kx[3] += kp;
        }
        Ok(())
    }
}

impl Element for FrictionPendulum {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn eval(
        &self,
        x: &[f64],
        _v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let u = [x[0], x[1]];
        self.add(u, self.friction([0.0; 2], [0.0; 2], u), t, r, tangent)
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        false
    }

    fn state_len(&self) -> usize {
        4
    }

    fn initial_state(&self, x: &[f64], _v: &[f64], state: &mut [f64]) {
        let u = [x[0], x[1]];
        let (f, _) = self.friction([0.0; 2], [0.0; 2], u);
        state.copy_from_slice(&[u[0], u[1], f[0], f[1]]);
    }

    fn eval_path(
        &self,
        x: &[f64],
        _v: &[f64],
        t: f64,
        history: PathState<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let c = history.committed;
        let u = [x[0], x[1]];
        let (f, kf) = self.friction([c[0], c[1]], [c[2], c[3]], u);
        self.add(u, (f, kf), t, r, tangent)?;
        history.trial.copy_from_slice(&[u[0], u[1], f[0], f[1]]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sticks_then_slides_radially() {
        let e = FrictionPendulum::new(0, 1, 2.0, 0.1, 50.0, 1e-3).unwrap(); // mu W = 5
        let (f, kt) = e.friction([0.0; 2], [0.0; 2], [3e-4, -4e-4]);
        assert!((f[0] - 1.5).abs() < 1e-14 && (f[1] + 2.0).abs() < 1e-14);
        assert_eq!(kt, [5000.0, 0.0, 0.0, 5000.0]);
        let (f, kt) = e.friction([0.0; 2], [0.0; 2], [0.03, 0.04]);
        assert!((f[0] - 3.0).abs() < 1e-14 && (f[1] - 4.0).abs() < 1e-14);
        // tangent: k0 (mu W / |f_trial|) (I - n n^T), |f_trial| = 250
        let s = 5000.0 * 5.0 / 250.0;
        let want = [s * 0.64, -s * 0.48, -s * 0.48, s * 0.36];
        assert!(kt.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12));
    }

    #[test]
    fn no_friction_is_a_pendulum() {
        let e = FrictionPendulum::new(0, 1, 2.0, 0.0, 50.0, 1e-3).unwrap();
        let mut r = [0.0; 2];
        e.eval(&[0.2, -0.1], &[1.0, 1.0], 0.0, &mut r, None)
            .unwrap();
        assert_eq!(r, [5.0, -2.5]);
    }
}
