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

// The materials are public modules, not re-exported here: each uses this module's trait, and
// a re-export would make this module depend on them (an import cycle); and a material is
// named in its own files and the registry only.
#[cfg(test)]
mod deterioration_tests;
pub mod elastic_multilinear;
pub mod hysteretic;
pub mod hysteretic_def;
pub mod imk;
pub mod imk_bilin;
mod imk_bilin_backbone;
pub mod imk_bilin_def;
pub mod imk_def;
mod imk_envelope;
pub mod imk_params;
mod imk_update;
pub mod material;
pub mod minmax;
pub mod multilinear;
pub mod parallel;
mod pinching4;
mod pinching4_damage;
pub mod pinching4_def;
mod pinching4_paths;
mod points;
#[cfg(test)]
mod restart_tests;
pub mod series;
mod state;
pub mod steel02;
pub mod takeda;
pub mod uniaxial;

pub use material::Material;

#[cfg(test)]
pub(crate) mod testing;
