//! One step in the space of the elements' dofs (the FNA iteration), end state included.
//!
//! With `z` the unknown half of the end state (`q1` for schemes b and c, `v1` for scheme a)
//! and `w` the other half, the node states are affine in `z`:
//! `q_i = q_i^0 + alpha_i z`, `v_i = v_i^0 + beta_i z`, where `q_i^0`, `v_i^0` are fixed
//! combinations of the start state (the same `alpha_i`, `beta_i` for every mode). Along the
//! eliminated mass law (or without one) the pseudo-force at node `i` is
//!
//! ```text
//! Q_i = g_i (p_i - c v_i - kappa k q_i) - mom_i v_i - s_i (K_i q_i + C_i v_i + Phi_D^T r_i)
//!     = Q_i^0 - (diag(d_i) + s_i M_i) z - s_i Phi_D^T r_i,      M_i = alpha_i K_i + beta_i C_i
//! ```
//!
//! (`s_i = 1/mu_i`, `K_i`, `C_i` the linear couplings at the node's time), affine in the
//! state but for the element forces `r_i`. The step equation `z = z_lin + sum_i W_i Q_i`
//! is therefore `A z = b - sum_i s_i W_i Phi_D^T r_i` with
//! `A = I + sum_i W_i (diag(d_i) + s_i M_i)` (diagonal without couplings) and
//! `b = z_lin + sum_i W_i Q_i^0`. With `P = Phi_D A^{-1}` and `y = Phi_D z` it becomes, in
//! the element coordinates,
//!
//! ```text
//! F(y) = y - P b + sum_i G_i r_i(U_i + alpha_i y, V_i + beta_i y) = 0,
//! G_i = s_i P diag(W_i) Phi_D^T,   J = I + sum_i G_i (alpha_i K_i + beta_i C_i),
//! ```
//!
//! `n_d` unknowns instead of `n` ([`iterate`]). From the converged forces, with
//! `t_i = Phi_D^T r_i`, `z = A^{-1} (b - sum_i s_i W_i t_i)`, every `Q_i` follows without
//! evaluating anything again, and `w = w_lin + sum_i W'_i Q_i` ([`affine`]). A step costs
//! about `5 n n_d` besides the Newton iterations (`O(n_nodes n_d^2 + n_d^3)` each) with a
//! diagonal `A`; couplings add a few `n x n` products, and a dense `A` that varies (a mass
//! law, couplings scaled by a time-varying speed) its factorisation, once per step. `A`,
//! `P` and `G_i` are formed once per run otherwise.

mod affine;
mod iterate;
mod lean;
mod reduced;
mod scaled;
mod single;

use super::super::force::PseudoForce;
use super::super::local::ElementSpace;
use super::super::scheme::{StepInput, Unknown};
use super::setting::Setting;
use crate::dense::DenseLu;
use crate::dense_kept::Eliminated;
use crate::error::CoreError;

/// What the rule says about node `i`'s state, `q_i = cq.0 q0 + cq.1 v0 + alpha z`,
/// `v_i = cv.0 q0 + cv.1 v0 + beta z`, and whether it is evaluated once per step.
#[derive(Debug, Clone, Copy)]
struct NodeMap {
    s: f64,
    cq: (f64, f64),
    cv: (f64, f64),
    alpha: f64,
    beta: f64,
    constant: bool,
}

/// What the element-space step writes.
pub(in super::super) struct End<'o> {
    /// The unknown half of the end state (`q1`; `v1` for scheme a).
    pub z: &'o mut [f64],
    /// The other half.
    pub w: &'o mut [f64],
    /// The pseudo-force at the start state, when the first node is that state, evaluated
    /// once (None otherwise).
    pub start: Option<&'o mut [f64]>,
}

