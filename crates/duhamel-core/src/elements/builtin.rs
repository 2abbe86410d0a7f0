//! How an evaluation calls its element: a built-in element (the registry's [`Runtime`]) is
//! called through a `match`, each arm a direct call to that type's own methods, without
//! dynamic dispatch (a device's force is a few flops: two indirect calls per evaluation —
//! the element, and the element inside [`Shifted`], its linear part taken out — cost about
//! as much and keep the compiler from inlining it). The arithmetic is the same functions'
//! (results bit for bit); any other element keeps the dynamic call.

use super::element::{Element, PathState, Tangent};
use super::registry::Runtime;
use super::shifted::Shifted;
use crate::error::CoreError;

/// How an evaluation calls its element, resolved once.
#[derive(Clone, Copy)]
pub(crate) enum Dispatch<'e> {
    /// Through the trait object.
    Dynamic,
    /// A built-in element, directly.
    Direct(&'e Runtime),
    /// A built-in element with its linear part taken out, both directly.
    Shifted(&'e Shifted, &'e Runtime),
}

fn runtime(element: &dyn Element) -> Option<&Runtime> {
    element.as_any()?.downcast_ref::<Runtime>()
}

impl<'e> Dispatch<'e> {
    /// How to call `element`.
    pub(crate) fn of(element: &'e dyn Element) -> Self {
        if let Some(r) = runtime(element) {
            return Dispatch::Direct(r);
        }
        let shifted = element.as_any().and_then(|a| a.downcast_ref::<Shifted>());
        match shifted.and_then(|s| runtime(s.inner()).map(|r| (s, r))) {
            Some((s, inner)) => Dispatch::Shifted(s, inner),
            None => Dispatch::Dynamic,
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
            Dispatch::Direct(b) => b.eval_path(x, v, t, history, r, tangent),
            Dispatch::Shifted(s, inner) => s.eval_path_over(inner, (x, v, t), history, r, tangent),
        }
    }
}
