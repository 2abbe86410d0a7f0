//! duhamel-core: semi-analytic ("BEM in time", Duhamel) transient integration of discretised
//! structural systems `M x'' + C x' + K x = f(t)`, after Holl, Belyaev and Irschik (1999).
//!
//! Pure Rust, no Python: the numerical engine behind the `duhamel` Python package.

pub mod error;
pub mod linear;
pub mod loads;
pub mod oscillator;

pub use error::CoreError;
pub use oscillator::Transfer;
