//! Factorisations kept across solves: a Newton matrix that is bit for bit the one of an
//! earlier iteration or step is solved with the factors of then, with the very operations a
//! fresh factorisation would apply (so the same solution, bit for bit, without the
//! `O(n^3)` work).

use faer::linalg::solvers::Solve;
use faer::Mat;

use crate::dense::{pivot_row, SMALL};

/// The factors [`crate::dense::solve_overwriting`] computes for a system above [`SMALL`], kept: a step
/// equation whose matrix is the same at every step (a linear pseudo-force with constant
/// couplings) is solved with them again, bit for bit the solution a fresh factorisation
/// gives, without the `O(n^3)` factorisation.
pub struct KeptLu {
    lu: faer::linalg::solvers::PartialPivLu<f64>,
}

impl KeptLu {
    /// faer's LU with partial pivoting of the row-major `n x n` matrix `a`.
    pub fn factor(n: usize, a: &[f64]) -> Self {
        let m = Mat::from_fn(n, n, |i, j| a[i * n + j]);
        KeptLu {
            lu: m.partial_piv_lu(),
        }
    }

    /// Whether [`crate::dense::solve_overwriting`] factorises a system of `n` unknowns with faer (the
    /// solves a [`KeptLu`] repeats bit for bit).
    pub fn applies(n: usize) -> bool {
        n > SMALL
    }

    /// Solves in place of `b`; false if the solution is not finite.
    pub fn solve(&self, b: &mut [f64]) -> bool {
        let n = b.len();
        let rhs = Mat::from_fn(n, 1, |i, _| b[i]);
        let x = self.lu.solve(&rhs);
        for (i, bi) in b.iter_mut().enumerate() {
            *bi = x[(i, 0)];
        }
        b.iter().all(|v| v.is_finite())
    }
}

/// [`crate::dense::eliminate`] with its row operations kept: [`Eliminated::solve`] repeats on another
/// right-hand side exactly the operations `crate::dense::eliminate` applies to `b` (the same exchanges,
/// multipliers and back substitution, in the same order), so a Newton iteration whose matrix
/// is bit for bit the last one's solves without forming and eliminating it again, with the
/// solution `crate::dense::eliminate` would give.
#[derive(Debug, Clone, Default)]
pub struct Eliminated {
    n: usize,
    /// The eliminated matrix (its upper triangle is `U`).
    u: Vec<f64>,
    /// The multipliers, row-major (`l[i n + k]` for `i > k`).
    l: Vec<f64>,
    /// The row exchanged with row `k` at step `k`.
    piv: Vec<usize>,
    /// The nonzero multipliers of each step `k` (`(i, l[i n + k])`, `i` ascending) from
    /// `lower[lower_at[k]]` on, and the nonzero entries right of the diagonal of each row
    /// `k` of `U` (`(j, u[k n + j])`, `j` ascending) from `upper[upper_at[k]]` on: what
    /// [`Eliminated::solve`] reads (a Newton matrix `I + G D` whose diagonal `D` is zero
    /// where an element's tangent is, e.g. an elastic hinge with its stiffness in the
    /// background, is mostly the identity's columns, and so are its factors).
    lower: Vec<(usize, f64)>,
    lower_at: Vec<usize>,
    upper: Vec<(usize, f64)>,
    upper_at: Vec<usize>,
    /// Whether the factors hold (the last elimination succeeded).
    pub valid: bool,
}

impl Eliminated {
    /// [`crate::dense::eliminate`] of `m` (overwritten) and `b`, keeping the operations; the result and
    /// `m` are those of `crate::dense::eliminate`.
    pub fn eliminate(&mut self, n: usize, m: &mut [f64], b: &mut [f64]) -> bool {
        // the same code for each small size, its loops then of known length (the
        // element-space Newton's few element dofs): the same operations in the same order
        match n {
            1 => self.eliminate_sized(1, m, b),
            2 => self.eliminate_sized(2, m, b),
            3 => self.eliminate_sized(3, m, b),
            4 => self.eliminate_sized(4, m, b),
            _ => self.eliminate_sized(n, m, b),
        }
    }

