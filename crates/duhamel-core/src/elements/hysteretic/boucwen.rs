//! Bouc-Wen smooth hysteretic element.
//!
//! With the deformation `u = x_i - x_j` (`x_i` when grounded), elastic stiffness `k`, yield
//! force `fy` (yield deformation `uy = fy / k`) and post-yield ratio `alpha`, the element
//! force (`r_i = +F`, `r_j = -F`) and the hysteretic variable `z` follow
//!
//! ```text
//! F = alpha k u + (1 - alpha) fy z,
//! dz/du = (1 / uy) [A - |z|^n (beta sgn(du z) + gamma)],   A = 1.
//! ```
//!
//! `|z|` saturates at `z_max = (beta + gamma)^(-1/n)` (1 for the default `beta = gamma = 0.5`).
//! OpenSees' `BoucWen` material is the same model with `z` in displacement units
//! (`z_OpenSees = uy z`, `ko = k`).
//!
//! **Update.** Along the (monotone) increment from the committed `(u_c, z_c)` to the trial
//! `u`, with `s = sgn(u - u_c)`, the scaled variables `xi = s (u - u_c) / uy` and `w = s z`
//! obey the autonomous ODE `dw/dxi = g(w)`,
//!
//! ```text
//! g(w) = 1 - c_- |w|^n  (w < 0, c_- = gamma - beta),    g(w) = 1 - c_+ w^n  (w >= 0, c_+ = beta + gamma),
//! ```
//!
//! integrated from `w_c = s z_c` over `xi in [0, |u - u_c| / uy]`:
//!
//! * `n = 1`: each branch is linear, `w' = 1 + c w`, solved exactly,
//!   `w(xi) = w_0 e^(c xi) + xi phi_1(c xi)` with `phi_1(y) = (e^y - 1) / y`; a start in
//!   `w < 0` crosses `w = 0` (the switch of `sgn(du z)`) at `xi_0 = -ln(1 + c_- w_0) / c_-`,
//!   after which the `w >= 0` branch continues. Exact to round-off.
//! * general `n`: classical RK4 on each branch with uniform substeps of length at most
//!   `h = 0.01 / max(1, lambda)`, `lambda = n max(|c_-|, c_+) max(1, z_max)^(n-1)` (a bound of
//!   `|g'|`), so that `lambda h <= 0.01` (local error about `(lambda h)^5 / 120 ~ 1e-12`; the
//!   tests measure `1e-11` to `3e-11` in `z` for integer `n`, tolerance `1e-10`). The crossing of `w = 0` is
//!   located inside its substep by swapping the roles of the variables (Henon's trick):
//!   `xi_0 - xi_k = integral_{w_k}^0 dw / g(w)` by Simpson's rule, then the `w >= 0` branch
//!   starts exactly at `w = 0`. For integer `n` both branches are polynomials and the scheme
//!   keeps its fourth order through the switch; for non-integer `n` the power `|w|^n` is not
//!   smooth at `w = 0` and the substeps next to the switch are only of order `n + 1`
//!   (about `1e-8` in `z`: 9e-9 measured for `n = 1.5` at 40 steps a cycle). Past saturation (`xi` beyond
//!   `2 z_max + 40 / (n c_+^(1/n))`) `w` sits at `z_max` to round-off: the integration stops
//!   there, which bounds the work for huge increments.
//! * **Bounded work** (`boucwen/substeps.rs`). A branch runs at most
//!   [`substeps::MAX_SUBSTEPS`] substeps (`n > 16`: [`substeps::MAX_ADAPTIVE`] in all); it
//!   ends early where `w` crosses 0 or stops moving (the substep's increment rounds away: the
//!   substeps left change nothing). An increment
//!   that needs more is refused with [`CoreError::OutOfDomain`] naming the element and the
//!   count — parameters many orders of magnitude apart (`fy = 1e-300` with `beta = gamma =
//!   1e-300`: `z` saturates at 3.5e180) — never integrated with longer substeps than the
//!   bound on `lambda h` allows (before, they were stretched to fit 1e6, a million substeps
//!   per evaluation), nor cut short. Ordinary parameters stay far below it (the default
//!   shape needs at most `200 n + 4,000`).
//!
//! **Tangent.** The exact flow map satisfies `d w(xi) / d xi = g(w(xi))`, hence
//! `dF/du = alpha k + (1 - alpha) k g(s z)` at the trial state — exact for `n = 1`, and
//! consistent with the RK4 map to its accuracy otherwise. At `u = u_c` (no increment) the
//! one-sided loading tangent (`s = sgn z_c`) is returned.
//!
//! Internal variables: `[u_c, z_c]`. **Initial state:** virgin (`z = 0`) at `u = 0`, loaded
//! monotonically to the initial deformation; [`Element::eval`] (no history) is this virgin
//! loading curve.

