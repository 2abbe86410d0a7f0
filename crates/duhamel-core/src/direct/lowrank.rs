//! Newton on large sparse models with few nonlinear elements, without refactorising.
//!
//! The iteration matrix of a step is `A = A0 + P D P^T`: `A0` the constant part (mass,
//! damping, stiffness; no mass law, no time-varying coupling) and `D` the elements' tangents
//! (`ck dr/dx + cc dr/dx'`) on the `nl` dofs the elements touch, `P` the `n x nl` selection
//! of those dofs. `A0` is factorised once per run and `Z = A0^-1 P` solved once (`nl` sparse
//! solves); a Newton update then costs one sparse solve and a dense `nl x nl` system
//! (Woodbury):
//!
//! `A^-1 r = y - Z S^-1 D P^T y`, `y = A0^-1 r`, `S = I + D P^T Z`,
//!
//! exact, not an approximation of the tangent: the iterates are those of the full Newton
//! matrix up to round-off. `S` is refactorised whenever the tangents change (`O(nl^3)`).

use super::assembly::{singular, Factorization};
use super::model::Model;
use crate::dense::DenseLu;
use crate::error::CoreError;

/// Use the low-rank form when the elements touch at most this fraction of the dofs.
pub(crate) const MAX_FRACTION: usize = 4;

/// `A0` factorised and the Woodbury terms of the elements' tangents.
pub(crate) struct LowRank {
    base: Factorization,
    n: usize,
    /// The dofs the elements touch, and each element's positions among them.
    dofs: Vec<usize>,
    local: Vec<Vec<usize>>,
    /// `Z = A0^-1 P`, column `c` at `z[c * n..(c + 1) * n]`.
    z: Vec<f64>,
    /// `W = P^T Z`, row-major `nl x nl`.
    w: Vec<f64>,
    /// Tangent block `D` and `S = I + D W`, row-major `nl x nl`.
    d: Vec<f64>,
    s_matrix: Vec<f64>,
    s: DenseLu,
    u: Vec<f64>,
    work: Vec<f64>,
}

impl LowRank {
    /// The dofs touched by `model`'s elements, sorted, with each element's positions; None
    /// when they are more than `n / MAX_FRACTION` (the dense update would cost more).
    pub(crate) fn dofs(model: &Model) -> Option<(Vec<usize>, Vec<Vec<usize>>)> {
        let mut dofs: Vec<usize> = model
            .slots
            .iter()
            .flat_map(|s| s.element.dofs().iter().copied())
            .collect();
        dofs.sort_unstable();
        dofs.dedup();
        if dofs.is_empty() || dofs.len() * MAX_FRACTION > model.n {
            return None;
        }
        let local = model
            .slots
            .iter()
            .map(|s| {
                let d = s.element.dofs();
                d.iter()
                    .map(|g| dofs.binary_search(g).unwrap_or(0))
                    .collect()
            })
            .collect();
        Some((dofs, local))
    }

    /// Solves `Z = A0^-1 P` with the factorised `base`.
    pub(crate) fn new(
        base: Factorization,
        n: usize,
        (dofs, local): (Vec<usize>, Vec<Vec<usize>>),
    ) -> Result<Self, CoreError> {
        let nl = dofs.len();
        let mut z = vec![0.0; n * nl];
        for (c, &g) in dofs.iter().enumerate() {
            let col = &mut z[c * n..(c + 1) * n];
            col[g] = 1.0;
            if !base.solve_in_place(col) {
                return Err(singular());
            }
        }
        let mut w = vec![0.0; nl * nl];
        for (a, &g) in dofs.iter().enumerate() {
            for c in 0..nl {
                w[a * nl + c] = z[c * n + g];
            }
        }
        Ok(LowRank {
            base,
            n,
            dofs,
            local,
            z,
            w,
            d: vec![0.0; nl * nl],
            s_matrix: vec![0.0; nl * nl],
            s: DenseLu::default(),
            u: vec![0.0; nl],
            work: vec![0.0; nl],
        })
    }

    /// Takes the elements' current tangents, `D = sum_e ck K_e + cc C_e`, and factorises
    /// `S = I + D W`; false when `S` is singular (the full matrix is).
    pub(crate) fn update(&mut self, model: &Model, ck: f64, cc: f64) -> bool {
        let nl = self.dofs.len();
        self.d.fill(0.0);
        for (slot, pos) in model.slots.iter().zip(&self.local) {
            let m = pos.len();
            for a in 0..m {
                for b in 0..m {
                    let v = ck * slot.kx[a * m + b] + cc * slot.cv[a * m + b];
                    self.d[pos[a] * nl + pos[b]] += v;
                }
            }
        }
        let s = &mut self.s_matrix;
        s.fill(0.0);
        for i in 0..nl {
            for k in 0..nl {
                let dik = self.d[i * nl + k];
                if dik != 0.0 {
                    let (row, wk) = (&mut s[i * nl..(i + 1) * nl], &self.w[k * nl..(k + 1) * nl]);
                    for (x, &y) in row.iter_mut().zip(wk) {
                        *x += dik * y;
                    }
                }
            }
            s[i * nl + i] += 1.0;
        }
        self.s.refactor(nl, &self.s_matrix)
    }

    /// `A^-1 r` in place of `r`; false if it is not finite.
    pub(crate) fn solve_in_place(&mut self, r: &mut [f64]) -> bool {
        if !self.base.solve_in_place(r) {
            return false;
        }
        let nl = self.dofs.len();
        for (i, ui) in self.u.iter_mut().enumerate() {
            let row = &self.d[i * nl..(i + 1) * nl];
            *ui = row.iter().zip(&self.dofs).map(|(dij, &g)| dij * r[g]).sum();
        }
        if !self.s.solve(&mut self.u, &mut self.work) {
            return false;
        }
        for (c, &wc) in self.u.iter().enumerate() {
            if wc != 0.0 {
                let col = &self.z[c * self.n..(c + 1) * self.n];
                for (x, &y) in r.iter_mut().zip(col) {
                    *x -= wc * y;
                }
            }
        }
        r.iter().all(|v| v.is_finite())
    }
}