    /// [`Eliminated::eliminate`]'s body, inlined where `n` is a constant.
    #[inline(always)]
    fn eliminate_sized(&mut self, n: usize, m: &mut [f64], b: &mut [f64]) -> bool {
        let (m, b) = (&mut m[..n * n], &mut b[..n]);
        self.n = n;
        self.valid = false;
        self.l.clear();
        self.l.resize(n * n, 0.0);
        self.piv.clear();
        self.piv.resize(n, 0);
        for k in 0..n {
            let Some(p) = pivot_row(m, n, k) else {
                return false;
            };
            self.piv[k] = p;
            if p != k {
                for j in 0..n {
                    m.swap(k * n + j, p * n + j);
                }
                b.swap(k, p);
            }
            let inv = 1.0 / m[k * n + k];
            for i in k + 1..n {
                let f = m[i * n + k] * inv;
                self.l[i * n + k] = f;
                if f != 0.0 {
                    for j in k..n {
                        m[i * n + j] -= f * m[k * n + j];
                    }
                    b[i] -= f * b[k];
                }
            }
        }
        self.u.clear();
        self.u.extend_from_slice(m);
        self.keep_nonzeros(n);
        self.valid = true;
        back_substitute(n, &self.u, b)
    }

    /// The nonzero multipliers and entries of `U` right of the diagonal, in the order the
    /// elimination and the back substitution meet them (`x != 0.0`: NaN kept).
    fn keep_nonzeros(&mut self, n: usize) {
        self.lower.clear();
        self.lower_at.clear();
        self.upper.clear();
        self.upper_at.clear();
        for k in 0..n {
            self.lower_at.push(self.lower.len());
            let column = (k + 1..n).map(|i| (i, self.l[i * n + k]));
            self.lower.extend(column.filter(|e| e.1 != 0.0));
            self.upper_at.push(self.upper.len());
            let row = (k + 1..n).map(|j| (j, self.u[k * n + j]));
            self.upper.extend(row.filter(|e| e.1 != 0.0));
        }
        self.lower_at.push(self.lower.len());
        self.upper_at.push(self.upper.len());
    }

    /// Solves with the kept operations in place of `b` (of length `n`); false if the
    /// solution is not finite or nothing is kept.
    pub fn solve(&self, b: &mut [f64]) -> bool {
        let n = self.n;
        if !self.valid || b.len() < n {
            return false;
        }
        let b = &mut b[..n];
        for k in 0..n {
            let p = self.piv[k];
            if p != k {
                b.swap(k, p);
            }
            // the multipliers `crate::dense::eliminate` applies (it skips the zero ones)
            for &(i, f) in &self.lower[self.lower_at[k]..self.lower_at[k + 1]] {
                b[i] -= f * b[k];
            }
        }
        // `back_substitute` on the nonzero entries of `U`: a product with a zero entry is a
        // zero (`b` finite; a non-finite `b` fails the test below either way), and adding a
        // zero to a sum leaves it unchanged unless the sum is itself a zero, whose sign only
        // the next nonzero term erases. Left out, the sum is therefore the same number but
        // possibly for the sign of a zero result, which `b_k - s` reads only when `b_k` is a
        // zero too: the full sum then.
        let zero_sum: f64 = std::iter::empty::<f64>().sum();
        for k in (0..n).rev() {
            let row = &self.upper[self.upper_at[k]..self.upper_at[k + 1]];
            let mut s = row.iter().fold(zero_sum, |s, &(j, u)| s + u * b[j]);
            if s == 0.0 && b[k] == 0.0 {
                s = (k + 1..n).map(|j| self.u[k * n + j] * b[j]).sum();
            }
            b[k] = (b[k] - s) / self.u[k * n + k];
        }
        b.iter().all(|v| v.is_finite())
    }
}

