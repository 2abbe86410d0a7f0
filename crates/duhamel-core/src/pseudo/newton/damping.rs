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
