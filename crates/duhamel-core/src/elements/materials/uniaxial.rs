//! A uniaxial material between dof `i` and dof `j` (or `i` and the ground), and what every
//! material's element definition answers the same way (from its law).
//!
//! The deformation is `u = x_i - x_j` (`x_i` when grounded), the force `F` acts as
//! `r_i = +F`, `r_j = -F`. The element's internal variables are the material's; before the
//! first step the material is virgin and taken along the deformation path from 0 to the
//! initial deformation `u_0` in one step (monotonic loading).
//!
//! **A loaded start** (`initial_deformation` `d0 != 0`, e.g. a hinge after a gravity
//! analysis): the material is driven from rest monotonically to `d0` in [`INITIAL_STEPS`]
//! equal increments (`0, d0/N, 2 d0/N, ..., d0`, committing at each, as
//! `duhamel.elements.drive` along `numpy.linspace(0, d0, N + 1)`), to the force `F0` and
//! its internal variables there. The element's deformation is then `d0 + x_i - x_j` and the
//! force it puts on the equations its change from `F0` (the loads that hold `F0` are not in
//! the model), as `Bilinear`'s `initial_force`.
//!
//! A material's definition (`Steel02Def`, ...) implements [`UniaxialDefinition`] (its dofs
//! and its law) and, through [`uniaxial_methods!`], the planner's questions of
//! [`Definition`](crate::elements::Definition): the linear part is the initial tangent
//! (`k0 > 0`), the tangent bound the law's, the stored energy `F^2 / (2 k0)` (the element
//! histories carry no internal variables; a path-independent law gives its potential).

use std::sync::Arc;

use super::material::Material;
use crate::elements::definition::{pair_matrix, Pair};
use crate::elements::element::{Element, PathState, Tangent};
use crate::elements::hysteretic::common::{finite, local_dofs, relative, scatter};
use crate::elements::registry::Defined;
use crate::error::CoreError;

/// The number of equal increments a loaded start is reached in (see the module
/// documentation).
pub const INITIAL_STEPS: usize = 100;

/// A loaded start: the deformation `d0`, the force `F0` and the internal variables there.
#[derive(Debug)]
struct Start {
    u0: f64,
    f0: f64,
    state: Vec<f64>,
}

/// A [`Material`] between two dofs (or a dof and the ground).
#[derive(Debug)]
pub struct Uniaxial<M: Material> {
    dofs: Vec<usize>,
    material: Arc<M>,
    start: Option<Arc<Start>>,
}

impl<M: Material> Clone for Uniaxial<M> {
    fn clone(&self) -> Self {
        Self {
            dofs: self.dofs.clone(),
            material: Arc::clone(&self.material),
            start: self.start.clone(),
        }
    }
}

/// The force and internal variables of `m` driven from rest to `u0` in [`INITIAL_STEPS`]
/// equal increments (committing at each, the first at 0). Errors name
/// `initial_deformation`.
pub fn loaded_state<M: Material + ?Sized>(m: &M, u0: f64) -> Result<(f64, Vec<f64>), CoreError> {
    let bad = |problem: String| CoreError::InvalidInput {
        name: "initial_deformation",
        problem,
    };
    if !u0.is_finite() {
        return Err(bad(format!("must be finite, got {u0}")));
    }
    if m.uses_rate() {
        return Err(bad(format!(
            "must be 0 for a rate-dependent material, got {u0}"
        )));
    }
    let n = m.state_len();
    let mut committed = vec![0.0; n];
    m.initial_state(&mut committed);
    let mut trial = committed.clone();
    let step = u0 / INITIAL_STEPS as f64;
    let mut f0 = 0.0;
    for k in 0..=INITIAL_STEPS {
        let u = if k == INITIAL_STEPS {
            u0
        } else {
            k as f64 * step
        };
        let (f, kt) = m.response(u, 0.0, &committed, &mut trial).map_err(|e| {
            bad(format!(
                "{u0:e} cannot be reached from rest (monotonically): {e}"
            ))
        })?;
        if !(f.is_finite() && kt.is_finite()) {
            return Err(bad(format!(
                "{u0:e} cannot be reached from rest: the force at {u:e} is {f}"
            )));
        }
        committed.copy_from_slice(&trial);
        f0 = f;
    }
    Ok((f0, committed))
}

impl<M: Material> Uniaxial<M> {
    /// The material `material` on the deformation `x_i - x_j` (`j` None: to ground). Errors
    /// name the parameter (`"j"` when `j == Some(i)`).
    pub fn new(i: usize, j: Option<usize>, material: M) -> Result<Self, CoreError> {
        Ok(Self {
            dofs: local_dofs(i, j)?,
            material: Arc::new(material),
            start: None,
        })
    }

    /// The same element starting loaded at the deformation `u0` (see the module
    /// documentation; `u0 == 0`: virgin). Errors name `initial_deformation`.
    pub fn starting_at(mut self, u0: f64) -> Result<Self, CoreError> {
        if u0 == 0.0 {
            self.start = None;
            return Ok(self);
        }
        let (f0, state) = loaded_state(self.material.as_ref(), u0)?;
        self.start = Some(Arc::new(Start { u0, f0, state }));
        Ok(self)
    }

