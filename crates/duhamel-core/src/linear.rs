//! Exact stepping of uncoupled modal oscillators (linear time-invariant systems).
//!
//! Each mode `q'' + c q' + k q = p(t)` is advanced by `y(n+1) = A y(n) + B (p0, Dp, DDp)` with
//! the exact matrices of [`crate::oscillator`]. The modes are independent, so the time loop
//! runs in blocks of steps: the loads of a block are evaluated once (shared by all modes),
//! then the modes are advanced in parallel chunks, each chunk vectorised over its modes.

use rayon::prelude::*;

use crate::error::CoreError;
use crate::loads::ModalLoad;
use crate::oscillator::Transfer;

/// Steps per block: loads are evaluated for a whole block before the modes advance.
const BLOCK: usize = 1024;
/// Fewest modes per parallel chunk.
const MIN_CHUNK: usize = 32;

/// Modal loads computed outside the engine (e.g. a Python callable), sampled in blocks.
pub trait ModalForcing {
    /// Fills `out` (`times.len()` rows of `n_modes`, row-major) with the modal load vector at
    /// each time.
    fn modal_loads(&mut self, times: &[f64], out: &mut [f64]) -> Result<(), CoreError>;
}

/// A linear modal problem: what to integrate and what to keep.
#[derive(Debug, Clone)]
pub struct LinearProblem<'a> {
    /// Modal stiffness `omega^2` per unit modal mass, one per mode (>= 0).
    pub k: &'a [f64],
    /// Modal damping `2 zeta omega` per unit modal mass, one per mode.
    pub c: &'a [f64],
    /// Initial modal coordinates.
    pub q0: &'a [f64],
    /// Initial modal velocities.
    pub v0: &'a [f64],
    /// Built-in loads, already projected on the modes.
    pub loads: &'a [ModalLoad],
    /// Step length (> 0).
    pub dt: f64,
    /// Number of steps (>= 1).
    pub n_steps: usize,
    /// Keep every `save_every`-th step (and always the last).
    pub save_every: usize,
    /// Worker threads; `None` uses rayon's global pool.
    pub threads: Option<usize>,
}

/// Saved modal history. Arrays are mode-major: entry `(mode, s)` at `mode * n_saved + s`.
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
    /// Modal accelerations `p - c v - k q`.
    pub a: Vec<f64>,
}

impl History {
    /// Number of saved instants.
    pub fn n_saved(&self) -> usize {
        self.t.len()
    }
}

/// A run that stopped early: the reason and everything computed before it.
#[derive(Debug, Clone)]
pub struct Failure {
    /// Why the run stopped.
    pub error: CoreError,
    /// The history up to the last good saved instant.
    pub partial: History,
}

impl From<CoreError> for Failure {
    fn from(error: CoreError) -> Self {
        Failure {
            error,
            partial: History::default(),
        }
    }
}

/// The step indices that are saved: multiples of `save_every`, and the last step.
fn saved_steps(n_steps: usize, save_every: usize) -> Vec<usize> {
    let mut s: Vec<usize> = (0..=n_steps).step_by(save_every).collect();
    if n_steps % save_every != 0 {
        s.push(n_steps);
    }
    s
}

fn check(problem: &LinearProblem) -> Result<(), CoreError> {
    let n = problem.k.len();
    let lens = [
        ("c", problem.c.len()),
        ("x0", problem.q0.len()),
        ("v0", problem.v0.len()),
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
    if !(problem.dt.is_finite() && problem.dt > 0.0) {
        return bad("dt", "must be a positive finite number");
    }
    if problem.n_steps == 0 {
        return bad("t_end", "must be at least one step `dt`");
    }
    if problem.save_every == 0 {
        return bad("save_every", "must be a positive integer");
    }
    if problem.k.iter().any(|&k| !(k.is_finite() && k >= 0.0)) {
        return bad("omega2", "must be finite and >= 0");
    }
    let all = problem.c.iter().chain(problem.q0).chain(problem.v0);
    if all.clone().any(|x| !x.is_finite()) {
        return bad("x0", "(initial state) and modal damping must be finite");
    }
    for load in problem.loads {
        if load.pattern.len() != n {
            return Err(CoreError::LengthMismatch {
                name: "load pattern",
                got: load.pattern.len(),
                expected: n,
            });
        }
        load.time.validate()?;
    }
    Ok(())
}

/// Per-mode constants: `A`, `B` and, per load, `pattern * B`.
struct Coefficients {
    a: [Vec<f64>; 4],
    b: [Vec<f64>; 6],
    /// `gl[l][r]`: entry `r` of `pattern_l * B` (rows x then v, columns p0, Dp, DDp).
    gl: Vec<[Vec<f64>; 6]>,
}

impl Coefficients {
    fn new(problem: &LinearProblem) -> Self {
        let n = problem.k.len();
        let mut a: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(n));
        let mut b: [Vec<f64>; 6] = std::array::from_fn(|_| Vec::with_capacity(n));
        for (&k, &c) in problem.k.iter().zip(problem.c) {
            let tr = Transfer::new(k, c, problem.dt);
            let bm = tr.b();
            for (slot, val) in a.iter_mut().zip(tr.a.iter().flatten()) {
                slot.push(*val);
            }
            for (slot, val) in b.iter_mut().zip(bm.iter().flatten()) {
                slot.push(*val);
            }
        }
        let gl = problem
            .loads
            .iter()
            .map(|load| {
                std::array::from_fn(|r| {
                    b[r].iter().zip(&load.pattern).map(|(x, p)| x * p).collect()
                })
            })
            .collect();
        Coefficients { a, b, gl }
    }
}

