//! `Series`: materials one after the other, carrying the same force, their deformations
//! adding up to the deformation — OpenSees' `Series` material, solved to convergence.
//!
//! The equations: every part carries the force, `s_i(e_i) = T`, and the parts' deformations
//! add up, `sum_i e_i = u`. From the committed parts and OpenSees' predictor
//! `T = T_c + K_c (u - u_c)`, Newton on them: `k_i de_i - dT = T - s_i`, `sum_i de_i = u -
//! sum_i e_i`, i.e. `dT = (u - sum_i e_i - sum_i (T - s_i)/k_i) K` with the series tangent
//! `K = 1 / sum_i 1/k_i` (OpenSees' flexibility `1/k` of a tangent `|k| <= 1e-12` is
//! `1e12`, likewise its stiffness of a flexibility sum), `de_i = (T - s_i + dT)/k_i`, except
//! that the most flexible part takes what compatibility leaves (exact on a plateau, where
//! its tangent is 0 and the force is fixed by it). Converged when every `|T - s_i| <= tol S`
//! (`S` the largest of `|T|`, the `|s_i|`, the `|k_i e_i|` and the committed forces) and
//! `|u - sum_i e_i| <= tol U` (`U` the largest of `|u|` and the `|e_i|`) — or, the
//! compatibility met, when the unbalance stalls within `1e-6 S` (it did not halve in an
//! iteration, after three: the round-off of a part's force, e.g. OpenSees' formulas that
//! subtract stresses of points far from the deformation); the tangent is then the series
//! tangent at the converged parts, exact. Not converged within `max_iter` iterations: an
//! error.
//!
//! One deliberate difference: OpenSees' `SeriesMaterial` keeps the force fixed at the
//! predictor inside its loop and corrects it once after (default `maxIter = 1`), so driven
//! at a fixed deformation (`setStrain`, a displacement-controlled step) its force lags the
//! series solution; here the force is the converged one, as OpenSees' chain of `zeroLength`
//! elements solved by Newton gives (docs/materials.md).

use serde::{Deserialize, Serialize};

use super::parallel::offsets_after;
use super::uniaxial::{
    initial_deformation_doc, part_law, uniaxial_methods, Uniaxial, UniaxialDefinition,
};
use super::Material;
use crate::elements::definition::{Definition, Pair};
use crate::elements::registry::Defined;
use crate::error::CoreError;

/// `duhamel.elements.Series`: the definition of a [`Series`] element.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeriesDef {
    pub i: usize,
    #[serde(default)]
    pub j: Option<usize>,
    pub materials: Vec<Defined>,
    #[serde(default = "max_iter")]
    pub max_iter: usize,
    #[serde(default = "tol")]
    pub tol: f64,
    #[serde(default)]
    pub initial_deformation: f64,
}

fn max_iter() -> usize {
    100
}
fn tol() -> f64 {
    1.0e-10
}

impl UniaxialDefinition for SeriesDef {
    fn initial_deformation(&self) -> f64 {
        self.initial_deformation
    }
    type Law = Series;
    fn pair(&self) -> Pair {
        (self.i, self.j)
    }
    fn law(&self) -> Result<Series, CoreError> {
        let parts = self
            .materials
            .iter()
            .enumerate()
            .map(|(k, m)| part_law(m, ("materials", Some(k)), self.pair(), "Series"))
            .collect::<Result<Vec<_>, _>>()?;
        Series::new(parts, self.max_iter, self.tol)
    }
}

impl Definition for SeriesDef {
    const NAME: &'static str = "Series";
    const SIGNATURE: &'static str =
        "(i, j=None, *, materials, max_iter=100, tol=1e-10, initial_deformation=0.0)";
    const DOC: &'static str = concat!(
        r#"Uniaxial materials in series on the deformation ``u = x_i - x_j``, as OpenSees'
``uniaxialMaterial Series tag tag1 tag2 ... <-iter maxIter tol>`` but solved to convergence:
the parts carry the same force and their deformations add up to ``u`` (Newton on the parts'
deformations from OpenSees' predictor; the tangent is the series tangent). A step that does
not converge within `max_iter` iterations stops the run with an error (never an unconverged
force). Unlike OpenSees' ``SeriesMaterial``, whose force under a fixed strain stays off the
series solution (docs/materials.md), this one equals OpenSees' chain of ``zeroLength``
elements.

Parameters
----------
i, j : int, dof label or None
    The dofs of the deformation ``x_i - x_j`` (``j=None``: to the ground).
materials : sequence of Element
    The parts (at least one, rate-independent): uniaxial material elements on the same
    ``i, j``.
max_iter : int
    Iterations allowed per evaluation, >= 1.
tol : float
    Relative tolerance of the force balance and the compatibility, in (0, 1).
"#,
        initial_deformation_doc!(),
        r#"
Examples
--------
>>> import duhamel
>>> E = duhamel.elements
>>> gusset = E.ElasticMultiLinear(0, strain=[-1.0, 1.0], stress=[-300.0, 300.0])
>>> brace = E.MultiLinear(0, strain=[0.01, 0.05], stress=[1.0, 1.4])
>>> both = E.Series(0, materials=[gusset, brace])
>>> E.drive(both, [0.004]).force.round(9).tolist()  # 1 / (1/300 + 1/100) per unit deformation
[0.3]
"#
    );
    type Runtime = Uniaxial<Series>;
    uniaxial_methods!();
}

