//! Fluid viscous damper in series with its brace (Maxwell model; OpenSees `ViscousDamper`
//! material with its axial stiffness `K`).
//!
//! On the deformation `u = x_i - x_j` (`x_i` when grounded) the brace (stiffness `k_b`) and
//! the damper (deformation `u_d`, force law `f` of [`ViscousDamper`], power law with the
//! regularisation below `v0`) carry the same force
//!
//! ```text
//! F = k_b (u - u_d) = f(u_d'),
//! ```
//!
//! so `u_d` is an internal variable that evolves in time. Over a step from the committed
//! `(u_d0, w0 = u_d0')` at time `t_c` to the evaluated time `t` (`h = (t - t_c) / 2`) the
//! trapezoidal rule `u_d = u_d0 + h (w0 + w)` (second order, A-stable) makes the force
//! balance one scalar equation in the damper's end velocity `w`:
//!
//! ```text
//! g(w) = f(w) + k_b h w - k_b (u - u_d0 - h w0) = 0,
//! ```
//!
//! strictly increasing in `w`: solved by Newton safeguarded by bisection. The consistent
//! tangent is `dF/du = k_b f'(w) / (f'(w) + k_b h)` (`k_b` at `h = 0`); the force does not
//! depend on the current velocity. The internal variables are `[u_d, u_d', t_c]`: the time
//! they were committed at gives the step length, whatever the integrator's step or
//! substep (the run's initial time comes from [`Element::initial_time`]). The element
//! starts unstressed: `u_d = u` at the initial state.

use super::common::{check, finite, relative, scatter};
use super::viscous::{ViscousDamper, DEFAULT_V0};
use crate::elements::definition::{along, Definition, Pair};
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;
use serde::{Deserialize, Serialize};

/// Fluid viscous damper in series with a brace of stiffness `k_b` (Maxwell model).
#[derive(Debug, Clone, PartialEq)]
pub struct MaxwellDamper {
    damper: ViscousDamper,
    kb: f64,
}

impl MaxwellDamper {
    /// The damper `damper` in series with a brace of stiffness `kb > 0` (named
    /// `"brace_stiffness"`).
    pub fn new(damper: ViscousDamper, kb: f64) -> Result<Self, CoreError> {
        check("brace_stiffness", kb, true)?;
        Ok(Self { damper, kb })
    }

    /// The brace stiffness `k_b`.
    pub fn brace_stiffness(&self) -> f64 {
        self.kb
    }

    /// The damper's end velocity `w`, the force `F` and `dF/du` after the half step `h`
    /// from `(ud0, w0)` at deformation `u`.
    pub fn solve(&self, u: f64, ud0: f64, w0: f64, h: f64) -> (f64, f64, f64) {
        let kb = self.kb;
        let b = kb * (u - ud0 - h * w0);
        let g = |w: f64| {
            let (f, df) = self.damper.force(w);
            (f + kb * h * w - b, df + kb * h, f, df)
        };
        // bracket the root of the increasing g around the committed velocity
        let mut w = w0;
        let (mut gw, mut dg, mut f, mut df) = g(w);
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        let scale = b.abs() + f.abs() + kb * h * w.abs();
        for _ in 0..200 {
            if gw.abs() <= 1e-15 * scale || gw == 0.0 {
                break;
            }
            if gw < 0.0 {
                lo = w;
            } else {
                hi = w;
            }
            let newton = if dg > 0.0 { w - gw / dg } else { f64::NAN };
            let next = if newton > lo && newton < hi {
                newton
            } else if lo.is_finite() && hi.is_finite() {
                0.5 * (lo + hi)
            } else {
                // expand toward the root
                let step = 2.0 * (1.0 + w.abs());
                if gw < 0.0 {
                    w + step
                } else {
                    w - step
                }
            };
            if next == w
                || (lo.is_finite() && hi.is_finite() && hi - lo <= 4.0 * f64::EPSILON * w.abs())
            {
                break;
            }
            w = next;
            (gw, dg, f, df) = g(w);
        }
        let dfdu = if df + kb * h > 0.0 {
            kb * df / (df + kb * h)
        } else {
            kb
        };
        (w, f, dfdu)
    }
}

