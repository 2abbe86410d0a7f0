//! Binding of the direct integrators (generalized-alpha family, cubic Hermite element).

use duhamel_core::direct::assembly::Matrix as CoreMatrix;
use duhamel_core::direct::{
    self, AlphaParams, DirectProblem, Method as CoreMethod, ScaledCoupling as CoreScaled,
};
use duhamel_core::elements::Tangent;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::arrays::{index_vec, vec_of};
use crate::driver::run as run_with;
use crate::element_build;
use crate::element_type::Element as ElementSpec;
use crate::error::core_err;
use crate::guard::guarded;
use crate::history::RunResult;
use crate::loads::{owned_loads, Load, PyForcing};
use crate::mass::Mass;
use crate::problem::{EnergySpec, Grid};
use crate::speed::SpeedLaw;

/// A dense or CSR sparse matrix for the direct integrators.
#[pyclass(frozen, name = "Matrix", module = "duhamel._core")]
pub(crate) struct Matrix(pub(crate) CoreMatrix);

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
pub(crate) struct Method(pub(crate) CoreMethod);

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

/// Matrices multiplied by a speed law `s(t)`: the force `s(t) (K x + C x')` (physical, direct
/// integrators) or the modal pseudo-force `-s(t) (K q + C q')` (the gyroscopic `omega(t) G`
/// of a run-up).
#[pyclass(frozen, name = "ScaledCoupling", module = "duhamel._core")]
pub(crate) struct ScaledCoupling {
    pub(crate) k: Option<Py<Matrix>>,
    pub(crate) c: Option<Py<Matrix>>,
    pub(crate) law: duhamel_core::speed::SpeedLaw,
}

#[pymethods]
impl ScaledCoupling {
    #[new]
    #[pyo3(signature = (k, c, law))]
    fn new(k: Option<Py<Matrix>>, c: Option<Py<Matrix>>, law: &SpeedLaw) -> Self {
        ScaledCoupling { k, c, law: law.0 }
    }
}

/// The physical matrices of a direct run: mass `m` (constant part of `M(t)`), stiffness `k`
/// (scaled with the mass law when the law says so), damping `c`, stiffness `k_fixed` that
/// never scales (linear couplings), and couplings `scaled` by a speed law.
#[pyclass(frozen, name = "Matrices", module = "duhamel._core")]
pub(crate) struct Matrices {
    m: Py<Matrix>,
    k: Py<Matrix>,
    c: Option<Py<Matrix>>,
    k_fixed: Option<Py<Matrix>>,
    scaled: Vec<Py<ScaledCoupling>>,
}

#[pymethods]
impl Matrices {
    #[new]
    #[pyo3(signature = (m, k, c=None, k_fixed=None, scaled=Vec::new()))]
    fn new(
        m: Py<Matrix>,
        k: Py<Matrix>,
        c: Option<Py<Matrix>>,
        k_fixed: Option<Py<Matrix>>,
        scaled: Vec<Py<ScaledCoupling>>,
    ) -> Self {
        Matrices {
            m,
            k,
            c,
            k_fixed,
            scaled,
        }
    }
}

/// A model for the direct integrators: its `matrices`, force `elements`, `mass` law (None:
/// constant), `method`, and the Newton `tol` and `max_iter` of implicit steps.
#[pyclass(frozen, name = "DirectModel", module = "duhamel._core")]
pub(crate) struct DirectModel {
    matrices: Py<Matrices>,
    elements: Vec<Py<ElementSpec>>,
    mass: Option<Py<Mass>>,
    method: CoreMethod,
    tol: f64,
    max_iter: usize,
}

