//! Exact stepping of uncoupled modal oscillators: the background propagator of a linear
//! time-invariant system with classical damping.
//!
//! Each mode `q'' + c q' + k q = p(t)` is advanced by `y(n+1) = A y(n) + B (p0, Dp, DDp)` with
//! the exact matrices of [`crate::kernel::oscillator`]. The modes are independent, so the
//! route advances a whole block of steps at a time: the loads of the block are evaluated once
//! (shared by all modes), then the modes are advanced in parallel chunks, each chunk
//! vectorised over its modes.

use rayon::prelude::*;

use crate::driver::{drive_modal, finish, Control, ModalRoute, StepFailure};
use crate::error::CoreError;
use crate::history::{size, zeroed, Coordinates, Failure, History};
use crate::kernel::oscillator::Transfer;
use crate::loads::block::BlockLoads;
use crate::loads::ModalForcing;
use crate::problem::ModalProblem;

/// Fewest modes per parallel chunk.
const MIN_CHUNK: usize = 32;

/// Per-mode constants: `A - 1`, `B` and, per load, `pattern * B`.
struct Coefficients {
    a: [Vec<f64>; 4],
    b: [Vec<f64>; 6],
    /// `gl[l][r]`: entry `r` of `pattern_l * B` (rows x then v, columns p0, Dp, DDp).
    gl: Vec<[Vec<f64>; 6]>,
}

