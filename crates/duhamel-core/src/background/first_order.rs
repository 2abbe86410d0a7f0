//! Exact stepping of a coupled linear system in its first-order (complex) modes.
//!
//! Non-classical damping, gyroscopic (`speed * G`) and circulatory (cross-coupled bearing)
//! terms couple the modal oscillators of the symmetric background: the retained modes obey
//! `q'' + D q' + S q = p(t)` with full `D`, `S`. Written in first order, `y = (q, q')`,
//! `y' = A y + B p`, and diagonalised, `A = V diag(lambda) V^-1`, each first-order modal
//! coordinate `eta_k` is an independent scalar equation `eta_k' = lambda_k eta_k + g_k . p(t)`
//! (`g_k` row `k` of `V^-1 B`), advanced exactly over a step (Duhamel's integral with the
//! complex exponential-integrator functions of [`crate::cphi`]):
//!
//! ```text
//! eta_k(n+1) = e^(lambda_k dt) eta_k(n) + sum_j w_j(lambda_k) (g_k . basis_j)
//! ```
//!
//! with the loads in the same per-step basis `(p0, Dp, DDp)` as the uncoupled engine and jumps
//! inside a step added exactly. So a linear time-invariant system with these couplings is
//! integrated as exactly as an uncoupled one: the only error is the representation of the
//! loads within a step (none for steps, ramps and quadratics). The decomposition itself
//! (eigenvalues, which of each conjugate pair to keep, and the way back to `(q, q')`) is done
//! by the caller; the engine only advances the given coordinates and saves them.

use super::energy::FirstOrderTap;
use crate::energy::EnergySpec;
use num_complex::Complex64;

use crate::driver::{drive_modal, finish, Control, ModalRoute, StepFailure};
use crate::error::CoreError;
use crate::history::{size, zeroed, Coordinates, Failure, History, Stats};
use crate::kernel::cphi;
use crate::loads::block::BlockLoads;
use crate::loads::ModalForcing;
use crate::output::{Mapper, Outputs};
use crate::problem::ModalProblem;
use crate::pseudo::first_order::{Corrector, Nonlinear};

pub use super::modes::FirstOrderModes;

/// Per-coordinate constants, split into real and imaginary parts (vectorisable loops).
struct Constants {
    /// `e^(lambda dt)`.
    e: [Vec<f64>; 2],
    /// `w_j(lambda)`, the weights of the basis `(p0, Dp, DDp)`.
    w: [[Vec<f64>; 2]; 3],
    /// `gl[l][j]`: `w_j (g . pattern_l)`.
    gl: Vec<[[Vec<f64>; 2]; 3]>,
}

impl Constants {
    fn new(problem: &ModalProblem, modes: &FirstOrderModes) -> Self {
        let r = modes.lambda_re.len();
        let mut e = [vec![0.0; r], vec![0.0; r]];
        let mut w: [[Vec<f64>; 2]; 3] = std::array::from_fn(|_| [vec![0.0; r], vec![0.0; r]]);
        let mut gl: Vec<[[Vec<f64>; 2]; 3]> = problem
            .loads
            .iter()
            .map(|_| std::array::from_fn(|_| [vec![0.0; r], vec![0.0; r]]))
            .collect();
        for k in 0..r {
            let lam = modes.lambda(k);
            let ek = (lam * problem.dt).exp();
            (e[0][k], e[1][k]) = (ek.re, ek.im);
            let wk = cphi::basis_weights(lam, problem.dt);
            for j in 0..3 {
                (w[j][0][k], w[j][1][k]) = (wk[j].re, wk[j].im);
            }
            for (load, g) in problem.loads.iter().zip(gl.iter_mut()) {
                let gk = modes.project(k, &load.pattern);
                for j in 0..3 {
                    let x = wk[j] * gk;
                    (g[j][0][k], g[j][1][k]) = (x.re, x.im);
                }
            }
        }
        Constants { e, w, gl }
    }
}

/// Coordinates advanced together in registers (one AVX-512 vector, two AVX2 vectors).
const LANES: usize = 8;

