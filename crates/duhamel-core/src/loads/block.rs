//! The loads of a block of steps, evaluated once before the modes advance, and what is kept
//! of them at the saved instants.

use crate::error::CoreError;
use crate::history::{reserve, size, zeroed};
use crate::kernel::oscillator::Transfer;
use crate::problem::{ModalProblem, SaveGrid};

use super::steps::Steps;
use super::ModalForcing;

/// A block whose loads could not all be evaluated: the error, and how many of its steps
/// (from its start) have their loads ready all the same.
#[derive(Debug)]
pub struct Stopped {
    pub error: CoreError,
    pub steps: usize,
    /// The sample at the block's start failed (for the first block: the initial state's
    /// load, without which nothing can be kept).
    pub at_start: bool,
}

/// The saved times, load values and modal forcing (if any) of a run.
pub type Saved = (Vec<f64>, Vec<f64>, Option<Vec<f64>>);

/// An in-step jump's response of every uncoupled mode: `(local step, dx, dv)`.
pub type ModalJump = (usize, Vec<f64>, Vec<f64>);

/// The loads of one block of steps, shared by every mode, and what is kept of them.
pub struct BlockLoads {
    /// First step of the block (its start is grid point `n0`).
    pub n0: usize,
    /// Steps in the block.
    pub len: usize,
    /// `basis[s * n_loads + l]`: the basis `(p0, Dp, DDp)` of load `l` over local step `s`;
    /// row `s = len` holds the values at the end of the block (only `[0]` is meaningful).
    pub basis: Vec<[f64; 3]>,
    /// Exact jumps of step loads inside a step, as the uncoupled oscillators' responses
    /// (empty unless built with `modal_jumps`).
    pub jumps: Vec<ModalJump>,
    /// The same jumps as found: `(local step, load, time from the break to the step end,
    /// jump coefficients)`, for backgrounds with their own modes.
    pub raw_jumps: Vec<(usize, usize, f64, [f64; 3])>,
    modal_jumps: bool,
    /// Modal samples of the external forcing at `t_n, t_n + dt/2, ..., t_end` of the block
    /// (row-major), or empty.
    pub forcing: Vec<f64>,
    /// History slot of the state at the start of each step of the block, if saved.
    pub slot: Vec<Option<usize>>,
    grid: SaveGrid,
    /// Saved instants in all, the next one to save, and its grid point.
    n_saved: usize,
    next_saved: usize,
    next_step: usize,
    times: Vec<f64>,
    n_modes: usize,
    n_loads: usize,
    /// Each load's value at the saved instants, `n_saved x n_loads`.
    pub load_values: Vec<f64>,
    forcing_saved: Option<Vec<f64>>,
}

impl BlockLoads {
    /// The modal load at the start and the end of local step `s` of a block and its bubble
    /// coefficient (built-in loads).
    pub fn modal_load_ends(
        &self,
        problem: &ModalProblem,
        s: usize,
        [p0, p1, p2]: &mut [Vec<f64>; 3],
    ) {
        for p in [&mut *p0, &mut *p1, &mut *p2] {
            p.fill(0.0);
        }
        let n_loads = problem.loads.len();
        for (load, b) in problem.loads.iter().zip(&self.basis[s * n_loads..]) {
            for (i, &pattern) in load.pattern.iter().enumerate() {
                p0[i] += pattern * b[0];
                p1[i] += pattern * (b[0] + b[1]);
                p2[i] += pattern * b[2];
            }
        }
    }

    /// The block loads of `problem`; with `modal_jumps`, in-step jumps are also turned into
    /// the responses of the uncoupled oscillators `problem.k`, `problem.c`. `forcing` says
    /// whether an external forcing will be sampled (its saved values are then kept).
    /// `row_width` is how many numbers the route saves per saved instant besides these: the
    /// whole history is checked against the machine's memory here, before anything of it is
    /// allocated ([`reserve`]).
    pub fn new(
        problem: &ModalProblem,
        modal_jumps: bool,
        forcing: bool,
        row_width: usize,
    ) -> Result<Self, CoreError> {
        let grid = SaveGrid::new(problem.n_steps, problem.save_every);
        let n_saved = grid.count();
        let n_loads = problem.loads.len();
        let n_modes = problem.n_modes();
        let per_row = row_width
            .saturating_add(n_loads)
            .saturating_add(1)
            .saturating_add(if forcing { n_modes } else { 0 });
        reserve(n_saved.saturating_mul(per_row))?;
        let forcing_saved = if forcing {
            Some(zeroed(
                size(n_saved, n_modes, "the modal forcing")?,
                "the modal forcing",
            )?)
        } else {
            None
        };
        Ok(BlockLoads {
            n0: 0,
            len: 0,
            basis: Vec::new(),
            jumps: Vec::new(),
            raw_jumps: Vec::new(),
            modal_jumps,
            forcing: Vec::new(),
            slot: Vec::new(),
            grid,
            n_saved,
            next_saved: 0,
            next_step: 0,
            times: Vec::new(),
            n_modes,
            n_loads,
            load_values: zeroed(
                size(n_saved, n_loads, "the load values")?,
                "the load values",
            )?,
            forcing_saved,
        })
    }

    /// Number of saved instants of the run.
    pub fn n_saved(&self) -> usize {
        self.n_saved
    }

    /// The save grid.
    pub fn grid(&self) -> SaveGrid {
        self.grid
    }

