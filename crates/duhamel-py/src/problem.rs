//! One run of a model: its time grid and initial state, as typed values.

use duhamel_core::loads::ModalLoad;
use duhamel_core::problem::MAX_THREADS;
use duhamel_core::ModalProblem;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{index_vec, vec_of};

/// The time grid of one run: `t0 + (step0 + n) dt`, `n = 0..=n_steps`, every `save_every`-th
/// instant kept, on `threads` worker threads (None: all cores).
#[pyclass(frozen, name = "Grid", module = "duhamel._core")]
#[derive(Clone, Copy)]
pub(crate) struct Grid {
    pub(crate) t0: f64,
    pub(crate) step0: usize,
    pub(crate) dt: f64,
    pub(crate) n_steps: usize,
    pub(crate) save_every: usize,
    pub(crate) threads: Option<usize>,
}

#[pymethods]
impl Grid {
    #[new]
    #[pyo3(signature = (t0, dt, n_steps, save_every, step0=0, threads=None))]
    fn new(
        t0: f64,
        dt: f64,
        n_steps: usize,
        save_every: usize,
        step0: usize,
        threads: Option<usize>,
    ) -> PyResult<Self> {
        let bad = |what: String| Err(PyValueError::new_err(what));
        if !(dt.is_finite() && dt > 0.0) {
            return bad(format!("`dt` must be a positive finite number, got {dt}"));
        }
        if !t0.is_finite() {
            return bad(format!("`t0` must be finite, got {t0}"));
        }
        if n_steps == 0 {
            return bad("`t_end` must be at least one step `dt` after `t0`".into());
        }
        if save_every == 0 {
            return bad("`save_every` must be a positive integer".into());
        }
        if let Some(t) = threads {
            if t == 0 || t > MAX_THREADS {
                return bad(format!(
                    "`threads` must be between 1 and {MAX_THREADS}, got {t}"
                ));
            }
        }
        Ok(Grid {
            t0,
            step0,
            dt,
            n_steps,
            save_every,
            threads,
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "Grid(t0={}, dt={}, n_steps={}, save_every={}, step0={}, threads={:?})",
            self.t0, self.dt, self.n_steps, self.save_every, self.step0, self.threads
        )
    }
}

/// The energy integrals a run accumulates (pseudo-force route; `duhamel_core::energy`): the
/// modal damping matrix `damping` (`Phi^T C Phi`, `n_modes x n_modes`), the loads that are
/// ground accelerations `base_loads`, their `base_w` (`Phi^T M r`, one row per base) and
/// `base_rr` (`r^T M r'`), the ground velocities `vg0` at the run's start, and the linear
/// parts `linear` the background took over from the elements (`k0`, `c0` per element); on
/// the first-order route, `back` (`2 r x 2 m`) makes the real modal state of its coordinates.
#[pyclass(frozen, name = "EnergySpec", module = "duhamel._core")]
#[derive(Clone)]
pub(crate) struct EnergySpec {
    damping: Vec<f64>,
    base_loads: Vec<usize>,
    base_w: Vec<f64>,
    base_rr: Vec<f64>,
    vg0: Vec<f64>,
    linear: Vec<f64>,
    back: Vec<f64>,
}

#[pymethods]
impl EnergySpec {
    #[new]
    #[pyo3(signature = (damping, base, vg0, linear, back=None))]
    fn new(
        damping: &Bound<'_, PyAny>,
        base: (Bound<'_, PyAny>, Bound<'_, PyAny>, Bound<'_, PyAny>),
        vg0: &Bound<'_, PyAny>,
        linear: &Bound<'_, PyAny>,
        back: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let (base_loads, base_w, base_rr) = base;
        Ok(EnergySpec {
            damping: vec_of(damping, "damping")?,
            base_loads: index_vec(&base_loads, "base_loads")?,
            base_w: vec_of(&base_w, "base_w")?,
            base_rr: vec_of(&base_rr, "base_rr")?,
            vg0: vec_of(vg0, "vg0")?,
            linear: vec_of(linear, "linear")?,
            back: back
                .map(|b| vec_of(b, "back"))
                .transpose()?
                .unwrap_or_default(),
        })
    }
}

impl EnergySpec {
    /// The first-order route's back-transformation to the real modal state.
    pub(crate) fn back(&self) -> &[f64] {
        &self.back
    }

    /// The core's view of it.
    pub(crate) fn core(&self) -> duhamel_core::energy::EnergySpec<'_> {
        duhamel_core::energy::EnergySpec {
            damping: &self.damping,
            base_loads: &self.base_loads,
            base_w: &self.base_w,
            base_rr: &self.base_rr,
            vg0: &self.vg0,
            linear: &self.linear,
        }
    }
}

/// One run of a prepared modal model (`duhamel._core.ModalModel.run`): its grid and the
/// state it starts from — modal coordinates and velocities `q0`, `v0`; on the first-order
/// route optionally the first-order coordinates `eta0` (`Re | Im`, else computed by the
/// caller); the elements' committed variables of a continued run, `element_state`, and its
/// growth guard's bounds, `guard_state` (`RunResult.guard_state` of the run before); the
/// energy integrals to accumulate, `energy` (an `EnergySpec`, pseudo-force route).
#[pyclass(frozen, name = "RunSpec", module = "duhamel._core")]
pub(crate) struct RunSpec {
    pub(crate) grid: Grid,
    pub(crate) q0: Vec<f64>,
    pub(crate) v0: Vec<f64>,
    pub(crate) eta0: Option<Vec<f64>>,
    pub(crate) element_state: Option<Vec<f64>>,
    pub(crate) guard_state: Option<Vec<f64>>,
    pub(crate) energy: Option<EnergySpec>,
}

#[pymethods]
impl RunSpec {
    #[new]
    #[pyo3(signature = (grid, q0, v0, eta0=None, element_state=None, guard_state=None, energy=None))]
    fn new(
        grid: &Grid,
        q0: &Bound<'_, PyAny>,
        v0: &Bound<'_, PyAny>,
        eta0: Option<&Bound<'_, PyAny>>,
        element_state: Option<&Bound<'_, PyAny>>,
        guard_state: Option<&Bound<'_, PyAny>>,
        energy: Option<PyRef<'_, EnergySpec>>,
    ) -> PyResult<Self> {
        Ok(RunSpec {
            grid: *grid,
            q0: vec_of(q0, "x0")?,
            v0: vec_of(v0, "v0")?,
            eta0: eta0.map(|e| vec_of(e, "eta0")).transpose()?,
            element_state: element_state
                .map(|e| vec_of(e, "element_state"))
                .transpose()?,
            guard_state: guard_state.map(|e| vec_of(e, "guard_state")).transpose()?,
            energy: energy.map(|e| e.clone()),
        })
    }
}

impl RunSpec {
    /// The core's problem of this run on the background `k`, `c` with `loads`.
    pub(crate) fn problem<'a>(
        &'a self,
        k: &'a [f64],
        c: &'a [f64],
        loads: &'a [ModalLoad],
    ) -> ModalProblem<'a> {
        let g = &self.grid;
        ModalProblem {
            k,
            c,
            q0: &self.q0,
            v0: &self.v0,
            loads,
            t0: g.t0,
            step0: g.step0,
            dt: g.dt,
            n_steps: g.n_steps,
            save_every: g.save_every,
            threads: g.threads,
        }
    }
}
