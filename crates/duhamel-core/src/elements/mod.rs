//! Elements: restoring forces `r(x, x', t)` on the left-hand side,
//! `M x'' + C x' + K x + r(x, x', t) = f(t)`, with their tangents.
//!
//! The integrators own the time discretisation; an element only returns its force and, on
//! request, `dr/dx` and `dr/dx'` at its own degrees of freedom ([`Element`]). One file per
//! element family.

mod builtin;
pub mod contact;
pub mod crack;
mod definition;
mod drive;
mod element;
mod evaluation;
pub mod hysteretic;
pub mod journal;
pub mod materials;
pub mod polynomial;
mod registry;
mod shifted;
pub mod spring;
pub mod table;

pub use definition::{along, deformation, pair_matrix, Definition, Pair};
pub use drive::{drive, Driven};
pub use element::{Element, ModalCubic, PathState, Tangent};
pub(crate) use evaluation::Evaluation;
pub use registry::{Defined, Runtime, ELEMENTS};
pub use shifted::Shifted;
