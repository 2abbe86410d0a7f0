//! The first-order modes of a coupled background, as the caller gives them to
//! [`super::first_order`].

use crate::error::CoreError;
use num_complex::Complex64;

/// The first-order modes of the coupled system, as complex numbers split into real and
/// imaginary parts (`r` coordinates, `m = problem.k.len()` real modes).
#[derive(Debug, Clone)]
pub struct FirstOrderModes<'a> {
    /// Eigenvalues `lambda_k`, real parts (length `r`).
    pub lambda_re: &'a [f64],
    /// Eigenvalues, imaginary parts.
    pub lambda_im: &'a [f64],
    /// `g[k * m + i]`: how much of the modal load `p_i` drives `eta_k` (row `k` of
    /// `V^-1 B`), real parts (`r x m`, row-major).
    pub gain_re: &'a [f64],
    /// The same, imaginary parts.
    pub gain_im: &'a [f64],
    /// Initial values `eta_k(0)`, real parts.
    pub eta0_re: &'a [f64],
    /// Initial values, imaginary parts.
    pub eta0_im: &'a [f64],
}

impl FirstOrderModes<'_> {
    pub(super) fn check(&self, n_modes: usize) -> Result<(), CoreError> {
        let r = self.lambda_re.len();
        // Saturating: a product that overflows matches no real length.
        let gains = r.saturating_mul(n_modes);
        let lens = [
            ("lambda_im", self.lambda_im.len(), r),
            ("gain_re", self.gain_re.len(), gains),
            ("gain_im", self.gain_im.len(), gains),
            ("eta0_re", self.eta0_re.len(), r),
            ("eta0_im", self.eta0_im.len(), r),
        ];
        for (name, got, expected) in lens {
            if got != expected {
                return Err(CoreError::LengthMismatch {
                    name,
                    got,
                    expected,
                });
            }
        }
        let all = [
            self.lambda_re,
            self.lambda_im,
            self.gain_re,
            self.gain_im,
            self.eta0_re,
            self.eta0_im,
        ];
        if all.iter().any(|s| s.iter().any(|x| !x.is_finite())) {
            return Err(CoreError::InvalidInput {
                name: "first-order modes",
                problem: "must be finite".to_string(),
            });
        }
        Ok(())
    }

    pub(super) fn lambda(&self, k: usize) -> Complex64 {
        Complex64::new(self.lambda_re[k], self.lambda_im[k])
    }

    /// `g_k . p` for a real modal vector `p`.
    pub(super) fn project(&self, k: usize, p: &[f64]) -> Complex64 {
        let m = p.len();
        let (gr, gi) = (&self.gain_re[k * m..][..m], &self.gain_im[k * m..][..m]);
        let re = gr.iter().zip(p).map(|(g, x)| g * x).sum();
        let im = gi.iter().zip(p).map(|(g, x)| g * x).sum();
        Complex64::new(re, im)
    }
}
