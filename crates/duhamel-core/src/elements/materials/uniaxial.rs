//! A uniaxial material between dof `i` and dof `j` (or `i` and the ground).
//!
//! The deformation is `u = x_i - x_j` (`x_i` when grounded), the force `F` acts as
//! `r_i = +F`, `r_j = -F`. The element's internal variables are the material's; before the
//! first step the material is virgin and taken along the deformation path from 0 to the
//! initial deformation `u_0` in one step (monotonic loading).

use super::material::Material;
use crate::elements::element::{Element, PathState, Tangent};
use crate::elements::hysteretic::common::{finite, local_dofs, relative, scatter};
use crate::error::CoreError;

/// A [`Material`] between two dofs (or a dof and the ground).
#[derive(Debug)]
pub struct Uniaxial<M: Material> {
    dofs: Vec<usize>,
    material: M,
}

impl<M: Material> Uniaxial<M> {
    /// The material `material` on the deformation `x_i - x_j` (`j` None: to ground). Errors
    /// name the parameter (`"j"` when `j == Some(i)`).
    pub fn new(i: usize, j: Option<usize>, material: M) -> Result<Self, CoreError> {
        Ok(Self {
            dofs: local_dofs(i, j)?,
            material,
        })
    }

    /// The material.
    pub fn material(&self) -> &M {
        &self.material
    }

    fn rate(v: &[f64]) -> f64 {
        relative(v)
    }
}

impl<M: Material + 'static> Element for Uniaxial<M> {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn eval(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let n = self.material.state_len();
        let mut virgin = vec![0.0; n];
        self.material.initial_state(&mut virgin);
        let mut trial = virgin.clone();
        let (f, kt) = self
            .material
            .response(relative(x), Self::rate(v), &virgin, &mut trial)?;
        finite(t, &[f, kt])?;
        scatter(f, kt, r, tangent.map(|tg| tg.kx));
        Ok(())
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        self.material.uses_rate()
    }

    fn state_len(&self) -> usize {
        self.material.state_len()
    }

    fn initial_state(&self, x: &[f64], v: &[f64], state: &mut [f64]) {
        let mut virgin = vec![0.0; state.len()];
        self.material.initial_state(&mut virgin);
        let u = relative(x);
        // monotonic loading from the virgin state to u (a law that refuses u keeps the
        // virgin state: its first evaluation then names the failure)
        let loaded = u != 0.0
            && self
                .material
                .response(u, Self::rate(v), &virgin, state)
                .is_ok();
        if !loaded {
            state.copy_from_slice(&virgin);
        }
    }

    fn eval_path(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        history: PathState<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let (f, kt) =
            self.material
                .response(relative(x), Self::rate(v), history.committed, history.trial)?;
        finite(t, &[f, kt])?;
        scatter(f, kt, r, tangent.map(|tg| tg.kx));
        Ok(())
    }
}
