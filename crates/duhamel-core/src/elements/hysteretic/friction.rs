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
    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
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
mod tests {
    use super::*;

    #[test]
    fn length_is_hypot_bit_for_bit() {
        for a in [
            0.0,
            -0.0,
            3.0,
            -2.5e-300,
            1.7e308,
            f64::INFINITY,
            f64::NAN,
            5e-324,
        ] {
            for b in [0.0, -0.0, a, 4.0] {
                assert_eq!(length(a, b).to_bits(), a.hypot(b).to_bits(), "{a} {b}");
                assert_eq!(length(b, a).to_bits(), b.hypot(a).to_bits(), "{b} {a}");
            }
        }
    }

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

    /// Central differences of the force at `(x, v)` from the committed `c`.
    fn numeric(e: &FrictionPendulum, c: &[f64; 4], x: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let n = x.len();
        let force = |x: &[f64], v: &[f64]| {
            let mut r = vec![0.0; n];
            let mut trial = [0.0; 4];
            let h = PathState {
                committed: c,
                trial: &mut trial,
            };
            e.eval_path(x, v, 0.0, h, &mut r, None).unwrap();
            r
        };
        let (mut kx, mut cv) = (vec![0.0; n * n], vec![0.0; n * n]);
        for j in 0..n {
            for (which, dst) in [(0, &mut kx), (1, &mut cv)] {
                let h = 1e-7;
                let (mut xp, mut vp, mut xm, mut vm) =
                    (x.to_vec(), v.to_vec(), x.to_vec(), v.to_vec());
                if which == 0 {
                    xp[j] += h;
                    xm[j] -= h;
                } else {
                    vp[j] += h;
                    vm[j] -= h;
                }
                let (rp, rm) = (force(&xp, &vp), force(&xm, &vm));
                for i in 0..n {
                    dst[i * n + j] = (rp[i] - rm[i]) / (2.0 * h);
                }
            }
        }
        (kx, cv)
    }

    #[test]
    fn velocity_dependent_tangents_are_consistent() {
        let e = FrictionPendulum::new(0, 1, 2.0, 0.1, 50.0, 1e-3)
            .unwrap()
            .with_velocity(0.04, 20.0)
            .unwrap();
        let c = [0.0, 0.0, 1.0, -0.5];
        for (x, v) in [([0.03, 0.01], [0.05, 0.02]), ([1e-4, 0.0], [0.0, 0.0])] {
            let (mut r, mut kx, mut cv) = ([0.0; 2], [0.0; 4], [0.0; 4]);
            let mut trial = [0.0; 4];
            let h = PathState {
                committed: &c,
                trial: &mut trial,
            };
            let tg = Tangent {
                kx: &mut kx,
                cv: &mut cv,
            };
            e.eval_path(&x, &v, 0.0, h, &mut r, Some(tg)).unwrap();
            let (nk, nc) = numeric(&e, &c, &x, &v);
            for k in 0..4 {
                assert!(
                    (kx[k] - nk[k]).abs() < 1e-5 * (1.0 + kx[k].abs()),
                    "{kx:?} {nk:?}"
                );
                assert!(
                    (cv[k] - nc[k]).abs() < 1e-5 * (1.0 + cv[k].abs()),
                    "{cv:?} {nc:?}"
                );
            }
        }
        // sliding fast: the force is mu_fast W; at rest the surface is mu_slow W
        let (mu, _) = e.coefficient(10.0);
        assert!((mu - 0.1).abs() < 1e-12);
        assert_eq!(e.coefficient(0.0).0, 0.04);
    }

    #[test]
    fn uniaxial_is_the_bidirectional_bearing_on_a_line() {
        let one = FrictionPendulum::uniaxial(3, 2.0, 0.1, 50.0, 1e-3).unwrap();
        let two = FrictionPendulum::new(3, 4, 2.0, 0.1, 50.0, 1e-3).unwrap();
        assert_eq!(one.dofs(), &[3]);
        let c = [0.001, 0.0, 4.0, 0.0];
        for x in [-0.02, 0.0015, 0.05] {
            let (mut r1, mut r2) = ([0.0; 1], [0.0; 2]);
            let (mut k1, mut c1, mut k2, mut c2) = ([0.0; 1], [0.0; 1], [0.0; 4], [0.0; 4]);
            let (mut t1, mut t2) = ([0.0; 4], [0.0; 4]);
            one.eval_path(
                &[x],
                &[0.1],
                0.0,
                PathState {
                    committed: &c,
                    trial: &mut t1,
                },
                &mut r1,
                Some(Tangent {
                    kx: &mut k1,
                    cv: &mut c1,
                }),
            )
            .unwrap();
            two.eval_path(
                &[x, 0.0],
                &[0.1, 0.0],
                0.0,
                PathState {
                    committed: &c,
                    trial: &mut t2,
                },
                &mut r2,
                Some(Tangent {
                    kx: &mut k2,
                    cv: &mut c2,
                }),
            )
            .unwrap();
            assert_eq!(r1[0], r2[0]);
            assert_eq!(k1[0], k2[0]);
            assert_eq!(t1, t2);
        }
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