/// One direct run: its grid, initial displacements `x0` and velocities `v0`, optionally the
/// initial acceleration `a0` (generalized-alpha; None: from the equation of motion), and the
/// dofs whose history is kept (`out_dofs`, int64); the energy integrals to accumulate,
/// `energy` (an `EnergySpec` without damping matrix).
#[pyclass(frozen, name = "DirectRun", module = "duhamel._core")]
pub(crate) struct DirectRun {
    grid: Grid,
    x0: Vec<f64>,
    v0: Vec<f64>,
    a0: Option<Vec<f64>>,
    out_dofs: Vec<usize>,
    energy: Option<EnergySpec>,
}

#[pymethods]
impl DirectRun {
    #[new]
    #[pyo3(signature = (grid, x0, v0, out_dofs, a0=None, energy=None))]
    fn new(
        grid: &Grid,
        x0: &Bound<'_, PyAny>,
        v0: &Bound<'_, PyAny>,
        out_dofs: &Bound<'_, PyAny>,
        a0: Option<&Bound<'_, PyAny>>,
        energy: Option<PyRef<'_, EnergySpec>>,
    ) -> PyResult<Self> {
        Ok(DirectRun {
            grid: *grid,
            x0: vec_of(x0, "x0")?,
            v0: vec_of(v0, "v0")?,
            a0: a0.map(|a| vec_of(a, "a0")).transpose()?,
            out_dofs: index_vec(out_dofs, "dofs")?,
            energy: energy.map(|e| e.clone()),
        })
    }
}

#[pymethods]
impl DirectModel {
    #[new]
    fn new(
        matrices: Py<Matrices>,
        elements: Vec<Py<ElementSpec>>,
        mass: Option<Py<Mass>>,
        method: &Method,
        tol: f64,
        max_iter: usize,
    ) -> Self {
        DirectModel {
            matrices,
            elements,
            mass,
            method: method.0,
            tol,
            max_iter,
        }
    }

    /// Integrates the physical equations of motion directly over `run`'s grid; `loads` are
    /// `_core.Load`s with physical patterns, `forcing` None or a Python function of time
    /// returning physical loads, `progress` as for `ModalModel.run`.
    #[pyo3(signature = (run, loads, forcing=None, progress=None))]
    fn run(
        &self,
        py: Python<'_>,
        run: &DirectRun,
        loads: Vec<PyRef<'_, Load>>,
        forcing: Option<&Bound<'_, PyAny>>,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<RunResult> {
        guarded(|| {
            let mats = self.matrices.get();
            let scaled: Vec<CoreScaled<CoreMatrix>> = mats
                .scaled
                .iter()
                .map(|s| {
                    let s = s.get();
                    CoreScaled {
                        k: s.k.as_ref().map(|m| &m.get().0),
                        c: s.c.as_ref().map(|m| &m.get().0),
                        law: s.law,
                    }
                })
                .collect();
            let loads = owned_loads(&loads);
            let built = element_build::build_all(py, &self.elements)?;
            let refs = built.refs();
            let g = run.grid;
            let p = DirectProblem {
                m: &mats.m.get().0,
                k: &mats.k.get().0,
                c: mats.c.as_ref().map(|m| &m.get().0),
                k_fixed: mats.k_fixed.as_ref().map(|m| &m.get().0),
                scaled: &scaled,
                elements: &refs,
                loads: &loads,
                mass: self.mass.as_ref().map(|m| &m.get().0),
                x0: &run.x0,
                v0: &run.v0,
                a0: run.a0.as_deref(),
                t0: g.t0,
                dt: g.dt,
                n_steps: g.n_steps,
                save_every: g.save_every,
                out_dofs: &run.out_dofs,
                method: self.method,
                tol: self.tol,
                max_iter: self.max_iter,
                energy: run.energy.as_ref().map(|e| e.core()),
            };
            let none = py.None().into_bound(py);
            let forcing = PyForcing::physical(forcing.unwrap_or(&none), run.x0.len());
            run_with(
                py,
                forcing,
                Some(&built),
                progress.unwrap_or(&none),
                |f, control| direct::integrate(&p, f, control),
            )
        })
    }
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
        let built = element_build::build(py, elements)?;
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