use super::common::{check, check_alpha, finite, local_dofs, relative, scatter};
use crate::elements::definition::{along, deformation, pair_matrix, Definition, Pair};
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;
use serde::{Deserialize, Serialize};

mod adaptive;
mod substeps;

/// Above this exponent the substeps follow the local stiffness of `g` (see
/// [`Flow::advance_adaptive`]): the uniform bound `lambda ~ n` would cost `100 n`
/// substeps per unit of `xi`.
const ADAPTIVE_N: f64 = 16.0;
/// RK4 substep bound, `lambda h <= H0`.
const H0: f64 = 0.01;

/// Bouc-Wen hysteretic spring between dofs `i` and `j` (or `i` and ground).
#[derive(Debug, Clone, PartialEq)]
pub struct BoucWen {
    dofs: Vec<usize>,
    k: f64,
    fy: f64,
    alpha: f64,
    flow: Flow,
}

/// The flow of the scaled hysteretic variable, `dw/dxi = g(w)` (see the module
/// documentation), and its integration over an increment: exact for `n = 1` (here), by RK4
/// substeps (`boucwen/substeps.rs`) or, for `n > 16`, adaptive ones (`boucwen/adaptive.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Flow {
    n: f64,
    beta: f64,
    gamma: f64,
    /// `n` when it is a small integer (`powi`).
    int_n: Option<i32>,
}

/// `(e^y - 1) / y`.
fn phi1(y: f64) -> f64 {
    if y == 0.0 {
        1.0
    } else {
        y.exp_m1() / y
    }
}

/// `ln(1 + y) / y`.
fn ln1p_ratio(y: f64) -> f64 {
    if y == 0.0 {
        1.0
    } else {
        y.ln_1p() / y
    }
}

/// `w(xi)` for `w' = 1 + c w`, `w(0) = w0`.
fn linear_flow(w0: f64, c: f64, xi: f64) -> f64 {
    w0 * (c * xi).exp() + xi * phi1(c * xi)
}

/// The material of a [`BoucWen`] element (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoucWenParams {
    /// Elastic stiffness, `> 0`.
    pub k: f64,
    /// Yield force, `> 0`.
    pub fy: f64,
    /// Post-yield stiffness ratio, `<= 1`.
    pub alpha: f64,
    /// Exponent, `>= 1` (usually 1).
    pub n: f64,
    /// Shape parameter, `> 0` (usually 0.5).
    pub beta: f64,
    /// Shape parameter, `> -beta` (usually 0.5).
    pub gamma: f64,
}

