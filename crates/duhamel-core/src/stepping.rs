//! What the modal time loops share: the loads of a block of steps, evaluated once before
//! the modes advance, and the saved history.

use crate::error::CoreError;
use crate::linear::LinearProblem;
use crate::oscillator::Transfer;

/// Steps per block: loads are evaluated for a whole block before the modes advance.
pub(crate) const BLOCK: usize = 1024;

/// Modal loads computed outside the engine (e.g. a Python callable), sampled in blocks.
pub trait ModalForcing {
    /// Fills `out` (`times.len()` rows of `n_modes`, row-major) with the modal load vector at
    /// each time.
    fn modal_loads(&mut self, times: &[f64], out: &mut [f64]) -> Result<(), CoreError>;
}

/// Saved modal history. Arrays are time-major: entry `(s, mode)` at `s * n_modes + mode`.
///
/// Modal accelerations are not stored: they follow exactly from the equation of motion,
/// `a = p - c v - k q`, with the modal load `p = sum_l pattern_l load_values[s, l] + forcing`;
/// recovering them afterwards for the wanted degrees of freedom only keeps the time loop
/// within the machine's memory bandwidth.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct History {
    /// Number of modes.
    pub n_modes: usize,
    /// Saved times.
    pub t: Vec<f64>,
    /// Modal coordinates.
    pub q: Vec<f64>,
    /// Modal velocities.
    pub v: Vec<f64>,
    /// Value of each built-in load's time function at the saved times (the value just after
    /// each saved time), `n_saved x n_loads`.
    pub load_values: Vec<f64>,
    /// Modal external forcing at the saved times, `n_saved x n_modes` (empty without forcing).
    pub forcing: Vec<f64>,
    /// Modal pseudo-force (everything not in the linear background) at the saved states,
    /// `n_saved x n_modes` (empty for a linear run).
    pub pseudo: Vec<f64>,
    /// First-order (complex) modal coordinates of a coupled run, `n_saved x 2 n_first`: the
    /// real parts then the imaginary parts of each row; `q` and `v` are then empty (see
    /// [`crate::coupled`]). Empty otherwise.
    pub eta: Vec<f64>,
    /// Outputs mapped from `eta` during a coupled run (`n_saved x n_cols`), or empty.
    pub out: Vec<f64>,
}

impl History {
    /// Number of saved instants.
    pub fn n_saved(&self) -> usize {
        self.t.len()
    }
}

/// A run that stopped early: the reason and everything computed before it (a modal
/// [`History`], or another integrator's history type).
#[derive(Debug, Clone)]
pub struct Failure<H = History> {
    /// Why the run stopped.
    pub error: CoreError,
    /// The history up to the last good saved instant.
    pub partial: H,
}

impl<H: Default> From<CoreError> for Failure<H> {
    fn from(error: CoreError) -> Self {
        Failure {
            error,
            partial: H::default(),
        }
    }
}

/// The step indices that are saved: multiples of `save_every`, and the last step.
pub(crate) fn saved_steps(n_steps: usize, save_every: usize) -> Vec<usize> {
    let mut s: Vec<usize> = (0..=n_steps).step_by(save_every).collect();
    if n_steps % save_every != 0 {
        s.push(n_steps);
    }
    s
}

/// The loads of one block of steps, shared by every mode, and what is kept of them.
pub(crate) struct BlockLoads {
    /// First step of the block.
    pub n0: usize,
    /// Steps in the block.
    pub len: usize,
    /// `basis[s * n_loads + l]`: the basis `(p0, Dp, DDp)` of load `l` over local step `s`;
    /// row `s = len` holds the values at the end of the block (only `[0]` is meaningful).
    pub basis: Vec<[f64; 3]>,
    /// Exact jumps of step loads inside a step: `(local step, dx per mode, dv per mode)`
    /// (empty when built by [`BlockLoads::raw`]).
    pub jumps: Vec<(usize, Vec<f64>, Vec<f64>)>,
    /// The same jumps as found: `(local step, load, time from the break to the step end,
    /// jump coefficients)`, for engines with their own modes.
    pub raw_jumps: Vec<(usize, usize, f64, [f64; 3])>,
    /// Whether `jumps` holds the uncoupled modal oscillators' responses.
    modal_jumps: bool,
    /// Modal samples of the external forcing at `t_n, t_n + dt/2, ..., t_end` (row-major), or
    /// empty.
    pub forcing: Vec<f64>,
    /// History slot of each step of the block (and of its end), if saved.
    pub slot: Vec<Option<usize>>,
    saved: Vec<usize>,
    next_saved: usize,
    times: Vec<f64>,
    n_modes: usize,
    n_loads: usize,
    dt: f64,
    n_steps: usize,
    pub(crate) load_values: Vec<f64>,
    forcing_saved: Vec<f64>,
}

