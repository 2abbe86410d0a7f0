//! Binding of the coupled linear engine (first-order complex modes).

use duhamel_core::coupled::{self, FirstOrderModes, Outputs};
use duhamel_core::coupled_step::Nonlinear;
use duhamel_core::elements::Element;
use duhamel_core::linear::{LinearProblem, ModalForcing};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::elements;
use crate::nonlinear::optional_matrix;
use crate::run::{finish_run, modal_inputs, PyForcing};
use crate::vec_of;

/// Integrates a linear system with modal couplings (non-classical damping, gyroscopic and
/// circulatory terms) exactly in its first-order modes; see `duhamel.solve`.
///
/// `k`, `c`, `q0`, `v0`, `loads`, `dt`, `n_steps`, `save_every`, `forcing`, `phi_t` as for
/// `solve_linear` (the real modal background); `lambda_re`, `lambda_im` the `r` first-order
/// eigenvalues kept, `gain_re`, `gain_im` (`r x n_modes`, flattened row-major) the rows of
/// `V^-1 B`, `eta0_re`, `eta0_im` the initial first-order coordinates. Returns the dict of
/// `solve_linear` with `eta` (`(n_saved, 2 r)`: real parts, then imaginary parts) instead of
/// `q` and `v` (None). With `out_map` (`2 r x n_out`, flattened) and `out_loads`
/// (`n_loads x n_out`), also `out` (`(n_saved, n_out)`): `[Re eta | Im eta] @ out_map +
/// load_values @ out_loads`, computed during the run. With `elements` (specs as for
/// `solve_nonlinear`), `phi` (`(n_dof, n_modes)`) and `back` (`2 r x 2 n_modes`: `[Re eta |
/// Im eta] @ back = [q | v]`), the elements' forces enter as a pseudo-force (scheme b,
/// trapezoid, Newton with `tol`, `max_iter`); `pseudo` then holds it at the saved states and
/// `stats` the Newton iterations.
#[pyfunction]
#[pyo3(signature = (k, c, q0, v0, loads, dt, n_steps, save_every, lambda_re, lambda_im, gain_re, gain_im, eta0_re, eta0_im, out_map=None, out_loads=None, n_out=0, threads=None, forcing=None, phi_t=None, phi=None, elements=None, back=None, tol=1e-10, max_iter=25))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_coupled<'py>(
    py: Python<'py>,
    k: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    q0: &Bound<'py, PyAny>,
    v0: &Bound<'py, PyAny>,
    loads: &Bound<'py, PyAny>,
    dt: f64,
    n_steps: usize,
    save_every: usize,
    lambda_re: &Bound<'py, PyAny>,
    lambda_im: &Bound<'py, PyAny>,
    gain_re: &Bound<'py, PyAny>,
    gain_im: &Bound<'py, PyAny>,
    eta0_re: &Bound<'py, PyAny>,
    eta0_im: &Bound<'py, PyAny>,
    out_map: Option<&Bound<'py, PyAny>>,
    out_loads: Option<&Bound<'py, PyAny>>,
    n_out: usize,
    threads: Option<usize>,
    forcing: Option<Py<PyAny>>,
    phi_t: Option<&Bound<'py, PyAny>>,
    phi: Option<&Bound<'py, PyAny>>,
    elements: Option<&Bound<'py, PyAny>>,
    back: Option<&Bound<'py, PyAny>>,
    tol: f64,
    max_iter: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let (k, c, q0, v0, loads) = modal_inputs(k, c, q0, v0, loads)?;
    let lambda_re = vec_of(lambda_re, "lambda_re")?;
    let lambda_im = vec_of(lambda_im, "lambda_im")?;
    let gain_re = vec_of(gain_re, "gain_re")?;
    let gain_im = vec_of(gain_im, "gain_im")?;
    let eta0_re = vec_of(eta0_re, "eta0_re")?;
    let eta0_im = vec_of(eta0_im, "eta0_im")?;
    let out_map = out_map.map(|a| vec_of(a, "out_map")).transpose()?;
    let out_loads = out_loads.map(|a| vec_of(a, "out_loads")).transpose()?;
    let mut py_forcing = PyForcing::new(forcing, phi_t, k.len())?;
    let problem = LinearProblem {
        k: &k,
        c: &c,
        q0: &q0,
        v0: &v0,
        loads: &loads,
        dt,
        n_steps,
        save_every,
        threads,
    };
    let modes = FirstOrderModes {
        lambda_re: &lambda_re,
        lambda_im: &lambda_im,
        gain_re: &gain_re,
        gain_im: &gain_im,
        eta0_re: &eta0_re,
        eta0_im: &eta0_im,
    };
    let outputs = match (&out_map, &out_loads) {
        (Some(map), Some(loads)) => Some(Outputs {
            map,
            loads,
            n_cols: n_out,
        }),
        _ => None,
    };
    let phi_v = optional_matrix(phi, "phi")?;
    let back_v = optional_matrix(back, "back")?;
    let (boxed, python) = match elements {
        Some(e) => elements::parse(e)?,
        None => Default::default(),
    };
    let refs: Vec<&dyn Element> = boxed.iter().map(|b| b.as_ref()).collect();
    let nonlinear = match (&phi_v, &back_v, refs.is_empty()) {
        (Some(phi), Some(back), false) => Some(Nonlinear {
            phi,
            n_dof: phi.len().checked_div(k.len()).unwrap_or(0),
            elements: &refs,
            back,
            tol,
            max_iter,
        }),
        _ => None,
    };
    let result = py.detach(|| {
        let f = py_forcing.as_mut().map(|f| f as &mut dyn ModalForcing);
        coupled::integrate(&problem, &modes, outputs.as_ref(), nonlinear.as_ref(), f)
    });
    finish_run(py, result, py_forcing, &python, |iterations, st| {
        st.set_item("newton_iterations", iterations)
    })
}