/// What one block shares between the mode chunks.
struct Block<'a> {
    n0: usize,
    len: usize,
    /// `basis[s * n_loads + l]`: the load basis of load `l` over local step `s`; one more row
    /// (`s = len`) holds the values at the end of the block (only `[0]` is used).
    basis: &'a [[f64; 3]],
    /// Modal samples of the external forcing at `t_n, t_n + dt/2, ..., t_end` (row-major), or
    /// empty.
    forcing: &'a [f64],
    /// Exact jumps of step loads inside a step: `(local step, dx per mode, dv per mode)`.
    jumps: &'a [(usize, Vec<f64>, Vec<f64>)],
    /// Saved slot of each step index in this block (plus the end), if saved.
    slot: &'a [Option<usize>],
}

/// One contiguous range of modes, with its state and history.
struct Chunk<'a> {
    start: usize,
    x: &'a mut [f64],
    v: &'a mut [f64],
    hq: &'a mut [f64],
    hv: &'a mut [f64],
    ha: &'a mut [f64],
    nx: Vec<f64>,
    nv: Vec<f64>,
}

struct Shared<'a> {
    problem: &'a LinearProblem<'a>,
    coef: &'a Coefficients,
    n_modes: usize,
    n_saved: usize,
}

impl Chunk<'_> {
    /// Writes the state at local step `s` into history slot `slot`.
    fn save(&mut self, sh: &Shared, blk: &Block, s: usize, slot: usize) {
        let n_loads = sh.problem.loads.len();
        let ns = sh.n_saved;
        for i in 0..self.x.len() {
            let gi = self.start + i;
            let mut p = 0.0;
            for (l, load) in sh.problem.loads.iter().enumerate() {
                p += load.pattern[gi] * blk.basis[s * n_loads + l][0];
            }
            if !blk.forcing.is_empty() {
                p += blk.forcing[2 * s * sh.n_modes + gi];
            }
            let (x, v) = (self.x[i], self.v[i]);
            self.hq[i * ns + slot] = x;
            self.hv[i * ns + slot] = v;
            self.ha[i * ns + slot] = p - sh.problem.c[gi] * v - sh.problem.k[gi] * x;
        }
    }

    /// Advances the chunk through the block; returns the first step index whose state is
    /// not finite.
    fn run(&mut self, sh: &Shared, blk: &Block) -> Option<usize> {
        let len = self.x.len();
        let r = self.start..self.start + len;
        let coef = sh.coef;
        let [a11, a12, a21, a22] = &coef.a;
        let (a11, a12, a21, a22) = (
            &a11[r.clone()],
            &a12[r.clone()],
            &a21[r.clone()],
            &a22[r.clone()],
        );
        let n_loads = sh.problem.loads.len();
        let mut jumps = blk.jumps.iter().peekable();
        for s in 0..blk.len {
            if let Some(slot) = blk.slot[s] {
                self.save(sh, blk, s, slot);
            }
            for i in 0..len {
                let (x, v) = (self.x[i], self.v[i]);
                self.nx[i] = a11[i] * x + a12[i] * v;
                self.nv[i] = a21[i] * x + a22[i] * v;
            }
            for (l, g) in coef.gl.iter().enumerate() {
                let [p0, dp, ddp] = blk.basis[s * n_loads + l];
                if p0 == 0.0 && dp == 0.0 && ddp == 0.0 {
                    continue;
                }
                let (gx0, gx1, gx2) = (&g[0][r.clone()], &g[1][r.clone()], &g[2][r.clone()]);
                let (gv0, gv1, gv2) = (&g[3][r.clone()], &g[4][r.clone()], &g[5][r.clone()]);
                for i in 0..len {
                    self.nx[i] += gx0[i] * p0 + gx1[i] * dp + gx2[i] * ddp;
                    self.nv[i] += gv0[i] * p0 + gv1[i] * dp + gv2[i] * ddp;
                }
            }
            if !blk.forcing.is_empty() {
                let nm = sh.n_modes;
                let f0 = &blk.forcing[2 * s * nm + self.start..][..len];
                let fm = &blk.forcing[(2 * s + 1) * nm + self.start..][..len];
                let f1 = &blk.forcing[(2 * s + 2) * nm + self.start..][..len];
                let b = &coef.b;
                for i in 0..len {
                    let gi = self.start + i;
                    let (p0, dp, ddp) = (f0[i], f1[i] - f0[i], fm[i] - 0.5 * (f0[i] + f1[i]));
                    self.nx[i] += b[0][gi] * p0 + b[1][gi] * dp + b[2][gi] * ddp;
                    self.nv[i] += b[3][gi] * p0 + b[4][gi] * dp + b[5][gi] * ddp;
                }
            }
            while let Some((_, dx, dv)) = jumps.next_if(|j| j.0 == s) {
                for i in 0..len {
                    self.nx[i] += dx[self.start + i];
                    self.nv[i] += dv[self.start + i];
                }
            }
            let mut acc = 0.0;
            for i in 0..len {
                self.x[i] = self.nx[i];
                self.v[i] = self.nv[i];
                acc += self.nx[i].abs() + self.nv[i].abs();
            }
            if !acc.is_finite() {
                return Some(blk.n0 + s + 1);
            }
        }
        if let Some(slot) = blk.slot[blk.len] {
            self.save(sh, blk, blk.len, slot);
        }
        None
    }
}