impl Element for MaxwellDamper {
    fn dofs(&self) -> &[usize] {
        self.damper.dofs()
    }

    fn eval(
        &self,
        x: &[f64],
        _v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        // without a history: the brace alone from an unstressed, resting damper at u_d = 0
        let u = relative(x);
        finite(t, &[u])?;
        scatter(self.kb * u, self.kb, r, tangent.map(|tg| tg.kx));
        Ok(())
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
        let u = relative(x);
        let (ud0, w0, tc) = (
            history.committed[0],
            history.committed[1],
            history.committed[2],
        );
        let mut dt = t - tc;
        // a step is evaluated at or after the committed time; round-off of the time grid aside
        if dt < 0.0 && dt >= -1e-12 * (1.0 + t.abs()) {
            dt = 0.0;
        }
        if dt.is_nan() || dt < 0.0 {
            return Err(CoreError::InvalidInput {
                name: "t",
                problem: format!(
                    "the Maxwell damper was evaluated at t = {t}, before its committed time {tc}"
                ),
            });
        }
        let h = 0.5 * dt;
        let (w, f, dfdu) = self.solve(u, ud0, w0, h);
        let ud = ud0 + h * (w0 + w);
        finite(t, &[u, w, f, dfdu, ud])?;
        history.trial[0] = ud;
        history.trial[1] = w;
        history.trial[2] = t;
        scatter(f, dfdu, r, tangent.map(|tg| tg.kx));
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        false
    }

    fn state_len(&self) -> usize {
        3
    }

    fn initial_state(&self, x: &[f64], _v: &[f64], state: &mut [f64]) {
        state[0] = relative(x);
        state[1] = 0.0;
        state[2] = 0.0;
    }

    fn initial_time(&self, t0: f64, state: &mut [f64]) {
        state[2] = t0;
    }
}

/// `duhamel.elements.ViscousDamper`: the definition of a [`ViscousDamper`], or of a
/// [`MaxwellDamper`] with `brace_stiffness`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViscousDamperDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub c: f64,
    #[serde(default = "one")]
    pub exponent: f64,
    #[serde(default = "default_v0")]
    pub v0: f64,
    #[serde(default)]
    pub brace_stiffness: Option<f64>,
}

fn one() -> f64 {
    1.0
}

fn default_v0() -> f64 {
    DEFAULT_V0
}

crate::element_variants! {
    /// A damper alone or in series with its brace.
    pub enum DamperElement {
        Plain(ViscousDamper),
        Braced(MaxwellDamper),
    }
}

impl Definition for ViscousDamperDef {
    const NAME: &'static str = "ViscousDamper";
    const SIGNATURE: &'static str =
        "(i, j=None, *, c, exponent=1.0, v0=0.0001, brace_stiffness=None)";
    const DOC: &'static str = r#"Fluid viscous damper ``F = c |v|^exponent sgn(v)`` on ``v = v_i - v_j`` (``j=None``: to
the ground), including ``exponent < 1``, the usual nonlinear dampers: below the speed `v0` an
odd cubic matching the power law's force and slope at `v0` keeps the force smooth and its
slope finite, so Newton converges (`v0` defaults to 1e-4, 0.1 mm/s in SI units).

