//! duhamel-core: semi-analytic ("BEM in time", Duhamel) transient integration of discretised
//! structural systems `M x'' + C x' + K x = f(t)`, after Holl, Belyaev and Irschik (1999).
//!
//! Pure Rust, no Python: the numerical engine behind the `duhamel` Python package.

pub mod coupled;
pub mod coupled_step;
pub mod cphi;
pub mod cubic;
pub mod dense;
pub mod direct;
pub mod elements;
pub mod error;
pub mod linear;
pub mod loads;
pub mod mass;
pub mod oscillator;
pub mod semianalytic;
pub mod speed;
pub(crate) mod stepping;

pub use error::CoreError;
pub use oscillator::Transfer;