/// Integrates the problem; `forcing` adds modal loads computed outside the engine.
pub fn integrate(
    problem: &LinearProblem,
    mut forcing: Option<&mut dyn ModalForcing>,
) -> Result<History, Box<Failure>> {
    check(problem).map_err(|e| Box::new(Failure::from(e)))?;
    let pool = match problem.threads {
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| {
                    Box::new(Failure::from(CoreError::InvalidInput {
                        name: "threads",
                        problem: e.to_string(),
                    }))
                })?,
        ),
        None => None,
    };
    let n_modes = problem.k.len();
    let n_threads = pool
        .as_ref()
        .map_or_else(rayon::current_num_threads, |p| p.current_num_threads());
    let dt = problem.dt;
    let n_steps = problem.n_steps;
    let saved = saved_steps(n_steps, problem.save_every);
    let n_saved = saved.len();
    let coef = Coefficients::new(problem);
    let mut x = problem.q0.to_vec();
    let mut v = problem.v0.to_vec();
    let mut hq = vec![0.0; n_modes * n_saved];
    let mut hv = vec![0.0; n_modes * n_saved];
    let mut ha = vec![0.0; n_modes * n_saved];
    let time = |n: usize| n as f64 * dt;

    // Mode chunks: enough for the threads, none smaller than MIN_CHUNK.
    let chunk_len = n_modes
        .div_ceil(n_threads)
        .max(MIN_CHUNK)
        .min(n_modes.max(1));
    let mut chunks: Vec<Chunk> = Vec::new();
    {
        let (mut xr, mut vr) = (&mut x[..], &mut v[..]);
        let (mut qr, mut vhr, mut ar) = (&mut hq[..], &mut hv[..], &mut ha[..]);
        let mut start = 0;
        while start < n_modes {
            let len = chunk_len.min(n_modes - start);
            let (xc, xt) = xr.split_at_mut(len);
            let (vc, vt) = vr.split_at_mut(len);
            let (qc, qt) = qr.split_at_mut(len * n_saved);
            let (vhc, vht) = vhr.split_at_mut(len * n_saved);
            let (ac, at) = ar.split_at_mut(len * n_saved);
            chunks.push(Chunk {
                start,
                x: xc,
                v: vc,
                hq: qc,
                hv: vhc,
                ha: ac,
                nx: vec![0.0; len],
                nv: vec![0.0; len],
            });
            (xr, vr, qr, vhr, ar) = (xt, vt, qt, vht, at);
            start += len;
        }
    }
    let shared = Shared {
        problem,
        coef: &coef,
        n_modes,
        n_saved,
    };
    let n_loads = problem.loads.len();
    let mut basis: Vec<[f64; 3]> = Vec::with_capacity((BLOCK + 1) * n_loads);
    let mut forcing_buf: Vec<f64> = Vec::new();
    let mut times: Vec<f64> = Vec::new();
    let mut slot: Vec<Option<usize>> = Vec::with_capacity(BLOCK + 1);
    let mut next_saved = 0;
    let mut failure: Option<(CoreError, usize)> = None;

    let mut n0 = 0;
    while n0 < n_steps {
        let len = BLOCK.min(n_steps - n0);
        // Loads of the block, shared by every mode.
        basis.clear();
        for s in 0..=len {
            let t = time(n0 + s);
            basis.extend(problem.loads.iter().map(|l| l.time.basis(t, dt)));
        }
        let mut jumps = Vec::new();
        for s in 0..len {
            let t = time(n0 + s);
            for load in problem.loads {
                if let Some(rest) = load.time.jump_in(t, dt) {
                    let (dx, dv) = jump_response(problem, &load.pattern, rest);
                    jumps.push((s, dx, dv));
                }
            }
        }
        forcing_buf.clear();
        if let Some(f) = forcing.as_deref_mut() {
            // Step starts and midpoints from the grid, not from accumulation.
            times.clear();
            times.extend((0..=2 * len).map(|j| time(n0 + j / 2) + 0.5 * (j % 2) as f64 * dt));
            forcing_buf.resize(times.len() * n_modes, 0.0);
            if let Err(e) = f.modal_loads(&times, &mut forcing_buf) {
                failure = Some((e, n0));
                break;
            }
        }
        slot.clear();
        // The end of the block is saved by the next block, or here if it is the last.
        for s in 0..=len {
            let n = n0 + s;
            let last = n == n_steps;
            if (s < len || last) && next_saved < n_saved && saved[next_saved] == n {
                slot.push(Some(next_saved));
                next_saved += 1;
            } else {
                slot.push(None);
            }
        }
        let block = Block {
            n0,
            len,
            basis: &basis,
            forcing: &forcing_buf,
            jumps: &jumps,
            slot: &slot,
        };
        let run = |ch: &mut Chunk| ch.run(&shared, &block);
        let bad = match (&pool, chunks.len()) {
            (_, 1) => chunks.iter_mut().filter_map(run).min(),
            (Some(p), _) => p.install(|| chunks.par_iter_mut().filter_map(run).min()),
            (None, _) => chunks.par_iter_mut().filter_map(run).min(),
        };
        if let Some(step) = bad {
            failure = Some((
                CoreError::NonFinite {
                    time: time(step),
                    step,
                    last_good_time: time(step - 1),
                },
                step,
            ));
            break;
        }
        n0 += len;
    }
    drop(chunks);
    let t: Vec<f64> = saved.iter().map(|&n| time(n)).collect();
    let history = History {
        n_modes,
        t,
        q: hq,
        v: hv,
        a: ha,
    };
    match failure {
        None => Ok(history),
        Some((error, first_bad)) => {
            let keep = saved.iter().take_while(|&&n| n < first_bad).count();
            Err(Box::new(Failure {
                error,
                partial: truncate(history, keep),
            }))
        }
    }
}

/// Response at the end of the step to a unit step load applied `rest` before the end.
fn jump_response(problem: &LinearProblem, pattern: &[f64], rest: f64) -> (Vec<f64>, Vec<f64>) {
    problem
        .k
        .iter()
        .zip(problem.c)
        .zip(pattern)
        .map(|((&k, &c), &p)| {
            let tr = Transfer::new(k, c, rest);
            (p * tr.m[0][0], p * tr.m[1][0])
        })
        .unzip()
}

/// Keeps the first `keep` saved instants of a mode-major history.
fn truncate(h: History, keep: usize) -> History {
    let ns = h.n_saved();
    let cut = |src: &[f64]| -> Vec<f64> {
        (0..h.n_modes)
            .flat_map(|m| src[m * ns..m * ns + keep].iter().copied())
            .collect()
    };
    History {
        n_modes: h.n_modes,
        t: h.t[..keep].to_vec(),
        q: cut(&h.q),
        v: cut(&h.v),
        a: cut(&h.a),
    }
}
