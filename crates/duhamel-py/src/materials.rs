//! `_core.drive_material`: one uniaxial material of the core (`elements::materials`) driven
//! through a deformation history, a commit after each point (OpenSees' `setStrain`), for
//! checking the materials against OpenSees before they are elements of their own.
//!
//! A material is named by `kind` and described by a dict of its parameters (OpenSees'
//! names); a composite's parts are nested dicts with their own `"kind"`. [`build`] has one
//! arm per material; unknown keys are refused.

use duhamel_core::elements::materials::elastic_multilinear::ElasticMultiLinear;
use duhamel_core::elements::materials::minmax::MinMax;
use duhamel_core::elements::materials::multilinear::MultiLinear;
use duhamel_core::elements::materials::parallel::Parallel;
use duhamel_core::elements::materials::series::Series;
use duhamel_core::elements::materials::steel02::Steel02;
use duhamel_core::elements::materials::takeda::Takeda;
use duhamel_core::elements::materials::Material;
use duhamel_core::CoreError;
use numpy::PyArray1;
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::arrays::vec_of;
use crate::guard::guarded;

/// The forces and tangents after each deformation point.
type ForceTangent<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// The material kinds [`build`] knows.
pub(crate) const KINDS: &[&str] = &[
    "Steel02",
    "MultiLinear",
    "ElasticMultiLinear",
    "Takeda",
    "MinMax",
    "Parallel",
    "Series",
];

/// A material's parameter dict, read key by key; [`Params::finish`] refuses the keys no
/// arm read.
struct Params<'py> {
    path: String,
    dict: Bound<'py, PyDict>,
    read: Vec<&'static str>,
}

impl<'py> Params<'py> {
    fn get(&mut self, key: &'static str) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.read.push(key);
        Ok(self.dict.get_item(key)?.filter(|v| !v.is_none()))
    }

    fn type_error(&self, key: &str, what: &str) -> PyErr {
        PyTypeError::new_err(format!("{}: `{key}` must be {what}", self.path))
    }

    fn float(&mut self, key: &'static str, default: Option<f64>) -> PyResult<f64> {
        match (self.get(key)?, default) {
            (Some(v), _) => v
                .extract::<f64>()
                .map_err(|_| self.type_error(key, "a number")),
            (None, Some(d)) => Ok(d),
            (None, None) => Err(PyValueError::new_err(format!(
                "{}: `{key}` is required",
                self.path
            ))),
        }
    }

    fn floats(&mut self, key: &'static str) -> PyResult<Option<Vec<f64>>> {
        match self.get(key)? {
            None => Ok(None),
            Some(v) => v
                .extract::<Vec<f64>>()
                .map(Some)
                .map_err(|_| self.type_error(key, "a sequence of numbers")),
        }
    }

    fn required_floats(&mut self, key: &'static str) -> PyResult<Vec<f64>> {
        self.floats(key)?
            .ok_or_else(|| PyValueError::new_err(format!("{}: `{key}` is required", self.path)))
    }

    fn material(&mut self, key: &'static str) -> PyResult<Box<dyn Material>> {
        let v = self
            .get(key)?
            .ok_or_else(|| PyValueError::new_err(format!("{}: `{key}` is required", self.path)))?;
        nested(&v, &format!("{}.{key}", self.path))
    }

    fn materials(&mut self, key: &'static str) -> PyResult<Vec<Box<dyn Material>>> {
        let v = self
            .get(key)?
            .ok_or_else(|| PyValueError::new_err(format!("{}: `{key}` is required", self.path)))?;
        let list = v
            .cast::<PyList>()
            .map_err(|_| self.type_error(key, "a list of material dicts"))?;
        list.iter()
            .enumerate()
            .map(|(i, item)| nested(&item, &format!("{}.{key}[{i}]", self.path)))
            .collect()
    }

    /// Refuses keys no arm read (besides `"kind"`).
    fn finish(&self) -> PyResult<()> {
        for key in self.dict.keys() {
            let key: String = key.extract()?;
            if key != "kind" && !self.read.contains(&key.as_str()) {
                return Err(PyValueError::new_err(format!(
                    "{}: unknown parameter `{key}` (known: {})",
                    self.path,
                    self.read.join(", ")
                )));
            }
        }
        Ok(())
    }
}

/// A nested material dict `{"kind": ..., ...}`.
fn nested(v: &Bound<'_, PyAny>, path: &str) -> PyResult<Box<dyn Material>> {
    let dict = v
        .cast::<PyDict>()
        .map_err(|_| PyTypeError::new_err(format!("`{path}` must be a dict with a \"kind\"")))?;
    let kind: String = match dict.get_item("kind")? {
        Some(k) => k
            .extract()
            .map_err(|_| PyTypeError::new_err(format!("`{path}.kind` must be a str")))?,
        None => {
            return Err(PyValueError::new_err(format!(
                "`{path}` needs a \"kind\" (one of {})",
                KINDS.join(", ")
            )))
        }
    };
    build_at(&kind, dict, path)
}

/// The material `kind` with the parameters `params`.
pub(crate) fn build(kind: &str, params: &Bound<'_, PyDict>) -> PyResult<Box<dyn Material>> {
    build_at(kind, params, "")
}

