//! duhamel-core: semi-analytic ("BEM in time", Duhamel) transient integration of discretised
//! structural systems `M x'' + C x' + K x = f(t)`, after Holl, Belyaev and Irschik (1999).
//!
//! Pure Rust, no Python: the numerical engine behind the `duhamel` Python package. Every modal
//! route is one composition run by one loop ([`driver`]): a [`problem`] goes through a
//! [`background`] propagator, an optional corrector ([`pseudo`]) and an [`output`]; the
//! reference integrators of [`direct`] step the physical equations.

pub mod accuracy;
pub mod background;
pub mod cubic;
pub mod dense;
mod dense_fixed;
pub mod dense_kept;
mod dense_rows;
pub mod direct;
pub mod driver;
pub mod elements;
pub mod energy;
pub mod error;
pub mod history;
pub mod kernel;
pub mod loads;
pub mod mass;
pub mod output;
pub mod problem;
pub mod pseudo;
pub mod spectra;
pub mod speed;
pub mod truncation;

pub use driver::{Control, Unattended};
pub use error::CoreError;
pub use history::{Coordinates, ElementRows, Failure, History, Stats};
pub use kernel::oscillator;
pub use kernel::oscillator::Transfer;
pub use problem::ModalProblem;