impl BoucWen {
    /// Element from dof `i` to dof `j` (`None`: to ground) of the material `params`: `beta`
    /// and `gamma` such that `z` is bounded and unloading from saturation is possible.
    pub fn new(i: usize, j: Option<usize>, params: BoucWenParams) -> Result<Self, CoreError> {
        let BoucWenParams {
            k,
            fy,
            alpha,
            n,
            beta,
            gamma,
        } = params;
        check("k", k, true)?;
        check("fy", fy, true)?;
        check_alpha(alpha)?;
        if !(n.is_finite() && n >= 1.0) {
            return Err(CoreError::InvalidInput {
                name: "n",
                problem: format!("must be finite and >= 1, got {n}"),
            });
        }
        check("beta", beta, true)?;
        if !(gamma.is_finite() && gamma > -beta) {
            return Err(CoreError::InvalidInput {
                name: "gamma",
                problem: format!("must be finite and > -beta = {}, got {gamma}", -beta),
            });
        }
        let int_n = (n.fract() == 0.0 && n <= 64.0).then_some(n as i32);
        Ok(Self {
            dofs: local_dofs(i, j)?,
            k,
            fy,
            alpha,
            flow: Flow {
                n,
                beta,
                gamma,
                int_n,
            },
        })
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

    /// The exponent `n` and the shape parameters `(beta, gamma)`.
    pub fn shape(&self) -> (f64, f64, f64) {
        (self.flow.n, self.flow.beta, self.flow.gamma)
    }

    /// Yield deformation `uy = fy / k`.
    pub fn yield_deformation(&self) -> f64 {
        self.fy / self.k
    }

    /// The saturation value `z_max = (beta + gamma)^(-1/n)` of `|z|`.
    pub fn z_max(&self) -> f64 {
        self.flow.z_max()
    }

    /// The hysteretic variable and the force and consistent tangent `(z, F, dF/du)` at
    /// deformation `u` reached from the committed `(u_c, z_c)`; an increment that needs
    /// more substeps than the bound is refused ([`CoreError::OutOfDomain`], naming the
    /// element and the count).
    pub fn response(&self, u_c: f64, z_c: f64, u: f64) -> Result<(f64, f64, f64), CoreError> {
        let uy = self.yield_deformation();
        let du = u - u_c;
        let s = if du > 0.0 || (du == 0.0 && z_c >= 0.0) {
            1.0
        } else {
            -1.0
        };
        let xi = du.abs() / uy;
        let z = if xi == 0.0 {
            z_c
        } else if self.flow.n == 1.0 {
            s * self.flow.advance_linear(s * z_c, xi)
        } else if self.flow.n > ADAPTIVE_N && self.flow.g(s * z_c, s * z_c >= 0.0) > 0.0 {
            s * self
                .flow
                .advance_adaptive(s * z_c, xi)
                .map_err(|e| self.flow.too_many(&self.dofs, uy, u_c, u, e))?
        } else {
            s * self
                .flow
                .advance_rk4(s * z_c, xi)
                .map_err(|e| self.flow.too_many(&self.dofs, uy, u_c, u, e))?
        };
        let w = s * z;
        let g = self.flow.g(w, w >= 0.0);
        let f = self.alpha * self.k * u + (1.0 - self.alpha) * self.fy * z;
        let kt = self.k * (self.alpha + (1.0 - self.alpha) * g);
        Ok((z, f, kt))
    }
}

/// `error` at time `t` (an element does not know its step: the driver locates it).
fn at(error: CoreError, t: f64) -> CoreError {
    match error {
        CoreError::OutOfDomain {
            message,
            step,
            last_good_time,
            ..
        } => CoreError::OutOfDomain {
            message,
            time: t,
            step,
            last_good_time,
        },
        other => other,
    }
}

impl Flow {
    /// The saturation value `z_max = (beta + gamma)^(-1/n)` of `|w|`.
    fn z_max(&self) -> f64 {
        (self.beta + self.gamma).powf(-1.0 / self.n)
    }

    fn pow(&self, a: f64) -> f64 {
        match self.int_n {
            Some(p) => a.powi(p),
            None => a.powf(self.n),
        }
    }

    /// `g(w)` on the branch `positive` (`w >= 0`) or not.
    fn g(&self, w: f64, positive: bool) -> f64 {
        let c = if positive {
            self.beta + self.gamma
        } else {
            self.gamma - self.beta
        };
        1.0 - c * self.pow(w.abs())
    }

