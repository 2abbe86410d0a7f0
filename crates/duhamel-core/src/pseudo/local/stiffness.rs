//! The stiffness watch's measure of the elements' tangent against the background they load
//! ([`ElementSpace::tangent_stiffness`]).

use super::{ElementSpace, Member, Outcome, DOMINANT};
use crate::error::CoreError;

/// The symmetric part of a row-major `nl x nl` tangent, entry `(i, j)`.
fn k_sym(kx: &[f64], nl: usize, i: usize, j: usize) -> f64 {
    0.5 * (kx[i * nl + j] + kx[j * nl + i])
}

impl ElementSpace<'_> {
    /// The squared frequency `omega_c^2` of the closed state at the modal state `(q, v)`,
    /// bounded as the modal stiffness the elements' current tangents add (for each element
    /// the largest `|eigenvalue|` of `Phi_e^T K_e Phi_e`, the symmetric part of its tangent
    /// `K_e` on its dofs' mode-shape rows `Phi_e`) plus that of the background they load
    /// (the modal stiffness `k` of the modes weighted by the element's share
    /// `|diag(Phi_e^T K_e Phi_e)|` in each, the largest over the elements); only elements that
    /// dominate that background (at least [`DOMINANT`] times it) count, and 0 when none
    /// does. With the index of the element adding most. Every element is watched: one
    /// evaluation with tangents per call (central differences for a Python element without a
    /// Jacobian: its stiffness escapes the step's stability limit no more than a built-in
    /// one's). Path-dependent elements are evaluated from their committed variables (their
    /// trial variables are overwritten, as any evaluation does). When the step solver's last
    /// evaluation was at its converged end state with tangents ([`ElementSpace::mark_end`])
    /// and none came after it, its tangents are used (the state the watch asks for is that
    /// one, up to the rounding of its element coordinates and Newton's tolerance).
    pub fn tangent_stiffness(
        &mut self,
        modal_k: &[f64],
        q: &[f64],
        v: &[f64],
        t: f64,
    ) -> Result<(f64, usize), CoreError> {
        let n = self.n_modes;
        let reuse = self.end_mark.take() == Some(self.evaluations());
        let key = (modal_k.as_ptr() as usize, modal_k.len());
        let fresh = self.share_key != key;
        self.share_key = key;
        if reuse && !fresh && self.single {
            if let Some(out) = self.single_reused() {
                return Ok(out);
            }
        }
        let phi = &self.phi;
        let diag = &mut self.diag;
        let (mut total, mut worst, mut largest, mut background) = (0.0, 0, 0.0, 0.0f64);
        for (index, m) in self.members.iter_mut().enumerate() {
            let e = &mut m.eval;
            if !reuse {
                for (j, &a) in m.at.iter().enumerate() {
                    let row = &phi[a * n..(a + 1) * n];
                    e.x[j] = crate::dense::dot(row, q);
                    e.v[j] = crate::dense::dot(row, v);
                }
                e.evaluate(t, true)?;
            }
            if fresh {
                m.measured = None;
            }
            // a two-dof element whose tangent is bit for bit the one last measured with
            // these modal stiffnesses: the same arithmetic on the same numbers
            let key = <[f64; 4]>::try_from(&e.kx[..])
                .ok()
                .map(|k| k.map(f64::to_bits));
            let outcome = match (key, m.measured) {
                (Some(key), Some((kept, out))) if key == kept => out,
                _ => {
                    let out = measure(m, (phi, n, modal_k, fresh), diag);
                    m.measured = key.map(|key| (key, out));
                    out
                }
            };
            let Some((lambda, share, weighted)) = outcome else {
                continue;
            };
            total += lambda;
            background = background.max(weighted / share);
            if lambda > largest {
                (largest, worst) = (lambda, index);
            }
        }
        self.background = if total > 0.0 { background } else { 0.0 };
        Ok((if total > 0.0 { total + background } else { 0.0 }, worst))
    }
}