/// The element-space step: its per-node maps, matrices and buffers.
pub(in super::super) struct LocalNewton {
    n: usize,
    nd: usize,
    map: Vec<NodeMap>,
    /// Whether the pseudo-force has affine terms besides the elements (mass law, couplings).
    affine: bool,
    /// Per node `s_i W_i` (`n`), and `G_i` (`n_d x n_d`); whether they hold for every step.
    w_hat: Vec<Vec<f64>>,
    g: Vec<Vec<f64>>,
    ready: bool,
    /// `P = Phi_D A^{-1}` (`n_d x n`, row-major); with a dense `A`, `P^T` and scratch.
    pmat: Vec<f64>,
    pt: Vec<f64>,
    pt_work: Vec<f64>,
    /// The diagonal of `A`, and with couplings `A` itself and its factors.
    diag: Vec<f64>,
    /// Whether `diag` is all ones (no mass law): the end state's division by it is then
    /// the identity and left out.
    unit: bool,
    a: Vec<f64>,
    lu: Option<DenseLu>,
    /// `A^{-1}` (row-major), formed with the factors when `A` holds for the whole run (no
    /// mass law, constant couplings): the end state's `A^{-1}` then one matrix-vector
    /// product (independent rows) instead of the substitutions (a chain of dependent ones).
    ainv: Vec<f64>,
    a_constant: bool,
    work: Vec<f64>,
    /// `b` (`n`).
    base: Vec<f64>,
    /// Per node: `s_i`, `Q_i^0` and `d_i` (`n`, with affine terms), `t_i = Phi_D^T r_i`.
    s: Vec<f64>,
    q_aff: Vec<Vec<f64>>,
    d: Vec<Vec<f64>>,
    t: Vec<Vec<f64>>,
    /// The couplings at each node (`n x n`; one shared pair when they are constant).
    kc: Vec<Vec<f64>>,
    cc: Vec<Vec<f64>>,
    /// Under a mass law with constant couplings, per node with a state-dependent coupling
    /// term: `(i, W_i (alpha_i K + beta_i C))` ([`scaled`]).
    h: Vec<(usize, Vec<f64>)>,
    /// With it, `Phi_D^T` (`n x n_d`, row-major), formed on the first step.
    phi_t: Vec<f64>,
    has_kc: (bool, bool),
    /// Coupling products `K q0, K v0, C q0, C v0`, `K z`, `C z` (constant couplings).
    prod: [Vec<f64>; 6],
    /// The last step's end `z` and its products `K z`, `C z` (constant couplings; an absent
    /// one's product zero): the next step's start products of that half, when its start
    /// is that `z` bit for bit (the same products, not formed again).
    last_z: Vec<f64>,
    last_prod: [Vec<f64>; 2],
    /// `Phi_D q0`, `Phi_D v0`, the force at the start state; per node `U_i`, `V_i`, the
    /// force and its tangents.
    pq: Vec<f64>,
    r_start: Vec<f64>,
    /// Whether `r_start` belongs to the current step's start state.
    start_ready: bool,
    pv: Vec<f64>,
    u0: Vec<Vec<f64>>,
    ud0: Vec<Vec<f64>>,
    r: Vec<Vec<f64>>,
    kt: Vec<Vec<f64>>,
    ct: Vec<Vec<f64>>,
    /// Newton's buffers in the element space.
    y: Vec<f64>,
    y0: Vec<f64>,
    y_prev: Vec<f64>,
    delta: Vec<f64>,
    res: Vec<f64>,
    mat: Vec<f64>,
    u: Vec<f64>,
    ud: Vec<f64>,
    /// The sparsity of the tangents' rows ([`ElementSpace::pattern`]).
    pattern: Vec<Vec<usize>>,
    /// The last elimination of Newton's matrix, and the varying nodes' tangents it was
    /// formed with (reused while they stay the same bit for bit and `G_i` is not rebuilt).
    kept: Eliminated,
    kept_kt: Vec<Vec<f64>>,
    kept_ct: Vec<Vec<f64>>,
    /// Whether the step is [`LocalNewton::step_lean`]'s (one element on one dof, nothing
    /// affine).
    lean: bool,
    /// Whether the last varying node is the end state with the unknown `z = q1` as its
    /// displacements (`q = 0 q0 + 0 v0 + 1 z`: schemes b and c): its element coordinate is
    /// then `Phi_D q1` up to rounding, and its evaluation the end state's.
    end_is_unknown: bool,
    /// The step in the elements' deformations, when the space is one of scalar two-node
    /// elements ([`reduced`]).
    red: Option<reduced::Reduced>,
}

