//! The triple friction pendulum's series model normalised by the vertical load
//! ([`super::triple`]): three elements ([`super::triple_segment`]) in series carry the same
//! normalised force `f` and add up to the bearing's displacement; solved by Newton's method
//! with a line search on its convex potential, from the committed state.

use super::common::{finite, solve4};
use super::triple_segment::{inverse, Segment, SegmentState, M2, V2};
use crate::error::CoreError;

/// The series model's solution at a displacement.
pub(super) struct Solved {
    /// The common (normalised) force.
    pub f: V2,
    /// The tangent `df/du`.
    pub k: M2,
    /// `[d_1, d_2, d_3, ep_1, ep_2, ep_3]`.
    pub state: [f64; 12],
}

/// The three elements in series (inner, outer 2, outer 3).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Surfaces {
    pub segments: [Segment; 3],
}

impl Surfaces {
    /// Evaluates the three elements at `d` (`d[2] = u - d[0] - d[1]`).
    fn segments_at(&self, d: [V2; 3], ep_c: [V2; 3]) -> [SegmentState; 3] {
        [0, 1, 2].map(|i| self.segments[i].eval(d[i], ep_c[i]))
    }

    /// Solves the series model at `u` from the committed `[d_i, ep_i]` (`c`), at time `t`.
    pub(super) fn solve(&self, c: &[f64], u: V2, t: f64) -> Result<Solved, CoreError> {
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
            let scale = self.segments[2].fy + s[2].f[0].hypot(s[2].f[1]);
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
}
