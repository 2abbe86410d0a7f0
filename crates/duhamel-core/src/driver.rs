//! The one time-stepping loop of every route, modal and direct.
//!
//! A modal route is a composition (see docs/architecture.md):
//!
//! ```text
//! ModalProblem -> background propagator -> corrector (optional) -> output
//! ```
//!
//! The background advances the linear time-invariant part exactly (uncoupled oscillators,
//! [`crate::background::uncoupled`], or first-order complex modes,
//! [`crate::background::first_order`]); the corrector solves the pseudo-force step equation of
//! everything else ([`crate::pseudo`]); the output keeps what was asked for. The direct
//! integrators ([`crate::direct`]) step the physical equations with a method's stepper. Each
//! is a [`Route`]: it advances a block of steps and saves the state it reaches. [`drive`]
//! runs the blocks over a [`Clock`]: it asks the [`Control`] whether to go on (Ctrl-C) and
//! reports progress between blocks, sizes the blocks so that a check comes at least every
//! [`CHECK_INTERVAL`], saves the state where the run stops, and turns every failure into a
//! [`CoreError`] that names its step and time, with the saved instants before it kept. A
//! modal route's loads are prepared block by block, once for every mode
//! ([`ModalRoute`], run by [`drive_modal`]).

use std::time::{Duration, Instant};

use crate::error::CoreError;
use crate::history::{Failure, History, Stats};
use crate::loads::block::{BlockLoads, Stopped};
use crate::loads::ModalForcing;
use crate::problem::{ModalProblem, SaveGrid};

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

/// The Python (or other outside) loads of a run, sampled by the route as its steps need them.
pub type Forcing<'f, 'g> = Option<&'f mut (dyn ModalForcing + 'g)>;

/// Why a block stopped early: a step that could not be completed, or loads that could not
/// all be evaluated (the steps before the first one that needs them were taken).
#[derive(Debug)]
pub enum Halt {
    Step(StepFailure),
    Loads(Stopped),
}

impl From<StepFailure> for Halt {
    fn from(f: StepFailure) -> Self {
        Halt::Step(f)
    }
}

/// One route, as the driver runs it: a modal route (background, corrector, output) or a
/// direct integrator (a method's stepper on the physical equations).
pub trait Route {
    /// Advances the `len` steps from grid point `n0` (`forcing` sampled as they need),
    /// saving the state at the start of every step that is a saved instant.
    fn block(&mut self, n0: usize, len: usize, forcing: Forcing) -> Result<(), Halt>;

    /// Saves the state reached, grid point `n` (where the run stops: its end, an
    /// interruption, loads that failed), if it is a saved instant.
    fn save_end(&mut self, n: usize, forcing: Forcing) -> Result<(), CoreError>;
}

/// A modal route's own part: it advances through a block whose loads are prepared for it
/// (once for every mode, [`BlockLoads`]); [`drive_modal`] runs it in the driver.
pub trait ModalRoute {
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

/// A modal route with its block loads: the [`Route`] the driver runs.
struct Modal<'r, 'p> {
    problem: &'p ModalProblem<'p>,
    route: &'r mut dyn ModalRoute,
    loads: BlockLoads,
}

impl Route for Modal<'_, '_> {
    fn block(&mut self, n0: usize, len: usize, forcing: Forcing) -> Result<(), Halt> {
        let prepared = self.loads.prepare(self.problem, n0, len, forcing);
        // A forcing that failed inside the block leaves the steps before it to be taken.
        self.route.block(self.problem, &self.loads)?;
        prepared.map_err(Halt::Loads)
    }

    fn save_end(&mut self, _n: usize, _forcing: Forcing) -> Result<(), CoreError> {
        match self.loads.end_slot() {
            Some(slot) => self.route.save_current(self.problem, &self.loads, slot),
            None => Ok(()),
        }
    }
}

/// The grid a run steps: the times `t0 + (step0 + n) dt`, `n = 0..=n_steps`, every
/// `save_every`-th instant saved (and the last).
#[derive(Debug, Clone, Copy)]
pub struct Clock {
    pub t0: f64,
    pub step0: usize,
    pub dt: f64,
    pub n_steps: usize,
    pub save_every: usize,
}

impl Clock {
    /// The time of grid point `n` (from the grid, never accumulated).
    pub fn time(&self, n: usize) -> f64 {
        self.t0 + (self.step0 + n) as f64 * self.dt
    }

    /// Which grid points are saved.
    pub fn saves(&self) -> SaveGrid {
        SaveGrid::new(self.n_steps, self.save_every)
    }
}

impl ModalProblem<'_> {
    /// The run's clock.
    pub fn clock(&self) -> Clock {
        Clock {
            t0: self.t0,
            step0: self.step0,
            dt: self.dt,
            n_steps: self.n_steps,
            save_every: self.save_every,
        }
    }
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

/// Runs `route` over the grid of `clock` block by block (the one block loop of every
/// route); returns how the run ended.
pub fn drive(
    clock: &Clock,
    route: &mut dyn Route,
    mut forcing: Option<&mut dyn ModalForcing>,
    control: &mut dyn Control,
) -> Ending {
    let time = |n: usize| clock.time(n);
    let grid = clock.saves();
    let n_steps = clock.n_steps;
    let mut pacer = Pacer::default();
    let mut n0 = 0;
    loop {
        control.progress(n0, n_steps, time(n0));
        let stop = n0 == n_steps || (n0 > 0 && control.interrupted());
        if stop {
            // The state reached is saved here if it is a saved instant (the run's end).
            if let Err(e) = route.save_end(n0, forcing.as_deref_mut()) {
                break Some((e.located(n0, time), grid.before(n0)));
            }
            if n0 == n_steps {
                break None;
            }
            let e = CoreError::Interrupted { time: 0.0, step: 0 };
            break Some((e.located(n0 + 1, time), grid.before(n0 + 1)));
        }
        let len = pacer.next(n_steps - n0);
        match route.block(n0, len, forcing.as_deref_mut()) {
            Ok(()) => {}
            Err(Halt::Step(f)) => break Some((f.error.located(f.step, time), grid.before(f.step))),
            Err(Halt::Loads(stopped)) => {
                let n = n0 + stopped.steps;
                if let Err(e) = route.save_end(n, forcing.as_deref_mut()) {
                    break Some((e.located(n, time), grid.before(n)));
                }
                if n == 0 && stopped.at_start {
                    // The initial state's load failed: its response is unknown, nothing is
                    // kept.
                    break Some((stopped.error.located(0, time), 0));
                }
                break Some((stopped.error.located(n + 1, time), grid.before(n + 1)));
            }
        }
        pacer.done(len);
        n0 += len;
    }
}

/// Runs the modal `route` over `problem` in the driver, its `loads` prepared block by block;
/// returns the block loads (with what was kept of the loads at the saved instants) and how
/// the run ended.
pub fn drive_modal(
    problem: &ModalProblem,
    route: &mut dyn ModalRoute,
    loads: BlockLoads,
    forcing: Option<&mut dyn ModalForcing>,
    control: &mut dyn Control,
) -> (BlockLoads, Ending) {
    let mut modal = Modal {
        problem,
        route,
        loads,
    };
    let ending = drive(&problem.clock(), &mut modal, forcing, control);
    (modal.loads, ending)
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