impl LocalNewton {
    pub fn new(pf: &PseudoForce, set: &Setting, n: usize) -> Self {
        let space = pf.space();
        let nd = space.len();
        let nodes = set.rule.nodes.len();
        let per_node = |len: usize| vec![vec![0.0; len]; nodes];
        let coupled = pf.has_couplings();
        let square = if coupled { n * n } else { 0 };
        let coupling_nodes = if pf.varying_couplings() { nodes } else { 1 };
        let affine = coupled || pf.has_mass();
        // A node whose element states do not depend on the unknown is evaluated once per
        // step: the affine terms (couplings, mass law) are in `A`, so only the elements'
        // reading of the velocity counts here (a damping coupling alone leaves it constant).
        let elements_velocity = space.uses_velocity();
        let map = set
            .rule
            .nodes
            .iter()
            .enumerate()
            .map(|(i, node)| {
                let [dqq, dqv, dvq, dvv] = node.d;
                let (alpha, beta) = match set.unknown {
                    Unknown::V1 => (dqv, dvv),
                    _ => (dqq, dvq),
                };
                let (q_q0, v_q0) = set.scheme.state(node.s, set.dt, 1.0, 0.0, 0.0, 0.0);
                let (q_v0, v_v0) = set.scheme.state(node.s, set.dt, 0.0, 1.0, 0.0, 0.0);
                NodeMap {
                    s: node.s,
                    cq: (q_q0, q_v0),
                    cv: (v_q0, v_v0),
                    alpha,
                    beta,
                    constant: set.constant[i]
                        || match set.unknown {
                            Unknown::Q1 => dqq == 0.0 && (dvq == 0.0 || !elements_velocity),
                            Unknown::V1 => dqv == 0.0 && (dvv == 0.0 || !elements_velocity),
                            Unknown::Both => false,
                        },
                }
            })
            .collect();
        let vec_n = |on: bool| vec![0.0; if on { n } else { 0 }];
        let mut newton = LocalNewton {
            n,
            nd,
            map,
            affine,
            w_hat: per_node(n),
            g: per_node(nd * nd),
            ready: false,
            pmat: vec![0.0; nd * n],
            pt: vec![0.0; if coupled { nd * n } else { 0 }],
            pt_work: vec![0.0; if coupled { nd * n } else { 0 }],
            diag: vec![1.0; n],
            unit: false,
            a: vec![0.0; square],
            lu: None,
            ainv: Vec::new(),
            a_constant: !(pf.has_mass() || pf.varying_couplings()),
            work: vec![0.0; n],
            base: vec![0.0; n],
            s: vec![1.0; nodes],
            q_aff: vec![vec_n(affine); nodes],
            d: vec![vec_n(pf.has_mass()); nodes],
            t: per_node(n),
            kc: vec![vec![0.0; square]; coupling_nodes],
            cc: vec![vec![0.0; square]; coupling_nodes],
            h: Vec::new(),
            phi_t: Vec::new(),
            has_kc: (false, false),
            prod: std::array::from_fn(|_| vec_n(coupled)),
            last_z: Vec::new(),
            last_prod: [Vec::new(), Vec::new()],
            pq: vec![0.0; nd],
            r_start: vec![0.0; nd],
            start_ready: false,
            pv: vec![0.0; nd],
            u0: per_node(nd),
            ud0: per_node(nd),
            r: per_node(nd),
            kt: per_node(nd * nd),
            ct: per_node(nd * nd),
            y: vec![0.0; nd],
            y0: vec![0.0; nd],
            y_prev: vec![0.0; nd],
            delta: vec![0.0; nd],
            res: vec![0.0; nd],
            mat: vec![0.0; nd * nd],
            u: vec![0.0; nd],
            ud: vec![0.0; nd],
            pattern: space.pattern(),
            kept: Eliminated::default(),
            kept_kt: Vec::new(),
            kept_ct: Vec::new(),
            lean: false,
            end_is_unknown: false,
            red: space
                .deformation_count()
                .map(|ne| reduced::Reduced::new(ne, nodes, n)),
        };
        let end = newton.map.iter().rev().find(|m| !m.constant);
        newton.end_is_unknown = set.unknown == Unknown::Q1
            && end.is_some_and(|m| m.s == 1.0 && m.cq == (0.0, 0.0) && m.alpha == 1.0);
        newton.lean = newton.lean_applies(space);
        newton
    }