    /// The force `F0` at `x = 0` of a loaded start (None: virgin there).
    pub fn initial_force(&self) -> Option<f64> {
        self.start.as_ref().map(|s| s.f0)
    }

    /// The deformation at `x = 0` and the force there.
    #[inline]
    fn origin(&self) -> (f64, f64) {
        self.start.as_ref().map_or((0.0, 0.0), |s| (s.u0, s.f0))
    }

    /// The internal variables at `x = 0` (virgin, or a loaded start's).
    fn base_state(&self, state: &mut [f64]) {
        match &self.start {
            Some(s) => state.copy_from_slice(&s.state),
            None => self.material.initial_state(state),
        }
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
        self.base_state(&mut virgin);
        let mut trial = virgin.clone();
        let (u0, f0) = self.origin();
        let (f, kt) =
            self.material
                .response(u0 + relative(x), Self::rate(v), &virgin, &mut trial)?;
        finite(t, &[f, kt])?;
        scatter(f - f0, kt, r, tangent.map(|tg| tg.kx));
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
        self.base_state(&mut virgin);
        let u = relative(x);
        // monotonic loading from the state at x = 0 to u (a law that refuses u keeps the
        // state at x = 0: its first evaluation then names the failure)
        let loaded = u != 0.0
            && self
                .material
                .response(self.origin().0 + u, Self::rate(v), &virgin, state)
                .is_ok();
        if !loaded {
            state.copy_from_slice(&virgin);
        }
    }

    #[inline]
    fn eval_path(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        history: PathState<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let (u0, f0) = self.origin();
        let (f, kt) = self.material.response(
            u0 + relative(x),
            Self::rate(v),
            history.committed,
            history.trial,
        )?;
        finite(t, &[f, kt])?;
        scatter(f - f0, kt, r, tangent.map(|tg| tg.kx));
        Ok(())
    }

    /// A law's trial variables depend on its committed ones and the deformation (and the
    /// rate, for a rate-dependent law) only.
    fn path_reads(&self) -> Option<(bool, bool)> {
        Some((self.material.uses_rate(), false))
    }

    /// A rate-free law whose zero increment changes nothing ([`Material::restarts_exactly`]).
    fn restarts_exactly(&self) -> bool {
        self.material.restarts_exactly() && !self.material.uses_rate()
    }

    /// A loaded start's deformation `d0 + x` rounds at the ulps of `d0`.
    fn resolution(&self) -> f64 {
        64.0 * f64::EPSILON * self.origin().0.abs()
    }
}

/// A material element's definition: where it acts and its law.
pub trait UniaxialDefinition {
    /// The law.
    type Law: Material + 'static;
    /// The dofs `(i, j)` of the deformation `x_i - x_j`.
    fn pair(&self) -> Pair;
    /// The law, checked (errors name the parameter).
    fn law(&self) -> Result<Self::Law, CoreError>;
    /// The deformation at `x = 0` (the parameter `initial_deformation`; 0: virgin there).
    fn initial_deformation(&self) -> f64;
}

/// The engine element of `d`.
pub fn build<D: UniaxialDefinition>(d: &D) -> Result<Uniaxial<D::Law>, CoreError> {
    let (i, j) = d.pair();
    let law = d.law()?;
    Uniaxial::new(i, j, law)?.starting_at(d.initial_deformation())
}

/// Whether the law is passive (a definition that does not build is not; nor one that
/// starts loaded: its initial force is held by loads outside the model).
pub fn passive<D: UniaxialDefinition>(d: &D) -> bool {
    d.initial_deformation() == 0.0 && d.law().is_ok_and(|m| m.passive())
}

/// The initial tangent as the linear part, when it is positive: a law whose initial
/// tangent is 0 or negative leaves the background as it is.
pub fn linear_stiffness<D: UniaxialDefinition>(d: &D) -> Option<Vec<f64>> {
    let k0 = d.law().ok()?.initial_tangent();
    (k0 > 0.0 && k0.is_finite()).then(|| pair_matrix(d.pair().1, k0))
}

/// The law's bound on `|dF/du|`, no damping.
pub fn tangent_bound<D: UniaxialDefinition>(d: &D) -> Option<(f64, f64)> {
    d.law().ok()?.tangent_bound().map(|k| (k, 0.0))
}

