//! The built-in elements the integrators call without dynamic dispatch.
//!
//! The elements reach the integrators as `&dyn Element`; a device's force is a few flops,
//! and two indirect calls per evaluation (the element, and the element inside [`Shifted`],
//! its linear part taken out) cost about as much and keep the compiler from inlining it.
//! An [`Evaluation`](super::Evaluation) resolves its element once, at construction, to a
//! [`Dispatch`]: a built-in element (or one shifted by its linear part) is then called
//! through a `match`, each arm a direct call to that type's own methods. The arithmetic is
//! the same functions' (results bit for bit); any other element keeps the dynamic call.

use super::element::{Element, PathState, Tangent};
use super::hysteretic::{Bilinear, FrictionPendulum, Gap, ViscousDamper};
use super::polynomial::Polynomial;
use super::shifted::Shifted;
use super::spring::Spring;
use crate::error::CoreError;

/// A built-in element by its type (from [`Element::as_any`]).
#[derive(Clone, Copy)]
pub(crate) enum Builtin<'e> {
    Bilinear(&'e Bilinear),
    Spring(&'e Spring),
    Gap(&'e Gap),
    Viscous(&'e ViscousDamper),
    Pendulum(&'e FrictionPendulum),
    Polynomial(&'e Polynomial),
    /// An element with its linear part taken out (resolved one level further down).
    Shifted(&'e Shifted),
}

impl<'e> Builtin<'e> {
    /// The built-in type of `element`, if it is one.
    fn of(element: &'e dyn Element) -> Option<Self> {
        let any = element.as_any()?;
        if let Some(e) = any.downcast_ref::<Bilinear>() {
            Some(Builtin::Bilinear(e))
        } else if let Some(e) = any.downcast_ref::<Spring>() {
            Some(Builtin::Spring(e))
        } else if let Some(e) = any.downcast_ref::<Gap>() {
            Some(Builtin::Gap(e))
        } else if let Some(e) = any.downcast_ref::<ViscousDamper>() {
            Some(Builtin::Viscous(e))
        } else if let Some(e) = any.downcast_ref::<FrictionPendulum>() {
            Some(Builtin::Pendulum(e))
        } else if let Some(e) = any.downcast_ref::<Polynomial>() {
            Some(Builtin::Polynomial(e))
        } else {
            any.downcast_ref::<Shifted>().map(Builtin::Shifted)
        }
    }

    /// [`Element::eval_path`] of the element, called directly.
    #[inline(always)]
    pub(crate) fn eval_path(
        self,
        (x, v, t): (&[f64], &[f64], f64),
        history: PathState<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        match self {
            Builtin::Bilinear(e) => e.eval_path(x, v, t, history, r, tangent),
            Builtin::Spring(e) => e.eval_path(x, v, t, history, r, tangent),
            Builtin::Gap(e) => e.eval_path(x, v, t, history, r, tangent),
            Builtin::Viscous(e) => e.eval_path(x, v, t, history, r, tangent),
            Builtin::Pendulum(e) => e.eval_path(x, v, t, history, r, tangent),
            Builtin::Polynomial(e) => e.eval_path(x, v, t, history, r, tangent),
            Builtin::Shifted(e) => e.eval_path(x, v, t, history, r, tangent),
        }
    }
}

/// How an evaluation calls its element, resolved once.
#[derive(Clone, Copy)]
pub(crate) enum Dispatch<'e> {
    /// Through the trait object.
    Dynamic,
    /// A built-in element, directly.
    Direct(Builtin<'e>),
    /// A built-in element with its linear part taken out, both directly.
    Shifted(&'e Shifted, Builtin<'e>),
}

impl<'e> Dispatch<'e> {
    /// How to call `element`.
    pub(crate) fn of(element: &'e dyn Element) -> Self {
        match Builtin::of(element) {
            None => Dispatch::Dynamic,
            Some(Builtin::Shifted(s)) => match Builtin::of(s.inner()) {
                Some(Builtin::Shifted(_)) | None => Dispatch::Dynamic,
                Some(inner) => Dispatch::Shifted(s, inner),
            },
            Some(b) => Dispatch::Direct(b),
        }
    }

    /// [`Element::eval_path`] of `element` (the one this dispatch was resolved for).
    #[inline(always)]
    pub(crate) fn eval_path(
        self,
        element: &dyn Element,
        (x, v, t): (&[f64], &[f64], f64),
        history: PathState<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        match self {
            Dispatch::Dynamic => element.eval_path(x, v, t, history, r, tangent),
            Dispatch::Direct(b) => b.eval_path((x, v, t), history, r, tangent),
            Dispatch::Shifted(s, inner) => s.eval_path_over(inner, (x, v, t), history, r, tangent),
        }
    }
}
