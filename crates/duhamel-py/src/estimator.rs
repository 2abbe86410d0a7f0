//! [`Estimator`]: what a prepared model's runs share for their error estimate (the modes,
//! the mode shapes at the estimated quantities, the parabola moments per step), made once;
//! a run's estimate and bound are then one call that reads the [`RunResult`] itself
//! (`duhamel._engine.accuracy`, docs/accuracy.md).

use std::sync::Mutex;

use duhamel_core::accuracy::{self, Quantity};
use numpy::{PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::accuracy::{check_step, errors_of, matrix, shape_error, view};
use crate::arrays::f64_array1;
use crate::guard::guarded;
use crate::history::RunResult;

/// One element as the estimate sees it: its dofs and whether it is a two-node element
/// (`j` given).
type ElementDofs = (Vec<usize>, bool);

/// The error estimate of a prepared modal model's runs (see the module docstring): its modes
/// (`omega`, `c`), the magnitudes of its mode shapes `phi` (`(n_dof, n)`) at the saved dofs
/// (`dofs`; None: not estimated) and along the elements' deformations (`elements`, per
/// element its dofs and whether it is a two-node element; None, or an element whose dofs
/// are not rows of `phi`: the elements not estimated).
#[pyclass(frozen, name = "Estimator", module = "duhamel._core")]
pub(crate) struct Estimator {
    omega: Vec<f64>,
    c: Vec<f64>,
    /// `(g, n)` row-major: the mode shapes (with their signs) at the saved dofs, then along
    /// the elements' deformations.
    signed: Vec<f64>,

    dofs: Option<Quantity>,
    /// Per element, its weight rows and whether it is a two-node element.
    elements: Option<Vec<(std::ops::Range<usize>, bool)>>,
    /// The parabola moments of the last internal steps.
    moments: Mutex<Vec<(f64, Vec<f64>)>>,
}

#[pymethods]
impl Estimator {
    #[new]
    #[pyo3(signature = (omega, c, phi, dofs, elements))]
    fn new(
        omega: &Bound<'_, PyAny>,
        c: &Bound<'_, PyAny>,
        phi: &Bound<'_, PyAny>,
        dofs: Option<&Bound<'_, PyAny>>,
        elements: Option<Vec<ElementDofs>>,
    ) -> PyResult<Self> {
        let omega = f64_array1(omega, "omega")?.as_slice()?.to_vec();
        let c = f64_array1(c, "c")?.as_slice()?.to_vec();
        let n = omega.len();
        if c.len() != n {
            return Err(shape_error("c", format!("({n},)"), &[c.len()]));
        }
        let phi = matrix(phi, "phi")?;
        if phi.shape()[1] != n {
            return Err(shape_error("phi", format!("(n_dof, {n})"), phi.shape()));
        }
        let n_dof = phi.shape()[0];
        let phi = phi.as_slice()?;
        let row = |d: usize| &phi[d * n..(d + 1) * n];
        let mut weights = Vec::new();
        let dofs = match dofs {
            Some(dofs) => {
                let dofs = crate::arrays::index_vec(dofs, "dofs")?;
                if dofs.iter().any(|&d| d >= n_dof) {
                    return Err(PyValueError::new_err(format!(
                        "`dofs` must be below the {n_dof} rows of `phi`"
                    )));
                }
                for &d in &dofs {
                    weights.extend_from_slice(row(d));
                }
                Some(Quantity {
                    rows: 0..dofs.len(),
                    columns: (0..dofs.len()).map(|a| (a, None)).collect(),
                })
            }
            None => None,
        };
        let mut at = dofs.as_ref().map_or(0, |d| d.rows.end);
        let reachable = |e: &ElementDofs| !e.0.is_empty() && e.0.iter().all(|&d| d < n_dof);
        let elements = match elements {
            Some(list) if list.iter().all(reachable) => {
                let mut out = Vec::with_capacity(list.len());
                for (element_dofs, two_node) in list {
                    if element_dofs.len() == 2 && two_node {
                        let (i, j) = (row(element_dofs[0]), row(element_dofs[1]));
                        weights.extend(i.iter().zip(j).map(|(a, b)| a - b));
                        out.push((at..at + 1, true));
                        at += 1;
                    } else {
                        for &d in &element_dofs {
                            weights.extend_from_slice(row(d));
                        }
                        out.push((at..at + element_dofs.len(), two_node));
                        at += element_dofs.len();
                    }
                }
                Some(out)
            }
            _ => None,
        };
        Ok(Self {
            omega,
            c,
            signed: weights,
            dofs,
            elements,
            moments: Mutex::new(Vec::new()),
        })
    }

    /// `(dofs, elements, dofs_bound, elements_bound)`: the estimate at the saved dofs (None
    /// where not estimated) and per element (empty where not estimated) of a whole
    /// successful run `result` of internal steps `h`, `k` of them between saved instants, and
    /// the same as bounds (the local errors added in magnitude); `x` its saved dofs'
    /// response; `elements`: its element histories are kept. None when an estimate is not a
    /// number (a history that is not finite).
    #[pyo3(signature = (result, h, k, x, elements))]
    fn estimate(
        &self,
        py: Python<'_>,
        result: &Bound<'_, RunResult>,
        h: f64,
        k: usize,
        x: &Bound<'_, PyAny>,
        elements: bool,
    ) -> PyResult<Option<Estimates>> {
        guarded(|| {
            check_step(h, k)?;
            let run = result.get().estimated();
            let t: PyReadonlyArray1<'_, f64> = run.t.bind(py).readonly();
            let t = t.as_slice()?;
            let span = match (t.first(), t.last()) {
                (Some(a), Some(b)) => b - a,
                _ => 0.0,
            };
            let n = self.omega.len();
            let g = self.signed.len() / n.max(1);
            let (errors, bounds) = match (run.pseudo, run.q) {
                (Some(pseudo), Some(q)) => {
                    let moments = self.moments_of(h);
                    let (pseudo, q) = (view(py, pseudo)?, view(py, q)?);
                    let step = (h, k, span);
                    let modes = (self.omega.as_slice(), self.c.as_slice());
                    let signed = (self.signed.as_slice(), g);
                    errors_of(py, &pseudo, &q, modes, &moments, signed, step)?
                }
                _ => (vec![0.0; g], vec![0.0; g]),
            };
            let both = |quantity: &Quantity, values: &[f64], width: usize| {
                accuracy::relative_both(&errors, &bounds, quantity, values, width)
            };
            let x = matrix(x, "x")?;
            let dofs = match &self.dofs {
                Some(quantity) => {
                    let width = x.shape()[1];
                    if quantity.columns.len() != width {
                        return Err(shape_error(
                            "x",
                            format!("(rows, {})", quantity.columns.len()),
                            x.shape(),
                        ));
                    }
                    Some(both(quantity, x.as_slice()?, width))
                }
                None => None,
            };
            let mut per_element = Vec::new();
            let histories = match (&self.elements, run.element_x, run.element_widths) {
                (Some(e), Some(ex), Some(w))
                    if elements && run.element_force && w.len() == e.len() =>
                {
                    Some((e, ex, w))
                }
                _ => None,
            };
            if let Some((quantities, history, widths)) = histories {
                let history = view(py, history)?;
                let width = history.shape()[1];
                if widths.iter().sum::<usize>() != width {
                    return Err(PyValueError::new_err(
                        "a run's element history does not match its widths",
                    ));
                }
                let values = history.as_slice()?;
                let mut column = 0;
                for ((rows, two_node), &w) in quantities.iter().zip(widths) {
                    // the history's deformation: x_i - x_j of a two-node element, else its
                    // local displacements
                    let columns = if w == 2 && *two_node {
                        vec![(column, Some(column + 1))]
                    } else {
                        (column..column + w).map(|a| (a, None)).collect()
                    };
                    let quantity = Quantity {
                        rows: rows.clone(),
                        columns,
                    };
                    per_element.push(both(&quantity, values, width));
                    column += w;
                }
            }
            let nan = |e: &(f64, f64)| e.0.is_nan() || e.1.is_nan();
            if dofs.as_ref().is_some_and(nan) || per_element.iter().any(nan) {
                return Ok(None);
            }
            let (elements, element_bounds) = per_element.into_iter().unzip();
            Ok(Some((
                dofs.map(|d| d.0),
                elements,
                dofs.map(|d| d.1),
                element_bounds,
            )))
        })
    }
}

/// What [`Estimator::estimate`] returns: the estimates at the saved dofs and per element,
/// then the bounds.
type Estimates = (Option<f64>, Vec<f64>, Option<f64>, Vec<f64>);

impl Estimator {
    /// The parabola moments over the internal step `h`, made once per step.
    fn moments_of(&self, h: f64) -> Vec<f64> {
        let mut kept = self.moments.lock().unwrap_or_else(|p| p.into_inner());
        if let Some((_, m)) = kept.iter().find(|(step, _)| *step == h) {
            return m.clone();
        }
        let m = accuracy::parabola_moments(&self.omega, &self.c, h);
        if kept.len() >= 8 {
            kept.remove(0);
        }
        kept.push((h, m.clone()));
        m
    }
}
