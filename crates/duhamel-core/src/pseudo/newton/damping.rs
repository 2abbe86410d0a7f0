//! The damping of Newton's method, shared by the modal and the element-space iterations.

use crate::error::CoreError;

/// The damping of a Newton iteration (shared by the modal and the element-space Newton): a
/// full step whose residual `norm` did not decrease from `prev` enough is cut back by
/// halving, `retry(lambda)` setting the state to `z0 + lambda delta` and returning its
/// residual, down to `lambda = 1/64` or until the previous residual is at round-off
/// (`64 eps scale0`). A stick-slip friction law, for instance, makes plain Newton cycle.
pub(super) fn backtrack(
    prev: f64,
    mut norm: f64,
    scale0: f64,
    mut retry: impl FnMut(f64) -> Result<f64, CoreError>,
) -> Result<f64, CoreError> {
    let floor = 64.0 * f64::EPSILON * scale0;
    let mut lambda = 1.0;
    while (norm.is_nan() || norm > prev * (1.0 - 1e-4 * lambda))
        && prev > floor
        && lambda > 1.0 / 64.0
    {
        lambda *= 0.5;
        norm = retry(lambda)?;
    }
    Ok(norm)
}

/// Whether the next Newton correction would be below rounding, so that the iterate just
/// formed is already the converged one to rounding: the correction `size` after one of
/// `prev` (max norms, the same iteration's residual not cut back by [`backtrack`]) at a
/// contraction of at least 100, where Newton's quadratic convergence,
/// `|d_{k+1}| ~ C |d_k|^2` with `C ~ |d_k| / |d_{k-1}|^2`, predicts
/// `|d_{k+1}| ~ |d_k|^3 / |d_{k-1}|^2`, at most `4 eps` of `scale` (the state's size). The
/// iteration that would only confirm it (measured on the paper's rotor: corrections
/// 3e-4, 2e-8, then 1e-16 of the state) is then left out; the result differs from
/// taking it by that correction, rounding. Only for smooth forces (polynomials with
/// analytic tangents): a contact or friction law converges piecewise, not quadratically.
pub(super) fn next_below_rounding(prev: Option<f64>, size: f64, scale: f64) -> bool {
    let Some(prev) = prev else {
        return false;
    };
    if !(scale > 0.0 && scale.is_finite() && size <= 1e-2 * prev) {
        return false;
    }
    let (d, p) = (size / scale, prev / scale);
    d * d * d <= 4.0 * f64::EPSILON * p * p
}

/// Whether a Newton correction of max norm `size` is below rounding of a state of size
/// `scale` (at most `4 eps` of it): the state it would correct, just evaluated, is the
/// solution to rounding, and the iteration stops there instead of taking the correction
/// and evaluating again (an affine step's second iteration: corrections of 1e-16 of the
/// state). The result differs from taking it by that correction.
#[inline(always)]
pub(super) fn below_rounding(size: f64, scale: f64) -> bool {
    size <= 4.0 * f64::EPSILON * scale
}

/// One Newton correction `delta` of the unknowns `y` (their values before it kept in
/// `y_prev`): None when it is below the rounding of `y` (scaled at least by `scale0`, see
/// [`below_rounding`]: the state just evaluated is the solution, nothing is changed); else
/// `y_prev = y`, `y += delta` and `(size, scale)`: the correction's largest magnitude and the
/// corrected `y`'s (at least `scale0`), what [`super::Setting::settled`] decides on.
pub(super) fn corrected(
    y: &mut [f64],
    y_prev: &mut [f64],
    delta: &[f64],
    scale0: f64,
) -> Option<(f64, f64)> {
    let largest = |x: &[f64]| x.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let size = largest(delta);
    if below_rounding(size, largest(y).max(scale0)) {
        return None;
    }
    y_prev.copy_from_slice(y);
    for (y, d) in y.iter_mut().zip(delta) {
        *y += d;
    }
    Some((size, largest(y).max(scale0)))
}

/// The Newton correction of a one-unknown system, `-res / mat` (the 1 x 1 elimination's
/// back substitution, its empty sum of the row's other terms included, so that it rounds as
/// the general elimination does); None where the pivot is zero or not finite, or the
/// correction is not finite (the iteration then stops and says it did not converge).
pub(super) fn scalar_correction(res: f64, mat: f64) -> Option<f64> {
    let pivot = mat.abs();
    if !(pivot.is_finite() && pivot > 0.0) {
        return None;
    }
    let none: f64 = std::iter::empty::<f64>().sum();
    let delta = (-res - none) / mat;
    delta.is_finite().then_some(delta)
}

#[cfg(test)]
mod tests {
    use super::next_below_rounding;

    #[test]
    fn only_a_quadratic_contraction_to_rounding_stops_early() {
        // the rotor's sequence: 3e-4, 2e-8 -> next ~1e-16
        assert!(next_below_rounding(Some(3e-4), 2e-8, 1.0));
        // the same relative to the state's size
        assert!(next_below_rounding(Some(3e-9), 2e-13, 1e-5));
        // first iteration: nothing to extrapolate from
        assert!(!next_below_rounding(None, 1e-12, 1.0));
        // next correction predicted ~1e-12: one more iteration
        assert!(!next_below_rounding(Some(1e-3), 1e-6, 1.0));
        // a slow (linear) contraction never stops early, however small the correction
        assert!(!next_below_rounding(Some(2e-9), 1e-9, 1.0));
        // a state of size zero or not finite: the usual test decides
        assert!(!next_below_rounding(Some(1e-4), 1e-12, 0.0));
        assert!(!next_below_rounding(Some(1e-4), 1e-12, f64::NAN));
    }
}
