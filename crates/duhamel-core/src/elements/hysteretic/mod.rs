//! Hysteretic and device elements of earthquake engineering: the path-dependent
//! [`Bilinear`], [`BoucWen`], [`FrictionPendulum`], [`AxialFrictionPendulum`] (its normal force from a vertical dof)
//! [`LeadRubberBearing`] and [`TripleFrictionPendulum`] (committed and trial internal
//! variables, [`crate::elements::PathState`]) the damper in series with its brace
//! [`MaxwellDamper`] (its internal deformation evolves in time) and the stateless
//! [`ViscousDamper`] and [`Gap`].
//! Each returns its exact (consistent) tangent.

mod bilinear;
mod boucwen;
pub(crate) mod common;
mod friction;
mod gap;
mod maxwell;
mod pendulum;
mod pendulum_axial;
mod rubber;
mod triple;
mod triple_model;
mod triple_segment;
mod viscous;

pub use bilinear::{Bilinear, BilinearDef};
pub use boucwen::{BoucWen, BoucWenDef, BoucWenParams};
pub use friction::{FrictionPendulum, DEFAULT_YIELD_DISPLACEMENT};
pub use gap::{Gap, GapDef};
pub use maxwell::{DamperElement, MaxwellDamper, ViscousDamperDef};
pub use pendulum::{FrictionPendulumDef, PendulumElement};
pub use pendulum_axial::AxialFrictionPendulum;
pub(crate) use rubber::rename_axes;
pub use rubber::{LeadRubberBearing, LeadRubberBearingDef};
pub use triple::TripleFrictionPendulum;
pub use triple_model::TripleFrictionPendulumDef;
pub use viscous::{ViscousDamper, DEFAULT_V0};
