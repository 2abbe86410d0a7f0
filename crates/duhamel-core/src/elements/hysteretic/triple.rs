//! Triple friction pendulum isolator (bidirectional, coupled; or uniaxial): the series model
//! of its four sliding surfaces, as OpenSees' `TripleFrictionPendulum` element writes it
//! (Dao, Ryan, Sato & Sasaki 2013, "Predicting the displacement of triple pendulum
//! bearings in a full-scale shaking experiment using a three-dimensional element",
//! Earthquake Engng Struct. Dyn. 42; after Fenz & Constantinou 2008, "Spherical sliding
//! isolation bearings with adaptive behavior: theory", Earthquake Engng Struct. Dyn. 37, and
//! "Modeling triple friction pendulum bearings for response-history analysis", Earthquake
//! Spectra 24).
//!
//! Effective radii `L1` (the two inner surfaces), `L2`, `L3` (the outer ones), friction
//! coefficients `mu1 <= mu2 <= mu3` and displacement capacities `d1, d2, d3` of the
//! surfaces. Three elements in series carry the same force `F = W f` (`f` normalised by the
//! vertical load `W`) and add up to the bearing's displacement `u = d_1 + d_2 + d_3`; each
//! is a bidirectional elastoplastic element with linear kinematic hardening in parallel
//! with a circular gap (the displacement restrainer):
//!
//! ```text
//! element   yield  sliding stiffness   gap (restrainer)
//! inner     mu1    1 / (2 L1)          2 (d1 + d3 L1 / L3)
//! outer 2   mu2    1 / (L2 - L1)       d2 (1 - L1 / L2)
//! outer 3   mu3    1 / (L3 - L1)       d3 (1 - L1 / L3)
//! ```
//!
//! with the elastic stiffness `E = 3 mu1 / uy` in every element (the bearing's pre-sliding
//! stiffness is `mu1 W / uy`), the hardening `H = E Ep / (E - Ep)` that makes the sliding
//! stiffness `Ep`, and the gap stiffness `E` beyond the gap. This gives Fenz & Constantinou's
//! regimes: I sliding on the inner surfaces from `F = mu1 W` (stiffness `W / (2 L1)`),
//! II on surface 2 from `mu2 W` (`W / (L1 + L2)`), III on both outer ones from `mu3 W`
//! (`W / (L2 + L3)`), IV surface 2 at its stop from `F = W (mu2 + d2 / L2)` (`W / (L1 + L3)`)
//! and V surface 3 at its stop from `F = W (mu3 + d3 / L3)` (`W / (2 L1)`), up to the
//! stiffening when the inner slider reaches its own.
//!
//! Each element's return mapping is backward Euler from the committed plastic displacement
//! (radial return, OpenSees' `BidirectionalPlastic`): for a given total displacement the
//! trial state is unique, the series equations (equal forces, displacements adding up to
//! `u`) are the stationarity conditions of a convex potential and are solved by Newton's
//! method with a line search on it, to round-off. The tangent is the exact one: the inverse
//! of the sum of the elements' compliances. `W` is constant (OpenSees' element with a
//! constant axial force and Coulomb friction). Internal variables: `[d_1, d_2, d_3, ep_1,
//! ep_2, ep_3]` (each 2 entries; `y` entries 0 for a uniaxial bearing). **Initial state:**
//! virgin at `u = 0`, loaded along the straight line to the initial displacement.

use super::common::{check, finite, solve4};
use crate::elements::element::distinct;
use crate::elements::element::{Element, PathState, Tangent};
use crate::error::CoreError;

use super::triple_segment::{inverse, Segment, SegmentState, M2, V2};

/// The series model's solution at a displacement.
struct Solved {
    /// The common (normalised) force.
    f: V2,
    /// The tangent `df/du`.
    k: M2,
    /// `[d_1, d_2, d_3, ep_1, ep_2, ep_3]`.
    state: [f64; 12],
}