With `brace_stiffness` ``k_b`` the damper acts in series with its brace (Maxwell model,
OpenSees ``ViscousDamper`` material with ``K``): ``F = k_b (u - u_d) = c |u_d'|^exponent
sgn(u_d')`` with the damper's own deformation ``u_d`` an internal variable, integrated over
each step by the trapezoidal rule (second order) and solved per evaluation by a safeguarded
Newton iteration, with the consistent tangent. The element starts unstressed and stores
``F^2 / (2 k_b)`` in the brace. None (default): a rigid brace.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
c : float
    Damping coefficient, >= 0.
exponent : float, default 1.0
    Velocity exponent, > 0.
v0 : float, default 1e-4
    Regularisation speed, > 0.
brace_stiffness : float or None, default None
    Stiffness of the brace in series, > 0 (None: rigid).

Examples
--------
>>> import duhamel
>>> damper = duhamel.elements.ViscousDamper(2, 1, c=3e5, exponent=0.35)
>>> braced = duhamel.elements.ViscousDamper(2, 1, c=3e5, exponent=0.35, brace_stiffness=2e7)
"#;
    const LEGACY: &'static [&'static str] = &["i", "j", "c", "exponent", "v0", "brace_stiffness"];
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] = &[("c", "0.0")];
    type Runtime = DamperElement;

    fn build(&self) -> Result<DamperElement, CoreError> {
        let damper = ViscousDamper::new(self.i, self.j, self.c, self.exponent)?.with_v0(self.v0)?;
        Ok(match self.brace_stiffness {
            None => DamperElement::Plain(damper),
            Some(kb) => DamperElement::Braced(MaxwellDamper::new(damper, kb)?),
        })
    }

    fn directions(&self) -> Option<Vec<Pair>> {
        along(self.i, self.j)
    }

    fn passive(&self) -> bool {
        true
    }

    fn stored_energy(&self, _u: &[f64], f: &[f64]) -> f64 {
        match self.brace_stiffness {
            Some(kb) => f[0] * f[0] / (2.0 * kb),
            None => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(d: &MaxwellDamper, u: f64, committed: &[f64], t: f64) -> (f64, f64, Vec<f64>) {
        let mut trial = vec![0.0; 3];
        let (mut r, mut kx, mut cv) = (vec![0.0], vec![0.0], vec![0.0]);
        let tangent = Tangent {
            kx: &mut kx,
            cv: &mut cv,
        };
        let history = PathState {
            committed,
            trial: &mut trial,
        };
        d.eval_path(&[u], &[0.0], t, history, &mut r, Some(tangent))
            .unwrap();
        (r[0], kx[0], trial)
    }

    #[test]
    fn tangent_is_consistent_and_the_force_balances() {
        for a in [0.3, 1.0, 1.8] {
            let d = MaxwellDamper::new(ViscousDamper::new(0, None, 2.0, a).unwrap(), 50.0).unwrap();
            let committed = [0.01, 0.3, 1.0];
            // (not u = 0.013: the root w = 0, where |w|^1.8 defeats central differences)
            for u in [-0.2, 0.0135, 0.05, 0.4] {
                let (f, k, trial) = eval(&d, u, &committed, 1.02);
                // brace force = damper force, trapezoidal internal deformation
                assert!((f - 50.0 * (u - trial[0])).abs() <= 1e-10 * (1.0 + f.abs()));
                assert!((trial[0] - (0.01 + 0.01 * (0.3 + trial[1]))).abs() < 1e-15);
                let e = 1e-7;
                let fd = (eval(&d, u + e, &committed, 1.02).0
                    - eval(&d, u - e, &committed, 1.02).0)
                    / (2.0 * e);
                assert!(
                    (k - fd).abs() <= 1e-6 * (1.0 + k.abs()),
                    "a={a} u={u}: {k} vs {fd}"
                );
            }
        }
    }

    #[test]
    fn zero_step_keeps_the_damper_and_earlier_time_is_refused() {
        let d = MaxwellDamper::new(ViscousDamper::new(0, None, 2.0, 0.5).unwrap(), 50.0).unwrap();
        let (f, k, trial) = eval(&d, 0.3, &[0.1, 0.0, 2.0], 2.0);
        assert!((f - 50.0 * 0.2).abs() < 1e-12 && (k - 50.0).abs() < 1e-9);
        assert_eq!(trial[0], 0.1);
        let mut trial = vec![0.0; 3];
        let history = PathState {
            committed: &[0.1, 0.0, 2.0],
            trial: &mut trial,
        };
        let mut r = vec![0.0];
        assert!(d
            .eval_path(&[0.3], &[0.0], 1.0, history, &mut r, None)
            .is_err());
        assert!(MaxwellDamper::new(ViscousDamper::new(0, None, 2.0, 0.5).unwrap(), 0.0).is_err());
    }
}
