//! The deteriorating and pinching materials of `duhamel_core::elements::materials`
//! (ModIMKPeakOriented, IMKBilin, Hysteretic, Pinching4) built from a kind and a dict of
//! parameters (OpenSees' vocabulary), for `_core.drive_material` (`materials.rs`).

use std::collections::HashSet;

use duhamel_core::elements::materials::{
    Hysteretic, HystereticParams, ImkBilin, ImkBilinParams, Material, ModImkParams,
    ModImkPeakOriented, Pinching4, Pinching4Damage, Pinching4Params,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::core_err;

/// The parameters of one material: reads each by name, then refuses names never read.
struct Params<'a, 'py> {
    kind: &'a str,
    dict: &'a Bound<'py, PyDict>,
    used: HashSet<String>,
}

impl<'a, 'py> Params<'a, 'py> {
    fn new(kind: &'a str, dict: &'a Bound<'py, PyDict>) -> Self {
        Self {
            kind,
            dict,
            used: HashSet::new(),
        }
    }

    /// The number `name`, or None when absent.
    fn opt(&mut self, name: &str) -> PyResult<Option<f64>> {
        self.used.insert(name.to_string());
        match self.dict.get_item(name)? {
            None => Ok(None),
            Some(v) => v.extract::<f64>().map(Some).map_err(|_| {
                PyTypeError::new_err(format!(
                    "`{name}` of {} must be a real number, got {}",
                    self.kind,
                    v.get_type().name().map_or("?".into(), |n| n.to_string())
                ))
            }),
        }
    }

    /// The number `name` (required).
    fn get(&mut self, name: &str) -> PyResult<f64> {
        self.opt(name)?
            .ok_or_else(|| PyValueError::new_err(format!("`{name}` is required by {}", self.kind)))
    }

    /// The string `name`, or `default`.
    fn string(&mut self, name: &str, default: &str) -> PyResult<String> {
        self.used.insert(name.to_string());
        match self.dict.get_item(name)? {
            None => Ok(default.to_string()),
            Some(v) => v.extract::<String>().map_err(|_| {
                PyTypeError::new_err(format!("`{name}` of {} must be a string", self.kind))
            }),
        }
    }

    /// Refuses parameters the material does not have.
    fn done(self) -> PyResult<()> {
        for key in self.dict.keys() {
            let key: String = key.extract()?;
            if !self.used.contains(&key) {
                return Err(PyValueError::new_err(format!(
                    "`{key}` is not a parameter of {}",
                    self.kind
                )));
            }
        }
        Ok(())
    }
}

fn mod_imk(p: &mut Params<'_, '_>) -> PyResult<Box<dyn Material>> {
    let params = ModImkParams {
        k0: p.get("K0")?,
        as_plus: p.get("as_plus")?,
        as_neg: p.get("as_neg")?,
        my_plus: p.get("My_plus")?,
        my_neg: p.get("My_neg")?,
        lambda_s: p.get("lambda_s")?,
        lambda_c: p.get("lambda_c")?,
        lambda_a: p.get("lambda_a")?,
        lambda_k: p.get("lambda_k")?,
        c_s: p.get("c_s")?,
        c_c: p.get("c_c")?,
        c_a: p.get("c_a")?,
        c_k: p.get("c_k")?,
        theta_p_plus: p.get("theta_p_plus")?,
        theta_p_neg: p.get("theta_p_neg")?,
        theta_pc_plus: p.get("theta_pc_plus")?,
        theta_pc_neg: p.get("theta_pc_neg")?,
        res_plus: p.get("res_plus")?,
        res_neg: p.get("res_neg")?,
        theta_u_plus: p.get("theta_u_plus")?,
        theta_u_neg: p.get("theta_u_neg")?,
        d_plus: p.get("D_plus")?,
        d_neg: p.get("D_neg")?,
        n_factor: p.opt("n_factor")?.unwrap_or(0.0),
    };
    Ok(Box::new(ModImkPeakOriented::new(params).map_err(core_err)?))
}

fn imk_bilin(p: &mut Params<'_, '_>) -> PyResult<Box<dyn Material>> {
    let params = ImkBilinParams {
        ke: p.get("Ke")?,
        theta_p_plus: p.get("theta_p_plus")?,
        theta_pc_plus: p.get("theta_pc_plus")?,
        theta_u_plus: p.get("theta_u_plus")?,
        my_plus: p.get("My_plus")?,
        mmax_my_plus: p.get("Mmax_My_plus")?,
        res_plus: p.get("res_plus")?,
        theta_p_neg: p.get("theta_p_neg")?,
        theta_pc_neg: p.get("theta_pc_neg")?,
        theta_u_neg: p.get("theta_u_neg")?,
        my_neg: p.get("My_neg")?,
        mmax_my_neg: p.get("Mmax_My_neg")?,
        res_neg: p.get("res_neg")?,
        lambda_s: p.get("lambda_s")?,
        lambda_c: p.get("lambda_c")?,
        lambda_k: p.get("lambda_k")?,
        c_s: p.get("c_s")?,
        c_c: p.get("c_c")?,
        c_k: p.get("c_k")?,
        d_plus: p.get("D_plus")?,
        d_neg: p.get("D_neg")?,
    };
    Ok(Box::new(ImkBilin::new(params).map_err(core_err)?))
}

fn hysteretic(p: &mut Params<'_, '_>) -> PyResult<Box<dyn Material>> {
    let mut side = |s: &str| -> PyResult<Vec<(f64, f64)>> {
        let mut points = Vec::new();
        for k in 1..=2 {
            points.push((p.get(&format!("s{k}{s}"))?, p.get(&format!("e{k}{s}"))?));
        }
        match (p.opt(&format!("s3{s}"))?, p.opt(&format!("e3{s}"))?) {
            (Some(f), Some(d)) => points.push((f, d)),
            (None, None) => {}
            _ => {
                return Err(PyValueError::new_err(format!(
                    "`s3{s}` and `e3{s}` of Hysteretic go together: give both or neither"
                )))
            }
        }
        Ok(points)
    };
    let pos = side("p")?;
    let neg = side("n")?;
    let params = HystereticParams {
        pos,
        neg,
        pinch_x: p.get("pinch_x")?,
        pinch_y: p.get("pinch_y")?,
        damage1: p.get("damage1")?,
        damage2: p.get("damage2")?,
        beta: p.opt("beta")?.unwrap_or(0.0),
    };
    Ok(Box::new(Hysteretic::new(params).map_err(core_err)?))
}

fn pinching4(p: &mut Params<'_, '_>) -> PyResult<Box<dyn Material>> {
    let mut pos = [(0.0, 0.0); 4];
    for (k, point) in pos.iter_mut().enumerate() {
        *point = (
            p.get(&format!("ePf{}", k + 1))?,
            p.get(&format!("ePd{}", k + 1))?,
        );
    }
    // the negative envelope and pinching: all given, or none (mirrored, OpenSees' short form)
    let mut neg = pos.map(|(f, d)| (-f, -d));
    let mut given = 0;
    for (k, point) in neg.iter_mut().enumerate() {
        let (f, d) = (
            p.opt(&format!("eNf{}", k + 1))?,
            p.opt(&format!("eNd{}", k + 1))?,
        );
        if let (Some(f), Some(d)) = (f, d) {
            *point = (f, d);
        }
        given += usize::from(f.is_some()) + usize::from(d.is_some());
    }
    let pinch_pos = [p.get("rDispP")?, p.get("rForceP")?, p.get("uForceP")?];
    let mut pinch_neg = pinch_pos;
    for (v, name) in pinch_neg.iter_mut().zip(["rDispN", "rForceN", "uForceN"]) {
        if let Some(x) = p.opt(name)? {
            *v = x;
            given += 1;
        }
    }
    if given != 0 && given != 11 {
        return Err(PyValueError::new_err(
            "`eNf1`..`eNf4`, `eNd1`..`eNd4`, `rDispN`, `rForceN`, `uForceN` of Pinching4: give \
             all eleven (the negative side) or none (mirrored from the positive side)",
        ));
    }
    let mut gamma = |g: &str| -> PyResult<[f64; 5]> {
        Ok([
            p.get(&format!("g{g}1"))?,
            p.get(&format!("g{g}2"))?,
            p.get(&format!("g{g}3"))?,
            p.get(&format!("g{g}4"))?,
            p.get(&format!("g{g}Lim"))?,
        ])
    };
    let (gk, gd, gf) = (gamma("K")?, gamma("D")?, gamma("F")?);
    let damage = match p.string("dmgType", "energy")?.as_str() {
        "energy" => Pinching4Damage::Energy,
        "cycle" => Pinching4Damage::Cycle,
        other => {
            return Err(PyValueError::new_err(format!(
                "`dmgType` of Pinching4 must be \"energy\" or \"cycle\", got {other:?}"
            )))
        }
    };
    let params = Pinching4Params {
        pos,
        neg,
        pinch_pos,
        pinch_neg,
        gk,
        gd,
        gf,
        ge: p.get("gE")?,
        damage,
    };
    Ok(Box::new(Pinching4::new(params).map_err(core_err)?))
}

/// The material `kind` with the parameters `params` (errors name the parameter).
pub(crate) fn build(kind: &str, params: &Bound<'_, PyDict>) -> PyResult<Box<dyn Material>> {
    let mut p = Params::new(kind, params);
    let material = match kind {
        "ModIMKPeakOriented" => mod_imk(&mut p)?,
        "IMKBilin" => imk_bilin(&mut p)?,
        "Hysteretic" => hysteretic(&mut p)?,
        "Pinching4" => pinching4(&mut p)?,
        other => {
            return Err(PyValueError::new_err(format!(
                "`kind` must be one of {}, ModIMKPeakOriented, IMKBilin, Hysteretic, \
                 Pinching4, got {other:?}",
                crate::materials::KINDS.join(", ")
            )))
        }
    };
    p.done()?;
    Ok(material)
}