/// [`crate::dense::eliminate`]'s back substitution with the eliminated `m`.
#[inline(always)]
fn back_substitute(n: usize, m: &[f64], b: &mut [f64]) -> bool {
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|j| m[k * n + j] * b[j]).sum();
        b[k] = (b[k] - s) / m[k * n + k];
    }
    b.iter().all(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dense::{eliminate, solve_overwriting};

    /// A deterministic pseudo-random matrix needing row exchanges (small diagonal).
    fn matrix(n: usize, seed: u64) -> Vec<f64> {
        let mut x = seed;
        (0..n * n)
            .map(|k| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let v = (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                if k % (n + 1) == 0 {
                    1e-3 * v
                } else {
                    v
                }
            })
            .collect()
    }

    fn rhs(n: usize, seed: u64) -> Vec<f64> {
        (0..n)
            .map(|i| ((i as u64 * 7 + seed) % 11) as f64 - 5.0)
            .collect()
    }

    #[test]
    fn kept_elimination_repeats_eliminate_bit_for_bit() {
        for n in [1, 2, 5, 17, 32] {
            let a = matrix(n, n as u64);
            let mut kept = Eliminated::default();
            let (mut m, mut b) = (a.clone(), rhs(n, 1));
            assert!(kept.eliminate(n, &mut m, &mut b));
            let (mut m2, mut b2) = (a.clone(), rhs(n, 1));
            assert!(eliminate(n, &mut m2, &mut b2));
            assert_eq!(b, b2);
            for seed in 2..6 {
                let (mut fresh, mut again) = (rhs(n, seed), rhs(n, seed));
                let mut m3 = a.clone();
                assert!(eliminate(n, &mut m3, &mut fresh));
                assert!(kept.solve(&mut again));
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&fresh), bits(&again), "n = {n}");
            }
        }
        // a singular matrix keeps nothing
        let mut kept = Eliminated::default();
        let (mut m, mut b) = (vec![0.0; 4], vec![1.0; 2]);
        assert!(!kept.eliminate(2, &mut m, &mut b));
        assert!(!kept.solve(&mut b));
    }

    /// A Newton matrix `I + G D` whose diagonal `D` is zero but at a few columns (elastic
    /// hinges with their stiffness in the background, a few yielded), and right-hand sides
    /// with zeros of both signs: the solve over the factors' nonzero entries gives what a
    /// fresh elimination gives, bit for bit, signed zeros included.
    #[test]
    fn kept_elimination_of_mostly_identity_columns_is_bit_for_bit() {
        let n = 16;
        let g = matrix(n, 7);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for yielded in [vec![], vec![3], vec![0, 9, 15], vec![2, 5, 6, 11]] {
            let mut a = vec![0.0; n * n];
            for i in 0..n {
                a[i * n + i] = 1.0;
                for &c in &yielded {
                    a[i * n + c] += g[i * n + c] * -0.98;
                }
            }
            let mut kept = Eliminated::default();
            let (mut m, mut b) = (a.clone(), rhs(n, 1));
            assert!(kept.eliminate(n, &mut m, &mut b));
            for seed in 0..40u64 {
                let mut fresh: Vec<f64> = rhs(n, seed);
                // zeros of either sign and tiny values where the sums cancel
                for (i, x) in fresh.iter_mut().enumerate() {
                    match (i as u64 + seed) % 5 {
                        0 => *x = 0.0,
                        1 => *x = -0.0,
                        2 => *x *= 1e-300,
                        _ => {}
                    }
                }
                let mut again = fresh.clone();
                let mut m2 = a.clone();
                assert!(eliminate(n, &mut m2, &mut fresh));
                assert!(kept.solve(&mut again));
                assert_eq!(bits(&fresh), bits(&again), "{yielded:?} seed {seed}");
            }
        }
    }

    #[test]
    fn kept_lu_repeats_solve_overwriting_bit_for_bit() {
        let n = 40;
        assert!(KeptLu::applies(n) && !KeptLu::applies(SMALL));
        let a = matrix(n, 3);
        let lu = KeptLu::factor(n, &a);
        for seed in 0..4 {
            let (mut fresh, mut again) = (rhs(n, seed), rhs(n, seed));
            let mut m = a.clone();
            assert!(solve_overwriting(n, &mut m, &mut fresh));
            assert!(lu.solve(&mut again));
            assert!(fresh
                .iter()
                .zip(&again)
                .all(|(x, y)| x.to_bits() == y.to_bits()));
            // and it solves the system
            let b = rhs(n, seed);
            for i in 0..n {
                let r: f64 = (0..n).map(|j| a[i * n + j] * again[j]).sum::<f64>() - b[i];
                assert!(r.abs() < 1e-9, "{r}");
            }
        }
    }
}