    /// Evaluates the loads of the `len` steps starting at grid point `n0`.
    ///
    /// When the external forcing fails at some sample, the block is cut to the steps before
    /// the first one that needs that sample: the loads of those steps are ready as usual, and
    /// the error comes back with their number ([`Stopped`]), so the run can still take them.
    pub fn prepare<'o>(
        &mut self,
        problem: &ModalProblem,
        n0: usize,
        len: usize,
        forcing: Option<&mut (dyn ModalForcing + 'o)>,
    ) -> Result<(), Stopped> {
        let (dt, n_loads, n_modes) = (problem.dt, self.n_loads, self.n_modes);
        let time = |n: usize| problem.time(n0 + n);
        let mut len = len;
        let mut stopped = None;
        self.forcing.clear();
        if let Some(f) = forcing {
            // Step starts and midpoints from the grid, not from accumulation.
            self.times.clear();
            self.times
                .extend((0..=2 * len).map(|j| time(j / 2) + 0.5 * (j % 2) as f64 * dt));
            self.forcing.resize(self.times.len() * n_modes, 0.0);
            if let Err(error) = f.modal_loads(&self.times, &mut self.forcing) {
                // Step s needs samples 2s, 2s + 1 and 2s + 2: the steps before the one that
                // needs the failed sample can still be taken.
                let failed = match error {
                    CoreError::Callback { time: t, .. } => {
                        self.times.iter().position(|&x| x == t).unwrap_or(0)
                    }
                    _ => 0,
                };
                len = failed.saturating_sub(1) / 2;
                stopped = Some(Stopped {
                    error,
                    steps: len,
                    at_start: failed == 0,
                });
            }
        }
        self.n0 = n0;
        self.len = len;
        self.basis.clear();
        self.basis.resize((len + 1) * n_loads, [0.0; 3]);
        let steps = Steps {
            time,
            dt,
            len: len + 1,
        };
        let mut l = 0;
        while l < n_loads {
            let load = &problem.loads[l].time;
            // The x and y parts of an unbalance share their sines and cosines.
            if let Some(next) = problem.loads.get(l + 1) {
                let pair = (l, l + 1);
                if load.pair_bases(&next.time, &steps, &mut self.basis, pair, n_loads) {
                    l += 2;
                    continue;
                }
            }
            load.bases(&steps, &mut self.basis, l, n_loads);
            l += 1;
        }
        self.jumps.clear();
        self.raw_jumps.clear();
        for s in 0..len {
            let t = time(s);
            for (l, load) in problem.loads.iter().enumerate() {
                if let Some((rest, j)) = load.time.jump_in(t, dt) {
                    if self.modal_jumps {
                        let (dx, dv) = jump_response(problem, &load.pattern, rest, j);
                        self.jumps.push((s, dx, dv));
                    }
                    self.raw_jumps.push((s, l, rest, j));
                }
            }
        }
        self.slot.clear();
        for s in 0..len {
            let slot = self.take_slot(n0 + s);
            self.slot.push(slot);
            if let Some(k) = slot {
                self.record(k, s);
            }
        }
        match stopped {
            None => Ok(()),
            Some(stop) => Err(stop),
        }
    }

    /// The history slot of grid point `n` if it is the next saved one (and takes it).
    #[inline(always)]
    fn take_slot(&mut self, n: usize) -> Option<usize> {
        let k = self.next_saved;
        if k >= self.n_saved || self.next_step != n {
            return None;
        }
        self.next_saved += 1;
        self.next_step = self.grid.step(self.next_saved);
        Some(k)
    }

    /// Keeps the loads at local grid point `s` of the block in saved row `k`.
    #[inline(always)]
    fn record(&mut self, k: usize, s: usize) {
        let (n_loads, n_modes) = (self.n_loads, self.n_modes);
        let values = &mut self.load_values[k * n_loads..][..n_loads];
        for (value, basis) in values.iter_mut().zip(&self.basis[s * n_loads..][..n_loads]) {
            *value = basis[0];
        }
        if let (Some(saved), false) = (self.forcing_saved.as_mut(), self.forcing.is_empty()) {
            saved[k * n_modes..][..n_modes]
                .copy_from_slice(&self.forcing[2 * s * n_modes..][..n_modes]);
        }
    }

    /// The slot of the end of the last prepared block, when the run stops there (its end or
    /// an interruption) and it is a saved instant; its loads are kept.
    pub fn end_slot(&mut self) -> Option<usize> {
        let end = self.n0 + self.len;
        let k = self.take_slot(end)?;
        self.record(k, self.len);
        Some(k)
    }

    /// The saved times, load values and forcing of the run.
    pub fn into_saved(self, problem: &ModalProblem) -> Result<Saved, CoreError> {
        let n_saved = self.grid.count();
        let mut t = zeroed(n_saved, "the saved times")?;
        for (k, tk) in t.iter_mut().enumerate() {
            *tk = problem.time(self.grid.step(k));
        }
        Ok((t, self.load_values, self.forcing_saved))
    }
}

/// Response at the end of the step to the load `j0 + j1 s + j2 s^2` (`s` the time since it
/// started) applied `rest` before the end: with the moments `M_k` of `(s/rest)^k` over `rest`,
/// `sum_k j_k rest^k M_k`.
pub(crate) fn jump_response(
    problem: &ModalProblem,
    pattern: &[f64],
    rest: f64,
    j: [f64; 3],
) -> (Vec<f64>, Vec<f64>) {
    let w = [j[0], j[1] * rest, j[2] * rest * rest];
    problem
        .k
        .iter()
        .zip(problem.c)
        .zip(pattern)
        .map(|((&k, &c), &p)| {
            let tr = Transfer::new(k, c, rest);
            let row = |r: usize| p * (0..3).map(|i| w[i] * tr.m[r][i]).sum::<f64>();
            (row(0), row(1))
        })
        .unzip()
}