/// Advances coordinates `i0..i0 + N` by one step, `eta <- e eta + sum_t b_t g_t` over the
/// step's load terms `(b, g_re, g_im)`; returns whether they stay finite.
#[inline(always)]
fn advance<const N: usize>(
    xr: &mut [f64],
    xi: &mut [f64],
    i0: usize,
    e: &[Vec<f64>; 2],
    terms: &[(f64, &[f64], &[f64])],
) -> bool {
    let r = i0..i0 + N;
    let (er, ei) = (&e[0][r.clone()], &e[1][r.clone()]);
    let mut ar = [0.0; N];
    let mut ai = [0.0; N];
    {
        let (x, y) = (&xr[r.clone()], &xi[r.clone()]);
        for j in 0..N {
            ar[j] = er[j] * x[j] - ei[j] * y[j];
            ai[j] = er[j] * y[j] + ei[j] * x[j];
        }
    }
    for &(b, gr, gi) in terms {
        let (gr, gi) = (&gr[r.clone()], &gi[r.clone()]);
        for j in 0..N {
            ar[j] += b * gr[j];
            ai[j] += b * gi[j];
        }
    }
    xr[r.clone()].copy_from_slice(&ar);
    xi[r].copy_from_slice(&ai);
    // A boolean AND-reduction vectorises; a floating-point sum would not.
    let mut finite = true;
    for j in 0..N {
        finite &= ar[j].is_finite() & ai[j].is_finite();
    }
    finite
}

/// The first-order background, with the elements' corrector if any, and the mapped outputs:
/// the route of a coupled problem.
struct FirstOrder<'s, 'a: 's> {
    modes: &'s FirstOrderModes<'a>,
    co: Constants,
    /// Current coordinates.
    xr: Vec<f64>,
    xi: Vec<f64>,
    /// The forcing's contribution to each step of the block (`len x r`), or empty.
    fr: Vec<f64>,
    fi: Vec<f64>,
    /// This block's in-step jumps: `(local step, response re, response im)`.
    jumps: Vec<(usize, Vec<f64>, Vec<f64>)>,
    /// The history rows not written yet.
    eta_rest: &'s mut [f64],
    corrector: Option<Corrector<'a>>,
    /// The pseudo-force at the saved states (`n_saved x m`), with a corrector.
    pseudo: &'s mut [f64],
    mapper: Option<Mapper<'s>>,
    /// The energy integrals, when asked for ([`crate::energy`]).
    energy: Option<FirstOrderTap>,
}

