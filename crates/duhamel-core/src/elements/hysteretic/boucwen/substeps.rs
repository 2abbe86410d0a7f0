//! Bouc-Wen's uniform RK4 substeps (`1 <= n <= 16`, see [`Flow::advance_rk4`]), the bound
//! on the substeps of one increment and the refusal of an increment that needs more (the
//! module documentation of [`super`], "Bounded work").

use super::{Flow, ADAPTIVE_N, H0};
use crate::error::CoreError;

/// Bound on the RK4 substeps of one branch (a saturated branch needs far fewer): an
/// increment that needs more is refused (see the module documentation).
pub(super) const MAX_SUBSTEPS: f64 = 1e6;

/// Bound on the substeps of the adaptive integration of one increment (`n > 16`, see
/// [`Flow::advance_adaptive`]; never reached by an admissible state: about
/// `(len + 80) / H0`, whatever `n`); an increment that reaches it is refused rather than cut
/// short.
pub(super) const MAX_ADAPTIVE: usize = 200_000;

/// The substeps an increment needs beyond the bound (`needed` at least; the bound itself
/// when the adaptive substeps reached it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TooManySubsteps {
    pub(super) needed: f64,
}

impl Flow {
    pub(super) fn rk4_step(&self, w: f64, h: f64, positive: bool) -> f64 {
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
    pub(super) fn advance_rk4(&self, w0: f64, xi: f64) -> Result<f64, TooManySubsteps> {
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

    /// The refusal of an increment from `u_c` to `u` (yield deformation `uy`) of the element
    /// on `dofs` that needs `too_many` substeps.
    pub(super) fn too_many(
        &self,
        dofs: &[usize],
        uy: f64,
        u_c: f64,
        u: f64,
        too_many: TooManySubsteps,
    ) -> CoreError {
        let needed = if self.n > ADAPTIVE_N {
            format!(
                "more than the bound of {} adaptive RK4 substeps",
                MAX_ADAPTIVE
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
                dofs,
                (u - u_c).abs() / uy,
                self.n,
                self.beta,
                self.gamma,
                self.z_max(),
            ),
        }
    }
}
