//! Response spectra of ground-motion records: the peak response of single-degree-of-freedom
//! oscillators `x'' + 2 zeta omega x' + omega^2 x = -a_g(t)` to records `a_g` that are linear
//! between their samples (Nigam and Jennings 1969 — the method of this crate for one
//! oscillator). Each step uses the exact transition and load-transfer matrices of
//! [`crate::Transfer`], stable for tiny and large `omega dt`, so the spectra are exact for the
//! piecewise-linear record at every period and damping; peaks are taken at the samples.
//!
//! * [`elastic`]: peak relative displacement, relative velocity and absolute acceleration
//!   for records x dampings x periods, in parallel, several oscillators per pass over a record
//!   ([`elastic::LANES`]: independent recurrences interleaved, so the loop is bound by
//!   throughput, not by the latency of one recurrence);
//! * [`exact`]: the same spectra with the true peaks between the samples (where the
//!   derivative of each quantity vanishes inside a step);
//! * [`rotd`]: the peak displacement of two horizontal components rotated through a set of
//!   angles (RotD50/RotD100 in Boore 2010's definition are its percentiles);
//! * [`inelastic`]: the bilinear oscillator's peak displacement for a yield strength, and the
//!   yield strength that reaches a target ductility (constant-ductility spectra).

mod common;
pub mod elastic;
pub mod exact;
mod gate;
pub mod inelastic;
mod inside;
pub mod rotd;

pub use common::Record;
pub use elastic::{elastic, Peaks};
pub use exact::elastic_exact;
pub use inelastic::{ductility_spectrum, BilinearOscillator};
pub use rotd::rotd;
