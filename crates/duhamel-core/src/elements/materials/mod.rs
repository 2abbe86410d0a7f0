//! Uniaxial materials: force-deformation laws with committed and trial internal variables,
//! as OpenSees' `UniaxialMaterial` (`setTrialStrain` / `commitState`), and the element that
//! puts one between two dofs (or a dof and the ground), [`uniaxial::Uniaxial`].
//!
//! A material sees the deformation `u = x_i - x_j` (and its rate) and returns the force and
//! its consistent tangent `dF/du`. Its internal variables follow OpenSees' vocabulary:
//! `committed` are those at the start of the step (read only), `trial` those at the
//! evaluated deformation, written by [`Material::response`]; a commit copies `trial` into
//! `committed`. Whatever OpenSees does in `commitState` (accumulating hysteretic energy,
//! updating an envelope) is done here in `response`, into `trial`: a commit is a copy.
//! A retried step evaluates from the committed variables again (nothing to revert).
//!
//! One file per material; wrappers (`MinMax`, `Parallel`, `Series`) hold other materials.

// The materials are public modules, not re-exported here: each uses this module's trait,
// and a re-export would make this module depend on them (an import cycle).
pub mod elastic_multilinear;
mod material;
pub mod minmax;
pub mod multilinear;
pub mod parallel;
mod points;
pub mod series;
pub mod steel02;
pub mod takeda;
pub mod uniaxial;

pub use material::Material;

#[cfg(test)]
pub(crate) mod testing;
