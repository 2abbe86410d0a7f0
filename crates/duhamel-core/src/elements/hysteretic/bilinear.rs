//! Bilinear elastoplastic element with kinematic hardening (OpenSees `Steel01` without
//! isotropic hardening).
//!
//! With the deformation `u = x_i - x_j` (`x_i` when grounded) the element force `F` acts as
//! `r_i = +F`, `r_j = -F`. Elastic stiffness `k`, yield force `fy` (yield deformation
//! `uy = fy / k`), post-yield stiffness `alpha k`. The force stays between the two bounding
//! lines of slope `alpha k`,
//!
//! ```text
//! F_lower(u) = alpha k u - (1 - alpha) fy  <=  F  <=  F_upper(u) = alpha k u + (1 - alpha) fy,
//! ```
//!
//! and moves with slope `k` inside the band: the classical linear kinematic hardening law
//! (back force `alpha k u_p` at plastic deformation `u_p`, `F = k (u - u_p)`). From the
//! committed `(u_c, F_c)` the return mapping to the trial `u` is exact for any increment:
//!
//! ```text
//! F_trial = F_c + k (u - u_c),   F = min(max(F_trial, F_lower(u)), F_upper(u)),
//! ```
//!
//! with the consistent tangent `dF/du = k` when `F_trial` lies strictly inside or on the band
//! and `alpha k` when it is cut back (the derivative of the map above; at the corner the
//! elastic branch is taken). Internal variables: `[u_c, F_c]`.
//!
//! **Initial state.** The element is virgin at `u = 0` and is taken as loaded monotonically
//! to the initial deformation `u_0`: `F_0 = B(u_0)`, the backbone
//! `B(u) = min(max(k u, F_lower(u)), F_upper(u))` (`k u` below yield, then slope `alpha k`).
//! [`Element::eval`] (no history) returns the same backbone.
//!
//! **A given initial state** `(u0, F0)` at `x = 0` (e.g. after a gravity analysis): the
//! element works in the deformation and force measured from it, `u' = u - u0`, `F' = F - F0`
//! (its internal variables too), with the band's distances from `F0` at `u0`; the force on
//! the equations is `F'`.
//!
//! A symmetric cycle between `+-u_max > uy` dissipates `4 (1 - alpha) fy (u_max - uy)`.

use serde::{Deserialize, Serialize};

use super::common::{check, check_alpha, finite, local_dofs, relative, scatter};
use crate::elements::definition::{along, pair_matrix, Definition, Pair};
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;

/// `duhamel.elements.Bilinear`: the definition of a [`Bilinear`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BilinearDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub k: f64,
    pub fy: f64,
    pub alpha: f64,
    #[serde(default)]
    pub initial_deformation: f64,
    #[serde(default)]
    pub initial_force: Option<f64>,
}

impl BilinearDef {
    /// The initial state `(u0, F0)` when one is given (None: virgin at `x = 0`).
    fn initial(&self) -> Option<(f64, f64)> {
        if self.initial_deformation == 0.0 && self.initial_force.is_none() {
            return None;
        }
        Some((
            self.initial_deformation,
            self.initial_force.unwrap_or(f64::NAN),
        ))
    }
}

impl Definition for BilinearDef {
    const NAME: &'static str = "Bilinear";
    const SIGNATURE: &'static str =
        "(i, j=None, *, k, fy, alpha, initial_deformation=0.0, initial_force=None)";
    const DOC: &'static str = r#"Bilinear elastoplastic spring with kinematic hardening (OpenSees ``Steel01`` without
isotropic hardening) on the deformation ``u = x_i - x_j`` (``j=None``: to the ground):
elastic stiffness `k`, yield force `fy`, post-yield stiffness ``alpha k`` (0:
elastic-perfectly plastic, negative: softening). The force stays between the lines
``alpha k u +- (1 - alpha) fy``; the return mapping is exact for any increment. The element
starts virgin at ``u = 0`` (an initial deformation is taken as reached monotonically). A
symmetric cycle of amplitude ``u_max > fy / k`` dissipates ``4 (1 - alpha) fy (u_max - fy / k)``.

