//! Loads `f(t) = sum_l pattern_l * s_l(t)`: a fixed spatial (here: modal) pattern times a
//! scalar time function evaluated in Rust.

pub mod block;
mod misalignment;
mod steps;
mod table;
mod time;

pub use misalignment::Coupling;
pub use steps::Steps;
pub use time::{Axis, TimeFunction};

use crate::error::CoreError;

/// Modal loads computed outside the engine (e.g. a Python callable), sampled in blocks.
pub trait ModalForcing {
    /// Fills `out` (`times.len()` rows of `n_modes`, row-major) with the modal load vector at
    /// each time.
    fn modal_loads(&mut self, times: &[f64], out: &mut [f64]) -> Result<(), CoreError>;
}

/// Checks `loads` for a model of `n` coordinates: patterns of length `n`, valid time
/// functions.
pub fn check_loads(loads: &[ModalLoad], n: usize) -> Result<(), CoreError> {
    for load in loads {
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

/// A load in modal coordinates: `pattern[mode] * s(t)`.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalLoad {
    /// Modal load per unit of the time function, one entry per retained mode.
    pub pattern: Vec<f64>,
    /// The time function.
    pub time: TimeFunction,
}