    /// The weights of the unknown half (`W_i`) and of the other one (`W'_i`).
    fn weights<'s>(set: &Setting<'s>) -> (&'s [Vec<f64>], &'s [Vec<f64>]) {
        if set.unknown == Unknown::V1 {
            (&set.rule.wv, &set.rule.wx)
        } else {
            (&set.rule.wx, &set.rule.wv)
        }
    }

    /// Solves the step into `end`. Returns the Newton iterations.
    pub fn step(
        &mut self,
        pf: &mut PseudoForce,
        set: &Setting,
        inp: &StepInput,
        end: End,
    ) -> Result<usize, CoreError> {
        let End { z, w, start } = end;
        self.start_ready = false;
        pf.space_mut().drop_start();
        let (z_lin, w_lin) = if set.unknown == Unknown::V1 {
            (inp.v_lin, inp.q_lin)
        } else {
            (inp.q_lin, inp.v_lin)
        };
        if self.lean {
            return self.step_lean(pf, set, inp, (z_lin, w_lin), End { z, w, start });
        }
        if self.affine {
            pf.space().to_local(inp.q0, &mut self.pq);
            pf.space().to_local(inp.v0, &mut self.pv);
        } else {
            // Without affine terms P = Phi_D (A = I) and b = z_lin: y0 = Phi_D z_lin in the
            // same pass.
            let out = [&mut self.pq[..], &mut self.pv[..], &mut self.y0[..]];
            pf.space().to_local3([inp.q0, inp.v0, z_lin], out);
        }
        for (i, m) in self.map.iter().enumerate() {
            for (a, (u, ud)) in self.u0[i].iter_mut().zip(&mut self.ud0[i]).enumerate() {
                *u = m.cq.0 * self.pq[a] + m.cq.1 * self.pv[a];
                *ud = m.cv.0 * self.pq[a] + m.cv.1 * self.pv[a];
            }
        }
        self.base.copy_from_slice(z_lin);
        let rebuild = pf.has_mass() || pf.varying_couplings() || !self.ready;
        if self.affine {
            self.affine_terms(pf, set, inp);
        }
        if rebuild {
            self.kept.valid = false; // G_i change
            if self.scaled_applies(pf.has_mass()) {
                self.assemble_scaled(set);
                self.prepare_scaled(pf.space())?;
            } else {
                self.assemble(pf, set);
                self.prepare(pf.space())?;
            }
        }
        if let Some(mut red) = self.red.take() {
            let solved = self.solve_reduced(&mut red, pf, (set, inp), rebuild);
            self.red = Some(red);
            let iterations = solved?;
            self.finish(pf.space(), set, z, (w_lin, w), start);
            return Ok(iterations);
        }
        // y0 = P b, then the constant nodes' forces, evaluated once.
        if self.affine {
            crate::dense_rows::matvec(&self.pmat, &self.base, &mut self.y0);
        }
        for i in 0..self.map.len() {
            if self.map[i].constant {
                let t = inp.t + self.map[i].s * set.dt;
                let space = pf.space_mut();
                space.eval(&self.u0[i], &self.ud0[i], t, &mut self.r[i], None)?;
                // the start state itself (its displacements bit for bit): kept for its record
                if self.map[i].s == 0.0 && same(&self.u0[i], &self.pq) {
                    let differs = !same(&self.ud0[i], &self.pv);
                    let (pq, pv) = (&self.pq[..], &self.pv[..]);
                    space.keep_start((inp.q0, inp.v0), t, (pq, pv), differs);
                }
                sub_product(&mut self.y0, &self.g[i], &self.r[i]);
            }
        }
        self.predict(pf.space_mut(), inp)?;
        // an element's deformation from a loaded start rounds at its resolution: below it
        // the corrections do not contract
        let largest = self
            .u0
            .iter()
            .fold(max_abs(&self.y0), |a, u| a.max(max_abs(u)));
        let scale0 = largest.max(pf.space().resolution() / set.tol);
        let iterations = if self.nd == 1 {
            self.newton_one(pf.space_mut(), set, inp, scale0)?
        } else {
            self.newton(pf.space_mut(), set, inp, scale0)?
        };
        self.finish(pf.space(), set, z, (w_lin, w), start);
        Ok(iterations)
    }

    /// The initial guess of `y`: the forces of the start state held over the step.
    fn predict(&mut self, space: &mut ElementSpace, inp: &StepInput) -> Result<(), CoreError> {
        self.y.copy_from_slice(&self.y0);
        let first = self.map[0];
        if !(first.constant && first.s == 0.0) {
            space.eval(&self.pq, &self.pv, inp.t, &mut self.r_start, None)?;
            space.keep_start((inp.q0, inp.v0), inp.t, (&self.pq, &self.pv), false);
        } else {
            self.r_start.copy_from_slice(&self.r[0]);
        }
        self.start_ready = true;
        for i in 0..self.map.len() {
            if !self.map[i].constant {
                sub_product(&mut self.y, &self.g[i], &self.r_start);
            }
        }
        Ok(())
    }
}

