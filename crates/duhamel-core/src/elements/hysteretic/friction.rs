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
//! **Uniaxial** ([`FrictionPendulum::uniaxial`]): one dof, the same law on a line
//! (`|f| <= mu W`, the return mapping a clamp): the bearing of a plane (2-D) model.
//!
//! **Velocity-dependent friction** ([`FrictionPendulum::with_velocity`]): the friction
//! coefficient of PTFE-type sliders, `mu(s) = mu_fast - (mu_fast - mu_slow) exp(-rate s)` with
//! `s = |u'|` the sliding speed (OpenSees' `VelDependent` friction model; `mu` is then
//! `mu_fast`); the surface `|f| <= mu(s) W` moves with the velocity, and the sliding force's
//! tangent gains `df/du' = W mu'(s) n (u' / s)^T`. The pre-sliding stiffness stays
//! `k0 = mu_fast W / Y`.
//!
//! `W` is constant: no coupling with the vertical motion or the axial force, no pressure
//! dependence of the friction, no uplift. Internal variables:
//! `[u_c_x, u_c_y, f_c_x, f_c_y]` (the `y` entries 0 for a uniaxial bearing). **Initial
//! state:** virgin (`f = 0`) at `u = 0` and loaded along the straight line to the initial
//! displacement (`f = k0 u` capped at `mu W` in its direction); [`Element::eval`] (no
//! history) is this virgin loading.

use super::common::{check, finite};
use crate::elements::element::distinct;
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;

/// `hypot(a, b)`, without the call when a component is zero (a uniaxial bearing, a
/// bidirectional one moving along an axis): `hypot(a, +-0) = |a|` exactly (IEEE 754; glibc's
/// agrees bit for bit, NaN and infinities included).
#[inline(always)]
fn length(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        a.abs()
    } else if a == 0.0 {
        b.abs()
    } else {
        a.hypot(b)
    }
}

/// The default yield (pre-sliding) displacement `Y`, in metres (0.25 mm).
pub const DEFAULT_YIELD_DISPLACEMENT: f64 = 2.5e-4;