impl<'s> FirstOrder<'s, '_> {
    /// The next `rows` history rows.
    fn take_rows(&mut self, rows: usize) -> &'s mut [f64] {
        let width = 2 * self.xr.len();
        let (rows, tail) = std::mem::take(&mut self.eta_rest).split_at_mut(rows * width);
        self.eta_rest = tail;
        rows
    }

    /// Maps `rows` saved rows, the first being history row `first`.
    fn map(&mut self, loads: &BlockLoads, rows: &'s [f64], first: usize, count: usize) {
        if let Some(mapper) = self.mapper.as_mut() {
            let n_loads = loads.load_values.len() / loads.n_saved().max(1);
            let values = loads.load_values[first * n_loads..][..count * n_loads].to_vec();
            mapper.map(rows, values, count);
        }
    }

    /// Writes the current state into `row` (and the pseudo-force there into its slot).
    fn save(&mut self, row: &mut [f64], slot: usize, t: f64) -> Result<(), CoreError> {
        let r = self.xr.len();
        row[..r].copy_from_slice(&self.xr);
        row[r..].copy_from_slice(&self.xi);
        if let Some(c) = self.corrector.as_mut() {
            let m = c.n_modes();
            let out = &mut self.pseudo[slot * m..][..m];
            c.at_state((&self.xr, &self.xi), (t, slot), out)?;
        }
        Ok(())
    }

    /// Steps the block, saving into `eta` (its first row being history row `row0`).
    fn steps(
        &mut self,
        problem: &ModalProblem,
        loads: &BlockLoads,
        row0: usize,
        eta: &mut [f64],
    ) -> Result<(), StepFailure> {
        let n0 = loads.n0;
        let modes = self.modes;
        let r = self.xr.len();
        let m = problem.k.len();
        let n_loads = problem.loads.len();
        let len = loads.len;
        // The forcing's contribution to each step: the first-order forcing g . f at the
        // step's start, middle and end (samples 2s, 2s + 1, 2s + 2) in the load basis.
        self.fr.clear();
        self.fi.clear();
        if !loads.forcing.is_empty() {
            let h: Vec<Complex64> = loads
                .forcing
                .chunks_exact(m)
                .flat_map(|f| (0..r).map(move |k| modes.project(k, f)))
                .collect();
            for s in 0..len {
                for k in 0..r {
                    let (p0, pm, p1) = (
                        h[2 * s * r + k],
                        h[(2 * s + 1) * r + k],
                        h[(2 * s + 2) * r + k],
                    );
                    let w = |j: usize| Complex64::new(self.co.w[j][0][k], self.co.w[j][1][k]);
                    let x = w(0) * p0 + w(1) * (p1 - p0) + w(2) * (pm - (p0 + p1) * 0.5);
                    self.fr.push(x.re);
                    self.fi.push(x.im);
                }
            }
        }
        self.jumps.clear();
        for &(s, l, rest, j) in &loads.raw_jumps {
            let pattern = &problem.loads[l].pattern;
            let (dr, di): (Vec<f64>, Vec<f64>) = (0..r)
                .map(|k| {
                    let x = cphi::polynomial_response(modes.lambda(k), rest, j)
                        * modes.project(k, pattern);
                    (x.re, x.im)
                })
                .unzip();
            self.jumps.push((s, dr, di));
        }
        let FirstOrder {
            xr,
            xi,
            fr,
            fi,
            jumps,
            co,
            corrector,
            pseudo,
            energy,
            ..
        } = self;
        // Reused across the steps of the block: no allocation per step.
        let mut terms: Vec<(f64, &[f64], &[f64])> = Vec::new();
        let guarded = corrector.as_ref().is_some_and(|c| c.guarded());
        let width = if guarded { m } else { 0 };
        let ends_buf = &mut [vec![0.0; width], vec![0.0; width], vec![0.0; width]];
        for s in 0..len {
            if let Some(slot) = loads.slot[s] {
                if let Some(tap) = energy.as_mut() {
                    tap.acc.save(slot);
                }
                let row = &mut eta[(slot - row0) * 2 * r..][..2 * r];
                row[..r].copy_from_slice(xr);
                row[r..].copy_from_slice(xi);
                if let Some(c) = corrector.as_mut() {
                    // The element pseudo-force at the saved state (for the accelerations).
                    let t = problem.time(n0 + s);
                    c.at_state((xr, xi), (t, slot), &mut pseudo[slot * m..][..m])
                        .map_err(StepFailure::at(n0 + s))?;
                }
            }
            terms.clear();
            for (l, g) in co.gl.iter().enumerate() {
                for (j, &b) in loads.basis[s * n_loads + l].iter().enumerate() {
                    if b != 0.0 {
                        terms.push((b, &g[j][0], &g[j][1]));
                    }
                }
            }
            for (_, dr, di) in jumps.iter().filter(|jp| jp.0 == s) {
                terms.push((1.0, dr, di));
            }
            if !fr.is_empty() {
                terms.push((1.0, &fr[s * r..][..r], &fi[s * r..][..r]));
            }
            let mut finite = true;
            let mut i0 = 0;
            while i0 + LANES <= r {
                finite &= advance::<LANES>(xr, xi, i0, &co.e, &terms);
                i0 += LANES;
            }
            while i0 < r {
                finite &= advance::<1>(xr, xi, i0, &co.e, &terms);
                i0 += 1;
            }
            let step = n0 + s + 1;
            if let (true, Some(c)) = (finite, corrector.as_mut()) {
                // The modal load at the step's ends, for the growth guard (loads computed
                // outside the engine are not known in real modal coordinates here: skipped).
                let ends = if c.guarded() && loads.forcing.is_empty() {
                    loads.modal_load_ends(problem, s, ends_buf);
                    Some((&ends_buf[0][..], &ends_buf[1][..], &ends_buf[2][..]))
                } else {
                    None
                };
                c.correct(problem.time(n0 + s), (xr, xi), ends)
                    .map_err(StepFailure::at(step))?;
                finite = xr.iter().chain(xi.iter()).all(|x| x.is_finite());
            }
            if !finite {
                let error = CoreError::NonFinite {
                    time: 0.0,
                    step,
                    last_good_time: None,
                };
                return Err(StepFailure { error, step });
            }
            if let Some(tap) = energy.as_mut() {
                loads.modal_load_ends(problem, s, &mut tap.ends);
                let basis = &loads.basis[s * n_loads..(s + 1) * n_loads];
                tap.step(problem.dt, (xr, xi), basis);
            }
        }
        Ok(())
    }
}

