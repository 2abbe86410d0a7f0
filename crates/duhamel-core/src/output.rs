//! What a route keeps besides its coordinates: physical outputs mapped from the saved rows
//! during the run, on a second thread while the next block is stepped.

use std::sync::mpsc::Sender;
use std::thread::Scope;

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};

use crate::error::CoreError;

/// Physical outputs computed from the saved coordinates during the run: each saved row of
/// coordinates (and of the load values) is mapped to `n_cols` outputs, e.g. displacements and
/// velocities of the wanted degrees of freedom.
#[derive(Debug, Clone)]
pub struct Outputs<'a> {
    /// `map[k * n_cols + o]`: output `o` per unit of coordinate `k` (`width x n_cols`,
    /// row-major).
    pub map: &'a [f64],
    /// `loads[l * n_cols + o]`: output `o` per unit value of load `l`'s time function
    /// (`n_loads x n_cols`).
    pub loads: &'a [f64],
    /// Number of outputs.
    pub n_cols: usize,
}

impl Outputs<'_> {
    /// Checks the maps against the coordinates' `width` and the number of loads.
    pub fn check(&self, width: usize, n_loads: usize) -> Result<(), CoreError> {
        for (name, got, rows) in [
            ("output map", self.map.len(), width),
            ("output load map", self.loads.len(), n_loads),
        ] {
            let Some(expected) = rows.checked_mul(self.n_cols) else {
                return Err(CoreError::InvalidInput {
                    name: "n_cols",
                    problem: format!("is too large: {rows} x {} values overflow", self.n_cols),
                });
            };
            if got != expected {
                return Err(CoreError::LengthMismatch {
                    name,
                    got,
                    expected,
                });
            }
        }
        Ok(())
    }

    /// `out = rows @ map + values @ loads` for a block of saved rows (faer's matrix product:
    /// measured twice as fast here as a register-blocked row loop).
    pub fn apply(&self, rows: &[f64], values: &[f64], out: &mut [f64]) {
        let n = self.n_cols;
        let count = out.len() / n.max(1);
        if count == 0 || n == 0 {
            return;
        }
        let width = rows.len() / count;
        let n_loads = values.len() / count;
        let mut dst = MatMut::from_row_major_slice_mut(out, count, n);
        let lhs = MatRef::from_row_major_slice(rows, count, width);
        let rhs = MatRef::from_row_major_slice(self.map, width, n);
        matmul(&mut dst, Accum::Replace, lhs, rhs, 1.0, Par::Seq);
        if n_loads > 0 {
            let lhs = MatRef::from_row_major_slice(values, count, n_loads);
            let rhs = MatRef::from_row_major_slice(self.loads, n_loads, n);
            matmul(&mut dst, Accum::Add, lhs, rhs, 1.0, Par::Seq);
        }
    }
}

/// A block of saved rows to map: coordinates, load values, where the outputs go.
type Job<'s> = (&'s [f64], Vec<f64>, &'s mut [f64]);

/// Maps saved rows to outputs as the run saves them, in order, into the output buffer:
/// on a worker thread of `scope` when one is given, at once otherwise.
pub struct Mapper<'s> {
    outputs: &'s Outputs<'s>,
    rest: &'s mut [f64],
    tx: Option<Sender<Job<'s>>>,
}

impl<'s> Mapper<'s> {
    /// A mapper writing into `out` (`n_saved x n_cols`); with `scope`, the products run on a
    /// worker thread that lives until the mapper is dropped.
    pub fn new<'env>(
        outputs: &'s Outputs<'s>,
        out: &'s mut [f64],
        scope: Option<&'s Scope<'s, 'env>>,
    ) -> Self {
        let tx = scope.map(|scope| {
            let (tx, rx) = std::sync::mpsc::channel::<Job<'s>>();
            scope.spawn(move || {
                for (rows, values, dst) in rx {
                    outputs.apply(rows, &values, dst);
                }
            });
            tx
        });
        Mapper {
            outputs,
            rest: out,
            tx,
        }
    }

    /// Maps the next saved rows `rows` with their load values.
    pub fn map(&mut self, rows: &'s [f64], values: Vec<f64>, count: usize) {
        // In bounds: the buffer has `n_saved x n_cols` values (its size checked by the route)
        // and each saved row is mapped once.
        let (dst, tail) = std::mem::take(&mut self.rest).split_at_mut(count * self.outputs.n_cols);
        self.rest = tail;
        match &self.tx {
            // The worker lives until `tx` is dropped, so the send cannot fail.
            Some(tx) => {
                let _ = tx.send((rows, values, dst));
            }
            None => self.outputs.apply(rows, &values, dst),
        }
    }
}
