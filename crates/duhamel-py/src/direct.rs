//! Binding of the direct integrators (generalized-alpha family, cubic Hermite element).

use duhamel_core::direct::assembly::Matrix as CoreMatrix;
use duhamel_core::direct::{
    self, AlphaParams, DirectProblem, Method as CoreMethod, ScaledCoupling,
};
use duhamel_core::elements::Tangent;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::arrays::{attr, index_vec, vec_of};
use crate::driver::run;
use crate::elements;
use crate::error::core_err;
use crate::guard::guarded;
use crate::history::RunResult;
use crate::loads::{loads_of, PyForcing};
use crate::mass::mass_of;
use crate::speed::speed_of;

/// A dense or CSR sparse matrix for the direct integrators.
#[pyclass(frozen, name = "Matrix", module = "duhamel._core")]
pub(crate) struct Matrix(CoreMatrix);

#[pymethods]
impl Matrix {
    /// A dense square float64 matrix.
    #[staticmethod]
    fn dense(a: &Bound<'_, PyAny>) -> PyResult<Self> {
        let arr = a
            .cast::<PyArray2<f64>>()
            .map_err(|_| PyTypeError::new_err("a dense matrix must be a float64 2-D array"))?;
        let shape = arr.shape().to_vec();
        if shape[0] != shape[1] {
            return Err(PyValueError::new_err("a matrix must be square"));
        }
        let ro = arr.readonly();
        // `as_slice` also accepts Fortran order, whose data read row-major is the transpose.
        if !ro.is_c_contiguous() {
            return Err(PyValueError::new_err(
                "a dense matrix must be C-contiguous (pass numpy.ascontiguousarray(a))",
            ));
        }
        Ok(Matrix(CoreMatrix::Dense {
            n: shape[0],
            data: ro.as_slice()?.to_vec(),
        }))
    }

    /// An `n x n` CSR matrix (int64 `indptr`, `indices`, float64 `data`).
    #[staticmethod]
    fn csr(
        n: usize,
        indptr: &Bound<'_, PyAny>,
        indices: &Bound<'_, PyAny>,
        data: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        Ok(Matrix(CoreMatrix::Csr {
            n,
            indptr: index_vec(indptr, "indptr")?,
            indices: index_vec(indices, "indices")?,
            data: vec_of(data, "data")?,
        }))
    }
}

/// A direct integration method.
#[pyclass(frozen, name = "Method", module = "duhamel._core")]
pub(crate) struct Method(CoreMethod);

#[pymethods]
impl Method {
    /// The generalized-alpha family in Chung and Hulbert's convention.
    #[staticmethod]
    fn alpha(alpha_m: f64, alpha_f: f64, gamma: f64, beta: f64) -> Self {
        Method(CoreMethod::Alpha(AlphaParams {
            alpha_m,
            alpha_f,
            gamma,
            beta,
        }))
    }

    /// The C1 cubic Hermite time element with `points` Gauss points.
    #[staticmethod]
    fn hermite(points: usize) -> Self {
        Method(CoreMethod::CubicHermite { points })
    }
}