/// Triple friction pendulum bearing on `(dof_x, dof_y)`, or on `dof_x` alone.
#[derive(Debug, Clone, PartialEq)]
pub struct TripleFrictionPendulum {
    dofs: Vec<usize>,
    mu: [f64; 3],
    radius: [f64; 3],
    capacity: [f64; 3],
    weight: f64,
    yield_displacement: f64,
    segments: [Segment; 3],
}

impl TripleFrictionPendulum {
    /// Bearing on the distinct dofs `(dof_x, dof_y)` with friction coefficients
    /// `mu = (mu1, mu2, mu3)`, `0 < mu1 <= mu2 <= mu3`, effective radii
    /// `radius = (L1, L2, L3)`, `0 < L1 < L2, L3`, displacement capacities
    /// `capacity = (d1, d2, d3) > 0`, vertical load `weight > 0` and the displacement
    /// `yield_displacement` where sliding starts (`> 0`, small enough that each element's
    /// elastic stiffness exceeds its sliding stiffness).
    pub fn new(
        dof_x: usize,
        dof_y: usize,
        mu: [f64; 3],
        radius: [f64; 3],
        capacity: [f64; 3],
        weight: f64,
        yield_displacement: f64,
    ) -> Result<Self, CoreError> {
        distinct(dof_x, dof_y)?;
        let bad = |name: &'static str, problem: String| CoreError::InvalidInput { name, problem };
        for (name, values) in [
            ("mu", mu),
            ("radius", radius),
            ("displacement_capacity", capacity),
        ] {
            if !values.iter().all(|v| v.is_finite() && *v > 0.0) {
                return Err(bad(
                    name,
                    format!("must be > 0 (three finite values), got {values:?}"),
                ));
            }
        }
        if !(mu[0] <= mu[1] && mu[1] <= mu[2]) {
            return Err(bad(
                "mu",
                format!("must be ordered mu1 <= mu2 <= mu3 (inner surfaces first), got {mu:?}"),
            ));
        }
        let [l1, l2, l3] = radius;
        if !(l2 > l1 && l3 > l1) {
            return Err(bad(
                "radius",
                format!("the inner radius L1 must be below L2 and L3, got {radius:?}"),
            ));
        }
        check("weight", weight, true)?;
        check("yield_displacement", yield_displacement, true)?;
        let e = 3.0 * mu[0] / yield_displacement;
        let slopes = [1.0 / (2.0 * l1), 1.0 / (l2 - l1), 1.0 / (l3 - l1)];
        let softest = slopes.iter().copied().fold(0.0, f64::max);
        if e <= softest {
            return Err(bad(
                "yield_displacement",
                format!(
                    "must be below 3 mu1 / max(1 / (2 L1), 1 / (L2 - L1), 1 / (L3 - L1)) = {} \
                     (the elastic stiffness of each sliding element must exceed its sliding \
                     stiffness), got {yield_displacement}",
                    3.0 * mu[0] / softest
                ),
            ));
        }
        let [d1, d2, d3] = capacity;
        let gaps = [
            2.0 * (l1 / l3 * d3 + d1),
            d2 * (1.0 - l1 / l2),
            d3 * (1.0 - l1 / l3),
        ];
        let segment = |i: usize| Segment {
            fy: mu[i],
            e,
            h: e * slopes[i] / (e - slopes[i]),
            gap: gaps[i],
        };
        Ok(Self {
            dofs: vec![dof_x, dof_y],
            mu,
            radius,
            capacity,
            weight,
            yield_displacement,
            segments: [segment(0), segment(1), segment(2)],
        })
    }

    /// Uniaxial bearing on `dof_x` (a plane model), the parameters as in [`Self::new`].
    pub fn uniaxial(
        dof_x: usize,
        mu: [f64; 3],
        radius: [f64; 3],
        capacity: [f64; 3],
        weight: f64,
        yield_displacement: f64,
    ) -> Result<Self, CoreError> {
        let mut e = Self::new(
            dof_x,
            dof_x + 1,
            mu,
            radius,
            capacity,
            weight,
            yield_displacement,
        )?;
        e.dofs = vec![dof_x];
        Ok(e)
    }

