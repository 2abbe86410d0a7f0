//! The pseudo-force route's hooks into the energy accumulator ([`crate::energy`]): the
//! step's end states, loads and element records, every step when the run asks for energy.

use super::force::PseudoForce;
use super::problem::NonlinearProblem;
use crate::driver::StepFailure;
use crate::energy::{EnergyTap, ModalStep};
use crate::error::CoreError;
use crate::loads::block::BlockLoads;
use crate::problem::ModalProblem;

/// The run's tap (None when energy is not asked for), its spec checked, started from the
/// initial state with the elements' committed variables (`pf` after its first commit). An
/// element that cannot be evaluated there leaves the start to the first step, which reports
/// that failure.
pub(super) fn energy_tap(
    problem: &NonlinearProblem,
    pf: &mut PseudoForce,
    widths: &[usize],
    n_saved: usize,
) -> Result<Option<EnergyTap>, CoreError> {
    let Some(spec) = &problem.energy else {
        return Ok(None);
    };
    let base = &problem.base;
    let n = base.n_modes();
    spec.check(n, base.loads.len(), widths)?;
    let mut tap = EnergyTap::new(spec, n, widths.to_vec(), n_saved);
    let start = (base.q0, base.v0);
    let _ = tap.start(start, base.time(0), &mut |x, t, rows| pf.record(x, t, rows));
    Ok(Some(tap))
}

/// Adds local step `s` of the block `loads` (from `(q, v)` to `(q1, v1)`, modal load basis
/// `pb`) to the energy integrals of `tap`, if asked for; `pf` records the elements.
pub(super) fn energy_step(
    tap: &mut Option<EnergyTap>,
    pf: &mut PseudoForce,
    (problem, loads, s): (&ModalProblem, &BlockLoads, usize),
    [q, v, q1, v1]: [&[f64]; 4],
    pb: &[Vec<f64>; 3],
) -> Result<(), StepFailure> {
    let Some(tap) = tap.as_mut() else {
        return Ok(());
    };
    let step = loads.n0 + s;
    let n_loads = problem.loads.len();
    let span = ModalStep {
        dt: problem.dt,
        t: (problem.time(step), problem.time(step + 1)),
        start: (q, v),
        end: (q1, v1),
        p: (&pb[0], &pb[1]),
        load_basis: &loads.basis[s * n_loads..(s + 1) * n_loads],
    };
    tap.step(&span, &mut |x, t, rows| pf.record(x, t, rows))
        .map_err(StepFailure::at(step + 1))
}
