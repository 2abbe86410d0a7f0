//! The modal problem, extracted once into Rust values.

use duhamel_core::loads::ModalLoad;
use duhamel_core::ModalProblem;
use pyo3::prelude::*;

use crate::arrays::{attr, vec_of};
use crate::loads::loads_of;

/// The owned inputs of a [`ModalProblem`], extracted from a Python object with the
/// attributes `k`, `c` (modal stiffness and damping), `q0`, `v0`, `loads`, `t0`, `dt`,
/// `n_steps`, `save_every` and `threads` (see `duhamel._solve.plan`), and optionally
/// `step0` (the grid point a continued run starts at; 0 otherwise).
pub(crate) struct ModalInput {
    k: Vec<f64>,
    c: Vec<f64>,
    q0: Vec<f64>,
    v0: Vec<f64>,
    loads: Vec<ModalLoad>,
    t0: f64,
    step0: usize,
    dt: f64,
    n_steps: usize,
    save_every: usize,
    threads: Option<usize>,
}

impl ModalInput {
    /// Extracts the inputs; errors name the Python-side parameter.
    pub(crate) fn extract(obj: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(ModalInput {
            k: vec_of(&obj.getattr("k")?, "omega2")?,
            c: vec_of(&obj.getattr("c")?, "c")?,
            q0: vec_of(&obj.getattr("q0")?, "x0")?,
            v0: vec_of(&obj.getattr("v0")?, "v0")?,
            loads: loads_of(&obj.getattr("loads")?)?,
            t0: attr(obj, "t0")?,
            step0: if obj.hasattr("step0")? {
                attr(obj, "step0")?
            } else {
                0
            },
            dt: attr(obj, "dt")?,
            n_steps: attr(obj, "n_steps")?,
            save_every: attr(obj, "save_every")?,
            threads: attr(obj, "threads")?,
        })
    }

    /// The core's view of the inputs.
    pub(crate) fn problem(&self) -> ModalProblem<'_> {
        ModalProblem {
            k: &self.k,
            c: &self.c,
            q0: &self.q0,
            v0: &self.v0,
            loads: &self.loads,
            t0: self.t0,
            step0: self.step0,
            dt: self.dt,
            n_steps: self.n_steps,
            save_every: self.save_every,
            threads: self.threads,
        }
    }
}