/// OpenSees' `uniaxialMaterial Series tag tag1 tag2 ... <-iter maxIter tol>`, converged.
#[derive(Debug)]
pub struct Series {
    parts: Vec<Box<dyn Material>>,
    max_iter: usize,
    tol: f64,
    offsets: Vec<usize>,
}

// state: committed deformation, force, tangent, then per part (deformation, force,
// tangent), then the parts' variables
const HEAD: usize = 3;

/// OpenSees' flexibility (or stiffness) of a tangent (or flexibility sum) near zero.
/// The most parts whose scratch the response keeps on the stack.
const STACK_PARTS: usize = 8;

fn inverse(k: f64) -> f64 {
    if k.abs() > 1.0e-12 {
        1.0 / k
    } else if k < 0.0 {
        -1.0e12
    } else {
        1.0e12
    }
}

impl Series {
    /// `parts` (at least one, rate-independent), iterated at most `max_iter` times (>= 1)
    /// to the relative tolerance `tol` (in (0, 1)). Errors name `materials`, `max_iter` or
    /// `tol`.
    pub fn new(
        parts: Vec<Box<dyn Material>>,
        max_iter: usize,
        tol: f64,
    ) -> Result<Self, CoreError> {
        let bad = |name: &'static str, problem: String| CoreError::InvalidInput { name, problem };
        if parts.is_empty() {
            return Err(bad("materials", "must hold at least one material".into()));
        }
        if parts.iter().any(|p| p.uses_rate()) {
            return Err(bad(
                "materials",
                "must be rate-independent (a part in series sees no rate)".into(),
            ));
        }
        if max_iter == 0 {
            return Err(bad("max_iter", "must be >= 1, got 0".into()));
        }
        if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
            return Err(bad("tol", format!("must be in (0, 1), got {tol}")));
        }
        let offsets = offsets_after(HEAD + 3 * parts.len(), &parts);
        Ok(Self {
            parts,
            max_iter,
            tol,
            offsets,
        })
    }

    fn range(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i]..self.offsets[i + 1]
    }
}

impl Material for Series {
    /// A deformation within `EPSILON` of the committed one returns the committed force.
    fn restarts_exactly(&self) -> bool {
        true
    }

    fn state_len(&self) -> usize {
        self.offsets[self.parts.len()]
    }

    fn initial_state(&self, s: &mut [f64]) {
        s[0] = 0.0;
        s[1] = 0.0;
        s[2] = self.initial_tangent();
        for (i, p) in self.parts.iter().enumerate() {
            s[HEAD + 3 * i] = 0.0;
            s[HEAD + 3 * i + 1] = 0.0;
            s[HEAD + 3 * i + 2] = p.initial_tangent();
            p.initial_state(&mut s[self.range(i)]);
        }
    }

