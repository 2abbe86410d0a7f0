//! The one time-stepping loop of every modal route.
//!
//! A route is a composition (see docs/architecture.md):
//!
//! ```text
//! ModalProblem -> background propagator -> corrector (optional) -> output
//! ```
//!
//! The background advances the linear time-invariant part exactly (uncoupled oscillators,
//! [`crate::background::uncoupled`], or first-order complex modes,
//! [`crate::background::first_order`]); the corrector solves the pseudo-force step equation of
//! everything else ([`crate::pseudo`]); the output keeps what was asked for. A [`Route`]
//! advances a block of steps; [`drive`] runs the blocks: it prepares each block's loads,
//! asks the [`Control`] whether to go on (Ctrl-C) and reports progress between blocks, sizes
//! the blocks so that a check comes at least every [`CHECK_INTERVAL`], and turns every
//! failure into a [`CoreError`] that names its step and time, with the history kept up to it.

use std::time::{Duration, Instant};

use crate::error::CoreError;
use crate::history::{Failure, History, Stats};
use crate::loads::block::BlockLoads;
use crate::loads::ModalForcing;
use crate::problem::ModalProblem;

/// Most steps in one block: loads are evaluated for a whole block before the modes advance.
pub const BLOCK: usize = 1024;
/// Steps in the first block, before its duration is known.
const FIRST_BLOCK: usize = 64;
/// Longest wished time between two checks for interruption.
pub const CHECK_INTERVAL: Duration = Duration::from_millis(100);

/// What the caller can do during a run: stop it, and watch it.
pub trait Control {
    /// Called between blocks; `true` stops the run (which then keeps its history so far and
    /// fails with [`CoreError::Interrupted`]).
    fn interrupted(&mut self) -> bool {
        false
    }

    /// Called between blocks and at the end: `step` steps of `n_steps` are done, the state is
    /// at time `t`.
    fn progress(&mut self, _step: usize, _n_steps: usize, _t: f64) {}
}

/// A run nobody watches.
pub struct Unattended;

impl Control for Unattended {}

/// A failure inside a block: the error and the step that could not be completed (the
/// history keeps the saved states before that step).
#[derive(Debug)]
pub struct StepFailure {
    pub error: CoreError,
    pub step: usize,
}

impl StepFailure {
    /// The failure of step `step`.
    pub fn at(step: usize) -> impl FnOnce(CoreError) -> StepFailure {
        move |error| StepFailure { error, step }
    }
}

/// One modal route: a background propagator with an optional corrector and an output.
pub trait Route {
    /// Advances through the prepared block `loads`, saving the state at the start of every
    /// step whose `loads.slot` is set.
    fn block(&mut self, problem: &ModalProblem, loads: &BlockLoads) -> Result<(), StepFailure>;

    /// Saves the current state (at the end of the last block) in history row `slot`.
    fn save_current(
        &mut self,
        problem: &ModalProblem,
        loads: &BlockLoads,
        slot: usize,
    ) -> Result<(), CoreError>;
}

/// How a run ended: `None`, or the located error and the number of saved instants to keep.
pub type Ending = Option<(CoreError, usize)>;

/// Adapts the number of steps per block so that blocks take about [`CHECK_INTERVAL`]
/// (never more than [`BLOCK`] steps), and says when a check is due. Results never depend on
/// the block length: loads, jumps and saves are per step.
pub struct Pacer {
    len: usize,
    started: Instant,
}

impl Default for Pacer {
    fn default() -> Self {
        Pacer {
            len: FIRST_BLOCK,
            started: Instant::now(),
        }
    }
}

impl Pacer {
    /// Steps for the next block (at most `left`), starting its clock.
    pub fn next(&mut self, left: usize) -> usize {
        self.started = Instant::now();
        self.len.min(left)
    }

    /// Records that the block of `len` steps just finished.
    pub fn done(&mut self, len: usize) {
        let took = self.started.elapsed().as_secs_f64();
        let target = CHECK_INTERVAL.as_secs_f64();
        let ideal = if took > 0.0 {
            (len as f64 * target / took) as usize
        } else {
            BLOCK
        };
        // Grow at most fourfold per block, shrink at once.
        self.len = ideal.clamp(1, (4 * len).clamp(FIRST_BLOCK, BLOCK));
    }
}

/// Runs `route` over `problem` block by block (the one block loop of the modal routes).
/// Returns the block loads (with what was kept of the loads at the saved instants) and how
/// the run ended.
pub fn drive(
    problem: &ModalProblem,
    route: &mut dyn Route,
    mut loads: BlockLoads,
    mut forcing: Option<&mut dyn ModalForcing>,
    control: &mut dyn Control,
) -> (BlockLoads, Ending) {
    let time = |n: usize| problem.time(n);
    let grid = loads.grid();
    let n_steps = problem.n_steps;
    let mut pacer = Pacer::default();
    let mut n0 = 0;
    let ending = loop {
        control.progress(n0, n_steps, time(n0));
        let stop = n0 == n_steps || (n0 > 0 && control.interrupted());
        if stop {
            // The state reached is saved here if it is a saved instant (the run's end).
            if let Some(slot) = loads.end_slot() {
                if let Err(e) = route.save_current(problem, &loads, slot) {
                    break Some((e.located(n0, time), grid.before(n0)));
                }
            }
            if n0 == n_steps {
                break None;
            }
            let e = CoreError::Interrupted { time: 0.0, step: 0 };
            break Some((e.located(n0 + 1, time), grid.before(n0 + 1)));
        }
        let len = pacer.next(n_steps - n0);
        let prepared = loads.prepare(problem, n0, len, forcing.as_deref_mut());
        // A forcing that failed inside the block leaves the steps before it to be taken.
        if let Err(f) = route.block(problem, &loads) {
            break Some((f.error.located(f.step, time), grid.before(f.step)));
        }
        if let Err(stopped) = prepared {
            let n = n0 + stopped.steps;
            if let Some(slot) = loads.end_slot() {
                if let Err(e) = route.save_current(problem, &loads, slot) {
                    break Some((e.located(n, time), grid.before(n)));
                }
            }
            if n == 0 && stopped.at_start {
                // The initial state's load failed: its response is unknown, nothing is kept.
                break Some((stopped.error.located(0, time), 0));
            }
            break Some((stopped.error.located(n + 1, time), grid.before(n + 1)));
        }
        pacer.done(len);
        n0 += len;
    };
    (loads, ending)
}

/// The one history builder of the modal routes: what the route kept (`kept`: its
/// coordinates, and the pseudo-force, outputs and element rows it has, the rest left at
/// their defaults) completed with the saved times, load values and forcing of the block
/// loads; or the run's failure with what is kept of that history.
pub fn finish(
    problem: &ModalProblem,
    loads: BlockLoads,
    kept: History,
    ending: Ending,
) -> Result<History, Box<Failure>> {
    let (t, load_values, forcing) = loads
        .into_saved(problem)
        .map_err(|e| Box::new(Failure::from(e)))?;
    let history = History {
        n_loads: problem.loads.len(),
        t,
        load_values,
        forcing,
        ..kept
    };
    conclude(history, ending)
}

/// The history of a run, or its failure with what is kept of the history.
fn conclude(mut history: History, ending: Ending) -> Result<History, Box<Failure>> {
    match ending {
        None => Ok(history),
        Some((error, keep)) => {
            history.truncate(keep);
            Err(Box::new(Failure {
                error,
                partial: history,
                stats: Stats::default(),
            }))
        }
    }
}