/// The matrix of attribute `name` (a `_core.Matrix`), or None.
fn matrix_of(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<CoreMatrix>> {
    let m = obj.getattr(name)?;
    if m.is_none() {
        return Ok(None);
    }
    Ok(Some(m.cast::<Matrix>()?.get().0.clone()))
}

/// Owned couplings scaled by a speed law.
type Scaled = (
    Option<CoreMatrix>,
    Option<CoreMatrix>,
    duhamel_core::speed::SpeedLaw,
);

/// Integrates the physical equations of motion directly; see `duhamel.solve`.
///
/// `problem` has `m`, `k`, `c`, `k_fixed` (`_core.Matrix` or None), `scaled` (objects with
/// `k`, `c` matrices or None and a `law`), `elements`, `loads` (objects with physical
/// `pattern` and `time`), `mass`, `x0`, `v0`, `a0` (or None: from the equation of motion),
/// `t0`, `dt`, `n_steps`, `save_every`, `out_dofs` (int64), `method` (a `_core.Method`),
/// `tol` and `max_iter`. `forcing` is None or a Python function of time returning physical
/// loads; `progress` as for `solve_uncoupled`.
#[pyfunction]
pub(crate) fn solve_direct(
    py: Python<'_>,
    problem: &Bound<'_, PyAny>,
    forcing: &Bound<'_, PyAny>,
    progress: &Bound<'_, PyAny>,
) -> PyResult<RunResult> {
    guarded(|| {
        let required = |name: &str| -> PyResult<CoreMatrix> {
            matrix_of(problem, name)?.ok_or_else(|| {
                PyValueError::new_err(format!("`{}` is required", name.to_uppercase()))
            })
        };
        let m = required("m")?;
        let k = required("k")?;
        let c = matrix_of(problem, "c")?;
        let k_fixed = matrix_of(problem, "k_fixed")?;
        let mut owned: Vec<Scaled> = Vec::new();
        for item in problem.getattr("scaled")?.try_iter()? {
            let item = item?;
            owned.push((
                matrix_of(&item, "k")?,
                matrix_of(&item, "c")?,
                speed_of(&item.getattr("law")?)?,
            ));
        }
        let scaled: Vec<ScaledCoupling<CoreMatrix>> = owned
            .iter()
            .map(|(k, c, law)| ScaledCoupling {
                k: k.as_ref(),
                c: c.as_ref(),
                law: *law,
            })
            .collect();
        let a0 = problem.getattr("a0")?;
        let a0 = if a0.is_none() {
            None
        } else {
            Some(vec_of(&a0, "a0")?)
        };
        let x0 = vec_of(&problem.getattr("x0")?, "x0")?;
        let v0 = vec_of(&problem.getattr("v0")?, "v0")?;
        let loads = loads_of(&problem.getattr("loads")?)?;
        let out_dofs = index_vec(&problem.getattr("out_dofs")?, "dofs")?;
        let method = problem.getattr("method")?.cast::<Method>()?.get().0;
        let built = elements::build(py, &problem.getattr("elements")?)?;
        let refs = built.refs();
        let mass = mass_of(&problem.getattr("mass")?)?;
        let p = DirectProblem {
            m: &m,
            k: &k,
            c: c.as_ref(),
            k_fixed: k_fixed.as_ref(),
            scaled: &scaled,
            elements: &refs,
            loads: &loads,
            mass: mass.as_ref(),
            x0: &x0,
            v0: &v0,
            a0: a0.as_deref(),
            t0: attr(problem, "t0")?,
            dt: attr(problem, "dt")?,
            n_steps: attr(problem, "n_steps")?,
            save_every: attr(problem, "save_every")?,
            out_dofs: &out_dofs,
            method,
            tol: attr(problem, "tol")?,
            max_iter: attr(problem, "max_iter")?,
        };
        let forcing = PyForcing::physical(forcing, x0.len());
        run(py, forcing, Some(&built), progress, |f, control| {
            direct::integrate(&p, f, control)
        })
    })
}

/// The elements' stiffness `dr/dx` at the state `(x, v)` and time `t`, as COO triplets
/// `(rows, cols, values)` (duplicates to be summed): for the central difference method's
/// stability check.
#[pyfunction]
pub(crate) fn element_stiffness<'py>(
    py: Python<'py>,
    elements: &Bound<'py, PyAny>,
    x: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    t: f64,
) -> PyResult<Bound<'py, PyTuple>> {
    guarded(|| {
        let x = vec_of(x, "x")?;
        let v = vec_of(v, "v")?;
        if v.len() != x.len() {
            return Err(PyValueError::new_err(format!(
                "`v` has length {}, expected {} (the length of `x`)",
                v.len(),
                x.len()
            )));
        }
        let built = elements::build(py, elements)?;
        // A failing Python element re-raises its own exception.
        let fail = |e: duhamel_core::CoreError| built.take_error().unwrap_or_else(|| core_err(e));
        let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
        for e in &built.elements {
            let dofs = e.dofs().to_vec();
            if let Some(&d) = dofs.iter().find(|&&d| d >= x.len()) {
                return Err(PyValueError::new_err(format!(
                    "`dof` {d} of an element is not a degree of freedom (n_dof = {})",
                    x.len()
                )));
            }
            let nl = dofs.len();
            let xl: Vec<f64> = dofs.iter().map(|&d| x[d]).collect();
            let vl: Vec<f64> = dofs.iter().map(|&d| v[d]).collect();
            let mut r = vec![0.0; nl];
            let mut kx = vec![0.0; nl * nl];
            let mut cv = vec![0.0; nl * nl];
            if e.has_tangent() {
                let tan = Tangent {
                    kx: &mut kx,
                    cv: &mut cv,
                };
                e.eval(&xl, &vl, t, &mut r, Some(tan)).map_err(fail)?;
            } else {
                // Central differences in x only.
                for j in 0..nl {
                    let hstep = f64::EPSILON.cbrt() * (1.0 + xl[j].abs());
                    let mut rp = vec![0.0; nl];
                    let mut rm = vec![0.0; nl];
                    let mut xp = xl.clone();
                    xp[j] += hstep;
                    e.eval(&xp, &vl, t, &mut rp, None).map_err(fail)?;
                    xp[j] = xl[j] - hstep;
                    e.eval(&xp, &vl, t, &mut rm, None).map_err(fail)?;
                    for i in 0..nl {
                        kx[i * nl + j] = (rp[i] - rm[i]) / (2.0 * hstep);
                    }
                }
            }
            for a in 0..nl {
                for b in 0..nl {
                    rows.push(dofs[a] as i64);
                    cols.push(dofs[b] as i64);
                    vals.push(kx[a * nl + b]);
                }
            }
        }
        PyTuple::new(
            py,
            [
                PyArray1::from_vec(py, rows).into_any(),
                PyArray1::from_vec(py, cols).into_any(),
                PyArray1::from_vec(py, vals).into_any(),
            ],
        )
    })
}
