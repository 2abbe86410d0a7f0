//! The error estimate of semi-analytic runs (`duhamel._engine.accuracy`): the per-mode
//! bounds from a run's saved modal history and the estimates at the saved dofs and at the
//! elements, computed in the core (`duhamel_core::accuracy`) on views of the run's arrays.
//! [`Estimator`] holds what a prepared model's runs share (the modes, the magnitudes of
//! the mode shapes at the estimated quantities, the parabola moments per step), made once;
//! a run's estimate is then one call that reads the [`RunResult`] itself.

use std::sync::Mutex;

use duhamel_core::accuracy::{self, ModalRun, Quantity};
use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::arrays::f64_array1;
use crate::guard::guarded;
use crate::history::RunResult;

/// A read-only C-contiguous float64 matrix view of `obj`, or an error naming `name`.
fn matrix<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<PyReadonlyArray2<'py, f64>> {
    let arr = obj.cast::<PyArray2<f64>>().map_err(|_| {
        PyTypeError::new_err(format!("`{name}` must be a 2-D numpy array of float64"))
    })?;
    let ro = arr.readonly();
    if !ro.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "`{name}` must be C-contiguous (pass numpy.ascontiguousarray({name}))"
        )));
    }
    Ok(ro)
}

/// A C-contiguous view of a run's array (the core made it so).
fn view<'py>(py: Python<'py>, a: &Py<PyArray2<f64>>) -> PyResult<PyReadonlyArray2<'py, f64>> {
    let ro = a.bind(py).readonly();
    if !ro.is_c_contiguous() {
        return Err(PyValueError::new_err("a run's history is not C-contiguous"));
    }
    Ok(ro)
}

fn shape_error(name: &str, want: String, got: &[usize]) -> PyErr {
    PyValueError::new_err(format!("`{name}` must have shape {want}, got {got:?}"))
}

/// Per mode, the largest accumulated bound of the modal displacement error over a run:
/// `pseudo` and `q` the saved modal pseudo-force and displacements `(rows, n)`, `omega` and
/// `c` per mode, `step` the run's stepping `(h, k, span)`: the internal step, the internal
/// steps between saved instants and the run's duration (they travel together, as in
/// [`bounds_of`]).
#[pyfunction]
pub(crate) fn mode_bounds<'py>(
    py: Python<'py>,
    pseudo: &Bound<'py, PyAny>,
    q: &Bound<'py, PyAny>,
    omega: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    step: (f64, usize, f64),
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (h, k, _) = step;
    guarded(|| {
        let (pseudo, q) = (matrix(pseudo, "pseudo")?, matrix(q, "q")?);
        let (omega, c) = (f64_array1(omega, "omega")?, f64_array1(c, "c")?);
        let (omega, c) = (omega.as_slice()?, c.as_slice()?);
        if c.len() != omega.len() {
            return Err(shape_error("c", format!("({},)", omega.len()), &[c.len()]));
        }
        check_step(h, k)?;
        let moments = accuracy::parabola_moments(omega, c, h);
        let bounds = bounds_of(py, &pseudo, &q, omega, c, &moments, step)?;
        Ok(PyArray1::from_vec(py, bounds))
    })
}

/// Per mode, the end state `(q, v)` of the parabola `4 s (1 - s)` over one step `h` from
/// rest, `(n, 2)` (`duhamel_core::accuracy::parabola_moments`).
#[pyfunction]
pub(crate) fn parabola_moments<'py>(
    py: Python<'py>,
    omega: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    h: f64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    guarded(|| {
        let (omega, c) = (f64_array1(omega, "omega")?, f64_array1(c, "c")?);
        let (omega, c) = (omega.as_slice()?, c.as_slice()?);
        if c.len() != omega.len() {
            return Err(shape_error("c", format!("({},)", omega.len()), &[c.len()]));
        }
        check_step(h, 1)?;
        let n = omega.len();
        PyArray1::from_vec(py, accuracy::parabola_moments(omega, c, h)).reshape([n, 2])
    })
}

/// Per row of `x` `(n, len)`, the largest value of the recurrence
/// `acc_{i+1} = decay acc_i + x_i` from 0 (bounded as `duhamel_core::accuracy::decaying_max`
/// says).
#[pyfunction]
pub(crate) fn decaying_max<'py>(
    py: Python<'py>,
    x: &Bound<'py, PyAny>,
    decay: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    guarded(|| {
        let x = matrix(x, "x")?;
        let decay = f64_array1(decay, "decay")?;
        if x.shape()[0] != decay.len() {
            return Err(shape_error(
                "x",
                format!("({}, len)", decay.len()),
                x.shape(),
            ));
        }
        let len = x.shape()[1];
        let best = accuracy::decaying_max(x.as_slice()?, len, decay.as_slice()?);
        Ok(PyArray1::from_vec(py, best))
    })
}

/// Per row of `g` `(n, len)`, the output of the oscillator of that row of `steps`
/// `(n, 9)` from rest under the row linear between samples
/// (`duhamel_core::truncation::hold_response`): the basis-truncation estimate's
/// left-out modes.
#[pyfunction]
pub(crate) fn hold_response<'py>(
    py: Python<'py>,
    steps: &Bound<'py, PyAny>,
    g: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    use duhamel_core::truncation::{self, STEP_VALUES};
    guarded(|| {
        let (steps, g) = (matrix(steps, "steps")?, matrix(g, "g")?);
        let n = g.shape()[0];
        if steps.shape() != [n, STEP_VALUES] {
            return Err(shape_error(
                "steps",
                format!("({n}, {STEP_VALUES})"),
                steps.shape(),
            ));
        }
        let len = g.shape()[1];
        let (steps, g) = (steps.as_slice()?, g.as_slice()?);
        // a pass over the whole history: other Python threads (solve_many) run meanwhile
        let y = py.detach(|| truncation::hold_response(steps, g, len));
        PyArray1::from_vec(py, y).reshape([n, len])
    })
}

