//! What every modal route integrates: the background modes, loads, initial state, time grid
//! and what to keep.

use std::sync::{Arc, Mutex};

use crate::error::CoreError;
use crate::loads::{check_loads, ModalLoad};

/// Most worker threads a run accepts; more is a mistake (a count of something else), not a
/// machine.
pub const MAX_THREADS: usize = 1024;

/// A modal problem: the uncoupled background oscillators, their loads, the initial state and
/// the time grid `t0 + n dt`, `n = 0..=n_steps`.
#[derive(Debug, Clone)]
pub struct ModalProblem<'a> {
    /// Modal stiffness `omega^2` per unit modal mass, one per mode (>= 0); `+inf` marks a
    /// coordinate without mass (a massless dof's, unit stiffness: `c q' + q = p`, its `c` a
    /// time constant; [`crate::kernel::relaxation`]).
    pub k: &'a [f64],
    /// Modal damping `2 zeta omega` per unit modal mass, one per mode.
    pub c: &'a [f64],
    /// Modal coordinates at `t0`.
    pub q0: &'a [f64],
    /// Modal velocities at `t0`.
    pub v0: &'a [f64],
    /// Built-in loads, already projected on the modes (their time functions use absolute
    /// time, so a run started at `t0` sees them as a run started at 0 would).
    pub loads: &'a [ModalLoad],
    /// Start time of the grid.
    pub t0: f64,
    /// The grid point this run starts at: its times are `t0 + (step0 + n) dt`. A run
    /// continued from a checkpoint at grid point `step0` keeps the original grid, so it
    /// reproduces the uninterrupted run bit for bit. 0 for a run from `t0`.
    pub step0: usize,
    /// Step length (> 0).
    pub dt: f64,
    /// Number of steps (>= 1).
    pub n_steps: usize,
    /// Keep every `save_every`-th step (and always the last).
    pub save_every: usize,
    /// Worker threads; `None` uses rayon's global pool.
    pub threads: Option<usize>,
}

impl ModalProblem<'_> {
    /// The time of grid point `n` of this run, `t0 + (step0 + n) dt` (from the grid, never
    /// accumulated).
    pub fn time(&self, n: usize) -> f64 {
        self.t0 + (self.step0 + n) as f64 * self.dt
    }

    /// Number of modes.
    pub fn n_modes(&self) -> usize {
        self.k.len()
    }

    /// Checks lengths and values; errors name the Python-side parameter.
    pub fn check(&self) -> Result<(), CoreError> {
        let n = self.k.len();
        let lens = [
            ("c", self.c.len()),
            ("x0", self.q0.len()),
            ("v0", self.v0.len()),
        ];
        for (name, got) in lens {
            if got != n {
                return Err(CoreError::LengthMismatch {
                    name,
                    got,
                    expected: n,
                });
            }
        }
        let bad = |name, problem: &str| {
            Err(CoreError::InvalidInput {
                name,
                problem: problem.to_string(),
            })
        };
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return bad("dt", "must be a positive finite number");
        }
        if !self.t0.is_finite() {
            return bad("t0", "must be finite");
        }
        if self.n_steps == 0 {
            return bad("t_end", "must be at least one step `dt`");
        }
        if self.step0.checked_add(self.n_steps).is_none() {
            return bad("step0", "is too large: step0 + n_steps overflows");
        }
        if !self.time(self.n_steps).is_finite() {
            return bad("t_end", "is too large: the end time overflows");
        }
        if self.save_every == 0 {
            return bad("save_every", "must be a positive integer");
        }
        if let Some(t) = self.threads {
            if t == 0 || t > MAX_THREADS {
                return Err(CoreError::InvalidInput {
                    name: "threads",
                    problem: format!("must be between 1 and {MAX_THREADS}, got {t}"),
                });
            }
        }
        if self
            .k
            .iter()
            .any(|&k| !(k >= 0.0 && (k.is_finite() || k == f64::INFINITY)))
        {
            return bad(
                "omega2",
                "must be finite and >= 0 (or +inf: a coordinate without mass)",
            );
        }
        let all = self.c.iter().chain(self.q0).chain(self.v0);
        if all.clone().any(|x| !x.is_finite()) {
            return bad("x0", "(initial state) and modal damping must be finite");
        }
        check_loads(self.loads, n)?;
        Ok(())
    }

    /// The rayon pool for `threads` (at most the machine's cores: more threads than cores
    /// only contend), or None for the global pool. Pools are made once per size and kept:
    /// a study of many short runs with `threads` set would otherwise start and join that many
    /// threads per run.
    pub(crate) fn pool(&self) -> Result<Option<Arc<rayon::ThreadPool>>, CoreError> {
        let Some(n) = self.threads else {
            return Ok(None);
        };
        let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
        let size = n.clamp(1, cores);
        static POOLS: Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());
        let mut pools = POOLS.lock().unwrap_or_else(|p| p.into_inner());
        if let Some((_, pool)) = pools.iter().find(|(s, _)| *s == size) {
            return Ok(Some(pool.clone()));
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(size)
            .build()
            .map(Arc::new)
            .map_err(|e| CoreError::InvalidInput {
                name: "threads",
                problem: e.to_string(),
            })?;
        pools.push((size, pool.clone()));
        Ok(Some(pool))
    }
}

/// Which grid points are saved: every `every`-th, and always the last, without listing
/// them (a list would be allocated before any memory check could refuse a huge run).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SaveGrid {
    n_steps: usize,
    every: usize,
}

impl SaveGrid {
    /// The grid of a run of `n_steps` steps keeping every `every`-th (`every >= 1`).
    pub fn new(n_steps: usize, every: usize) -> Self {
        SaveGrid {
            n_steps,
            every: every.max(1),
        }
    }

    /// Number of saved instants (saturating: `usize::MAX` steps all saved is more than any
    /// memory, and refused as such by [`crate::history::reserve`]).
    pub fn count(&self) -> usize {
        (self.n_steps / self.every)
            .saturating_add(1)
            .saturating_add(usize::from(self.n_steps % self.every != 0))
    }

    /// The grid point of saved instant `k` (`k < count()`).
    pub fn step(&self, k: usize) -> usize {
        k.saturating_mul(self.every).min(self.n_steps)
    }

    /// How many saved instants lie strictly before grid point `n`.
    pub fn before(&self, n: usize) -> usize {
        if n == 0 {
            0
        } else if n > self.n_steps {
            self.count()
        } else {
            (n - 1) / self.every + 1
        }
    }
}
