//! An element defined once: its parameters as the user gives them (serialisable, checked
//! when the engine element is built), its call signature and documentation, and what the
//! planner asks of it (passivity, linear part, tangent bound, directions, stored energy).
//!
//! A definition is the element as a model holds it; [`Definition::build`] makes the engine
//! element ([`Definition::Runtime`], an [`Element`]) the integrators evaluate. The binding
//! exposes every definition of the registry (`registry.rs`) as the Python class
//! `duhamel.elements.<NAME>`, parsing its arguments by [`Definition::SIGNATURE`]; the store
//! writes it through serde.

use serde::de::DeserializeOwned;
use serde::Serialize;

use super::element::Element;
use super::materials::material::Material;
use crate::error::CoreError;

/// The dofs of a deformation `x_i - x_j` (`j` None: to the ground).
pub type Pair = (usize, Option<usize>);

/// An element as a model defines it (see the module documentation).
pub trait Definition:
    Serialize + DeserializeOwned + Clone + std::fmt::Debug + Send + Sync + 'static
{
    /// The class name: `duhamel.elements.<NAME>`, and the store's tag.
    const NAME: &'static str;
    /// The Python call signature, e.g. `"(i, j=None, *, k, fy, alpha=0.0)"`: the dofs the
    /// element connects first (positional or keyword: `i, j` of a deformation, `dofs` of a
    /// device on several dofs), its physical parameters keyword-only, required where they
    /// have no default. Parameter names are the serde field names.
    const SIGNATURE: &'static str;
    /// The numpydoc documentation, with a runnable example.
    const DOC: &'static str;
    /// The positional parameters of the previous release, in order: a call with more
    /// positional arguments than the signature takes maps them onto these names (with a
    /// `DeprecationWarning` naming the new spelling). Names not in the signature are
    /// renamed by [`Definition::rename`].
    const LEGACY: &'static [&'static str] = &[];

    /// Defaults of the previous release for parameters that are now required (a physical
    /// value has no default): `(name, JSON value)`. A call without the parameter still
    /// runs with that value for this release, with a `DeprecationWarning`.
    const LEGACY_DEFAULTS: &'static [(&'static str, &'static str)] = &[];

    /// The engine's element.
    type Runtime: Element + Clone + 'static;

    /// The engine element, checked (errors name the parameter).
    fn build(&self) -> Result<Self::Runtime, CoreError>;

    /// An old parameter name and its new one with how the value moves:
    /// `("dof_x", "dofs", Some(0))` puts the value at position 0 of the tuple `dofs`,
    /// `("dof", "i", None)` renames. Default: none.
    fn rename(_old: &str) -> Option<(&'static str, Option<usize>)> {
        None
    }

    /// Whether the element only stores or dissipates the work done on it (a spring with a
    /// potential bounded below, a hysteretic or viscous device, a stop): the growth guard
    /// then bounds the response's energy by what the loads supply. False by default.
    fn passive(&self) -> bool {
        false
    }

    /// The linear stiffness part `k0` (row-major, over the engine element's dofs) the
    /// linear background takes over (`Semianalytic(linear_parts="background")`), or None.
    fn linear_stiffness(&self) -> Option<Vec<f64>> {
        None
    }

    /// The element without its linear part as a definition of its own, where one exists in
    /// closed form (a spring with `k = 0`); None: the remainder is the element minus
    /// `k0 x` (a `Shifted` element).
    fn without_linear(&self) -> Option<Self> {
        None
    }

    /// Bounds `(k, c)` on the norms of the tangent stiffness and damping as a pseudo-force
    /// over every state the element can reach, or None (no bound known).
    fn tangent_bound(&self) -> Option<(f64, f64)> {
        None
    }

    /// The directions the force acts along, each `(i, j)`: the deformation `x_i - x_j`
    /// (`j` None: `x_i` alone). None (the default): each of the element's dofs alone.
    fn directions(&self) -> Option<Vec<Pair>> {
        None
    }

    /// The recoverable energy at local displacements `u` and local forces `f` (the energy
    /// released by unloading along the elastic branch); 0 where the element defines none.
    fn stored_energy(&self, _u: &[f64], _f: &[f64]) -> f64 {
        0.0
    }

    /// When the element is exactly linear, its local stiffness and damping matrices
    /// (row-major over its dofs) and None otherwise, with the reason.
    fn linear(&self) -> Result<(Vec<f64>, Vec<f64>), String> {
        Err(format!("is not linear ({} is nonlinear)", Self::NAME))
    }

    /// For a uniaxial material element, its law without its dofs (a part of a `MinMax`,
    /// `Parallel` or `Series`), checked; None (the default) for any other element.
    fn material(&self) -> Option<Result<Box<dyn Material>, CoreError>> {
        None
    }
}

