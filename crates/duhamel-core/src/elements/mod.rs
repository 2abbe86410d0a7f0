//! Elements: restoring forces `r(x, x', t)` on the left-hand side,
//! `M x'' + C x' + K x + r(x, x', t) = f(t)`, with their tangents.
//!
//! The integrators own the time discretisation; an element only returns its force and, on
//! request, `dr/dx` and `dr/dx'` at its own degrees of freedom ([`Element`]). One file per
//! element family.

mod builtin;
mod contact;
mod crack;
mod definition;
mod drive;
mod element;
mod evaluation;
pub(crate) mod hysteretic;
mod journal;
pub mod materials;
mod polynomial;
mod registry;
mod shifted;
mod spring;
mod table;

pub use contact::{Contact, ContactDef};
pub use crack::{Breathing, BreathingCrack, BreathingCrackDef};
pub use definition::{along, deformation, pair_matrix, Definition, Pair};
pub use drive::{drive, Driven};
pub use element::{Element, ModalCubic, PathState, Tangent};
pub(crate) use evaluation::Evaluation;
pub use hysteretic::{
    AxialFrictionPendulum, Bilinear, BilinearDef, BoucWen, BoucWenDef, BoucWenParams,
    DamperElement, FrictionPendulum, FrictionPendulumDef, Gap, GapDef, LeadRubberBearing,
    LeadRubberBearingDef, MaxwellDamper, PendulumElement, TripleFrictionPendulum,
    TripleFrictionPendulumDef, ViscousDamper, ViscousDamperDef, DEFAULT_V0,
    DEFAULT_YIELD_DISPLACEMENT,
};
pub use journal::{JournalElementDef, JournalFilm, ShortJournalBearing};
pub use polynomial::{CubicDef, Polynomial, PolynomialDef};
pub use registry::{Defined, Runtime, ELEMENTS};
pub use shifted::Shifted;
pub use spring::{Damper, DamperDef, Spring, SpringDef};
pub use table::{SpeedTableBearing, SpeedTableBearingDef};
