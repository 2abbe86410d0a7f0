//! The exact step kernels of one mode, shared by the background propagators and the
//! correctors: the real oscillator's transition and load-transfer matrices ([`oscillator`])
//! and the complex exponential-integrator functions of a first-order mode ([`cphi`]).

pub mod cphi;
mod far;
pub mod oscillator;