impl Coefficients {
    fn new(problem: &ModalProblem) -> Self {
        let n = problem.k.len();
        let mut a: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(n));
        let mut b: [Vec<f64>; 6] = std::array::from_fn(|_| Vec::with_capacity(n));
        for (&k, &c) in problem.k.iter().zip(problem.c) {
            let tr = Transfer::new(k, c, problem.dt);
            let bm = tr.b();
            // the diagonal as `A - 1`: the step adds the increment to the state last
            // (`pseudo::rows`: no drift of the round-off over many short steps)
            let [d0, d1] = tr.a_less_one;
            for (slot, val) in a.iter_mut().zip([d0, tr.a[0][1], tr.a[1][0], d1]) {
                slot.push(val);
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

/// One contiguous range of modes, with its own state and its columns of the history.
struct Chunk {
    start: usize,
    x: Vec<f64>,
    v: Vec<f64>,
    out: HistoryWriter,
}

/// Writes one chunk's columns of the time-major history buffers.
///
/// The chunks of one run own disjoint column ranges `start..start + len` of the same
/// `n_saved x n_modes` buffers, so they write through raw pointers instead of borrows.
#[derive(Clone, Copy)]
struct HistoryWriter {
    q: *mut f64,
    v: *mut f64,
    n_modes: usize,
    n_saved: usize,
}

// SAFETY: a `HistoryWriter` only writes (never reads) through its pointers, each chunk writes
// only its own column range (see `rows`), and the buffers outlive the parallel section (they
// are owned by `integrate`, which drops the chunks before touching them again).
unsafe impl Send for HistoryWriter {}
// SAFETY: as above; shared references never write.
unsafe impl Sync for HistoryWriter {}

impl HistoryWriter {
    /// The `(q, v)` slices of row `slot`, columns `start..start + len`.
    fn rows(&mut self, slot: usize, start: usize, len: usize) -> [&mut [f64]; 2] {
        // Holds by construction (slots come from the save grid, ranges from the chunks): it
        // guards the unsafe writes below, and would panic (`InternalError`), never corrupt.
        assert!(slot < self.n_saved && start + len <= self.n_modes);
        let off = slot * self.n_modes + start;
        // SAFETY: `off + len <= n_saved * n_modes`, the length of each buffer (checked above);
        // the column range `start..start + len` belongs to this chunk alone, so no other
        // thread reads or writes these elements while the slices live, and `&mut self`
        // prevents two live slices from the same writer.
        unsafe {
            [
                std::slice::from_raw_parts_mut(self.q.add(off), len),
                std::slice::from_raw_parts_mut(self.v.add(off), len),
            ]
        }
    }
}

struct Shared<'a> {
    n_loads: usize,
    coef: &'a Coefficients,
    n_modes: usize,
}

/// Modes advanced together in registers (one AVX-512 vector, two AVX2 vectors).
const LANES: usize = 8;

/// What one step adds to every mode of a chunk, as slices over the chunk's modes.
struct StepTerms<'s> {
    /// `(b, gain_x, gain_v)`: the state gains `b * gain` of the shared load terms.
    shared: &'s [(f64, &'s [f64], &'s [f64])],
    /// External forcing at the start, middle and end of the step.
    forcing: Option<[&'s [f64]; 3]>,
    /// History rows `(q, v)` to fill with the state at the step start.
    save: Option<[&'s mut [f64]; 2]>,
}

/// Per-chunk slices of the per-mode constants.
struct ChunkCoef<'s> {
    a: [&'s [f64]; 4],
    b: [&'s [f64]; 6],
}

/// `a * b + c`, fused where the target has FMA (one rounding), plain otherwise (a software
/// `fma` call would be far slower than the two operations it replaces).
#[inline(always)]
fn fmadd(a: f64, b: f64, c: f64) -> f64 {
    if cfg!(target_feature = "fma") {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// Advances modes `i0..i0 + N` of a chunk by one step; with `CHECK`, returns whether they
/// stay finite (otherwise `true`).
#[inline(always)]
fn advance<const N: usize, const CHECK: bool>(
    x: &mut [f64],
    v: &mut [f64],
    i0: usize,
    co: &ChunkCoef,
    terms: &mut StepTerms,
) -> bool {
    let r = i0..i0 + N;
    let mut xs = [0.0; N];
    let mut vs = [0.0; N];
    xs.copy_from_slice(&x[r.clone()]);
    vs.copy_from_slice(&v[r.clone()]);
    if let Some([hq, hv]) = terms.save.as_mut() {
        hq[r.clone()].copy_from_slice(&xs);
        hv[r.clone()].copy_from_slice(&vs);
    }
    let [a11, a12, a21, a22] = co.a.map(|s| &s[r.clone()]);
    let mut nx = [0.0; N];
    let mut nv = [0.0; N];
    for j in 0..N {
        nx[j] = fmadd(a11[j], xs[j], a12[j] * vs[j]);
        nv[j] = fmadd(a21[j], xs[j], a22[j] * vs[j]);
    }
    for &(b, gx, gv) in terms.shared {
        let (gx, gv) = (&gx[r.clone()], &gv[r.clone()]);
        for j in 0..N {
            nx[j] = fmadd(gx[j], b, nx[j]);
            nv[j] = fmadd(gv[j], b, nv[j]);
        }
    }
    if let Some([f0, fm, f1]) = terms.forcing.map(|f| f.map(|s| &s[r.clone()])) {
        let b = co.b.map(|s| &s[r.clone()]);
        for j in 0..N {
            let (p0, dp, ddp) = (f0[j], f1[j] - f0[j], fm[j] - 0.5 * (f0[j] + f1[j]));
            nx[j] += b[0][j] * p0 + b[1][j] * dp + b[2][j] * ddp;
            nv[j] += b[3][j] * p0 + b[4][j] * dp + b[5][j] * ddp;
        }
    }
    for j in 0..N {
        nx[j] += xs[j];
        nv[j] += vs[j];
    }
    x[r.clone()].copy_from_slice(&nx);
    v[r].copy_from_slice(&nv);
    // A boolean AND-reduction vectorises; a floating-point sum would not.
    let mut finite = true;
    if CHECK {
        for j in 0..N {
            finite &= nx[j].is_finite() & nv[j].is_finite();
        }
    }
    finite
}

impl Chunk {
    /// Advances the chunk through the block; returns the first step index whose state is
    /// not finite.
    ///
    /// A linear step maps a non-finite state to a non-finite state, so finiteness is checked
    /// once, at the end of the block; only if that fails is the block run again from its
    /// start, checking every step, to find where the state first overflowed.
    fn run(&mut self, sh: &Shared, blk: &BlockLoads) -> Option<usize> {
        let (x0, v0) = (self.x.clone(), self.v.clone());
        self.steps::<false>(sh, blk);
        if self.x.iter().chain(&self.v).all(|u| u.is_finite()) {
            return None;
        }
        self.x.copy_from_slice(&x0);
        self.v.copy_from_slice(&v0);
        self.steps::<true>(sh, blk)
    }

    /// The steps of one block; with `CHECK`, stops at the first non-finite state.
    fn steps<const CHECK: bool>(&mut self, sh: &Shared, blk: &BlockLoads) -> Option<usize> {
        let len = self.x.len();
        let r = self.start..self.start + len;
        let coef = sh.coef;
        let co = ChunkCoef {
            a: std::array::from_fn(|i| &coef.a[i][r.clone()]),
            b: std::array::from_fn(|i| &coef.b[i][r.clone()]),
        };
        let n_loads = sh.n_loads;
        let nm = sh.n_modes;
        let mut out = self.out;
        // The block's arrays as slices, held in registers across the steps.
        let (slots, bases, jumps, forcing) = (
            &blk.slot[..blk.len],
            &blk.basis[..],
            &blk.jumps[..],
            &blk.forcing[..],
        );
        // Reused across steps: no allocation in the time loop.
        let mut shared: Vec<(f64, &[f64], &[f64])> = Vec::new();
        for (s, slot) in slots.iter().enumerate() {
            let save = slot.map(|slot| out.rows(slot, self.start, len));
            shared.clear();
            for (l, g) in coef.gl.iter().enumerate() {
                for (j, &b) in bases[s * n_loads + l].iter().enumerate() {
                    if b != 0.0 {
                        shared.push((b, &g[j][r.clone()], &g[j + 3][r.clone()]));
                    }
                }
            }
            for (_, dx, dv) in jumps.iter().filter(|j| j.0 == s) {
                shared.push((1.0, &dx[r.clone()], &dv[r.clone()]));
            }
            let mut terms = StepTerms {
                shared: &shared,
                forcing: (!forcing.is_empty()).then(|| {
                    std::array::from_fn(|h| &forcing[(2 * s + h) * nm + self.start..][..len])
                }),
                save,
            };
            let mut finite = true;
            let mut i0 = 0;
            while i0 + LANES <= len {
                finite &= advance::<LANES, CHECK>(&mut self.x, &mut self.v, i0, &co, &mut terms);
                i0 += LANES;
            }
            while i0 < len {
                finite &= advance::<1, CHECK>(&mut self.x, &mut self.v, i0, &co, &mut terms);
                i0 += 1;
            }
            if CHECK && !finite {
                return Some(blk.n0 + s + 1);
            }
        }
        None
    }
}

impl Chunk {
    /// Saves the chunk's current state in row `slot`.
    fn save(&mut self, slot: usize) {
        let [hq, hv] = self.out.rows(slot, self.start, self.x.len());
        hq.copy_from_slice(&self.x);
        hv.copy_from_slice(&self.v);
    }
}

/// The uncoupled background without a corrector: whole blocks, mode chunks in parallel.
struct Uncoupled {
    chunks: Vec<Chunk>,
    coef: Coefficients,
    pool: Option<std::sync::Arc<rayon::ThreadPool>>,
}

impl ModalRoute for Uncoupled {
    fn block(&mut self, problem: &ModalProblem, loads: &BlockLoads) -> Result<(), StepFailure> {
        let shared = Shared {
            n_loads: problem.loads.len(),
            coef: &self.coef,
            n_modes: problem.n_modes(),
        };
        let run = |ch: &mut Chunk| ch.run(&shared, loads);
        let bad = match (&self.pool, self.chunks.len()) {
            (_, 1) => self.chunks.iter_mut().filter_map(run).min(),
            (Some(p), _) => p.install(|| self.chunks.par_iter_mut().filter_map(run).min()),
            (None, _) => self.chunks.par_iter_mut().filter_map(run).min(),
        };
        match bad {
            None => Ok(()),
            Some(step) => Err(StepFailure {
                error: CoreError::NonFinite {
                    time: 0.0,
                    step,
                    last_good_time: None,
                },
                step,
            }),
        }
    }

    fn save_current(
        &mut self,
        _problem: &ModalProblem,
        _loads: &BlockLoads,
        slot: usize,
    ) -> Result<(), CoreError> {
        for chunk in &mut self.chunks {
            chunk.save(slot);
        }
        Ok(())
    }
}

/// Integrates the uncoupled linear problem exactly; `forcing` adds modal loads computed
/// outside the engine, `control` may stop or watch the run.
pub fn integrate(
    problem: &ModalProblem,
    forcing: Option<&mut dyn ModalForcing>,
    control: &mut dyn Control,
) -> Result<History, Box<Failure>> {
    let fail = |e: CoreError| Box::new(Failure::from(e));
    problem.check().map_err(fail)?;
    let pool = problem.pool().map_err(fail)?;
    let n_modes = problem.n_modes();
    let n_threads = pool
        .as_ref()
        .map_or_else(rayon::current_num_threads, |p| p.current_num_threads());
    let loads = BlockLoads::new(problem, true, forcing.is_some(), 2 * n_modes).map_err(fail)?;
    let n_saved = loads.n_saved();
    let cells = size(n_saved, n_modes, "the modal history").map_err(fail)?;
    let mut hq = zeroed(cells, "the modal history (q)").map_err(fail)?;
    let mut hv = zeroed(cells, "the modal history (v)").map_err(fail)?;

    // Mode chunks: enough for the threads, none smaller than MIN_CHUNK, whole cache lines.
    let chunk_len = n_modes
        .div_ceil(n_threads)
        .next_multiple_of(LANES)
        .max(MIN_CHUNK)
        .min(n_modes.max(1));
    let writer = HistoryWriter {
        q: hq.as_mut_ptr(),
        v: hv.as_mut_ptr(),
        n_modes,
        n_saved,
    };
    let mut chunks: Vec<Chunk> = Vec::new();
    let mut start = 0;
    while start < n_modes {
        let len = chunk_len.min(n_modes - start);
        chunks.push(Chunk {
            start,
            x: problem.q0[start..start + len].to_vec(),
            v: problem.v0[start..start + len].to_vec(),
            out: writer,
        });
        start += len;
    }
    let mut route = Uncoupled {
        chunks,
        coef: Coefficients::new(problem),
        pool,
    };
    let (loads, ending) = drive_modal(problem, &mut route, loads, forcing, control);
    // The chunks' writers point into `hq`, `hv`: drop them before the buffers move.
    drop(route);
    let kept = History {
        n_modes,
        coordinates: Coordinates::Modal { q: hq, v: hv },
        ..History::default()
    };
    finish(problem, loads, kept, ending)
}