fn build_at(kind: &str, params: &Bound<'_, PyDict>, path: &str) -> PyResult<Box<dyn Material>> {
    let mut p = Params {
        path: if path.is_empty() {
            kind.to_string()
        } else {
            format!("{path} ({kind})")
        },
        dict: params.clone(),
        read: Vec::new(),
    };
    let core = |r: Result<Box<dyn Material>, CoreError>, p: &Params| {
        r.map_err(|e| PyValueError::new_err(format!("{}: {e}", p.path)))
    };
    let material = match kind {
        "Steel02" => {
            let m = Steel02::new(
                p.float("fy", None)?,
                p.float("E", None)?,
                p.float("b", None)?,
                p.float("R0", Some(15.0))?,
                p.float("cR1", Some(0.925))?,
                p.float("cR2", Some(0.15))?,
                [
                    p.float("a1", Some(0.0))?,
                    p.float("a2", Some(1.0))?,
                    p.float("a3", Some(0.0))?,
                    p.float("a4", Some(1.0))?,
                ],
                p.float("sig_init", Some(0.0))?,
            );
            core(m.map(|m| Box::new(m) as Box<dyn Material>), &p)?
        }
        "MultiLinear" => {
            let (e, s) = (p.required_floats("strain")?, p.required_floats("stress")?);
            core(MultiLinear::new(&e, &s).map(|m| Box::new(m) as _), &p)?
        }
        "ElasticMultiLinear" => {
            let (e, s) = (p.required_floats("strain")?, p.required_floats("stress")?);
            core(
                ElasticMultiLinear::new(&e, &s).map(|m| Box::new(m) as _),
                &p,
            )?
        }
        "Takeda" => {
            let (e, s) = (p.required_floats("strain")?, p.required_floats("stress")?);
            let (en, sn) = (p.floats("strain_neg")?, p.floats("stress_neg")?);
            let alpha = p.float("alpha", Some(0.4))?;
            let neg = match (&en, &sn) {
                (Some(en), Some(sn)) => Some((en.as_slice(), sn.as_slice())),
                (None, None) => None,
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "{}: `strain_neg` and `stress_neg` go together",
                        p.path
                    )))
                }
            };
            core(
                Takeda::new(&e, &s, neg, alpha).map(|m| Box::new(m) as _),
                &p,
            )?
        }
        "MinMax" => {
            let inner = p.material("material")?;
            let (min, max) = (p.float("min", Some(-1e16))?, p.float("max", Some(1e16))?);
            core(MinMax::new(inner, min, max).map(|m| Box::new(m) as _), &p)?
        }
        "Parallel" => {
            let parts = p.materials("materials")?;
            let factors = p.floats("factors")?;
            core(Parallel::new(parts, factors).map(|m| Box::new(m) as _), &p)?
        }
        "Series" => {
            let parts = p.materials("materials")?;
            let max_iter = p.float("max_iter", Some(100.0))?;
            if !(max_iter >= 1.0 && max_iter.fract() == 0.0 && max_iter <= 1e6) {
                return Err(PyValueError::new_err(format!(
                    "{}: `max_iter` must be an integer >= 1, got {max_iter}",
                    p.path
                )));
            }
            let tol = p.float("tol", Some(1e-10))?;
            core(
                Series::new(parts, max_iter as usize, tol).map(|m| Box::new(m) as _),
                &p,
            )?
        }
        _ => return crate::materials_deteriorating::build(kind, params),
    };
    p.finish()?;
    Ok(material)
}

/// The material `kind` (parameters `params`) from its virgin state through the points
/// of `deformation`, committed after each: `(force, tangent)` after each point.
#[pyfunction]
pub(crate) fn drive_material<'py>(
    py: Python<'py>,
    kind: &str,
    params: &Bound<'py, PyDict>,
    deformation: &Bound<'py, PyAny>,
) -> PyResult<ForceTangent<'py>> {
    guarded(|| {
        let material = build(kind, params)?;
        let us = vec_of(deformation, "deformation")?;
        if let Some(k) = us.iter().position(|u| !u.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "`deformation` must be finite, got {} at index {k}",
                us[k]
            )));
        }
        let result = py.detach(|| -> Result<(Vec<f64>, Vec<f64>), String> {
            let mut committed = vec![0.0; material.state_len()];
            material.initial_state(&mut committed);
            let mut trial = committed.clone();
            let (mut force, mut tangent) =
                (Vec::with_capacity(us.len()), Vec::with_capacity(us.len()));
            for (k, &u) in us.iter().enumerate() {
                let at = |what: String| format!("{kind} at deformation[{k}] = {u}: {what}");
                let (f, kt) = material
                    .response(u, 0.0, &committed, &mut trial)
                    .map_err(|e| at(e.to_string()))?;
                if !(f.is_finite() && kt.is_finite()) {
                    return Err(at(format!("non-finite force {f} or tangent {kt}")));
                }
                committed.copy_from_slice(&trial);
                force.push(f);
                tangent.push(kt);
            }
            Ok((force, tangent))
        });
        let (force, tangent) = result.map_err(PyRuntimeError::new_err)?;
        Ok((
            PyArray1::from_vec(py, force),
            PyArray1::from_vec(py, tangent),
        ))
    })
}
