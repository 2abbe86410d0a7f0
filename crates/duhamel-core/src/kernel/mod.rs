//! The exact step kernels of one mode, shared by the background propagators and the
//! correctors: the real oscillator's transition and load-transfer matrices ([`oscillator`])
//! and the complex exponential-integrator functions of a first-order mode ([`cphi`]); a
//! coordinate without mass (a massless dof's relaxation or static coordinate) in
//! [`relaxation`]; the matrices of a model's modes over a step, made once per content, in
//! [`transfer_memo`].

pub mod cphi;
mod far;
pub mod oscillator;
pub mod relaxation;
pub mod transfer_memo;
