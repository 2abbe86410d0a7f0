//! An element driven through a history of local states, as OpenSees' `setTrialStrain` and
//! `commitState` drive a material: at each instant the element is evaluated at the state
//! (force and tangents) and its internal variables committed there.

use super::element::Element;
use super::evaluation::Evaluation;
use crate::error::CoreError;

/// What a drive gives at each instant: the local force (`n_local`) and the tangents
/// `dr/dx`, `dr/dx'` (row-major `n_local x n_local` each).
pub struct Driven {
    pub force: Vec<f64>,
    pub kx: Vec<f64>,
    pub cv: Vec<f64>,
}

/// Drives `element` from its virgin state through the local displacements `x` and
/// velocities `v` (`n` rows of the element's `n_local` dofs, row-major) at the times `t`
/// (`n`), committing after each row. A failure names the row it happened at (its time).
pub fn drive(element: &dyn Element, x: &[f64], v: &[f64], t: &[f64]) -> Result<Driven, CoreError> {
    let nl = element.dofs().len();
    let n = t.len();
    if x.len() != n * nl || v.len() != n * nl {
        return Err(CoreError::InvalidInput {
            name: "deformation",
            problem: format!(
                "must hold {n} rows of the element's {nl} local dofs, got {} and {} values",
                x.len(),
                v.len()
            ),
        });
    }
    let mut eval = Evaluation::new(element);
    let t0 = t.first().copied().unwrap_or(0.0);
    eval.start(t0);
    let mut out = Driven {
        force: Vec::with_capacity(n * nl),
        kx: Vec::with_capacity(n * nl * nl),
        cv: Vec::with_capacity(n * nl * nl),
    };
    for (k, &tk) in t.iter().enumerate() {
        eval.x.copy_from_slice(&x[k * nl..(k + 1) * nl]);
        eval.v.copy_from_slice(&v[k * nl..(k + 1) * nl]);
        eval.evaluate(tk, true)?;
        out.force.extend_from_slice(&eval.r);
        out.kx.extend_from_slice(&eval.kx);
        out.cv.extend_from_slice(&eval.cv);
        eval.commit(tk)?;
    }
    Ok(out)
}