impl<'s> ModalRoute for FirstOrder<'s, '_> {
    fn block(&mut self, problem: &ModalProblem, loads: &BlockLoads) -> Result<(), StepFailure> {
        let rows = loads.slot.iter().flatten().count();
        let row0 = loads.slot.iter().flatten().next().copied().unwrap_or(0);
        let eta = self.take_rows(rows);
        let result = self.steps(problem, loads, row0, eta);
        self.map(loads, eta, row0, rows);
        result
    }

    fn save_current(
        &mut self,
        problem: &ModalProblem,
        loads: &BlockLoads,
        slot: usize,
    ) -> Result<(), CoreError> {
        let row = self.take_rows(1);
        if let Some(tap) = self.energy.as_mut() {
            tap.acc.save(slot);
        }
        let result = self.save(row, slot, problem.time(loads.n0 + loads.len));
        self.map(loads, row, slot, 1);
        result
    }
}

/// The energy integrals of a first-order run: their spec and the back-transformation.
pub type EnergyRun<'e> = (EnergySpec<'e>, &'e [f64]);

/// Integrates the coupled problem exactly in its first-order modes; `forcing` adds modal
/// loads computed outside the engine, `control` may stop or watch the run.
/// `problem.k`, `problem.c` are the diagonal of the real modal background (checked, and
/// defining the number of real modes); the saved history holds the first-order
/// coordinates ([`Coordinates::FirstOrder`]) and the load values.
///
/// With `outputs`, the saved rows are also mapped to outputs ([`History::outputs`]), block by
/// block, on a second thread while the next block is stepped (unless `problem.threads` is
/// 1 or the machine has one core). With `nonlinear`, element forces enter every step as a
/// pseudo-force on the exact coupled background ([`crate::pseudo::first_order`]); the
/// pseudo-force at the saved states is kept in [`History::pseudo`].
pub fn integrate(
    problem: &ModalProblem,
    modes: &FirstOrderModes,
    outputs: Option<&Outputs>,
    nonlinear: Option<&Nonlinear>,
    forcing: Option<&mut dyn ModalForcing>,
    control: &mut dyn Control,
) -> Result<(History, Stats), Box<Failure>> {
    let run = (outputs, nonlinear, None);
    integrate_with(problem, modes, run, forcing, control)
}

