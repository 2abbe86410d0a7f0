//! Binding of the direct integrators (generalized-alpha family, cubic Hermite element).

use duhamel_core::direct::assembly::Matrix;
use duhamel_core::direct::{
    self, AlphaParams, DirectHistory, DirectProblem, Method, ScaledCoupling,
};
use duhamel_core::elements::{Element, Tangent};
use duhamel_core::linear::ModalForcing;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::nonlinear::parse_mass;
use crate::run::{finish_run, parse_loads, parse_speed, IntoDict, PyForcing};
use crate::{core_err, elements, vec_of};

impl IntoDict for DirectHistory {
    fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let d = PyDict::new(py);
        let (ns, no) = (self.t.len(), self.n_out);
        d.set_item("t", PyArray1::from_vec(py, self.t))?;
        for (key, values) in [("x", self.x), ("v", self.v), ("a", self.a)] {
            d.set_item(key, PyArray1::from_vec(py, values).reshape([ns, no])?)?;
        }
        Ok(d)
    }
}

/// Non-negative integers from a 1-D int64 array.
fn index_vec(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<usize>> {
    let arr = obj.cast::<PyArray1<i64>>().map_err(|_| {
        PyTypeError::new_err(format!("`{name}` must be a 1-D numpy array of int64"))
    })?;
    let ro = arr.readonly();
    ro.as_slice()?
        .iter()
        .map(|&i| {
            usize::try_from(i).map_err(|_| PyValueError::new_err(format!("`{name}` is negative")))
        })
        .collect()
}

/// `("dense", array (n, n))` or `("csr", n, indptr, indices, data)`.
fn parse_matrix(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Matrix> {
    let tup = obj
        .cast::<PyTuple>()
        .map_err(|_| PyTypeError::new_err(format!("`{name}` spec must be a tuple")))?;
    let kind: String = tup.get_item(0)?.extract()?;
    match kind.as_str() {
        "dense" => {
            let arr = tup.get_item(1)?;
            let arr = arr
                .cast::<PyArray2<f64>>()
                .map_err(|_| PyTypeError::new_err(format!("`{name}` must be a float64 matrix")))?;
            let shape = arr.shape().to_vec();
            if shape[0] != shape[1] {
                return Err(PyValueError::new_err(format!("`{name}` must be square")));
            }
            let ro = arr.readonly();
            Ok(Matrix::Dense {
                n: shape[0],
                data: ro.as_slice()?.to_vec(),
            })
        }
        "csr" => Ok(Matrix::Csr {
            n: tup.get_item(1)?.extract()?,
            indptr: index_vec(&tup.get_item(2)?, "indptr")?,
            indices: index_vec(&tup.get_item(3)?, "indices")?,
            data: vec_of(&tup.get_item(4)?, "data")?,
        }),
        other => Err(PyValueError::new_err(format!(
            "unknown matrix kind {other:?} for `{name}`"
        ))),
    }
}

fn parse_method(method: &Bound<'_, PyAny>) -> PyResult<Method> {
    let kind: String = method.get_item(0)?.extract()?;
    match kind.as_str() {
        "alpha" => Ok(Method::Alpha(AlphaParams {
            alpha_m: method.get_item(1)?.extract()?,
            alpha_f: method.get_item(2)?.extract()?,
            gamma: method.get_item(3)?.extract()?,
            beta: method.get_item(4)?.extract()?,
        })),
        "hermite" => Ok(Method::CubicHermite {
            points: method.get_item(1)?.extract()?,
        }),
        other => Err(PyValueError::new_err(format!("unknown method {other:?}"))),
    }
}

fn optional_matrix(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<Matrix>> {
    obj.map(|m| parse_matrix(m, name)).transpose()
}

/// Integrates the physical equations of motion directly; see `duhamel.solve`.
///
/// Matrices are `("dense", array)` or `("csr", n, indptr, indices, data)`; `method` is
/// `("alpha", alpha_m, alpha_f, gamma, beta)` or `("hermite", points)`; `a0` overrides the
/// initial acceleration (generalized-alpha methods only); `scaled` is a list of
/// `(K spec or None, C spec or None, speed law spec)` couplings scaled by a speed law.
/// Returns a dict with
/// `t` and time-major `x`, `v`, `a` for `out_dofs`, `error` (as `solve_linear`) and `stats`
/// (`newton_iterations`, `factorizations`).
#[pyfunction]
#[pyo3(signature = (m, k, x0, v0, loads, dt, n_steps, save_every, out_dofs, method, tol, max_iter, c=None, k_fixed=None, elements=None, mass=None, forcing=None, a0=None, scaled=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_direct<'py>(
    py: Python<'py>,
    m: &Bound<'py, PyAny>,
    k: &Bound<'py, PyAny>,
    x0: &Bound<'py, PyAny>,
    v0: &Bound<'py, PyAny>,
    loads: &Bound<'py, PyAny>,
    dt: f64,
    n_steps: usize,
    save_every: usize,
    out_dofs: &Bound<'py, PyAny>,
    method: &Bound<'py, PyAny>,
    tol: f64,
    max_iter: usize,
    c: Option<&Bound<'py, PyAny>>,
    k_fixed: Option<&Bound<'py, PyAny>>,
    elements: Option<&Bound<'py, PyAny>>,
    mass: Option<&Bound<'py, PyAny>>,
    forcing: Option<Py<PyAny>>,
    a0: Option<&Bound<'py, PyAny>>,
    scaled: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let m = parse_matrix(m, "M")?;
    let mut scaled_mats = Vec::new();
    if let Some(list) = scaled {
        for item in list.try_iter()? {
            let item = item?;
            let opt = |i: usize, name: &str| -> PyResult<Option<Matrix>> {
                let m = item.get_item(i)?;
                optional_matrix((!m.is_none()).then_some(&m), name)
            };
            scaled_mats.push((opt(0, "K")?, opt(1, "C")?, parse_speed(&item.get_item(2)?)?));
        }
    }
    let scaled: Vec<ScaledCoupling> = scaled_mats
        .iter()
        .map(|(k, c, law)| ScaledCoupling {
            k: k.as_ref(),
            c: c.as_ref(),
            law: *law,
        })
        .collect();
    let a0 = a0.map(|a| vec_of(a, "a0")).transpose()?;
    let k = parse_matrix(k, "K")?;
    let c = optional_matrix(c, "C")?;
    let k_fixed = optional_matrix(k_fixed, "K")?;
    let x0 = vec_of(x0, "x0")?;
    let v0 = vec_of(v0, "v0")?;
    let loads = parse_loads(loads)?;
    let out_dofs = index_vec(out_dofs, "dofs")?;
    let method = parse_method(method)?;
    let (boxed, python) = match elements {
        Some(e) => elements::parse(e)?,
        None => (Vec::new(), Vec::new()),
    };
    let refs: Vec<&dyn Element> = boxed.iter().map(|b| b.as_ref()).collect();
    let mass = mass.map(parse_mass).transpose()?;
    let mut py_forcing = PyForcing::physical(forcing, x0.len());
    let problem = DirectProblem {
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
        dt,
        n_steps,
        save_every,
        out_dofs: &out_dofs,
        method,
        tol,
        max_iter,
    };
    let result = py.detach(|| {
        let f = py_forcing.as_mut().map(|f| f as &mut dyn ModalForcing);
        direct::integrate(&problem, f)
    });
    finish_run(py, result, py_forcing, &python, |s, st| {
        st.set_item("newton_iterations", s.newton_iterations)?;
        st.set_item("factorizations", s.factorizations)
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
    let x = vec_of(x, "x")?;
    let v = vec_of(v, "v")?;
    let (boxed, python) = elements::parse(elements)?;
    // A failing Python element re-raises its own exception.
    let fail = |e: duhamel_core::CoreError| {
        python
            .iter()
            .find_map(|p| p.error.lock().unwrap_or_else(|x| x.into_inner()).take())
            .unwrap_or_else(|| core_err(e))
    };
    let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
    for e in &boxed {
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
}
