//! Device elements the binding builds outside `elements.rs` (which lists each element kind
//! once): `_core.Element.device(kind, args)` checks the arguments of `kind` and keeps the
//! made element as a prototype, cloned for each run.

use duhamel_core::elements::{Element, TripleFrictionPendulum};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::error::core_err;
use crate::guard::guarded;

/// A checked core element, cloned fresh (initial state) for each run.
trait Prototype: Send + Sync {
    fn fresh(&self) -> Box<dyn Element>;
    fn dofs(&self) -> Vec<usize>;
}

impl<T: Element + Clone + 'static> Prototype for T {
    fn fresh(&self) -> Box<dyn Element> {
        Box::new(self.clone())
    }

    fn dofs(&self) -> Vec<usize> {
        Element::dofs(self).to_vec()
    }
}

/// A device element made by [`build`].
pub(crate) struct Device(Box<dyn Prototype>);

impl Device {
    /// A fresh core element.
    pub(crate) fn fresh(&self) -> Box<dyn Element> {
        self.0.fresh()
    }

    /// The global dofs the element acts on, in its local order.
    pub(crate) fn dofs(&self) -> Vec<usize> {
        self.0.dofs()
    }
}

/// The arguments of a triple friction pendulum: `(dof_x, dof_y, mu, radius,
/// displacement_capacity, weight, yield_displacement)`.
type TripleArgs = (usize, Option<usize>, [f64; 3], [f64; 3], [f64; 3], f64, f64);

/// The device `kind` from its arguments `args` (a tuple), checked.
pub(crate) fn build(kind: &str, args: &Bound<'_, PyAny>) -> PyResult<Device> {
    match kind {
        "triple_friction_pendulum" => {
            let (dof_x, dof_y, mu, radius, capacity, weight, uy): TripleArgs = args.extract()?;
            let made = guarded(|| {
                match dof_y {
                    Some(y) => {
                        TripleFrictionPendulum::new(dof_x, y, mu, radius, capacity, weight, uy)
                    }
                    None => {
                        TripleFrictionPendulum::uniaxial(dof_x, mu, radius, capacity, weight, uy)
                    }
                }
                .map_err(core_err)
            })?;
            Ok(Device(Box::new(made)))
        }
        _ => Err(PyValueError::new_err(format!(
            "unknown device kind {kind:?}"
        ))),
    }
}