/// The stored energy at the local displacements `u` and forces `f`: a path-independent
/// law's potential, else `F^2 / (2 k0)` (unloading at the initial tangent; 0 when it is
/// not positive). A loaded start's is measured from its state at `x = 0`, as its force.
pub fn stored_energy<D: UniaxialDefinition>(d: &D, u: &[f64], f: &[f64]) -> f64 {
    let Ok(m) = d.law() else { return 0.0 };
    let du = u[0] - u.get(1).copied().unwrap_or(0.0);
    let u0 = d.initial_deformation();
    let f0 = if u0 == 0.0 {
        0.0
    } else {
        match loaded_state(&m, u0) {
            Ok((f0, _)) => f0,
            Err(_) => return 0.0,
        }
    };
    let total = |u: f64, force: f64| {
        if m.state_len() == 0 {
            return m.stored_energy(&[], u, force);
        }
        let k0 = m.initial_tangent();
        if k0 > 0.0 {
            0.5 * force * force / k0
        } else {
            0.0
        }
    };
    total(u0 + du, f0 + f[0]) - total(u0, f0)
}

/// The law of `d` as a part of a wrapper (a part starts where its wrapper starts: its own
/// `initial_deformation` must be 0).
pub fn as_material<D: UniaxialDefinition>(d: &D) -> Result<Box<dyn Material>, CoreError> {
    let u0 = d.initial_deformation();
    if u0 != 0.0 {
        return Err(CoreError::InvalidInput {
            name: "initial_deformation",
            problem: format!("of a part of a wrapper must be 0 (give it on the wrapper), got {u0}"),
        });
    }
    d.law().map(|m| Box::new(m) as Box<dyn Material>)
}

/// The law of the part `part` (entry `k` of the parameter `name`, or the parameter itself
/// when `k` is None) of a wrapper on `pair` (`wrapper` its name): an error names the
/// parameter when the part is no uniaxial material or acts on other dofs.
pub fn part_law(
    part: &Defined,
    (name, k): (&'static str, Option<usize>),
    pair: Pair,
    wrapper: &str,
) -> Result<Box<dyn Material>, CoreError> {
    let entry = k.map_or(String::new(), |k| format!("entry {k} "));
    let bad = |problem: String| CoreError::InvalidInput { name, problem };
    let law = part.material().ok_or_else(|| {
        bad(format!(
            "{entry}must be a uniaxial material element (Steel02, MultiLinear, \
             ElasticMultiLinear, Takeda, Hysteretic, Pinching4, ModIMKPeakOriented, IMKBilin, \
             MinMax, Parallel, Series), got a {}",
            part.name()
        ))
    })?;
    let at = part.directions().and_then(|d| d.first().copied());
    if at != Some(pair) {
        let show = |(i, j): Pair| match j {
            Some(j) => format!("({i}, {j})"),
            None => format!("({i}, None)"),
        };
        return Err(bad(format!(
            "{entry}acts on {}, the {wrapper} on {}: a part acts on its wrapper's dofs `i, j`",
            at.map_or("?".into(), show),
            show(pair)
        )));
    }
    law.map_err(|e| match e {
        CoreError::InvalidInput {
            name: inner,
            problem,
        } => bad(format!("{entry}({}): `{inner}` {problem}", part.name())),
        other => other,
    })
}

/// The [`Definition`](crate::elements::Definition) methods of a material element, from its
/// [`UniaxialDefinition`] (inside the `impl Definition` block, after `type Runtime`).
macro_rules! uniaxial_methods {
    () => {
        fn build(&self) -> Result<Self::Runtime, $crate::error::CoreError> {
            $crate::elements::materials::uniaxial::build(self)
        }

        fn directions(&self) -> Option<Vec<$crate::elements::Pair>> {
            Some(vec![
                <Self as $crate::elements::materials::uniaxial::UniaxialDefinition>::pair(self),
            ])
        }

        fn passive(&self) -> bool {
            $crate::elements::materials::uniaxial::passive(self)
        }

        fn linear_stiffness(&self) -> Option<Vec<f64>> {
            $crate::elements::materials::uniaxial::linear_stiffness(self)
        }

        fn tangent_bound(&self) -> Option<(f64, f64)> {
            $crate::elements::materials::uniaxial::tangent_bound(self)
        }

        fn stored_energy(&self, u: &[f64], f: &[f64]) -> f64 {
            $crate::elements::materials::uniaxial::stored_energy(self, u, f)
        }

        fn material(
            &self,
        ) -> Option<
            Result<
                Box<dyn $crate::elements::materials::Material>,
                $crate::error::CoreError,
            >,
        > {
            Some($crate::elements::materials::uniaxial::as_material(self))
        }
    };
}

pub(crate) use uniaxial_methods;

/// The `initial_deformation` parameter's documentation, the same in every material's `DOC`
/// (the parameter is implemented once, here).
macro_rules! initial_deformation_doc {
    () => {
        r#"initial_deformation : float, default 0.0
    The deformation at ``x = 0`` (a loaded start, e.g. after a gravity analysis): the
    material is first driven from rest monotonically to it (in 100 equal increments, as
    :func:`duhamel.elements.drive` along ``numpy.linspace(0, initial_deformation, 101)``),
    its deformation is then ``initial_deformation + x_i - x_j`` and the force it adds to the
    equations its change from the force there (held by loads outside the model).
"#
    };
}
pub(crate) use initial_deformation_doc;