/// Single friction pendulum bearing on the dofs `(dof_x, dof_y)`, or on `dof_x` alone.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionPendulum {
    dofs: Vec<usize>,
    radius: f64,
    mu: f64,
    weight: f64,
    yield_displacement: f64,
    /// `(mu_slow, rate)` of velocity-dependent friction (None: constant `mu`).
    velocity: Option<(f64, f64)>,
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
            dofs: vec![dof_x, dof_y],
            radius,
            mu,
            weight,
            yield_displacement,
            velocity: None,
        })
    }

    /// Uniaxial bearing on `dof_x` (a plane model), the parameters as in [`Self::new`].
    pub fn uniaxial(
        dof_x: usize,
        radius: f64,
        mu: f64,
        weight: f64,
        yield_displacement: f64,
    ) -> Result<Self, CoreError> {
        let mut e = Self::new(dof_x, dof_x + 1, radius, mu, weight, yield_displacement)?;
        e.dofs = vec![dof_x];
        Ok(e)
    }

    /// The same bearing with velocity-dependent friction from `mu_fast = mu` down to
    /// `mu_slow` (`0 <= mu_slow <= mu`) at rest, with `rate >= 0` (s/m; 0: constant `mu`).
    pub fn with_velocity(mut self, mu_slow: f64, rate: f64) -> Result<Self, CoreError> {
        check("mu_slow", mu_slow, false)?;
        check("rate", rate, false)?;
        if mu_slow > self.mu {
            return Err(CoreError::InvalidInput {
                name: "mu_slow",
                problem: format!("must be <= mu (mu_fast) = {}, got {mu_slow}", self.mu),
            });
        }
        self.velocity = (rate > 0.0 && mu_slow < self.mu).then_some((mu_slow, rate));
        Ok(self)
    }

    /// The friction coefficient and its derivative at sliding speed `s`.
    pub fn coefficient(&self, s: f64) -> (f64, f64) {
        match self.velocity {
            None => (self.mu, 0.0),
            Some((slow, rate)) => {
                let e = (-rate * s).exp();
                (self.mu - (self.mu - slow) * e, rate * (self.mu - slow) * e)
            }
        }
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
    /// and its consistent tangent `df/du` (row-major 2 x 2), with the constant `mu`.
    pub fn friction(&self, u_c: [f64; 2], f_c: [f64; 2], u: [f64; 2]) -> ([f64; 2], [f64; 4]) {
        self.friction_at(u_c, f_c, u, self.mu)
    }

    /// As [`Self::friction`] with the friction coefficient `mu` (the pre-sliding stiffness
    /// `k0 = mu_fast W / Y` whatever `mu`).
    fn friction_at(
        &self,
        u_c: [f64; 2],
        f_c: [f64; 2],
        u: [f64; 2],
        mu: f64,
    ) -> ([f64; 2], [f64; 4]) {
        let f_max = mu * self.weight;
        let k0 = self.mu * self.weight / self.yield_displacement;
        let trial = [f_c[0] + k0 * (u[0] - u_c[0]), f_c[1] + k0 * (u[1] - u_c[1])];
        let norm = length(trial[0], trial[1]);
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

    /// The friction force and its tangents `df/du`, `df/du'` (row-major 2 x 2) at `(u, v)`
    /// from the committed `(u_c, f_c)`.
    fn state(
        &self,
        u_c: [f64; 2],
        f_c: [f64; 2],
        u: [f64; 2],
        v: [f64; 2],
    ) -> ([f64; 2], [f64; 4], [f64; 4]) {
        // With constant friction the speed and the sliding test serve nothing (`dmu = 0`):
        // two `hypot` calls of the three per evaluation left out.
        let Some(_) = self.velocity else {
            let (f, kf) = self.friction_at(u_c, f_c, u, self.mu);
            return (f, kf, [0.0; 4]);
        };
        let speed = length(v[0], v[1]);
        let (mu, dmu) = self.coefficient(speed);
        let (f, kf) = self.friction_at(u_c, f_c, u, mu);
        let mut cf = [0.0; 4];
        let f_max = mu * self.weight;
        let sliding = f_max > 0.0 && length(f[0], f[1]) >= f_max * (1.0 - 1e-14);
        if sliding && dmu != 0.0 && speed > 0.0 {
            let n = [f[0] / f_max, f[1] / f_max];
            let dir = [v[0] / speed, v[1] / speed];
            let w = self.weight * dmu;
            cf = [
                w * n[0] * dir[0],
                w * n[0] * dir[1],
                w * n[1] * dir[0],
                w * n[1] * dir[1],
            ];
        }
        (f, kf, cf)
    }

    /// The local `(x, y)` of `x` (`y = 0` for a uniaxial bearing).
    fn plane(&self, x: &[f64]) -> [f64; 2] {
        [x[0], if self.dofs.len() == 2 { x[1] } else { 0.0 }]
    }

    fn add(
        &self,
        u: [f64; 2],
        (f, kf, cf): ([f64; 2], [f64; 4], [f64; 4]),
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let kp = self.weight / self.radius;
        let force = [kp * u[0] + f[0], kp * u[1] + f[1]];
        finite(t, &force)?;
        finite(t, &kf)?;
        finite(t, &cf)?;
        let n = self.dofs.len();
        for i in 0..n {
            r[i] += force[i];
        }
        if let Some(tg) = tangent {
            for i in 0..n {
                for j in 0..n {
                    tg.kx[i * n + j] += kf[2 * i + j];
                    tg.cv[i * n + j] += cf[2 * i + j];
                }
                tg.kx[i * n + i] += kp;
            }
        }
        Ok(())
    }
}

impl Element for FrictionPendulum {
    fn path_reads(&self) -> Option<(bool, bool)> {
        Some((self.uses_velocity(), false))
    }

    fn restarts_exactly(&self) -> bool {
        false
    }

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
        let (u, vel) = (self.plane(x), self.plane(v));
        self.add(u, self.state([0.0; 2], [0.0; 2], u, vel), t, r, tangent)
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        self.velocity.is_some()
    }

    fn state_len(&self) -> usize {
        4
    }

    fn initial_state(&self, x: &[f64], v: &[f64], state: &mut [f64]) {
        let u = self.plane(x);
        let (f, _, _) = self.state([0.0; 2], [0.0; 2], u, self.plane(v));
        state.copy_from_slice(&[u[0], u[1], f[0], f[1]]);
    }

    fn eval_path(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        history: PathState<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let c = history.committed;
        let u = self.plane(x);
        let (f, kf, cf) = self.state([c[0], c[1]], [c[2], c[3]], u, self.plane(v));
        self.add(u, (f, kf, cf), t, r, tangent)?;
        history.trial.copy_from_slice(&[u[0], u[1], f[0], f[1]]);
        Ok(())
    }
}

#[cfg(test)]
#[path = "friction_tests.rs"]
mod tests;
