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

/// The values of a float64 matrix of `rows` rows and `cols` columns (row-major, copied); a
/// ValueError naming `name` for any other shape. `None` for either count accepts any.
pub(crate) fn matrix_of(
    obj: &Bound<'_, PyAny>,
    name: &str,
    rows: Option<usize>,
    cols: Option<usize>,
) -> PyResult<(Vec<f64>, usize, usize)> {
    let arr = obj.cast::<numpy::PyArray2<f64>>().map_err(|_| {
        PyTypeError::new_err(format!("`{name}` must be a 2-D numpy array of float64"))
    })?;
    let ro = arr.readonly();
    let (r, c) = (ro.shape()[0], ro.shape()[1]);
    if rows.is_some_and(|n| n != r) || cols.is_some_and(|n| n != c) {
        let want = |n: Option<usize>| n.map_or("any".to_string(), |n| n.to_string());
        return Err(PyValueError::new_err(format!(
            "`{name}` must have shape ({}, {}), got ({r}, {c})",
            want(rows),
            want(cols)
        )));
    }
    if !ro.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "`{name}` must be C-contiguous (pass numpy.ascontiguousarray({name}))"
        )));
    }
    Ok((ro.as_slice()?.to_vec(), r, c))
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

/// A dof index (any Python or numpy integer, not a bool) `>= 0`, or an error naming `name`.
pub(crate) fn dof_index(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    let integral = obj.is_instance_of::<pyo3::types::PyInt>()
        || (obj.hasattr("__index__")? && !obj.hasattr("__float__")?)
        || obj
            .getattr("dtype")
            .and_then(|d| d.getattr("kind"))
            .and_then(|k| k.extract::<String>())
            .is_ok_and(|k| k == "i" || k == "u");
    if obj.is_instance_of::<pyo3::types::PyBool>() || !integral {
        return Err(PyTypeError::new_err(format!(
            "`{name}` must be an integer dof index or a dof label, got {}",
            obj.get_type().name()?
        )));
    }
    let value: i64 = obj.call_method0("__index__")?.extract()?;
    usize::try_from(value).map_err(|_| {
        PyValueError::new_err(format!(
            "`{name}` must be a degree-of-freedom index (negative indices are not allowed), \
             got {value}"
        ))
    })
}