**Initial state** (a model whose ``x = 0`` is a loaded state, e.g. after a gravity
analysis, :func:`duhamel.opensees.from_opensees`): at ``x = 0`` the element is at the
deformation `initial_deformation` ``u0`` with the force `initial_force` ``F0`` (a state
reached on any path: ``|F0 - alpha k u0| <= (1 - alpha) fy``; default: loaded monotonically,
the backbone at ``u0``). Its deformation is then ``u0 + x_i - x_j`` and the force it adds to
the equations is its change from ``F0`` (the loads that hold ``F0`` are not in the model:
the element's total force is ``F0`` plus the one reported).

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
k : float
    Elastic stiffness, > 0.
fy : float
    Yield force, > 0.
alpha : float
    Post-yield stiffness ratio, <= 1.
initial_deformation : float, default 0.0
    The deformation at ``x = 0``.
initial_force : float, optional
    The force at ``x = 0`` (default: the backbone's at `initial_deformation`).

Examples
--------
>>> import numpy as np, duhamel
>>> sdof = duhamel.System(np.eye(1), 10.0 * np.eye(1), zeta=0.02)
>>> sdof = sdof.add(duhamel.elements.Bilinear(0, k=100.0, fy=1.0, alpha=0.05))
>>> sol = duhamel.solve(sdof, duhamel.Semianalytic(), t_end=2.0, dt=0.01, v0=[1.0])
>>> bool(abs(sol.elements[0].axial_force).max() <= 1.0 + 0.05 * 100 * 0.2)
True

A hinge yielded under gravity (``F0`` on the upper line) and unloaded from there:

>>> hinge = duhamel.elements.Bilinear(0, k=100.0, fy=1.0, alpha=0.0,
...                                   initial_deformation=0.03, initial_force=1.0)
>>> duhamel.elements.drive(hinge, [0.0, 0.005, -0.01]).force.tolist()
[0.0, 0.0, -1.5]
"#;
    const LEGACY: &'static [&'static str] = &["i", "j", "k", "fy", "alpha"];
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] =
        &[("k", "1.0"), ("fy", "1.0"), ("alpha", "0.0")];
    type Runtime = Bilinear;

    fn build(&self) -> Result<Bilinear, CoreError> {
        let e = Bilinear::new(self.i, self.j, self.k, self.fy, self.alpha)?;
        match self.initial() {
            None => Ok(e),
            Some((u0, f0)) => e.starting_at(u0, self.initial_force.map(|_| f0)),
        }
    }

    fn directions(&self) -> Option<Vec<Pair>> {
        along(self.i, self.j)
    }

    fn passive(&self) -> bool {
        // an initial force is held by loads outside the model, whose work is not counted
        self.alpha >= 0.0 && self.initial().is_none()
    }

    fn linear_stiffness(&self) -> Option<Vec<f64>> {
        Some(pair_matrix(self.j, self.k)) // the initial stiffness
    }

    fn tangent_bound(&self) -> Option<(f64, f64)> {
        Some((self.k.abs() * self.alpha.abs().max(1.0), 0.0)) // elastic k, post-yield alpha k
    }

    fn stored_energy(&self, _u: &[f64], f: &[f64]) -> f64 {
        match self.build().ok().and_then(|e| e.initial_force()) {
            // measured from the initial state, as the force
            Some(f0) => ((f[0] + f0).powi(2) - f0 * f0) / (2.0 * self.k),
            None => f[0] * f[0] / (2.0 * self.k),
        }
    }
}

/// An initial state: the force `F0` at `x = 0` and the distances `(c_up, c_down)` from it
/// to the upper and lower bounding lines there. The element then works in the variables
/// measured from that state (`u - u0`, `F - F0`: no cancellation of the large `F0` in the
/// small increments), where the band is `alpha k u' - c_down <= F' <= alpha k u' + c_up`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Start {
    f0: f64,
    up: f64,
    down: f64,
}

/// Bilinear kinematic-hardening spring between dofs `i` and `j` (or `i` and ground).
#[derive(Debug, Clone, PartialEq)]
pub struct Bilinear {
    dofs: Vec<usize>,
    k: f64,
    fy: f64,
    alpha: f64,
    /// The state at `x = 0` when one is given (None: virgin there).
    initial: Option<Start>,
}

impl Bilinear {
    /// Element from dof `i` to dof `j` (`None`: to ground) with elastic stiffness `k > 0`,
    /// yield force `fy > 0` and post-yield stiffness ratio `alpha <= 1` (0: elastic-perfectly
    /// plastic, negative: softening, 1: linear). Errors name the parameter (`"j"` when
    /// `j == Some(i)`).
    pub fn new(i: usize, j: Option<usize>, k: f64, fy: f64, alpha: f64) -> Result<Self, CoreError> {
        check("k", k, true)?;
        check("fy", fy, true)?;
        check_alpha(alpha)?;
        Ok(Self {
            dofs: local_dofs(i, j)?,
            k,
            fy,
            alpha,
            initial: None,
        })
    }

