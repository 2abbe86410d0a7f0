//! An element with a linear part taken out: `r(x, x') - K0 x - C0 x'`.
//!
//! The linear part of an element (a hysteretic element's initial stiffness, a friction
//! pendulum's gravity stiffness `W / R`) belongs to the linear background: the modes are
//! computed with it, and only the remainder is a pseudo-force (the effective link stiffness
//! of the "Fast Nonlinear Analysis"). [`Shifted`] is that remainder for any element whose
//! force is not a closed form the caller could rewrite (a spring's `k` is simply set to 0).

use super::element::{Element, ModalCubic, PathState, Tangent};
use crate::error::CoreError;

/// `inner`'s force minus `K0 x + C0 x'` at its own dofs (`K0`, `C0` row-major `n x n`).
pub struct Shifted<E: ?Sized + Element = dyn Element> {
    inner: Box<E>,
    k0: Vec<f64>,
    c0: Vec<f64>,
    damped: bool,
}

impl<E: Element + Clone> Clone for Shifted<E> {
    fn clone(&self) -> Self {
        Shifted {
            inner: self.inner.clone(),
            k0: self.k0.clone(),
            c0: self.c0.clone(),
            damped: self.damped,
        }
    }
}

impl<E: Element + std::fmt::Debug> std::fmt::Debug for Shifted<E> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Shifted")
            .field("inner", &self.inner)
            .field("k0", &self.k0)
            .field("c0", &self.c0)
            .finish()
    }
}

impl<E: ?Sized + Element> Shifted<E> {
    /// `inner` minus the local stiffness `k0` and damping `c0` (row-major, `n x n` for the
    /// `n` dofs of `inner`). Errors: wrong sizes (named `"k0"`, `"c0"`), non-finite entries.
    pub fn new(inner: Box<E>, k0: Vec<f64>, c0: Vec<f64>) -> Result<Self, CoreError> {
        let n = inner.dofs().len();
        for (name, m) in [("k0", &k0), ("c0", &c0)] {
            if m.len() != n * n {
                return Err(CoreError::InvalidInput {
                    name,
                    problem: format!("must hold {n} x {n} = {} entries, got {}", n * n, m.len()),
                });
            }
            if let Some(v) = m.iter().find(|v| !v.is_finite()) {
                return Err(CoreError::InvalidInput {
                    name,
                    problem: format!("must be finite, got {v}"),
                });
            }
        }
        let damped = c0.iter().any(|&c| c != 0.0);
        Ok(Self {
            inner,
            k0,
            c0,
            damped,
        })
    }

    /// The element whose linear part is taken out.
    pub fn inner(&self) -> &E {
        &self.inner
    }

    /// Whether the linear part acts on the relative coordinate alone: one dof, or two with
    /// `K0 = k [[1, -1], [-1, 1]]` and `C0 = c [[1, -1], [-1, 1]]` (bit for bit), so that it
    /// is `k (x_i - x_j)` on `i` and its opposite on `j` (up to the rounding of the product).
    pub fn relative(&self) -> bool {
        let pair = |m: &[f64]| match m {
            [_] => true,
            [a, b, c, d] => *b == -*a && *c == -*a && *d == *a,
            _ => false,
        };
        pair(&self.k0) && pair(&self.c0)
    }

    /// [`Element::eval_path`] with `inner` (this element's own, resolved to its type) called
    /// directly: the same arithmetic.
    #[inline(always)]
    pub(crate) fn eval_path_over(
        &self,
        inner: &super::registry::Runtime,
        (x, v, t): (&[f64], &[f64], f64),
        history: PathState<'_>,
        r: &mut [f64],
        mut tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        inner.eval_path(x, v, t, history, r, again(&mut tangent))?;
        self.subtract(x, v, r, tangent);
        Ok(())
    }

    /// Subtracts `K0 x + C0 v` from `r` and the matrices from the tangent.
    #[inline(always)]
    pub(crate) fn subtract(
        &self,
        x: &[f64],
        v: &[f64],
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) {
        let n = x.len();
        if let ([x0], [v0], [r0], [k00], [c00]) = (x, v, &mut *r, &self.k0[..], &self.c0[..]) {
            // one dof (a device on one dof): the same sums as the loop below, without its
            // slicing (`once(..).sum()` keeps the loop's rounding and sign of zero)
            let kx: f64 = std::iter::once(k00 * x0).sum();
            let cv: f64 = std::iter::once(c00 * v0).sum();
            *r0 -= kx + cv;
            if let Some(t) = tangent {
                t.kx[0] -= k00;
                t.cv[0] -= c00;
            }
            return;
        }
        if let ([x0, x1], [v0, v1], [r0, r1], [k00, k01, k10, k11], [c00, c01, c10, c11]) =
            (x, v, &mut *r, &self.k0[..], &self.c0[..])
        {
            // two dofs (a two-node device): the loop below's sums on fixed arrays (the same
            // products added in the same order by the same `sum`)
            let kx0: f64 = [k00 * x0, k01 * x1].into_iter().sum();
            let cv0: f64 = [c00 * v0, c01 * v1].into_iter().sum();
            *r0 -= kx0 + cv0;
            let kx1: f64 = [k10 * x0, k11 * x1].into_iter().sum();
            let cv1: f64 = [c10 * v0, c11 * v1].into_iter().sum();
            *r1 -= kx1 + cv1;
            if let Some(t) = tangent {
                for (a, b) in t.kx.iter_mut().zip([k00, k01, k10, k11]) {
                    *a -= b;
                }
                for (a, b) in t.cv.iter_mut().zip([c00, c01, c10, c11]) {
                    *a -= b;
                }
            }
            return;
        }
        for (i, ri) in r.iter_mut().enumerate().take(n) {
            let row = i * n..(i + 1) * n;
            let kx: f64 = self.k0[row.clone()].iter().zip(x).map(|(a, b)| a * b).sum();
            let cv: f64 = self.c0[row].iter().zip(v).map(|(a, b)| a * b).sum();
            *ri -= kx + cv;
        }
        if let Some(t) = tangent {
            for (a, b) in t.kx.iter_mut().zip(&self.k0) {
                *a -= b;
            }
            for (a, b) in t.cv.iter_mut().zip(&self.c0) {
                *a -= b;
            }
        }
    }
}