    fn response(
        &self,
        u: f64,
        _rate: f64,
        c: &[f64],
        t: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        t.copy_from_slice(c);
        if (u - c[0]).abs() < f64::EPSILON {
            return Ok((c[1], c[2]));
        }
        let n = self.parts.len();
        let mut stress = c[1] + c[2] * (u - c[0]);
        // the parts' flexibilities and deformation changes: on the stack for a few parts
        // (no allocation per evaluation)
        let mut stack = [0.0; 2 * STACK_PARTS];
        let mut heap = Vec::new();
        let buf: &mut [f64] = if n <= STACK_PARTS {
            &mut stack[..2 * n]
        } else {
            heap.resize(2 * n, 0.0);
            &mut heap
        };
        let (flex, change) = buf.split_at_mut(n);
        // the force scale of the step: the committed forces too (a step from rest is tiny)
        let mut scale = stress.abs().max(c[1].abs());
        for i in 0..n {
            scale = scale.max(c[HEAD + 3 * i + 1].abs());
        }
        let mut previous = f64::INFINITY;
        for iteration in 0..=self.max_iter {
            // the force unbalances and the compatibility residual
            let (mut unbalance, mut gap) = (0.0_f64, u);
            let (mut u_ref, mut s_ref) = (u.abs(), stress.abs().max(scale));
            for (i, f) in flex.iter_mut().enumerate() {
                let j = HEAD + 3 * i;
                unbalance = unbalance.max((stress - t[j + 1]).abs());
                gap -= t[j];
                u_ref = u_ref.max(t[j].abs());
                s_ref = s_ref.max(t[j + 1].abs()).max((t[j + 2] * t[j]).abs());
                *f = inverse(t[j + 2]);
            }
            if !(unbalance.is_finite() && gap.is_finite()) {
                break;
            }
            let compatible = gap.abs() <= self.tol * u_ref;
            // converged, or stalled at the parts' round-off (no halving of the unbalance
            // after three iterations, within 1e-6 of the forces, or within the deformation
            // a part resolves: OpenSees' Steel02 ignores increments below 10 eps, so a step
            // from rest can leave an unbalance of its stiffness times 1e-15)
            let resolved =
                unbalance * flex.iter().fold(0.0_f64, |m, f| m.max(f.abs())) <= 64.0 * f64::EPSILON;
            let stalled = iteration >= 3
                && unbalance >= 0.5 * previous
                && (unbalance <= 1e-6 * s_ref || resolved);
            previous = unbalance;
            if compatible && (unbalance <= self.tol * s_ref || stalled) {
                let tangent = inverse(flex.iter().sum());
                t[0] = u;
                t[1] = stress;
                t[2] = tangent;
                return Ok((stress, tangent));
            }
            if iteration == self.max_iter {
                return Err(CoreError::NoConvergence {
                    time: 0.0,
                    step: 0,
                    residual: unbalance.max(gap.abs()),
                    iterations: iteration,
                    last_good_time: None,
                });
            }
            // Newton: k_i de_i - dT = T - s_i, sum_i de_i = gap; the most flexible part takes
            // the compatibility (exact when its tangent is 0: a plateau fixes the force)
            let weighted: f64 = (0..n)
                .map(|i| flex[i] * (stress - t[HEAD + 3 * i + 1]))
                .sum();
            let d_stress = (gap - weighted) * inverse(flex.iter().sum());
            let p = (0..n)
                .max_by(|&a, &b| flex[a].abs().total_cmp(&flex[b].abs()))
                .unwrap_or(0);
            let mut others = 0.0;
            for i in (0..n).filter(|&i| i != p) {
                change[i] = flex[i] * (stress - t[HEAD + 3 * i + 1] + d_stress);
                others += change[i];
            }
            change[p] = gap - others;
            stress += d_stress;
            for (i, part) in self.parts.iter().enumerate() {
                let j = HEAD + 3 * i;
                t[j] += change[i];
                let r = self.range(i);
                let (si, ki) = part.response(t[j], 0.0, &c[r.clone()], &mut t[r])?;
                t[j + 1] = si;
                t[j + 2] = ki;
            }
        }
        Err(CoreError::NonFinite {
            time: 0.0,
            step: 0,
            last_good_time: None,
        })
    }

    /// OpenSees': the series combination of the parts' initial tangents (0 when a pair
    /// sums to 0).
    fn initial_tangent(&self) -> f64 {
        let mut kf = self.parts[0].initial_tangent();
        for p in &self.parts[1..] {
            let k = p.initial_tangent();
            if kf + k != 0.0 {
                kf = kf * k / (kf + k);
            } else {
                return 0.0;
            }
        }
        kf
    }

    /// None: a softening part in series with a stiffer one makes the series tangent
    /// unbounded (`1 / (1/k_1 + 1/k_2)` as `k_1 -> -k_2`).
    fn tangent_bound(&self) -> Option<f64> {
        None
    }

    fn passive(&self) -> bool {
        self.parts.iter().all(|p| p.passive())
    }

    /// The parts' stored energies at their committed deformations and forces.
    fn stored_energy(&self, s: &[f64], _u: f64, _force: f64) -> f64 {
        (0..self.parts.len())
            .map(|i| {
                let j = HEAD + 3 * i;
                self.parts[i].stored_energy(&s[self.range(i)], s[j], s[j + 1])
            })
            .sum()
    }
}

#[cfg(test)]
#[path = "series_tests.rs"]
mod tests;
