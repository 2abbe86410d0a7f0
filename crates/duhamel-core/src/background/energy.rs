//! The first-order route's energy tap ([`crate::energy`]): the real modal state of every
//! step's end from the first-order coordinates, fed to the accumulator.

use crate::energy::{EnergyAccumulator, EnergySpec, StepEnd};
use crate::error::CoreError;

/// The accumulator on first-order coordinates (the coupled linear route): the real modal
/// state `[q | v] = [Re eta | Im eta] back` of every step's end, its built-in loads.
#[derive(Debug, Clone)]
pub struct FirstOrderTap {
    pub acc: EnergyAccumulator,
    /// `2 r x 2 m`, row-major.
    back: Vec<f64>,
    qv: Vec<f64>,
    /// The modal load at the step's start and end and its bubble coefficient.
    pub ends: [Vec<f64>; 3],
}

impl FirstOrderTap {
    /// The tap of `spec` for `m` real modes and `2 r x 2 m` back-transformation `back`,
    /// saving `n_saved` rows; started at the coordinates `(re, im)`.
    pub fn new(
        spec: &EnergySpec,
        (m, back): (usize, &[f64]),
        (re, im): (&[f64], &[f64]),
        n_saved: usize,
    ) -> Result<Self, CoreError> {
        if back.len() != 2 * re.len() * 2 * m {
            return Err(CoreError::LengthMismatch {
                name: "energy back-transformation",
                got: back.len(),
                expected: 4 * re.len() * m,
            });
        }
        let mut tap = FirstOrderTap {
            acc: EnergyAccumulator::new(spec, m, Vec::new(), n_saved),
            back: back.to_vec(),
            qv: vec![0.0; 2 * m],
            ends: std::array::from_fn(|_| vec![0.0; m]),
        };
        tap.real(re, im);
        let m = tap.qv.len() / 2;
        let v = tap.qv[m..].to_vec();
        tap.acc.start(&v, (&[], &[]));
        Ok(tap)
    }

    fn real(&mut self, re: &[f64], im: &[f64]) {
        let w = self.qv.len();
        self.qv.fill(0.0);
        for (&x, row) in re.iter().chain(im).zip(self.back.chunks_exact(w.max(1))) {
            for (o, b) in self.qv.iter_mut().zip(row) {
                *o += x * b;
            }
        }
    }

    /// Adds the step of length `dt` ending at `(re, im)`, with its loads' basis (the modal
    /// loads at its ends in `ends`).
    pub fn step(&mut self, dt: f64, (re, im): (&[f64], &[f64]), load_basis: &[[f64; 3]]) {
        self.real(re, im);
        let m = self.qv.len() / 2;
        let end = StepEnd {
            v: &self.qv[m..],
            p: (&self.ends[0], &self.ends[1]),
            load_basis,
            elements: (&[], &[]),
            damping_power: None,
        };
        self.acc.step(dt, &end);
    }
}