    /// `n = 1`: `w` after `xi >= 0` from `w0`, exactly.
    fn advance_linear(&self, w0: f64, xi: f64) -> f64 {
        let (cm, cp) = (self.gamma - self.beta, self.beta + self.gamma);
        let (mut w, mut rest) = (w0, xi);
        if w < 0.0 {
            let a = 1.0 + cm * w;
            if a <= 0.0 {
                // an inadmissible start (below -z_max) that never reaches 0
                return linear_flow(w, cm, rest);
            }
            let xi0 = -w * ln1p_ratio(cm * w);
            if xi0 > rest {
                return linear_flow(w, cm, rest);
            }
            w = 0.0;
            rest -= xi0;
        }
        linear_flow(w, -cp, rest)
    }
}

impl Element for BoucWen {
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
        let (_, f, kt) = self.response(0.0, 0.0, relative(x)).map_err(|e| at(e, t))?;
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
        // an initial deformation beyond the substep bound: z is NaN, and the first
        // evaluation reports the refusal (this trait method cannot)
        state[1] = self.response(0.0, 0.0, u).map_or(f64::NAN, |r| r.0);
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
        let (u_c, z_c) = (history.committed[0], history.committed[1]);
        if z_c.is_nan() && u_c.is_finite() {
            // the initial state's loading from rest was refused (see `initial_state`)
            self.response(0.0, 0.0, u_c).map_err(|e| at(e, t))?;
        }
        let (z, f, kt) = self.response(u_c, z_c, u).map_err(|e| at(e, t))?;
        finite(t, &[z, f, kt])?;
        history.trial[0] = u;
        history.trial[1] = z;
        scatter(f, kt, r, tangent.map(|tg| tg.kx));
        Ok(())
    }
}

/// `duhamel.elements.BoucWen`: the definition of a [`BoucWen`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoucWenDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub k: f64,
    pub fy: f64,
    pub alpha: f64,
    #[serde(default = "one")]
    pub n: f64,
    #[serde(default = "half")]
    pub beta: f64,
    #[serde(default = "half")]
    pub gamma: f64,
}

fn one() -> f64 {
    1.0
}

fn half() -> f64 {
    0.5
}

impl Definition for BoucWenDef {
    const NAME: &'static str = "BoucWen";
    const SIGNATURE: &'static str = "(i, j=None, *, k, fy, alpha, n=1.0, beta=0.5, gamma=0.5)";
    const DOC: &'static str = r#"Bouc-Wen smooth hysteretic spring on the deformation ``u = x_i - x_j`` (``j=None``: to
the ground), ``F = alpha k u + (1 - alpha) fy z`` with
``dz/du = (k / fy) [1 - |z|^n (beta sgn(du z) + gamma)]`` (OpenSees ``BoucWen`` with ``z`` in
displacement units ``fy / k``). For ``n = 1`` the update of ``z`` over a step is exact; for
other ``n`` it is integrated to about 1e-11 (integer ``n``) or 1e-8.

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
n : float, default 1.0
    Yield exponent, >= 1.
beta, gamma : float, default 0.5
    Loop shape: ``beta > 0``, ``gamma > -beta``.

Examples
--------
>>> import duhamel
>>> isolator = duhamel.elements.BoucWen(0, k=2e6, fy=5e4, alpha=0.1)
>>> isolator.n, isolator.beta, isolator.gamma
(1.0, 0.5, 0.5)
"#;
    const LEGACY: &'static [&'static str] = &["i", "j", "k", "fy", "alpha", "n", "beta", "gamma"];
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] =
        &[("k", "1.0"), ("fy", "1.0"), ("alpha", "0.0")];
    type Runtime = BoucWen;

    fn build(&self) -> Result<BoucWen, CoreError> {
        let params = BoucWenParams {
            k: self.k,
            fy: self.fy,
            alpha: self.alpha,
            n: self.n,
            beta: self.beta,
            gamma: self.gamma,
        };
        BoucWen::new(self.i, self.j, params)
    }

    fn directions(&self) -> Option<Vec<Pair>> {
        along(self.i, self.j)
    }

    fn passive(&self) -> bool {
        // the hysteretic loop dissipates for beta >= |gamma| (Bouc-Wen's passivity condition)
        self.alpha >= 0.0 && self.beta >= self.gamma.abs()
    }

    fn linear_stiffness(&self) -> Option<Vec<f64>> {
        Some(pair_matrix(self.j, self.k)) // the initial stiffness
    }

    fn stored_energy(&self, u: &[f64], f: &[f64]) -> f64 {
        let ue = deformation(u);
        let hyst = f[0] - self.alpha * self.k * ue;
        let soft = (1.0 - self.alpha) * self.k;
        let elastic = 0.5 * self.alpha * self.k * ue * ue;
        elastic
            + if soft > 0.0 {
                hyst * hyst / (2.0 * soft)
            } else {
                0.0
            }
    }
}

#[cfg(test)]
#[path = "boucwen_tests.rs"]
mod tests;