impl BlockLoads {
    pub fn new(problem: &LinearProblem) -> Self {
        let saved = saved_steps(problem.n_steps, problem.save_every);
        let n_loads = problem.loads.len();
        BlockLoads {
            n0: 0,
            len: 0,
            basis: Vec::new(),
            jumps: Vec::new(),
            raw_jumps: Vec::new(),
            modal_jumps: true,
            forcing: Vec::new(),
            slot: Vec::new(),
            load_values: vec![0.0; saved.len() * n_loads],
            saved,
            next_saved: 0,
            times: Vec::new(),
            n_modes: problem.k.len(),
            n_loads,
            dt: problem.dt,
            n_steps: problem.n_steps,
            forcing_saved: Vec::new(),
        }
    }

    /// Block loads whose in-step jumps are left raw (`raw_jumps`), for an engine whose modes
    /// are not the uncoupled oscillators of `problem.k`, `problem.c`.
    pub fn raw(problem: &LinearProblem) -> Self {
        BlockLoads {
            modal_jumps: false,
            ..Self::new(problem)
        }
    }

    /// Number of saved instants of the run.
    pub fn n_saved(&self) -> usize {
        self.saved.len()
    }

    fn time(&self, n: usize) -> f64 {
        n as f64 * self.dt
    }

    /// Evaluates the loads of the block starting at step `n0`.
    pub fn prepare<'o>(
        &mut self,
        problem: &LinearProblem,
        n0: usize,
        forcing: Option<&mut (dyn ModalForcing + 'o)>,
    ) -> Result<(), CoreError> {
        let (dt, n_loads, n_modes) = (self.dt, self.n_loads, self.n_modes);
        let len = BLOCK.min(self.n_steps - n0);
        self.n0 = n0;
        self.len = len;
        self.basis.clear();
        self.basis.resize((len + 1) * n_loads, [0.0; 3]);
        let time = |n: usize| (n0 + n) as f64 * dt;
        let mut l = 0;
        while l < n_loads {
            let load = &problem.loads[l].time;
            // The x and y parts of an unbalance share their sines and cosines.
            if let Some(next) = problem.loads.get(l + 1) {
                let pair = (l, l + 1);
                if load.pair_bases(
                    &next.time,
                    time,
                    dt,
                    len + 1,
                    &mut self.basis,
                    pair,
                    n_loads,
                ) {
                    l += 2;
                    continue;
                }
            }
            load.bases(time, dt, len + 1, &mut self.basis, l, n_loads);
            l += 1;
        }
        self.jumps.clear();
        self.raw_jumps.clear();
        for s in 0..len {
            let t = self.time(n0 + s);
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
        self.forcing.clear();
        if let Some(f) = forcing {
            // Step starts and midpoints from the grid, not from accumulation.
            self.times.clear();
            self.times.extend(
                (0..=2 * len).map(|j| (n0 + j / 2) as f64 * dt + 0.5 * (j % 2) as f64 * dt),
            );
            self.forcing.resize(self.times.len() * n_modes, 0.0);
            f.modal_loads(&self.times, &mut self.forcing)?;
        }
        self.slot.clear();
        // The end of the block is saved by the next block, or here if it is the last.
        for s in 0..=len {
            let n = n0 + s;
            let last = n == self.n_steps;
            let next = self.saved.get(self.next_saved);
            if (s < len || last) && next == Some(&n) {
                self.slot.push(Some(self.next_saved));
                self.next_saved += 1;
            } else {
                self.slot.push(None);
            }
        }
        // What the loads are at the saved instants (for the accelerations), kept here once.
        for (s, sl) in self.slot.iter().enumerate() {
            if let Some(k) = *sl {
                for l in 0..n_loads {
                    self.load_values[k * n_loads + l] = self.basis[s * n_loads + l][0];
                }
                if !self.forcing.is_empty() {
                    self.forcing_saved
                        .extend_from_slice(&self.forcing[2 * s * n_modes..][..n_modes]);
                }
            }
        }
        Ok(())
    }

    /// The history of the run, or the failure with what was kept before `first_bad`.
    pub fn finish(
        self,
        n_modes: usize,
        q: Vec<f64>,
        v: Vec<f64>,
        pseudo: Vec<f64>,
        failure: Option<(CoreError, usize)>,
    ) -> Result<History, Box<Failure>> {
        self.finish_with_eta(n_modes, q, v, pseudo, Vec::new(), failure)
    }

    /// [`BlockLoads::finish`] for a run that saved first-order coordinates (`eta`, see
    /// [`History::eta`]) instead of `q`, `v`.
    pub fn finish_first_order(
        self,
        n_modes: usize,
        eta: Vec<f64>,
        pseudo: Vec<f64>,
        failure: Option<(CoreError, usize)>,
    ) -> Result<History, Box<Failure>> {
        self.finish_with_eta(n_modes, Vec::new(), Vec::new(), pseudo, eta, failure)
    }

    fn finish_with_eta(
        self,
        n_modes: usize,
        q: Vec<f64>,
        v: Vec<f64>,
        pseudo: Vec<f64>,
        eta: Vec<f64>,
        failure: Option<(CoreError, usize)>,
    ) -> Result<History, Box<Failure>> {
        let dt = self.dt;
        let t: Vec<f64> = self.saved.iter().map(|&n| n as f64 * dt).collect();
        let history = History {
            n_modes,
            t,
            q,
            v,
            load_values: self.load_values,
            forcing: self.forcing_saved,
            pseudo,
            eta,
            out: Vec::new(),
        };
        match failure {
            None => Ok(history),
            Some((error, first_bad)) => {
                let keep = self.saved.iter().take_while(|&&n| n < first_bad).count();
                Err(Box::new(Failure {
                    error,
                    partial: truncate(history, keep),
                }))
            }
        }
    }
}

/// Response at the end of the step to the load `j0 + j1 s + j2 s^2` (`s` the time since it
/// started) applied `rest` before the end: with the moments `M_k` of `(s/rest)^k` over `rest`,
/// `sum_k j_k rest^k M_k`.
pub(crate) fn jump_response(
    problem: &LinearProblem,
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

/// A zeroed buffer, or a clean error when the memory cannot be had (instead of an abort).
///
/// The buffer comes from `alloc_zeroed` (fresh, lazily zeroed pages for large sizes, no
/// memset) and is advised to use transparent huge pages: a history of a few hundred MB would
/// otherwise cost one page fault per 4 KiB written inside the time loop.
pub(crate) fn zeroed(len: usize) -> Result<Vec<f64>, Box<Failure>> {
    if len == 0 {
        return Ok(Vec::new());
    }
    let too_big = || {
        Box::new(Failure::from(CoreError::InvalidInput {
            name: "save_every",
            problem: format!(
                "is too small: the modal history needs {:.1} GiB; save fewer steps or retain fewer modes",
                2.0 * len as f64 * 8.0 / (1u64 << 30) as f64
            ),
        }))
    };
    let layout = std::alloc::Layout::array::<f64>(len).map_err(|_| too_big())?;
    // SAFETY: `layout` has a non-zero size (len > 0).
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<f64>();
    if ptr.is_null() {
        return Err(too_big());
    }
    advise_huge_pages(ptr, len);
    // SAFETY: `ptr` was allocated by the global allocator with the layout of `[f64; len]`
    // (capacity `len`, alignment of f64), as `Vec` requires; its bytes are all zero, a valid
    // `0.0_f64` for each of the `len` elements, so the length `len` is initialised.
    Ok(unsafe { Vec::from_raw_parts(ptr, len, len) })
}

/// Asks Linux to back the 2 MiB-aligned interior of a buffer with transparent huge pages.
#[cfg(target_os = "linux")]
fn advise_huge_pages(ptr: *mut f64, len: usize) {
    const HUGE: usize = 2 << 20;
    let start = ptr as usize;
    let end = start + len * std::mem::size_of::<f64>();
    let first = start.next_multiple_of(HUGE);
    let last = end - end % HUGE;
    if last > first {
        // SAFETY: [first, last) lies inside the live allocation [start, end) and is page
        // aligned; MADV_HUGEPAGE is advisory and never changes the contents or validity of
        // the memory. A failure (e.g. THP disabled) is harmless and ignored.
        unsafe {
            libc::madvise(
                first as *mut libc::c_void,
                last - first,
                libc::MADV_HUGEPAGE,
            );
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_ptr: *mut f64, _len: usize) {}

/// Keeps the first `keep` saved instants of a time-major history.
pub(crate) fn truncate(mut h: History, keep: usize) -> History {
    let n_loads = h.load_values.len() / h.t.len().max(1);
    let n_eta = h.eta.len() / h.t.len().max(1);
    let n = keep * h.n_modes;
    h.eta.truncate(keep * n_eta);
    h.t.truncate(keep);
    h.q.truncate(n);
    h.v.truncate(n);
    h.load_values.truncate(keep * n_loads);
    h.forcing.truncate(if h.forcing.is_empty() { 0 } else { n });
    h.pseudo.truncate(if h.pseudo.is_empty() { 0 } else { n });
    h
}
