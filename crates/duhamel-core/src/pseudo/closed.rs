//! The single-mode closed-form step (the paper's cubic): with one mode and polynomial forces
//! of degree <= 3, the step equation and every node's pseudo-force are cubics in the unknown.

use super::force::PseudoForce;
use super::scalar::{compose, eval, shift, CubicPoly};
use super::scheme::{Rule, Scheme, StepInput, Unknown};
use crate::cubic::nearest_root;
use crate::elements::ModalCubic;

/// One node of the single-mode analytic step: the state there is affine in the unknown `u`,
/// `q = cq . (q0, v0) + qb u`, `v = cv . (q0, v0) + vb u`.
#[derive(Debug, Clone, Copy)]
pub(super) struct ScalarNode {
    s: f64,
    cq: [f64; 2],
    cv: [f64; 2],
    qb: f64,
    vb: f64,
    /// Weights of the node's pseudo-force on the unknown's row and on the other row.
    wu: f64,
    wo: f64,
}

/// The single-mode analytic step, prepared once.
pub(super) struct ScalarPlan {
    a: ModalCubic,
    /// `rho(q) = sum p_k q^k` when the force does not depend on the velocity.
    q_only: Option<[f64; 4]>,
    nodes: Vec<ScalarNode>,
    w_sum: f64,
}

impl ScalarPlan {
    pub(super) fn new(a: ModalCubic, rule: &Rule, scheme: Scheme, dt: f64, on_v: bool) -> Self {
        let q_only = (1..4)
            .all(|j| (0..4 - j).all(|i| a[i][j] == 0.0))
            .then(|| [a[0][0], a[1][0], a[2][0], a[3][0]]);
        let (w_u, w_o) = if on_v {
            (&rule.wv, &rule.wx)
        } else {
            (&rule.wx, &rule.wv)
        };
        let nodes = rule
            .nodes
            .iter()
            .enumerate()
            .map(|(i, node)| {
                // the state is linear in (q0, v0) with the unknown (and the other end value,
                // which it does not depend on) at zero
                let unit = |q0: f64, v0: f64| scheme.state(node.s, dt, q0, v0, 0.0, 0.0);
                let (e_q, e_v) = (unit(1.0, 0.0), unit(0.0, 1.0));
                let [dqq, dqv, dvq, dvv] = node.d;
                let (qb, vb) = if on_v { (dqv, dvv) } else { (dqq, dvq) };
                ScalarNode {
                    s: node.s,
                    cq: [e_q.0, e_v.0],
                    cv: [e_q.1, e_v.1],
                    qb,
                    vb,
                    wu: w_u[i][0],
                    wo: w_o[i][0],
                }
            })
            .collect();
        ScalarPlan {
            a,
            q_only,
            nodes,
            w_sum: w_u.iter().map(|w| w[0]).sum(),
        }
    }

    /// `rho` along `q = qa + qb u`, `v = va + vb u`, as a cubic in `u`.
    #[inline(always)]
    pub(super) fn along(&self, qa: f64, qb: f64, va: f64, vb: f64) -> CubicPoly {
        match self.q_only {
            Some([p0, p1, p2, p3]) => {
                // Taylor expansion at u = 0
                let g0 = ((p3 * qa + p2) * qa + p1) * qa + p0;
                let g1 = ((3.0 * p3 * qa + 2.0 * p2) * qa + p1) * qb;
                let g2 = (3.0 * p3 * qa + p2) * qb * qb;
                [g0, g1, g2, p3 * qb * qb * qb]
            }
            None => compose(&self.a, [qa, qb], [va, vb]),
        }
    }
}

/// One mode with polynomial forces: the step equation and every node's pseudo-force are
/// cubics in the unknown, written down directly from the modal force's coefficients; the
/// root nearest the predictor solves the step (the paper's cubic). Returns `(q1, v1, Q at
/// the start state)`, or `None` when the cubic has no real root.
pub(super) fn scalar_step(
    plan: &ScalarPlan,
    dt: f64,
    unknown: Unknown,
    pf: &PseudoForce,
    inp: &StepInput,
) -> Option<(f64, f64, f64)> {
    let t = inp.t;
    let (q0, v0) = (inp.q0[0], inp.v0[0]);
    let on_v = unknown == Unknown::V1;
    let mass = pf.has_mass();
    let mut cubics = [[0.0; 4]; 4];
    let mut r: CubicPoly = [0.0; 4];
    for (node, cubic) in plan.nodes.iter().zip(cubics.iter_mut()) {
        let qa = node.cq[0] * q0 + node.cq[1] * v0;
        let va = node.cv[0] * q0 + node.cv[1] * v0;
        let mut qi = plan.along(qa, node.qb, va, node.vb);
        if mass {
            let s = node.s;
            let p = inp.pb[0][0] + inp.pb[1][0] * s + 4.0 * inp.pb[2][0] * s * (1.0 - s);
            let [al, be, ga, de] = pf.scalar_terms(t + s * dt, p, s == 1.0);
            for c in qi.iter_mut() {
                *c *= al;
            }
            qi[0] += be * qa + ga * va + de;
            qi[1] += be * node.qb + ga * node.vb;
        } else {
            for c in qi.iter_mut() {
                *c = -*c;
            }
        }
        for (rc, c) in r.iter_mut().zip(&qi) {
            *rc += node.wu * c;
        }
        *cubic = qi;
    }
    let base = if on_v { inp.v_lin[0] } else { inp.q_lin[0] };
    let residual = [-base - r[0], 1.0 - r[1], -r[2], -r[3]];
    // Predictor and the start state's pseudo-force (kept for the saved history).
    let rho0 = plan.along(q0, 0.0, v0, 0.0)[0];
    let q_start = if mass {
        let [al, be, ga, de] = pf.scalar_terms(t, inp.pb[0][0], false);
        al * rho0 + be * q0 + ga * v0 + de
    } else {
        -rho0
    };
    let u_pred = base + plan.w_sum * q_start;
    let u_start = if on_v { v0 } else { q0 };
    let h = (u_pred - u_start)
        .abs()
        .max(1e-6 * u_pred.abs().max(u_start.abs()))
        .max(1e-100);
    let delta = nearest_root(shift(&residual, u_pred, h), 0.0).filter(|d| d.is_finite())?;
    let u = u_pred + h * delta;
    let other_base = if on_v { inp.q_lin[0] } else { inp.v_lin[0] };
    let other = other_base
        + plan
            .nodes
            .iter()
            .zip(&cubics)
            .map(|(node, c)| node.wo * eval(c, u))
            .sum::<f64>();
    Some(if on_v {
        (other, u, q_start)
    } else {
        (u, other, q_start)
    })
}

/// Monomial coefficients on `[0, 1]` of the cubic with value and slope `f0` at 0, `f1` at 1.
pub(super) fn hermite(f0: [f64; 2], f1: [f64; 2]) -> [f64; 4] {
    let ([y0, d0], [y1, d1]) = (f0, f1);
    [
        y0,
        d0,
        3.0 * (y1 - y0) - 2.0 * d0 - d1,
        2.0 * (y0 - y1) + d0 + d1,
    ]
}