    /// The same element in the state `(u0, F0)` at `x = 0` (`f0` None: the backbone's force
    /// at `u0`): its deformation is `u0 + x_i - x_j` and its force the change from `F0`.
    /// Errors: a non-finite `u0`/`F0` or a force outside the band at `u0` (named
    /// `"initial_deformation"`, `"initial_force"`).
    pub fn starting_at(mut self, u0: f64, f0: Option<f64>) -> Result<Self, CoreError> {
        if !u0.is_finite() {
            return Err(CoreError::InvalidInput {
                name: "initial_deformation",
                problem: format!("must be finite, got {u0}"),
            });
        }
        let f0 = match f0 {
            None => self.backbone(u0).0,
            Some(f) => {
                let line = self.alpha * self.k * u0;
                let band = (1.0 - self.alpha) * self.fy;
                // OpenSees' state read back: on the line to its round-off
                let slack = 1e-9 * (band.abs() + line.abs());
                if !f.is_finite() || (f - line).abs() > band + slack {
                    return Err(CoreError::InvalidInput {
                        name: "initial_force",
                        problem: format!(
                            "must lie between alpha k u0 -+ (1 - alpha) fy = {:.6e} and {:.6e} \
                             at initial_deformation {u0:e} (a state the element can reach), got {f}",
                            line - band,
                            line + band
                        ),
                    });
                }
                f.clamp(line - band, line + band)
            }
        };
        let line = self.alpha * self.k * u0;
        let band = (1.0 - self.alpha) * self.fy;
        self.initial = Some(Start {
            f0,
            up: (line + band - f0).max(0.0),
            down: (f0 - line + band).max(0.0),
        });
        Ok(self)
    }

    /// The force and tangent from the initial state `s` (both measured from it): the
    /// return mapping of [`Self::response`] in the shifted band.
    fn shifted(&self, s: &Start, u_c: f64, f_c: f64, u: f64) -> (f64, f64) {
        let trial = f_c + self.k * (u - u_c);
        let line = self.alpha * self.k * u;
        if trial > line + s.up {
            (line + s.up, self.alpha * self.k)
        } else if trial < line - s.down {
            (line - s.down, self.alpha * self.k)
        } else {
            (trial, self.k)
        }
    }

    /// The force `F0` at `x = 0` of an element with an initial state (None: virgin).
    pub fn initial_force(&self) -> Option<f64> {
        self.initial.map(|s| s.f0)
    }

    /// Elastic stiffness `k`.
    pub fn k(&self) -> f64 {
        self.k
    }

    /// Yield force `fy`.
    pub fn fy(&self) -> f64 {
        self.fy
    }

    /// Post-yield stiffness ratio `alpha`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// Yield deformation `uy = fy / k`.
    pub fn yield_deformation(&self) -> f64 {
        self.fy / self.k
    }

    /// The force and consistent tangent `(F, dF/du)` at deformation `u` reached from the
    /// committed deformation `u_c` and force `f_c` (the return mapping).
    pub fn response(&self, u_c: f64, f_c: f64, u: f64) -> (f64, f64) {
        let trial = f_c + self.k * (u - u_c);
        let line = self.alpha * self.k * u;
        let band = (1.0 - self.alpha) * self.fy;
        if trial > line + band {
            (line + band, self.alpha * self.k)
        } else if trial < line - band {
            (line - band, self.alpha * self.k)
        } else {
            (trial, self.k)
        }
    }

    /// The force and tangent `(F, dF/du)` at deformation `u` from the committed variables
    /// `(u_c, F_c)`, measured from the initial state when there is one (what
    /// [`Element::eval_path`] computes).
    #[inline(always)]
    pub(crate) fn path_response(&self, (uc, fc): (f64, f64), u: f64) -> (f64, f64) {
        match &self.initial {
            None => self.response(uc, fc, u),
            Some(s) => self.shifted(s, uc, fc, u),
        }
    }

    /// The virgin backbone `(F, dF/du)` at deformation `u`.
    pub fn backbone(&self, u: f64) -> (f64, f64) {
        self.response(0.0, 0.0, u)
    }
}

impl crate::elements::registry::ScalarLaw for Bilinear {
    #[inline(always)]
    fn path_response(&self, committed: (f64, f64), u: f64) -> (f64, f64) {
        Bilinear::path_response(self, committed, u)
    }
}

impl Element for Bilinear {
    fn path_reads(&self) -> Option<(bool, bool)> {
        Some((false, false))
    }

