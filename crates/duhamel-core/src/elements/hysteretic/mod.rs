//! Hysteretic and device elements of earthquake engineering, one module each: the
//! path-dependent [`bilinear`], [`boucwen`], [`friction`] (the friction pendulum),
//! [`pendulum_axial`] (its normal force from a vertical dof), [`rubber`] (the lead-rubber
//! bearing) and [`triple`] (the triple friction pendulum) (committed and trial internal
//! variables, [`crate::elements::PathState`]), the damper in series with its brace
//! [`maxwell`] (its internal deformation evolves in time) and the stateless [`viscous`]
//! damper and [`gap`]. Each returns its exact (consistent) tangent.

pub mod bilinear;
pub mod boucwen;
pub(crate) mod common;
pub mod friction;
pub mod gap;
pub mod maxwell;
pub mod pendulum;
pub mod pendulum_axial;
pub mod rubber;
pub mod triple;
pub mod triple_model;
mod triple_segment;
mod triple_series;
pub mod viscous;

pub(crate) use rubber::rename_axes;