fn check_step(h: f64, k: usize) -> PyResult<()> {
    if !(h.is_finite() && h > 0.0) || k == 0 {
        return Err(PyValueError::new_err(format!(
            "`h` must be positive and finite and `k` at least 1, got {h} and {k}"
        )));
    }
    Ok(())
}

/// [`accuracy::mode_bounds`] of checked views, with the GIL released (a pass over the
/// whole history: other Python threads, as `solve_many`'s, run meanwhile); `step` is
/// `(h, k, span)`.
fn bounds_of(
    py: Python<'_>,
    pseudo: &PyReadonlyArray2<'_, f64>,
    q: &PyReadonlyArray2<'_, f64>,
    omega: &[f64],
    c: &[f64],
    moments: &[f64],
    step: (f64, usize, f64),
) -> PyResult<Vec<f64>> {
    let n = omega.len();
    if pseudo.shape()[1] != n {
        return Err(shape_error(
            "pseudo",
            format!("(rows, {n})"),
            pseudo.shape(),
        ));
    }
    if q.shape() != pseudo.shape() {
        return Err(shape_error("q", format!("{:?}", pseudo.shape()), q.shape()));
    }
    let (h, k, span) = step;
    let run = ModalRun {
        pseudo: pseudo.as_slice()?,
        q: q.as_slice()?,
        rows: pseudo.shape()[0],
        omega,
        c,
        moments,
        h,
        k,
        span,
    };
    Ok(py.detach(|| accuracy::mode_bounds(&run)))
}

/// [`accuracy::row_errors`] of checked views, with the GIL released: `modes` is `(omega,
/// c)`, `signed` the `(g, n)` row-major shapes and `g`, `step` `(h, k, span)`.
fn errors_of(
    py: Python<'_>,
    pseudo: &PyReadonlyArray2<'_, f64>,
    q: &PyReadonlyArray2<'_, f64>,
    modes: (&[f64], &[f64]),
    moments: &[f64],
    signed: (&[f64], usize),
    step: (f64, usize, f64),
) -> PyResult<Vec<f64>> {
    let (omega, c) = modes;
    let n = omega.len();
    if pseudo.shape()[1] != n {
        return Err(shape_error(
            "pseudo",
            format!("(rows, {n})"),
            pseudo.shape(),
        ));
    }
    if q.shape() != pseudo.shape() {
        return Err(shape_error("q", format!("{:?}", pseudo.shape()), q.shape()));
    }
    let (shapes, g) = signed;
    if shapes.len() != g * n {
        return Err(shape_error(
            "signed",
            format!("({g}, {n})"),
            &[shapes.len()],
        ));
    }
    let (h, k, span) = step;
    let run = ModalRun {
        pseudo: pseudo.as_slice()?,
        q: q.as_slice()?,
        rows: pseudo.shape()[0],
        omega,
        c,
        moments,
        h,
        k,
        span,
    };
    Ok(py.detach(|| accuracy::row_errors(&run, shapes, g)))
}

/// The run's error at each row of `signed` (`(g, n)`: mode shapes with their signs at the
/// quantities' components) from its modal history `pseudo` and `q` (`(rows, n)`), the modes
/// `omega`, `c` and `step = (h, k, span)` (`duhamel_core::accuracy::row_errors`).
#[pyfunction]
pub(crate) fn row_errors<'py>(
    py: Python<'py>,
    pseudo: &Bound<'py, PyAny>,
    q: &Bound<'py, PyAny>,
    omega: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    signed: &Bound<'py, PyAny>,
    step: (f64, usize, f64),
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    guarded(|| {
        check_step(step.0, step.1)?;
        let omega = f64_array1(omega, "omega")?;
        let c = f64_array1(c, "c")?;
        let (omega, c) = (omega.as_slice()?, c.as_slice()?);
        if c.len() != omega.len() {
            return Err(shape_error("c", format!("({},)", omega.len()), &[c.len()]));
        }
        let (pseudo, q, signed) = (
            matrix(pseudo, "pseudo")?,
            matrix(q, "q")?,
            matrix(signed, "signed")?,
        );
        let g = signed.shape()[0];
        let moments = accuracy::parabola_moments(omega, c, step.0);
        let shapes = (signed.as_slice()?, g);
        let out = errors_of(py, &pseudo, &q, (omega, c), &moments, shapes, step)?;
        Ok(PyArray1::from_vec(py, out))
    })
}

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
                    let errors = errors_of(py, &pseudo, &q, modes, &moments, signed, step)?;
                    let bounds = bounds_of(py, &pseudo, &q, modes.0, modes.1, &moments, step)?;
                    (errors, accuracy::bound_rows(&bounds, &self.signed))
                }
                _ => (vec![0.0; g], vec![0.0; g]),
            };
            let both = |quantity: &Quantity, values: &[f64], width: usize| {
                (
                    accuracy::relative_rows(&errors, quantity, values, width),
                    accuracy::relative_rows(&bounds, quantity, values, width),
                )
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
