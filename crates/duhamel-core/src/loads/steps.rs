//! The steps of a grid whose load bases are wanted.

/// Consecutive steps of a grid: `len` steps `[time(n), time(n) + dt]`, `n = 0 .. len`, with
/// the grid times `t0 + n dt` computed by `time(n)` (never by accumulation).
#[derive(Debug, Clone, Copy)]
pub struct Steps<F: Fn(usize) -> f64> {
    /// The start of step `n`.
    pub time: F,
    /// The step length.
    pub dt: f64,
    /// The number of steps.
    pub len: usize,
}
