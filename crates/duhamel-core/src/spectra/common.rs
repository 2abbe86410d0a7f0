//! What every spectrum shares: the record, the exact step of one oscillator, input checks
//! and the thread pool.

use crate::error::CoreError;
use crate::kernel::oscillator::Transfer;

/// One record: accelerations (any consistent unit) at samples `dt` apart.
#[derive(Debug, Clone, Copy)]
pub struct Record<'a> {
    /// Samples of the ground acceleration.
    pub acc: &'a [f64],
    /// Sampling interval.
    pub dt: f64,
}

/// The per-step recurrence of one oscillator under a piecewise-linear load
/// `p(s dt) = p0 + (p1 - p0) s`: `(x, v) <- A (x, v) + b0 p0 + b1 p1`.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Step {
    pub a: [[f64; 2]; 2],
    /// Response to `p0` (`m0 - m1`) and to `p1` (`m1`), rows displacement and velocity.
    pub b0: [f64; 2],
    pub b1: [f64; 2],
}

impl Step {
    /// The exact step of `x'' + 2 zeta omega x' + omega^2 x = p` over `dt`.
    pub(crate) fn new(omega: f64, zeta: f64, dt: f64) -> Result<Self, CoreError> {
        let tr = Transfer::from_omega_zeta(omega, zeta, dt);
        if !tr.is_finite() {
            return Err(CoreError::InvalidInput {
                name: "periods",
                problem: format!(
                    "give step matrices that overflow at omega = {omega:e} rad/s, zeta = \
                     {zeta}, dt = {dt:e} s"
                ),
            });
        }
        Ok(Step::from_transfer(&tr))
    }

    /// The recurrence of the exact matrices `tr` (load linear over the step).
    pub(crate) fn from_transfer(tr: &Transfer) -> Self {
        let m = tr.m;
        Step {
            a: tr.a,
            b0: [m[0][0] - m[0][1], m[1][0] - m[1][1]],
            b1: [m[0][1], m[1][1]],
        }
    }
}

impl Step {
    /// The state after the step from `(x, v)` under the load `p0 -> p1`; the one expression
    /// (fused multiply-adds, in this order) every spectrum uses, so that the elastic lanes,
    /// RotD and the bilinear oscillator's elastic branch agree to the last bit.
    /// (`target-cpu=native`, .cargo/config.toml, makes `mul_add` one instruction on any
    /// x86-64 CPU since 2013.)
    #[inline(always)]
    pub(crate) fn apply(&self, x: f64, v: f64, p0: f64, p1: f64) -> (f64, f64) {
        let [[a00, a01], [a10, a11]] = self.a;
        (
            a00.mul_add(x, a01.mul_add(v, self.b0[0].mul_add(p0, self.b1[0] * p1))),
            a10.mul_add(x, a11.mul_add(v, self.b0[1].mul_add(p0, self.b1[1] * p1))),
        )
    }
}

/// Checks the inputs shared by every spectrum.
pub(crate) fn check(
    records: &[Record],
    periods: &[f64],
    dampings: &[f64],
) -> Result<(), CoreError> {
    let bad = |name, problem: String| Err(CoreError::InvalidInput { name, problem });
    for (i, r) in records.iter().enumerate() {
        if !(r.dt.is_finite() && r.dt > 0.0) {
            return bad(
                "dt",
                format!("of record {i} must be positive and finite, got {}", r.dt),
            );
        }
        if r.acc.len() < 2 {
            return bad(
                "motions",
                format!("record {i} has {} samples, needs 2", r.acc.len()),
            );
        }
        if let Some(k) = r.acc.iter().position(|a| !a.is_finite()) {
            return bad(
                "motions",
                format!("record {i} has a non-finite sample at index {k}"),
            );
        }
    }
    if let Some(&p) = periods.iter().find(|p| !(p.is_finite() && **p >= 0.0)) {
        return bad("periods", format!("must be finite and >= 0, got {p}"));
    }
    if let Some(&z) = dampings.iter().find(|z| !(z.is_finite() && **z >= 0.0)) {
        return bad("damping", format!("must be finite and >= 0, got {z}"));
    }
    Ok(())
}

/// `f` applied to every task, in order: on the calling thread for `threads = Some(1)` (no
/// pool to build), else in parallel on a rayon pool of `threads` workers (at most the
/// cores) or on the global pool (None). The first error (in task order) is returned.
pub(crate) fn map_tasks<T: Sync, R: Send>(
    threads: Option<usize>,
    tasks: &[T],
    f: impl Fn(&T) -> Result<R, CoreError> + Sync + Send,
) -> Result<Vec<R>, CoreError> {
    use rayon::prelude::*;
    match threads {
        Some(1) => tasks.iter().map(f).collect(),
        None => tasks.par_iter().map(f).collect(),
        Some(n) => {
            let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n.clamp(1, cores))
                .build()
                .map_err(|e| CoreError::InvalidInput {
                    name: "threads",
                    problem: e.to_string(),
                })?;
            pool.install(|| tasks.par_iter().map(f).collect())
        }
    }
}
