//! The exact step kernels of one mode, shared by the background propagators and the
//! correctors: the real oscillator's transition and load-transfer matrices ([`oscillator`])
//! and the complex exponential-integrator functions of a first-order mode ([`cphi`]); a
//! coordinate without mass (a massless dof's relaxation or static coordinate) in
//! [`relaxation`].

pub mod cphi;
mod far;
pub mod oscillator;
pub mod relaxation;