    /// Friction coefficients `(mu1, mu2, mu3)`.
    pub fn mu(&self) -> [f64; 3] {
        self.mu
    }

    /// Effective radii `(L1, L2, L3)`.
    pub fn radius(&self) -> [f64; 3] {
        self.radius
    }

    /// Displacement capacities `(d1, d2, d3)`.
    pub fn displacement_capacity(&self) -> [f64; 3] {
        self.capacity
    }

    /// Vertical load `W`.
    pub fn weight(&self) -> f64 {
        self.weight
    }

    /// Displacement where sliding starts, `uy`.
    pub fn yield_displacement(&self) -> f64 {
        self.yield_displacement
    }

    /// Evaluates the three elements at `d` (`d[2] = u - d[0] - d[1]`).
    fn segments_at(&self, d: [V2; 3], ep_c: [V2; 3]) -> [SegmentState; 3] {
        [0, 1, 2].map(|i| self.segments[i].eval(d[i], ep_c[i]))
    }

    /// Solves the series model at `u` from the committed `[d_i, ep_i]` (`c`), at time `t`.
    fn solve(&self, c: &[f64], u: V2, t: f64) -> Result<Solved, CoreError> {
        let ep_c = [[c[6], c[7]], [c[8], c[9]], [c[10], c[11]]];
        let du = [u[0] - c[0] - c[2] - c[4], u[1] - c[1] - c[3] - c[5]];
        // unknowns d_1, d_2 (d_3 closes the sum); the predictor splits the increment by the
        // elements' tangents for continued loading from the committed state (exact while
        // no element changes state)
        let compliance = [0, 1, 2].map(|i| {
            let d = [c[2 * i], c[2 * i + 1]];
            inverse(self.segments[i].loading_tangent(d, ep_c[i]))
        });
        let sum = [0, 1, 2, 3].map(|k| compliance[0][k] + compliance[1][k] + compliance[2][k]);
        let kp = inverse(sum);
        let df = [kp[0] * du[0] + kp[1] * du[1], kp[2] * du[0] + kp[3] * du[1]];
        let step = |i: usize| {
            let ci = compliance[i];
            [ci[0] * df[0] + ci[1] * df[1], ci[2] * df[0] + ci[3] * df[1]]
        };
        let (s0, s1) = (step(0), step(1));
        let mut x = [c[0] + s0[0], c[1] + s0[1], c[2] + s1[0], c[3] + s1[1]];
        let split = |x: &[f64; 4]| -> [V2; 3] {
            [
                [x[0], x[1]],
                [x[2], x[3]],
                [u[0] - x[0] - x[2], u[1] - x[1] - x[3]],
            ]
        };
        let gradient = |s: &[SegmentState; 3]| -> [f64; 4] {
            [
                s[0].f[0] - s[2].f[0],
                s[0].f[1] - s[2].f[1],
                s[1].f[0] - s[2].f[0],
                s[1].f[1] - s[2].f[1],
            ]
        };
        let norm = |g: &[f64; 4]| g.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let energy = |s: &[SegmentState; 3]| s.iter().map(|s| s.energy).sum::<f64>();
        let mut s = self.segments_at(split(&x), ep_c);
        let mut g = gradient(&s);
        let mut iterations = 0;
        loop {
            finite(t, &g)?;
            let scale = self.mu[2] + s[2].f[0].hypot(s[2].f[1]);
            let residual = norm(&g);
            if residual <= 1e-12 * scale {
                break;
            }
            iterations += 1;
            let fail = || CoreError::NoConvergence {
                time: t,
                step: 0,
                residual,
                iterations,
                last_good_time: None,
            };
            if iterations > 100 {
                return Err(fail());
            }
            let (k0, k1, k2) = (s[0].k, s[1].k, s[2].k);
            let a = [
                [k0[0] + k2[0], k0[1] + k2[1], k2[0], k2[1]],
                [k0[2] + k2[2], k0[3] + k2[3], k2[2], k2[3]],
                [k2[0], k2[1], k1[0] + k2[0], k1[1] + k2[1]],
                [k2[2], k2[3], k1[2] + k2[2], k1[3] + k2[3]],
            ];
            let p = solve4(a, g.map(|v| -v));
            let slope: f64 = (0..4).map(|i| g[i] * p[i]).sum();
            let e0 = energy(&s);
            // Armijo on the convex potential (with a round-off allowance)
            let allowance = 1e-14 * (e0.abs() + scale * scale);
            let mut alpha = 1.0;
            loop {
                let trial = [0, 1, 2, 3].map(|i| x[i] + alpha * p[i]);
                let st = self.segments_at(split(&trial), ep_c);
                if energy(&st) - e0 <= 1e-4 * alpha * slope + allowance {
                    x = trial;
                    g = gradient(&st);
                    s = st;
                    break;
                }
                alpha *= 0.5;
                if alpha < 1e-12 {
                    // stalled at round-off near the solution, or lost
                    if residual <= 1e-8 * scale {
                        break;
                    }
                    return Err(fail());
                }
            }
            if alpha < 1e-12 {
                break;
            }
        }
        let f = [
            (s[0].f[0] + s[1].f[0] + s[2].f[0]) / 3.0,
            (s[0].f[1] + s[1].f[1] + s[2].f[1]) / 3.0,
        ];
        let c0 = inverse(s[0].k);
        let c1 = inverse(s[1].k);
        let c2 = inverse(s[2].k);
        let k = inverse([0, 1, 2, 3].map(|i| c0[i] + c1[i] + c2[i]));
        let d = split(&x);
        let mut state = [0.0; 12];
        for i in 0..3 {
            state[2 * i] = d[i][0];
            state[2 * i + 1] = d[i][1];
            state[6 + 2 * i] = s[i].ep[0];
            state[7 + 2 * i] = s[i].ep[1];
        }
        Ok(Solved { f, k, state })
    }