/// The local matrix `k [[1, -1], [-1, 1]]` of a deformation (`[k]` to the ground).
pub fn pair_matrix(j: Option<usize>, k: f64) -> Vec<f64> {
    match j {
        None => vec![k],
        Some(_) => vec![k, -k, -k, k],
    }
}

/// The one direction of an element on a deformation: `(i, j)`.
pub fn along(i: usize, j: Option<usize>) -> Option<Vec<Pair>> {
    Some(vec![(i, j)])
}

/// `x_i - x_j` of local displacements (`x_i` to the ground).
pub fn deformation(u: &[f64]) -> f64 {
    u[0] - u.get(1).copied().unwrap_or(0.0)
}

/// An enum of engine elements that is itself an [`Element`], each call passed to the
/// variant's own (a definition whose engine element depends on its parameters: a friction
/// pendulum with or without its vertical dof).
#[macro_export]
macro_rules! element_variants {
    ($(#[$meta:meta])* $vis:vis enum $name:ident { $($variant:ident($ty:ty)),* $(,)? }) => {
        $(#[$meta])*
        #[derive(Debug, Clone)]
        $vis enum $name { $($variant($ty)),* }

        impl $crate::elements::Element for $name {
            fn dofs(&self) -> &[usize] {
                match self { $($name::$variant(e) => e.dofs(),)* }
            }
            #[inline]
            fn eval(
                &self,
                x: &[f64],
                v: &[f64],
                t: f64,
                r: &mut [f64],
                tangent: Option<$crate::elements::Tangent<'_>>,
            ) -> Result<(), $crate::CoreError> {
                match self { $($name::$variant(e) => e.eval(x, v, t, r, tangent),)* }
            }
            fn polynomial_degree(&self) -> Option<u32> {
                match self { $($name::$variant(e) => e.polynomial_degree(),)* }
            }
            fn uses_velocity(&self) -> bool {
                match self { $($name::$variant(e) => e.uses_velocity(),)* }
            }
            fn has_tangent(&self) -> bool {
                match self { $($name::$variant(e) => e.has_tangent(),)* }
            }
            fn state_len(&self) -> usize {
                match self { $($name::$variant(e) => e.state_len(),)* }
            }
            fn initial_state(&self, x: &[f64], v: &[f64], state: &mut [f64]) {
                match self { $($name::$variant(e) => e.initial_state(x, v, state),)* }
            }
            fn initial_time(&self, t0: f64, state: &mut [f64]) {
                match self { $($name::$variant(e) => e.initial_time(t0, state),)* }
            }
            #[inline]
            fn eval_path(
                &self,
                x: &[f64],
                v: &[f64],
                t: f64,
                history: $crate::elements::PathState<'_>,
                r: &mut [f64],
                tangent: Option<$crate::elements::Tangent<'_>>,
            ) -> Result<(), $crate::CoreError> {
                match self {
                    $($name::$variant(e) => e.eval_path(x, v, t, history, r, tangent),)*
                }
            }
            fn modal_cubic(&self, phi: &[f64]) -> Option<$crate::elements::ModalCubic> {
                match self { $($name::$variant(e) => e.modal_cubic(phi),)* }
            }
            fn path_reads(&self) -> Option<(bool, bool)> {
                match self { $($name::$variant(e) => e.path_reads(),)* }
            }
            fn restarts_exactly(&self) -> bool {
                match self { $($name::$variant(e) => e.restarts_exactly(),)* }
            }
            fn resolution(&self) -> f64 {
                match self { $($name::$variant(e) => e.resolution(),)* }
            }
        }
    };
}
