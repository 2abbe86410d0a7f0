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
//! * **Bounded work.** A branch runs at most [`MAX_SUBSTEPS`] of its substeps (`n > 16`:
//!   [`adaptive::MAX_ADAPTIVE`] in all); it ends early where `w` crosses 0 or stops moving
//!   (the substep's increment rounds away: the substeps left change nothing). An increment
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
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;

mod adaptive;

/// Above this exponent the substeps follow the local stiffness of `g` (see
/// [`BoucWen::advance_adaptive`]): the uniform bound `lambda ~ n` would cost `100 n`
/// substeps per unit of `xi`.
const ADAPTIVE_N: f64 = 16.0;
/// RK4 substep bound, `lambda h <= H0`.
const H0: f64 = 0.01;
/// Bound on the RK4 substeps of one branch (a saturated branch needs far fewer): an
/// increment that needs more is refused (see the module documentation).
pub const MAX_SUBSTEPS: f64 = 1e6;

/// The substeps an increment needs beyond the bound (`needed` at least; the bound itself
/// when the adaptive substeps reached it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TooManySubsteps {
    needed: f64,
}

/// Bouc-Wen hysteretic spring between dofs `i` and `j` (or `i` and ground).
#[derive(Debug, Clone, PartialEq)]
pub struct BoucWen {
    dofs: Vec<usize>,
    k: f64,
    fy: f64,
    alpha: f64,
    n: f64,
    beta: f64,
    gamma: f64,
    /// `n` when it is a small integer (`powi`).
    int_n: Option<i32>,
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
            n,
            beta,
            gamma,
            int_n,
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
        (self.n, self.beta, self.gamma)
    }

    /// Yield deformation `uy = fy / k`.
    pub fn yield_deformation(&self) -> f64 {
        self.fy / self.k
    }

    /// The saturation value `z_max = (beta + gamma)^(-1/n)` of `|z|`.
    pub fn z_max(&self) -> f64 {
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

    fn rk4_step(&self, w: f64, h: f64, positive: bool) -> f64 {
        let k1 = self.g(w, positive);
        let k2 = self.g(w + 0.5 * h * k1, positive);
        let k3 = self.g(w + 0.5 * h * k2, positive);
        let k4 = self.g(w + h * k3, positive);
        w + h / 6.0 * (k1 + 2.0 * (k2 + k3) + k4)
    }

    /// General `n`: `w` after `xi >= 0` from `w0`, by RK4 with the switch located. A
    /// branch runs its uniform substeps up to [`MAX_SUBSTEPS`] of them: it ends early where
    /// `w` crosses 0 or stops moving (its increments round away: the substeps left would
    /// change nothing), and an increment that needs more is refused.
    fn advance_rk4(&self, w0: f64, xi: f64) -> Result<f64, TooManySubsteps> {
        let (cm, cp) = (self.gamma - self.beta, self.beta + self.gamma);
        let z_max = self.z_max();
        let lambda = self.n * cm.abs().max(cp) * self.pow(z_max.max(1.0)) / z_max.max(1.0);
        let h_max = H0 / lambda.max(1.0);
        let substeps = |len: f64| (len / h_max).ceil().max(1.0);
        let beyond = |m: f64| TooManySubsteps { needed: m };
        let (mut w, mut rest) = (w0, xi);
        if w < 0.0 {
            // g is monotone in |w|: at least g_min on the way up to 0, which is reached
            // within |w0| / g_min when g_min > 0 (an admissible start)
            let g_min = self.g(w, false).min(1.0);
            let bound = if g_min > 0.0 {
                -w / g_min
            } else {
                2.0 * (-w) + 40.0 / lambda.max(1.0)
            };
            let reaches = g_min > 0.0 && rest > bound;
            let len = rest.min(bound);
            let m = substeps(len);
            let h = len / m;
            let mut crossed = false;
            for _ in 0..m.min(MAX_SUBSTEPS) as usize {
                let next = self.rk4_step(w, h, false);
                if next >= 0.0 {
                    // xi to reach w = 0 from w: Simpson on dxi/dw = 1 / g(w) (g(0) = 1)
                    let d =
                        -w / 6.0 * (1.0 / self.g(w, false) + 4.0 / self.g(0.5 * w, false) + 1.0);
                    rest -= d.clamp(0.0, h);
                    crossed = true;
                    break;
                }
                if next == w && m > MAX_SUBSTEPS {
                    // h g(w) rounds away: w never moves again, so never within the bound
                    return Err(beyond(m));
                }
                w = next;
                rest -= h;
            }
            if !crossed && m > MAX_SUBSTEPS {
                return Err(beyond(m)); // `len` not covered within the bound
            }
            if !crossed {
                if !reaches {
                    return Ok(w);
                }
                // reached 0 at the end of `bound` (g constant) up to round-off
                rest = rest.max(0.0);
            }
            w = 0.0;
            rest = rest.max(0.0);
        }
        // past saturation the state no longer moves
        let saturation = 2.0 * z_max.max(w) + 40.0 / (self.n * cp.powf(1.0 / self.n));
        let len = rest.min(saturation);
        if len <= 0.0 {
            return Ok(w);
        }
        let m = substeps(len);
        let h = len / m;
        for _ in 0..m.min(MAX_SUBSTEPS) as usize {
            let next = self.rk4_step(w, h, true);
            if next == w {
                return Ok(w); // at rest to round-off: the substeps left change nothing
            }
            w = next;
        }
        if m > MAX_SUBSTEPS {
            return Err(beyond(m));
        }
        Ok(w)
    }

    /// The refusal of an increment from `u_c` to `u` that needs `too_many` substeps.
    fn too_many(&self, u_c: f64, u: f64, too_many: TooManySubsteps) -> CoreError {
        let uy = self.yield_deformation();
        let needed = if self.n > ADAPTIVE_N {
            format!(
                "more than the bound of {} adaptive RK4 substeps",
                adaptive::MAX_ADAPTIVE
            )
        } else {
            format!(
                "more than the bound of {MAX_SUBSTEPS:.0e} RK4 substeps (up to {:.3e} of the \
                 length its accuracy allows)",
                too_many.needed
            )
        };
        CoreError::OutOfDomain {
            time: 0.0,
            step: 0,
            last_good_time: None,
            message: format!(
                "BoucWen (dofs {:?}): the deformation increment from {u_c:e} to {u:e} \
                 ({:.3e} yield deformations fy / k = {uy:e}) needs {needed} to integrate its \
                 hysteretic variable (n = {}, beta = {:e}, gamma = {:e}: z saturates at \
                 {:e}); check `fy`, `k`, `beta` and `gamma` (values many orders of magnitude \
                 apart), or reduce `dt`",
                self.dofs,
                (u - u_c).abs() / uy,
                self.n,
                self.beta,
                self.gamma,
                self.z_max(),
            ),
        }
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
        } else if self.n == 1.0 {
            s * self.advance_linear(s * z_c, xi)
        } else if self.n > ADAPTIVE_N && self.g(s * z_c, s * z_c >= 0.0) > 0.0 {
            s * self
                .advance_adaptive(s * z_c, xi)
                .map_err(|e| self.too_many(u_c, u, e))?
        } else {
            s * self
                .advance_rk4(s * z_c, xi)
                .map_err(|e| self.too_many(u_c, u, e))?
        };
        let w = s * z;
        let g = self.g(w, w >= 0.0);
        let f = self.alpha * self.k * u + (1.0 - self.alpha) * self.fy * z;
        let kt = self.k * (self.alpha + (1.0 - self.alpha) * g);
        Ok((z, f, kt))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A grounded element at dof 0 of `[k, fy, alpha, n, beta, gamma]`.
    pub(super) fn grounded([k, fy, alpha, n, beta, gamma]: [f64; 6]) -> Result<BoucWen, CoreError> {
        let params = BoucWenParams {
            k,
            fy,
            alpha,
            n,
            beta,
            gamma,
        };
        BoucWen::new(0, None, params)
    }

    #[test]
    fn rk4_matches_the_exact_linear_flow() {
        // n = 1 integrated both ways, across the switch at w = 0 and into saturation
        for (beta, gamma) in [(0.5, 0.5), (0.25, 0.75), (0.8, 0.2), (1.0, -0.5)] {
            let e = grounded([1.0, 1.0, 0.0, 1.0, beta, gamma]).unwrap();
            for w0 in [-0.95 / (beta + gamma), -0.3, 0.0, 0.4] {
                for xi in [1e-3, 0.05, 0.3, 1.0, 2.5, 40.0] {
                    let exact = e.advance_linear(w0, xi);
                    let rk4 = e.advance_rk4(w0, xi).unwrap();
                    assert!(
                        (exact - rk4).abs() < 1e-10,
                        "beta {beta} gamma {gamma} w0 {w0} xi {xi}: {exact} vs {rk4}"
                    );
                }
            }
        }
    }

    #[test]
    fn saturates_at_z_max_for_huge_increments() {
        for n in [1.0, 2.0, 2.5, 25.0] {
            let e = grounded([2.0, 1.0, 0.1, n, 0.3, 0.5]).unwrap();
            let (z, _, kt) = e.response(0.0, -0.2, 1e9).unwrap();
            assert!((z - e.z_max()).abs() < 1e-12, "n {n}: {z}");
            assert!((kt - 0.2).abs() < 1e-10, "n {n}: {kt}");
        }
    }

    /// The message of an `OutOfDomain` refusal (panics on anything else).
    fn refusal(result: Result<(f64, f64, f64), CoreError>) -> String {
        match result {
            Err(CoreError::OutOfDomain { message, .. }) => message,
            other => panic!("expected a refusal, got {other:?}"),
        }
    }

    /// Parameters many orders of magnitude apart (issue 38: `fy = 1e-300, beta = 1e-300,
    /// n = 1.66` took more than 30 s for a few steps, a million substeps per evaluation)
    /// are refused naming the element and the count, on both branches and with the
    /// adaptive substeps; ordinary parameters integrate the same huge increments.
    #[test]
    fn refuses_increments_beyond_the_substep_bound() {
        // the issue's element unloading from saturation (beta ~ 0: g ~ 1e-12 there): z
        // leaves it exponentially (rate n / z_max) and saturates the other way, within
        // a few thousand substeps although the bound on the length to w = 0 is 1e12
        let e = grounded([1.0, 1e-300, 0.0, 1.66, 1e-300, 0.5]).unwrap();
        let (z, _, _) = e.response(0.0, (1.0 - 1e-12) * e.z_max(), -0.01).unwrap();
        assert!((z + e.z_max()).abs() < 1e-12, "{z}");
        // beta = gamma = 1e-300: z saturates at 3.5e180, beyond any substep budget, loading
        // (the positive branch) and unloading (g = 1 on the way to w = 0: w0 = -1e10)
        let e = grounded([1.0, 1e-300, 0.0, 1.66, 1e-300, 1e-300]).unwrap();
        for (z_c, u) in [(0.0, 0.01), (-1e10, 0.01)] {
            let msg = refusal(e.response(0.0, z_c, u));
            assert!(msg.starts_with("BoucWen (dofs [0])"), "{msg}");
            assert!(
                msg.contains("more than the bound of 1e6 RK4 substeps"),
                "{msg}"
            );
        }
        // n > 16: the adaptive substeps reach their bound instead of stopping short
        let e = grounded([1.0, 1e-300, 0.0, 20.0, 1e-30, 1e-30]).unwrap();
        let msg = refusal(e.response(0.0, 0.0, 0.01));
        assert!(msg.contains("bound of 200000 adaptive"), "{msg}");
        // an initial deformation beyond the bound: the first evaluation reports it
        let e = grounded([1.0, 1e-300, 0.0, 1.66, 1e-300, 1e-300]).unwrap();
        let mut state = [0.0; 2];
        e.initial_state(&[0.01], &[0.0], &mut state);
        assert!(state[1].is_nan());
        let (mut trial, mut r) = ([0.0; 2], [0.0]);
        let history = PathState {
            committed: &state,
            trial: &mut trial,
        };
        match e.eval_path(&[0.01], &[0.0], 0.5, history, &mut r, None) {
            Err(CoreError::OutOfDomain { time, .. }) => assert_eq!(time, 0.5),
            other => panic!("{other:?}"),
        }
        // ordinary parameters: huge increments stay within the bound
        for n in [1.5, 2.0, 16.0, 17.0, 64.0] {
            for (beta, gamma) in [(0.5, 0.5), (0.05, 0.005), (0.9, -0.5)] {
                let e = grounded([2.0, 1e-3, 0.1, n, beta, gamma]).unwrap();
                let zm = e.z_max();
                for (z_c, u) in [(0.0, 1e6), (0.99 * zm, -1e6), (-0.99 * zm, 1e3)] {
                    assert!(
                        e.response(0.0, z_c, u).is_ok(),
                        "n {n} beta {beta} z_c {z_c}"
                    );
                }
            }
        }
    }

    #[test]
    fn validates_parameters() {
        let name = |e: CoreError| match e {
            CoreError::InvalidInput { name, .. } => name,
            other => panic!("{other:?}"),
        };
        let make = |n, beta, gamma| grounded([1.0, 1.0, 0.1, n, beta, gamma]);
        assert_eq!(name(make(0.5, 0.5, 0.5).unwrap_err()), "n");
        assert_eq!(name(make(f64::INFINITY, 0.5, 0.5).unwrap_err()), "n");
        assert_eq!(name(make(1.0, 0.0, 0.5).unwrap_err()), "beta");
        assert_eq!(name(make(1.0, 0.5, -0.5).unwrap_err()), "gamma");
        let e = grounded([1.0, 0.0, 0.1, 1.0, 0.5, 0.5]);
        assert_eq!(name(e.unwrap_err()), "fy");
    }
}
