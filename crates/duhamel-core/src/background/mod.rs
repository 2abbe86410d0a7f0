//! Background propagators: the exact step of the linear time-invariant part of a modal
//! problem.
//!
//! * [`uncoupled`]: classically damped modes, each an independent oscillator stepped with its
//!   exact transition and load-transfer matrices ([`crate::kernel::oscillator`]);
//! * [`first_order`]: modes coupled by non-classical damping, gyroscopic or circulatory terms,
//!   diagonalised in first order and stepped with complex exponentials
//!   ([`crate::kernel::cphi`]).

mod energy;
pub mod first_order;
mod modes;
pub mod uncoupled;