/// [`integrate`] with the energy integrals of `energy` (its spec and the `2 r x 2 m`
/// back-transformation to the real modal state) accumulated every step; linear runs only
/// (no `nonlinear`), built-in loads only (no `forcing`).
pub fn integrate_with(
    problem: &ModalProblem,
    modes: &FirstOrderModes,
    (outputs, nonlinear, energy): (Option<&Outputs>, Option<&Nonlinear>, Option<EnergyRun>),
    forcing: Option<&mut dyn ModalForcing>,
    control: &mut dyn Control,
) -> Result<(History, Stats), Box<Failure>> {
    let fail = |e: CoreError| Box::new(Failure::from(e));
    if energy.is_some() && (nonlinear.is_some() || forcing.is_some()) {
        return Err(fail(CoreError::InvalidInput {
            name: "energy",
            problem: "is accumulated on the first-order route without elements and Python \
                      loads only"
                .into(),
        }));
    }
    problem.check().map_err(fail)?;
    let m = problem.n_modes();
    modes.check(m).map_err(fail)?;
    let r = modes.lambda_re.len();
    if let Some(o) = outputs {
        o.check(2 * r, problem.loads.len()).map_err(fail)?;
    }
    let mut corrector = nonlinear
        .map(|nl| {
            let lambda: Vec<Complex64> = (0..r).map(|k| modes.lambda(k)).collect();
            let (gain, eta0) = (
                (modes.gain_re, modes.gain_im),
                (modes.eta0_re, modes.eta0_im),
            );
            Corrector::new(
                nl,
                problem.k,
                problem.c,
                &lambda,
                gain,
                eta0,
                (problem.time(0), problem.dt),
            )
        })
        .transpose()
        .map_err(fail)?;
    let n_cols = outputs.map_or(0, |o| o.n_cols);
    // Saturating: `n_cols` is bounded by the output map's length only when `r > 0`; a huge
    // width is then refused as too much memory.
    let width = (2 * r)
        .saturating_add(n_cols)
        .saturating_add(if corrector.is_some() { m } else { 0 });
    let loads = BlockLoads::new(problem, false, forcing.is_some(), width).map_err(fail)?;
    let n_saved = loads.n_saved();
    if let Some(c) = corrector.as_mut() {
        c.keep_rows(n_saved).map_err(fail)?;
    }
    let mut eta = zeroed(
        size(n_saved, 2 * r, "the modal history").map_err(fail)?,
        "the modal history",
    )
    .map_err(fail)?;
    let mut pseudo = if corrector.is_some() {
        zeroed(
            size(n_saved, m, "the pseudo-force").map_err(fail)?,
            "the pseudo-force",
        )
        .map_err(fail)?
    } else {
        Vec::new()
    };
    let mut out = zeroed(
        size(n_saved, n_cols, "the outputs").map_err(fail)?,
        "the outputs",
    )
    .map_err(fail)?;
    let threads = problem
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pipelined = threads > 1;
    let has_corrector = corrector.is_some();
    let tap = match energy {
        Some((spec, back)) => {
            spec.check(m, problem.loads.len(), &[]).map_err(fail)?;
            let eta0 = (modes.eta0_re, modes.eta0_im);
            Some(FirstOrderTap::new(&spec, (m, back), eta0, n_saved).map_err(fail)?)
        }
        None => None,
    };

    let (loads, ending, stats) = std::thread::scope(|scope| {
        let mapper = outputs.map(|o| Mapper::new(o, &mut out, pipelined.then_some(scope)));
        let mut route = FirstOrder {
            modes,
            co: Constants::new(problem, modes),
            xr: modes.eta0_re.to_vec(),
            xi: modes.eta0_im.to_vec(),
            fr: Vec::new(),
            fi: Vec::new(),
            jumps: Vec::new(),
            eta_rest: &mut eta,
            corrector,
            pseudo: &mut pseudo,
            mapper,
            energy: tap,
        };
        let (loads, ending) = drive_modal(problem, &mut route, loads, forcing, control);
        let stats = route
            .corrector
            .as_ref()
            .map_or_else(Stats::default, |c| Stats {
                newton_iterations: c.iterations,
                factorizations: c.factorizations,
                ..Stats::default()
            });
        let records = route.corrector.as_mut().map(|c| c.take_records());
        let energy = route.energy.map(|tap| tap.acc.into_rows());
        (loads, ending, (stats, records.unwrap_or_default(), energy))
    });
    let (stats, (elements, element_state, guard_state), energy) = stats;
    let kept = History {
        n_modes: m,
        n_outputs: n_cols,
        coordinates: Coordinates::FirstOrder { eta, width: 2 * r },
        pseudo: has_corrector.then_some(pseudo),
        outputs: outputs.is_some().then_some(out),
        elements,
        element_state,
        guard_state,
        energy,
        ..History::default()
    };
    finish(problem, loads, kept, ending).map(|h| (h, stats))
}