/// Reborrows an optional tangent so that it can be used twice.
fn again<'b>(tangent: &'b mut Option<Tangent<'_>>) -> Option<Tangent<'b>> {
    tangent.as_mut().map(|t| Tangent {
        kx: &mut *t.kx,
        cv: &mut *t.cv,
    })
}

impl<E: ?Sized + Element + 'static> Element for Shifted<E> {
    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
    }

    fn path_reads(&self) -> Option<(bool, bool)> {
        self.inner.path_reads()
    }

    fn restarts_exactly(&self) -> bool {
        self.inner.restarts_exactly()
    }

    fn resolution(&self) -> f64 {
        self.inner.resolution()
    }

    fn dofs(&self) -> &[usize] {
        self.inner.dofs()
    }

    fn eval(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        mut tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        self.inner.eval(x, v, t, r, again(&mut tangent))?;
        self.subtract(x, v, r, tangent);
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        self.inner.polynomial_degree().map(|d| d.max(1))
    }

    fn uses_velocity(&self) -> bool {
        self.inner.uses_velocity() || self.damped
    }

    /// The linear part's damping adds the constant `-C0` to `dr/dx'` and nothing to `dr/dx`.
    fn stiffness_reads_velocity(&self) -> bool {
        self.inner.stiffness_reads_velocity()
    }

    fn has_tangent(&self) -> bool {
        self.inner.has_tangent()
    }

    fn state_len(&self) -> usize {
        self.inner.state_len()
    }

    fn initial_state(&self, x: &[f64], v: &[f64], state: &mut [f64]) {
        self.inner.initial_state(x, v, state)
    }

    fn initial_time(&self, t0: f64, state: &mut [f64]) {
        self.inner.initial_time(t0, state)
    }

    fn eval_path(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        history: PathState<'_>,
        r: &mut [f64],
        mut tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        self.inner
            .eval_path(x, v, t, history, r, again(&mut tangent))?;
        self.subtract(x, v, r, tangent);
        Ok(())
    }

    fn modal_cubic(&self, phi: &[f64]) -> Option<ModalCubic> {
        let mut a = self.inner.modal_cubic(phi)?;
        let n = phi.len();
        let quad = |m: &[f64]| -> f64 {
            (0..n)
                .map(|i| phi[i] * (0..n).map(|j| m[i * n + j] * phi[j]).sum::<f64>())
                .sum()
        };
        a[1][0] -= quad(&self.k0);
        a[0][1] -= quad(&self.c0);
        Some(a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::hysteretic::bilinear::Bilinear;
    use crate::elements::spring::Spring;

    #[test]
    fn spring_minus_its_linear_part_is_its_cubic() {
        let spring = Spring::new(0, Some(1), 3.0, 2.0).unwrap();
        let k0 = vec![3.0, -3.0, -3.0, 3.0];
        let shifted = Shifted::new(Box::new(spring), k0, vec![0.0; 4]).unwrap();
        let (x, v) = ([0.7, -0.2], [0.0, 0.0]);
        let mut r = [0.0; 2];
        let (mut kx, mut cv) = ([0.0; 4], [0.0; 4]);
        let tangent = Tangent {
            kx: &mut kx,
            cv: &mut cv,
        };
        shifted.eval(&x, &v, 0.0, &mut r, Some(tangent)).unwrap();
        let d: f64 = 0.9;
        assert!((r[0] - 2.0 * d.powi(3)).abs() < 1e-14);
        assert!((r[1] + 2.0 * d.powi(3)).abs() < 1e-14);
        assert!((kx[0] - 6.0 * d * d).abs() < 1e-13);
        let cubic = Spring::new(0, Some(1), 0.0, 2.0).unwrap();
        let phi = [0.4, -1.1];
        assert_eq!(
            shifted.modal_cubic(&phi).map(|a| a[1][0].abs() < 1e-14),
            Some(true)
        );
        assert!(cubic.modal_cubic(&phi).is_some());
    }

    #[test]
    fn bilinear_minus_initial_stiffness_is_zero_while_elastic() {
        let b = Bilinear::new(0, None, 10.0, 1.0, 0.1).unwrap();
        let shifted = Shifted::new(Box::new(b), vec![10.0], vec![0.0]).unwrap();
        let committed = vec![0.0; shifted.state_len()];
        let mut trial = committed.clone();
        let mut r = [0.0];
        let history = PathState {
            committed: &committed,
            trial: &mut trial,
        };
        shifted
            .eval_path(&[0.05], &[0.0], 0.0, history, &mut r, None)
            .unwrap();
        assert!(r[0].abs() < 1e-15);
    }

    #[test]
    fn wrong_sizes_are_named() {
        let spring = Spring::new(0, None, 1.0, 0.0).unwrap();
        let err = Shifted::new(Box::new(spring), vec![1.0, 2.0], vec![0.0])
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(err.contains("k0"), "{err}");
    }
}