/// One member's part of [`ElementSpace::tangent_stiffness`] at its current tangent `kx`:
/// `(lambda, share, weighted)` when it adds to the closed state's stiffness, None when it
/// adds nothing or does not dominate the background it loads (`modal_k` the modal
/// stiffnesses, `fresh` when they are not those its `share`/`massless` were formed with).
fn measure(
    m: &mut Member,
    (phi, n, modal_k, fresh): (&[f64], usize, &[f64], bool),
    diag: &mut Vec<f64>,
) -> Outcome {
    let nl = m.at.len();
    // G = Phi_e Phi_e^T; the nonzero eigenvalues of Phi_e^T K Phi_e are those of K G
    let g = |i: usize, j: usize| m.gram[i * nl + j];
    let k = |i: usize, j: usize| k_sym(&m.eval.kx, nl, i, j);
    let lambda = match nl {
        0 => 0.0,
        1 => (k(0, 0) * g(0, 0)).abs(),
        2 => {
            let p = |i: usize, j: usize| k(i, 0) * g(0, j) + k(i, 1) * g(1, j);
            let (tr, det) = (p(0, 0) + p(1, 1), p(0, 0) * p(1, 1) - p(0, 1) * p(1, 0));
            let disc = (0.25 * tr * tr - det).max(0.0).sqrt();
            (0.5 * tr).abs() + disc
        }
        _ => {
            // the Frobenius norm of K G bounds its spectral radius
            let mut sum = 0.0;
            for i in 0..nl {
                for j in 0..nl {
                    let pij: f64 = (0..nl).map(|l| k(i, l) * g(l, j)).sum();
                    sum += pij * pij;
                }
            }
            sum.sqrt()
        }
    };
    if !(lambda > 0.0 && lambda.is_finite()) {
        return None; // adds nothing (a zero tangent: an FNA element in its linear range)
    }
    // the background it loads: the modal stiffness weighted by the element's share
    // |diag(Phi_e^T K_e Phi_e)| in each mode (one dof: |k| phi^2, so |k| times sums
    // fixed for the run)
    let (share, weighted) = if nl == 1 {
        if fresh {
            m.share = None;
        }
        let row = &phi[m.at[0] * n..(m.at[0] + 1) * n];
        let (s, w) = *m.share.get_or_insert_with(|| {
            row.iter()
                .zip(modal_k)
                .fold((0.0, 0.0), |(s, w), (&p, &km)| {
                    (s + p * p, w + stiffness_share(p * p, km))
                })
        });
        let a = m.eval.kx[0].abs();
        (a * s, a * w)
    } else {
        if fresh {
            m.massless = None;
        }
        let at = &m.at;
        let touched = m.massless.get_or_insert_with(|| {
            let reaches = |mode: usize| at.iter().any(|&a| phi[a * n + mode] != 0.0);
            (0..n)
                .filter(|&mode| modal_k[mode] == f64::INFINITY && reaches(mode))
                .collect()
        });
        // one mode's `d = diag(Phi_e^T K_e Phi_e)`, summed over `i`, then `j`
        let d_of = |mode: usize| {
            let mut d = 0.0;
            for i in 0..nl {
                for j in 0..nl {
                    let kij = k_sym(&m.eval.kx, nl, i, j);
                    d += kij * phi[at[i] * n + mode] * phi[at[j] * n + mode];
                }
            }
            d
        };
        // `d != 0` on a coordinate without mass: the sum below would be infinite
        // (or NaN: not positive) and the element skipped; skipped without it (and
        // without the pass over the modes).
        if touched.iter().any(|&mode| d_of(mode) != 0.0) {
            return None;
        }
        // `diag(Phi_e^T K_e Phi_e)` of every mode at once: each mode's `d` summed over
        // `i`, then `j`, as one mode's loop would (the same terms in the same order)
        diag.clear();
        diag.resize(n, 0.0);
        for i in 0..nl {
            let pi = &phi[at[i] * n..(at[i] + 1) * n];
            for j in 0..nl {
                let kij = k_sym(&m.eval.kx, nl, i, j);
                let pj = &phi[at[j] * n..(at[j] + 1) * n];
                for ((d, a), b) in diag.iter_mut().zip(pi).zip(pj) {
                    *d += kij * a * b;
                }
            }
        }
        let (mut share, mut weighted) = (0.0, 0.0);
        for (d, &km) in diag.iter().zip(modal_k) {
            share += d.abs();
            weighted += stiffness_share(d.abs(), km);
        }
        (share, weighted)
    };
    if !(lambda > 0.0 && lambda.is_finite() && share > 0.0) || lambda * share < DOMINANT * weighted
    {
        return None;
    }
    Some((lambda, share, weighted))
}

impl ElementSpace<'_> {
    /// [`ElementSpace::tangent_stiffness`] of one element on one dof whose end-state
    /// tangent is reused and whose share of the background is formed (every step of a
    /// one-dof device after the first): the loop's arithmetic for that member, without the
    /// loop (None when the share is not formed yet).
    #[inline]
    fn single_reused(&mut self) -> Option<(f64, usize)> {
        let m = &self.members[0];
        let (s, w) = m.share?;
        let kx = m.eval.kx[0];
        let lambda = (k_sym(&m.eval.kx, 1, 0, 0) * m.gram[0]).abs();
        let a = kx.abs();
        let (share, weighted) = (a * s, a * w);
        // the loop's two tests: an element adding nothing, one that does not dominate
        let adds = lambda > 0.0 && lambda.is_finite();
        if !(adds && share > 0.0) || lambda * share < DOMINANT * weighted {
            self.background = 0.0;
            return Some((0.0, 0));
        }
        let total = 0.0 + lambda;
        let background = 0.0f64.max(weighted / share);
        self.background = background;
        Some((total + background, 0))
    }
}

/// `share * k` of one coordinate, with no stiffness counted below 0; a coordinate without mass
/// (`k = +inf`: a massless dof's, infinitely stiff against its mass) that the element does
/// not load counts nothing (not `0 * inf`), one that it loads makes the background infinite
/// (the element never dominates it: such a coordinate's step is stable at any stiffness).
fn stiffness_share(share: f64, k: f64) -> f64 {
    if share == 0.0 {
        0.0
    } else {
        share * k.max(0.0)
    }
}
