//! Elements: restoring forces `r(x, x', t)` on the left-hand side,
//! `M x'' + C x' + K x + r(x, x', t) = f(t)`, with their tangents.
//!
//! The integrators own the time discretisation; an element only returns its force and, on
//! request, `dr/dx` and `dr/dx'` at its own degrees of freedom ([`Element`]). One file per
//! element family.

mod builtin;
mod contact;
mod crack;
mod element;
mod evaluation;
pub(crate) mod hysteretic;
mod journal;
pub mod materials;
mod polynomial;
mod shifted;
mod spring;
mod table;

pub use contact::Contact;
pub use crack::{Breathing, BreathingCrack};
pub use element::{Element, ModalCubic, PathState, Tangent};
pub(crate) use evaluation::Evaluation;
pub use hysteretic::TripleFrictionPendulum;
pub use hysteretic::{
    AxialFrictionPendulum, Bilinear, BoucWen, BoucWenParams, FrictionPendulum, Gap,
    LeadRubberBearing, MaxwellDamper, ViscousDamper, DEFAULT_V0, DEFAULT_YIELD_DISPLACEMENT,
};
pub use journal::ShortJournalBearing;
pub use polynomial::Polynomial;
pub use shifted::Shifted;
pub use spring::{Damper, Spring};
pub use table::SpeedTableBearing;
