//! Arrays across the boundary: read-only float64 views with errors that name the parameter.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// A read-only float64 1-D view of `obj`, or a TypeError/ValueError naming `name`.
pub(crate) fn f64_array1<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<PyReadonlyArray1<'py, f64>> {
    let arr = obj.cast::<PyArray1<f64>>().map_err(|_| {
        let what = match obj.getattr("dtype") {
            Ok(dt) => format!(
                "an array of dtype {dt} (ndim {})",
                obj.getattr("ndim").map_or("?".into(), |n| n.to_string())
            ),
            Err(_) => obj.get_type().name().map_or("?".into(), |n| n.to_string()),
        };
        PyTypeError::new_err(format!(
            "`{name}` must be a 1-D numpy array of float64, got {what}"
        ))
    })?;
    let ro = arr.readonly();
    if !ro.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "`{name}` must be C-contiguous (pass numpy.ascontiguousarray({name}))"
        )));
    }
    Ok(ro)
}

/// The values of a float64 1-D array, copied.
pub(crate) fn vec_of(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    Ok(f64_array1(obj, name)?.as_slice()?.to_vec())
}

/// The values of a float64 array of any shape (row-major), copied.
pub(crate) fn flat_of(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    vec_of(&obj.call_method0("ravel")?, name)
}

/// Non-negative integers from a 1-D int64 array.
pub(crate) fn index_vec(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<usize>> {
    let arr = obj.cast::<numpy::PyArray1<i64>>().map_err(|_| {
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