    fn restarts_exactly(&self) -> bool {
        true
    }

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
        let (f, kt) = match &self.initial {
            None => self.backbone(relative(x)),
            Some(s) => self.shifted(s, 0.0, 0.0, relative(x)),
        };
        finite(t, &[f, kt])?;
        scatter(f, kt, r, tangent.map(|tg| tg.kx));
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        false
    }

    fn state_len(&self) -> usize {
        2
    }

    fn initial_state(&self, x: &[f64], _v: &[f64], state: &mut [f64]) {
        let u = relative(x);
        state[0] = u;
        state[1] = match &self.initial {
            None => self.backbone(u).0,
            Some(s) => self.shifted(s, 0.0, 0.0, u).0,
        };
    }

    #[inline]
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
        let (f, kt) = self.path_response((history.committed[0], history.committed[1]), u);
        finite(t, &[f, kt])?;
        history.trial[0] = u;
        history.trial[1] = f;
        scatter(f, kt, r, tangent.map(|tg| tg.kx));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validates_parameters() {
        let name = |e: CoreError| match e {
            CoreError::InvalidInput { name, .. } => name,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            name(Bilinear::new(0, None, 0.0, 1.0, 0.1).unwrap_err()),
            "k"
        );
        assert_eq!(
            name(Bilinear::new(0, None, 1.0, f64::NAN, 0.1).unwrap_err()),
            "fy"
        );
        assert_eq!(
            name(Bilinear::new(0, None, 1.0, 1.0, 1.5).unwrap_err()),
            "alpha"
        );
        assert_eq!(
            name(Bilinear::new(0, None, 1.0, 1.0, f64::NAN).unwrap_err()),
            "alpha"
        );
        assert_eq!(
            name(Bilinear::new(2, Some(2), 1.0, 1.0, 0.1).unwrap_err()),
            "j"
        );
    }

    #[test]
    fn backbone_and_unloading() {
        let b = Bilinear::new(0, None, 100.0, 2.0, 0.1).unwrap(); // uy = 0.02
        assert_eq!(b.backbone(0.01), (1.0, 100.0));
        let (f, kt) = b.backbone(0.05);
        assert!((f - (2.0 + 10.0 * 0.03)).abs() < 1e-14 && kt == 10.0);
        // unload elastically by 2 uy, then yield in reverse on the lower line
        let (f1, k1) = b.response(0.05, f, 0.02);
        assert!((f1 - (f - 3.0)).abs() < 1e-14 && k1 == 100.0);
        let (f2, k2) = b.response(0.05, f, 0.0);
        assert!((f2 - (-1.8)).abs() < 1e-14 && k2 == 10.0);
    }

    #[test]
    fn an_initial_state_is_continued_as_the_total_return_mapping() {
        // virgin, loaded to u0 = 0.05 (yielded), unloaded to 0.03: the state (u0, F0)
        let b = Bilinear::new(0, None, 100.0, 2.0, 0.1).unwrap();
        let (f1, _) = b.backbone(0.05);
        let (f0, _) = b.response(0.05, f1, 0.03);
        let s = b.clone().starting_at(0.03, Some(f0)).unwrap();
        let (mut uc, mut fc) = (0.03, f0); // the total path
        let mut state = [0.0; 2];
        s.initial_state(&[0.0], &[0.0], &mut state);
        for du in [0.01, 0.04, -0.02, -0.09, 0.03] {
            let u = uc + du;
            let (f, kt) = b.response(uc, fc, u);
            let mut r = [0.0];
            let mut kx = [0.0];
            let mut trial = [0.0; 2];
            let history = PathState {
                committed: &state,
                trial: &mut trial,
            };
            let tg = Tangent {
                kx: &mut kx,
                cv: &mut [0.0],
            };
            s.eval_path(&[u - 0.03], &[0.0], 0.0, history, &mut r, Some(tg))
                .unwrap();
            assert!(
                (r[0] - (f - f0)).abs() < 1e-12 && kx[0] == kt,
                "{du}: {r:?} {f} {f0}"
            );
            state = trial;
            (uc, fc) = (u, f);
        }
        // a force the element cannot hold there is refused, named
        let e = b.clone().starting_at(0.0, Some(2.5)).unwrap_err();
        assert!(matches!(
            e,
            CoreError::InvalidInput {
                name: "initial_force",
                ..
            }
        ));
    }

    #[test]
    fn non_finite_state_is_an_error() {
        let b = Bilinear::new(0, Some(1), 1.0, 1.0, 0.0).unwrap();
        let mut r = [0.0; 2];
        let mut trial = [0.0; 2];
        let history = PathState {
            committed: &[0.0, 0.0],
            trial: &mut trial,
        };
        let e = b.eval_path(&[f64::NAN, 0.0], &[0.0; 2], 1.0, history, &mut r, None);
        assert!(matches!(e, Err(CoreError::NonFinite { .. })));
    }
}
