//! Response spectra (`duhamel.spectra`): records arrive as float64 arrays (validated in
//! Python), the loops run in the core with the GIL released.

use duhamel_core::spectra::{self, BilinearOscillator, Record};
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::arrays::vec_of;
use crate::error::core_err;
use crate::guard::guarded;

/// Elastic spectra: `(sd, sv, sa)`, each flat `[record][damping][period]`; with `exact`,
/// the peaks between the samples too.
#[pyfunction]
#[pyo3(signature = (records, dts, periods, dampings, threads=None, exact=false))]
#[allow(clippy::type_complexity)]
pub(crate) fn elastic_spectra<'py>(
    py: Python<'py>,
    records: Vec<Bound<'py, PyAny>>,
    dts: Vec<f64>,
    periods: &Bound<'py, PyAny>,
    dampings: &Bound<'py, PyAny>,
    threads: Option<usize>,
    exact: bool,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    guarded(|| {
        let accs = records
            .iter()
            .map(|r| vec_of(r, "motions"))
            .collect::<PyResult<Vec<_>>>()?;
        let periods = vec_of(periods, "periods")?;
        let dampings = vec_of(dampings, "damping")?;
        let recs: Vec<Record> = accs
            .iter()
            .zip(&dts)
            .map(|(a, &dt)| Record { acc: a, dt })
            .collect();
        let peaks = py
            .detach(|| {
                if exact {
                    spectra::elastic_exact(&recs, &periods, &dampings, threads)
                } else {
                    spectra::elastic(&recs, &periods, &dampings, threads)
                }
            })
            .map_err(core_err)?;
        Ok((
            PyArray1::from_vec(py, peaks.sd),
            PyArray1::from_vec(py, peaks.sv),
            PyArray1::from_vec(py, peaks.sa),
        ))
    })
}

/// RotD peaks of the two components `pair` (sampled at `dt`): flat
/// `[damping][period][angle]`.
#[pyfunction]
#[pyo3(signature = (pair, dt, periods, dampings, n_angles, threads=None))]
pub(crate) fn rotd_peaks<'py>(
    py: Python<'py>,
    pair: (Bound<'py, PyAny>, Bound<'py, PyAny>),
    dt: f64,
    periods: &Bound<'py, PyAny>,
    dampings: &Bound<'py, PyAny>,
    n_angles: usize,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    guarded(|| {
        let (a, b) = (vec_of(&pair.0, "motion_1")?, vec_of(&pair.1, "motion_2")?);
        let periods = vec_of(periods, "periods")?;
        let dampings = vec_of(dampings, "damping")?;
        let out = py
            .detach(|| {
                let (r1, r2) = (Record { acc: &a, dt }, Record { acc: &b, dt });
                spectra::rotd(r1, r2, &periods, &dampings, n_angles, threads)
            })
            .map_err(core_err)?;
        Ok(PyArray1::from_vec(py, out))
    })
}

/// Constant-ductility yield displacements of the bilinear oscillator `(zeta, alpha)`
/// (damping ratio, post-yield stiffness ratio), flat `[ductility][period]`.
#[pyfunction]
#[pyo3(signature = (acc, dt, periods, oscillator, ductilities, threads=None))]
pub(crate) fn ductility_spectrum<'py>(
    py: Python<'py>,
    acc: &Bound<'py, PyAny>,
    dt: f64,
    periods: &Bound<'py, PyAny>,
    oscillator: (f64, f64),
    ductilities: &Bound<'py, PyAny>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    guarded(|| {
        let (zeta, alpha) = oscillator;
        let a = vec_of(acc, "motions")?;
        let periods = vec_of(periods, "periods")?;
        let mus = vec_of(ductilities, "ductility")?;
        let out = py
            .detach(|| {
                let rec = Record { acc: &a, dt };
                spectra::ductility_spectrum(rec, &periods, zeta, alpha, &mus, threads)
            })
            .map_err(core_err)?;
        Ok(PyArray1::from_vec(py, out))
    })
}

/// Peak displacement of one bilinear oscillator with yield displacement `uy`.
#[pyfunction]
pub(crate) fn bilinear_peak(
    py: Python<'_>,
    acc: &Bound<'_, PyAny>,
    dt: f64,
    omega: f64,
    zeta: f64,
    alpha: f64,
    uy: f64,
) -> PyResult<f64> {
    guarded(|| {
        let a = vec_of(acc, "motions")?;
        let o = BilinearOscillator { omega, zeta, alpha };
        py.detach(|| spectra::inelastic::peak_displacement(&o, uy, Record { acc: &a, dt }))
            .map_err(core_err)
    })
}