/// Whether `a` and `b` hold the same numbers bit for bit.
fn same(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// `t = Phi_D^T r_i` of node `i`'s element forces: from its deformations' forces when the
/// step ran in them.
fn project_node(
    red: &Option<reduced::Reduced>,
    space: &ElementSpace,
    (i, r): (usize, &[f64]),
    t: &mut [f64],
) {
    match red {
        Some(red) => space.project_deformation(&red.f[i], t),
        None => space.project(r, t),
    }
}

/// `x.iter().fold(0.0, |a, b| a.max(b.abs()))` in four independent chains: the same number
/// (`max` drops NaN and every candidate is `+0` or positive, so the largest is the same in
/// any order), without one chain of dependent `max` over every entry.
fn max_abs(x: &[f64]) -> f64 {
    let mut acc = [0.0_f64; 4];
    let chunks = x.chunks_exact(4);
    let tail = chunks
        .remainder()
        .iter()
        .fold(0.0_f64, |a, b| a.max(b.abs()));
    for c in chunks {
        for k in 0..4 {
            acc[k] = acc[k].max(c[k].abs());
        }
    }
    acc[0].max(acc[1]).max(acc[2].max(acc[3])).max(tail)
}

/// `y -= G r` for a row-major `n_d x n_d` matrix `G`.
fn sub_product(y: &mut [f64], g: &[f64], r: &[f64]) {
    // each row `y_a - dot(row, r)` bit for bit, four rows at a time
    crate::dense_rows::sub_matvec(y, g, r);
}

#[cfg(test)]
mod tests {
    use super::max_abs;

    /// The four chains give the one chain's number: NaN dropped, zeros of either sign,
    /// every length's tail.
    #[test]
    fn max_abs_is_the_sequential_fold() {
        let values = [
            0.3,
            -2.5,
            f64::NAN,
            -0.0,
            1e-300,
            7.25,
            -7.5,
            0.0,
            3.0,
            f64::NAN,
            -1.0,
        ];
        for len in 0..=values.len() {
            for shift in 0..values.len() {
                let x: Vec<f64> = (0..len)
                    .map(|i| values[(i + shift) % values.len()])
                    .collect();
                let one = x.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
                assert_eq!(max_abs(&x).to_bits(), one.to_bits(), "{x:?}");
            }
        }
    }
}
