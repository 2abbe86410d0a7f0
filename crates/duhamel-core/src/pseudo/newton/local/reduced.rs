//! The element-space step in the elements' deformations (a space of scalar two-node
//! elements, [`ElementSpace::deformation_count`]).
//!
//! With `e = B y` the members' deformations (`B` the `n_e x n_d` difference map) and
//! `r_i = B^T f_i`, the parent module's equation `F(y) = 0` multiplied by `B` reads
//!
//! ```text
//! F_e(e) = e - B P b + sum_i (B G_i B^T) f_i(B U_i + alpha_i e, B V_i + beta_i e) = 0,
//! J_e = I + sum_i (B G_i B^T) (alpha_i diag(k_i) + beta_i diag(c_i)),
//! ```
//!
//! the same equation (every term of `F` is `B` of something but the forces, which only
//! see `B y`) in `n_e` unknowns with a diagonal element tangent: the frame's 16 hinges on 32
//! dofs iterate on 16. The end state needs only `t_i = Phi_D^T r_i = Phi_E^T f_i`.

use super::super::super::force::PseudoForce;
use super::super::super::local::{zero, ElementSpace};
use super::super::super::scheme::StepInput;
use super::super::damping::{backtrack, corrected};
use super::{max_abs, same, sub_product, LocalNewton, NodeMap, Setting};
use crate::dense_kept::Eliminated;
use crate::dense_rows::{add_matvec, matvec};
use crate::error::CoreError;

/// The deformation step's matrices and buffers (`n_e` per vector).
pub(super) struct Reduced {
    ne: usize,
    /// `B P` (`n_e x n`) and per node `B G_i B^T` (`n_e x n_e`).
    pe: Vec<f64>,
    ge: Vec<Vec<f64>>,
    /// Per node `B U_i`, `B V_i`; its forces and their tangents.
    e0n: Vec<Vec<f64>>,
    ed0n: Vec<Vec<f64>>,
    pub(super) f: Vec<Vec<f64>>,
    kd: Vec<Vec<f64>>,
    cd: Vec<Vec<f64>>,
    /// The forces at the start state.
    f_start: Vec<f64>,
    /// Newton's buffers.
    e: Vec<f64>,
    e0: Vec<f64>,
    e_prev: Vec<f64>,
    delta: Vec<f64>,
    res: Vec<f64>,
    mat: Vec<f64>,
    eu: Vec<f64>,
    eud: Vec<f64>,
    /// The last elimination and the varying nodes' tangents it was formed with.
    kept: Eliminated,
    kept_kd: Vec<Vec<f64>>,
    kept_cd: Vec<Vec<f64>>,
}

impl Reduced {
    /// The buffers for `ne` deformations, `nodes` quadrature nodes and `n` modes.
    pub(super) fn new(ne: usize, nodes: usize, n: usize) -> Self {
        let per_node = |len: usize| vec![vec![0.0; len]; nodes];
        Reduced {
            ne,
            pe: vec![0.0; ne * n],
            ge: per_node(ne * ne),
            e0n: per_node(ne),
            ed0n: per_node(ne),
            f: per_node(ne),
            kd: per_node(ne),
            cd: per_node(ne),
            f_start: vec![0.0; ne],
            e: vec![0.0; ne],
            e0: vec![0.0; ne],
            e_prev: vec![0.0; ne],
            delta: vec![0.0; ne],
            res: vec![0.0; ne],
            mat: vec![0.0; ne * ne],
            eu: vec![0.0; ne],
            eud: vec![0.0; ne],
            kept: Eliminated::default(),
            kept_kd: Vec::new(),
            kept_cd: Vec::new(),
        }
    }