    /// The local `(x, y)` of `x` (`y = 0` for a uniaxial bearing).
    fn plane(&self, x: &[f64]) -> V2 {
        [x[0], if self.dofs.len() == 2 { x[1] } else { 0.0 }]
    }

    fn add(
        &self,
        solved: &Solved,
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let w = self.weight;
        let force = [w * solved.f[0], w * solved.f[1]];
        finite(t, &force)?;
        finite(t, &solved.k)?;
        let n = self.dofs.len();
        for i in 0..n {
            r[i] += force[i];
        }
        if let Some(tg) = tangent {
            for i in 0..n {
                for j in 0..n {
                    tg.kx[i * n + j] += w * solved.k[2 * i + j];
                }
            }
        }
        Ok(())
    }
}

impl Element for TripleFrictionPendulum {
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
        let solved = self.solve(&[0.0; 12], self.plane(x), t)?;
        self.add(&solved, t, r, tangent)
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        false
    }

    fn state_len(&self) -> usize {
        12
    }

    fn initial_state(&self, x: &[f64], _v: &[f64], state: &mut [f64]) {
        // a state the model cannot solve (non-finite x) starts virgin; the run then fails
        // at its first evaluation with the error
        let solved = self.solve(&[0.0; 12], self.plane(x), 0.0);
        state.copy_from_slice(&solved.map(|s| s.state).unwrap_or([0.0; 12]));
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
        let solved = self.solve(history.committed, self.plane(x), t)?;
        self.add(&solved, t, r, tangent)?;
        history.trial.copy_from_slice(&solved.state);
        Ok(())
    }
}

#[cfg(test)]
#[path = "triple_tests.rs"]
mod tests;