    /// Evaluates the varying nodes at `e` and returns the residual's max norm.
    fn residual(
        &mut self,
        map: &[NodeMap],
        space: &mut ElementSpace,
        (set, inp): (&Setting, &StepInput),
        tangent: bool,
    ) -> Result<f64, CoreError> {
        let ne = self.ne;
        for ((r, e), e0) in self.res.iter_mut().zip(&self.e).zip(&self.e0) {
            *r = e - e0;
        }
        for (i, m) in map.iter().enumerate() {
            if m.constant {
                continue;
            }
            for a in 0..ne {
                self.eu[a] = self.e0n[i][a] + m.alpha * self.e[a];
                self.eud[a] = self.ed0n[i][a] + m.beta * self.e[a];
            }
            let t = inp.t + m.s * set.dt;
            let tan = tangent.then_some((&mut self.kd[i][..], &mut self.cd[i][..]));
            space.eval_deformation((&self.eu, &self.eud), t, &mut self.f[i], tan)?;
            add_matvec(&mut self.res, &self.ge[i], &self.f[i]);
        }
        // NaN must not vanish in the max (f64::max drops it).
        Ok(self.res.iter().fold(0.0_f64, |acc, &r| {
            if r.is_nan() || r.abs() > acc {
                r.abs()
            } else {
                acc
            }
        }))
    }

    /// `J_e` over the varying nodes.
    fn jacobian(&mut self, map: &[NodeMap]) {
        let ne = self.ne;
        zero(&mut self.mat);
        for a in 0..ne {
            self.mat[a * ne + a] = 1.0;
        }
        for (i, m) in map.iter().enumerate() {
            if m.constant {
                continue;
            }
            let (g, kd, cd) = (&self.ge[i], &self.kd[i], &self.cd[i]);
            for (row, grow) in self.mat.chunks_exact_mut(ne).zip(g.chunks_exact(ne)) {
                for (((x, gac), k), c) in row.iter_mut().zip(grow).zip(kd).zip(cd) {
                    *x += gac * (m.alpha * k + m.beta * c);
                }
            }
        }
    }

    /// Whether the kept elimination is that of the matrix [`Reduced::jacobian`] would form
    /// now (the same `B G_i B^T` and the varying nodes' tangents bit for bit).
    fn same_tangents(&self, map: &[NodeMap]) -> bool {
        if !self.kept.valid {
            return false;
        }
        let varying = map.iter().enumerate().filter(|(_, m)| !m.constant);
        varying
            .zip(self.kept_kd.iter().zip(&self.kept_cd))
            .all(|((i, _), (kk, ck))| same(&self.kd[i], kk) && same(&self.cd[i], ck))
    }

    /// Keeps the varying nodes' tangents the matrix is formed with.
    fn keep_tangents(&mut self, map: &[NodeMap]) {
        let varying: Vec<usize> = (0..map.len()).filter(|&i| !map[i].constant).collect();
        self.kept_kd.resize(varying.len(), Vec::new());
        self.kept_cd.resize(varying.len(), Vec::new());
        for (slot, &i) in varying.iter().enumerate() {
            self.kept_kd[slot].clone_from(&self.kd[i]);
            self.kept_cd[slot].clone_from(&self.cd[i]);
        }
    }
}

impl LocalNewton {
    /// The step's element part in the deformations, from the node maps `U_i`, `V_i`, `b`
    /// (and `y0 = Phi_D z_lin` without affine terms) on: the constant nodes, the prediction
    /// and Newton. Leaves the nodes' forces in `red.f` for [`LocalNewton::finish`].
    pub(super) fn solve_reduced(
        &mut self,
        red: &mut Reduced,
        pf: &mut PseudoForce,
        (set, inp): (&Setting, &StepInput),
        rebuild: bool,
    ) -> Result<usize, CoreError> {
        let (n, nd) = (self.n, self.nd);
        let space = pf.space_mut();
        if rebuild {
            red.kept.valid = false;
            space.rows_to_deformation(&self.pmat, n, &mut red.pe);
            for (ge, g) in red.ge.iter_mut().zip(&self.g) {
                space.square_to_deformation(g, nd, ge);
            }
        }
        if self.affine {
            matvec(&red.pe, &self.base, &mut red.e0);
        } else {
            space.to_deformation(&self.y0, &mut red.e0);
        }
        for i in 0..self.map.len() {
            space.to_deformation(&self.u0[i], &mut red.e0n[i]);
            space.to_deformation(&self.ud0[i], &mut red.ed0n[i]);
            if !self.map[i].constant {
                continue;
            }
            let t = inp.t + self.map[i].s * set.dt;
            let state = (&red.e0n[i][..], &red.ed0n[i][..]);
            space.eval_deformation(state, t, &mut red.f[i], None)?;
            // the start state itself (its displacements bit for bit): kept for its record
            if self.map[i].s == 0.0 && same(&self.u0[i], &self.pq) {
                let differs = !same(&self.ud0[i], &self.pv);
                let (pq, pv) = (&self.pq[..], &self.pv[..]);
                space.keep_start((inp.q0, inp.v0), t, (pq, pv), differs);
            }
            sub_product(&mut red.e0, &red.ge[i], &red.f[i]);
        }
        // the initial guess: the forces of the start state held over the step
        red.e.copy_from_slice(&red.e0);
        let first = self.map[0];
        if !(first.constant && first.s == 0.0) {
            space.to_deformation(&self.pq, &mut red.eu);
            space.to_deformation(&self.pv, &mut red.eud);
            space.eval_deformation((&red.eu, &red.eud), inp.t, &mut red.f_start, None)?;
            space.keep_start((inp.q0, inp.v0), inp.t, (&self.pq, &self.pv), false);
        } else {
            red.f_start.copy_from_slice(&red.f[0]);
        }
        space.scatter_deformation(&red.f_start, &mut self.r_start);
        self.start_ready = true;
        for i in 0..self.map.len() {
            if !self.map[i].constant {
                sub_product(&mut red.e, &red.ge[i], &red.f_start);
            }
        }
        // the scale of the deformations' rounding: the element coordinates they are
        // differences of
        let largest = self
            .u0
            .iter()
            .fold(max_abs(&red.e0), |a, u| a.max(max_abs(u)));
        let scale0 = largest.max(space.resolution() / set.tol);
        self.newton_reduced(red, space, (set, inp), scale0)
    }

    /// [`LocalNewton::newton`] on `F_e(e) = 0`.
    fn newton_reduced(
        &self,
        red: &mut Reduced,
        space: &mut ElementSpace,
        (set, inp): (&Setting, &StepInput),
        scale0: f64,
    ) -> Result<usize, CoreError> {
        let map = &self.map;
        let mut last: Option<f64> = None;
        let mut last_size: Option<f64> = None;
        let mut norm = f64::INFINITY;
        for iter in 1..=set.max_iter {
            norm = red.residual(map, space, (set, inp), true)?;
            let mut cut = false;
            if let Some(prev) = last {
                norm = backtrack(prev, norm, scale0, |lambda| {
                    cut = true;
                    for ((e, ep), d) in red.e.iter_mut().zip(&red.e_prev).zip(&red.delta) {
                        *e = ep + lambda * d;
                    }
                    red.residual(map, space, (set, inp), true)
                })?;
            }
            for (d, r) in red.delta.iter_mut().zip(&red.res) {
                *d = -r;
            }
            if red.same_tangents(map) {
                if !red.kept.solve(&mut red.delta) {
                    break;
                }
            } else {
                red.jacobian(map);
                red.keep_tangents(map);
                if !red.kept.eliminate(red.ne, &mut red.mat, &mut red.delta) {
                    break;
                }
            }
            let Some((size, scale)) = corrected(&mut red.e, &mut red.e_prev, &red.delta, scale0)
            else {
                self.accept(space);
                return Ok(iter);
            };
            if set.settled(last_size, size, scale, cut) {
                let at_end = self.ends_at_end();
                red.residual(map, space, (set, inp), at_end)?;
                if at_end {
                    self.accept(space);
                }
                return Ok(iter);
            }
            last = Some(norm);
            last_size = Some(size);
        }
        Err(set.no_convergence(inp, norm))
    }
}
