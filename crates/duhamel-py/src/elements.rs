//! Elements: specifications as typed values (checked once, when made), and the Python
//! `Callable` element.

use duhamel_core::elements::{
    AxialFrictionPendulum, Bilinear, BoucWen, BoucWenParams, FrictionPendulum, Gap,
    LeadRubberBearing, MaxwellDamper, ViscousDamper,
};
use duhamel_core::elements::{Breathing, BreathingCrack};
use duhamel_core::elements::{Contact, Damper, Element, Polynomial, Shifted, Spring};
use duhamel_core::elements::{ShortJournalBearing, SpeedTableBearing, Tangent};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::vec_of;
use crate::callable::{ArcElement, Built, PyElement};
use crate::devices::{build as build_device, Device};
use crate::error::core_err;
use crate::guard::guarded;

/// What an element is, checked; the run builds a fresh element from it.
enum Spec {
    Polynomial(Polynomial),
    Spring(Spring),
    Damper(Damper),
    Contact(Contact),
    Bilinear(Bilinear),
    BoucWen(BoucWen),
    FrictionPendulum(FrictionPendulum),
    LeadRubber(LeadRubberBearing),
    ViscousDamper(ViscousDamper),
    Maxwell(MaxwellDamper),
    AxialPendulum(AxialFrictionPendulum),
    Gap(Gap),
    Journal(ShortJournalBearing),
    SpeedTable(SpeedTableBearing),
    Crack(BreathingCrack),
    /// A device built by `devices.rs` (a prototype cloned per run).
    Device(Device),
    Callable {
        dofs: Vec<usize>,
        func: Py<PyAny>,
        jacobian: Option<Py<PyAny>>,
        state: Option<Vec<f64>>,
    },
    /// Another element minus a local linear part (checked: sizes and finiteness).
    Shifted {
        inner: Py<ElementSpec>,
        k0: Vec<f64>,
        c0: Vec<f64>,
    },
}

/// A force element of `duhamel.elements`, checked.
#[pyclass(frozen, name = "Element", module = "duhamel._core")]
pub(crate) struct ElementSpec(Spec);

#[pymethods]
impl ElementSpec {
    /// The global dofs the element acts on, in its local order.
    #[getter]
    fn dofs(&self) -> Vec<usize> {
        self.dof_list()
    }

    /// `r = sum_k coefficients[k] x^k` at `dof`.
    #[staticmethod]
    fn polynomial(dof: usize, coefficients: &Bound<'_, PyAny>) -> PyResult<Self> {
        let coefficients = vec_of(coefficients, "coefficients")?;
        let e = guarded(|| Polynomial::new(dof, coefficients).map_err(core_err))?;
        Ok(ElementSpec(Spec::Polynomial(e)))
    }

    /// Spring `k d + k3 d^3` on `d = x_i - x_j` (`j` None: to ground).
    #[staticmethod]
    #[pyo3(signature = (i, j, k, k3))]
    fn spring(i: usize, j: Option<usize>, k: f64, k3: f64) -> PyResult<Self> {
        let e = guarded(|| Spring::new(i, j, k, k3).map_err(core_err))?;
        Ok(ElementSpec(Spec::Spring(e)))
    }

    /// Viscous damper `c d'` on `d = x_i - x_j`.
    #[staticmethod]
    #[pyo3(signature = (i, j, c))]
    fn damper(i: usize, j: Option<usize>, c: f64) -> PyResult<Self> {
        let e = guarded(|| Damper::new(i, j, c).map_err(core_err))?;
        Ok(ElementSpec(Spec::Damper(e)))
    }

    /// Radial rub contact with Coulomb friction.
    #[staticmethod]
    fn contact(
        dof_x: usize,
        dof_y: usize,
        clearance: f64,
        stiffness: f64,
        friction: f64,
        smoothing: f64,
        velocity_smoothing: f64,
    ) -> PyResult<Self> {
        let e = guarded(|| {
            Contact::new(
                dof_x,
                dof_y,
                clearance,
                stiffness,
                friction,
                smoothing,
                velocity_smoothing,
            )
            .map_err(core_err)
        })?;
        Ok(ElementSpec(Spec::Contact(e)))
    }

    /// Short (Ocvirk) journal bearing with half-film cavitation on the journal's dofs
    /// `(x, y)`, spinning at `law`.
    #[staticmethod]
    fn journal_bearing(
        dofs: (usize, usize),
        radius: f64,
        length: f64,
        clearance: f64,
        viscosity: f64,
        law: &crate::speed::SpeedLaw,
    ) -> PyResult<Self> {
        let (dof_x, dof_y) = dofs;
        let e = guarded(|| {
            ShortJournalBearing::new(dof_x, dof_y, radius, length, clearance, viscosity, law.0)
                .map_err(core_err)
        })?;
        Ok(ElementSpec(Spec::Journal(e)))
    }

    /// A bearing with stiffness and damping tabulated against the spin speed (`values` and
    /// optional Hermite `slopes`: 8 rows `kxx .. cyy` of `len(speeds)`), at `law`.
    #[staticmethod]
    #[pyo3(signature = (dof_x, dof_y, speeds, values, slopes, law))]
    fn speed_table(
        dof_x: usize,
        dof_y: usize,
        speeds: Vec<f64>,
        values: Vec<Vec<f64>>,
        slopes: Option<Vec<Vec<f64>>>,
        law: &crate::speed::SpeedLaw,
    ) -> PyResult<Self> {
        let e = guarded(|| {
            SpeedTableBearing::new(dof_x, dof_y, speeds, values, slopes, law.0).map_err(core_err)
        })?;
        Ok(ElementSpec(Spec::SpeedTable(e)))
    }

    /// A breathing crack on a shaft node's lateral dofs: the stiffness losses `dk_xi`,
    /// `dk_eta` of the open crack in the rotating frame at the angle `law.theta(t) + phase`,
    /// `breathing` "switching" (Gasch) or "cosine" (Mayes & Davies).
    #[staticmethod]
    #[pyo3(signature = (dof_x, dof_y, dk_xi, dk_eta, breathing, phase, law))]
    fn breathing_crack(
        dof_x: usize,
        dof_y: usize,
        dk_xi: f64,
        dk_eta: f64,
        breathing: &str,
        phase: f64,
        law: &crate::speed::SpeedLaw,
    ) -> PyResult<Self> {
        let breathing = match breathing {
            "switching" => Breathing::Switching,
            "cosine" => Breathing::Cosine,
            other => {
                return Err(PyValueError::new_err(format!(
                    "`breathing` must be 'switching' or 'cosine', got {other:?}"
                )))
            }
        };
        let e = guarded(|| {
            BreathingCrack::new(dof_x, dof_y, dk_xi, dk_eta, breathing, phase, law.0)
                .map_err(core_err)
        })?;
        Ok(ElementSpec(Spec::Crack(e)))
    }

    /// The restoring force and its tangents `(r, dr/dx, dr/dx')` (row-major) of a
    /// path-independent element at local displacements `x`, velocities `v`, time `t`.
    fn evaluate(
        &self,
        py: Python<'_>,
        x: &Bound<'_, PyAny>,
        v: &Bound<'_, PyAny>,
        t: f64,
    ) -> PyResult<(Vec<f64>, Vec<f64>, Vec<f64>)> {
        let mut built = Built {
            elements: Vec::new(),
            python: Vec::new(),
        };
        let element = make(py, self, &mut built)?;
        let n = element.dofs().len();
        if element.state_len() > 0 {
            return Err(PyValueError::new_err(
                "evaluate: a path-dependent element's force depends on its history",
            ));
        }
        let (x, v) = (vec_of(x, "x")?, vec_of(v, "v")?);
        if x.len() != n || v.len() != n {
            return Err(PyValueError::new_err(format!(
                "evaluate: `x` and `v` must have the element's {n} local dofs, got {} and {}",
                x.len(),
                v.len()
            )));
        }
        let (mut r, mut kx, mut cv) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; n * n]);
        let result = guarded(|| {
            let tangent = Tangent {
                kx: &mut kx,
                cv: &mut cv,
            };
            element
                .eval(&x, &v, t, &mut r, Some(tangent))
                .map_err(core_err)
        });
        if let Some(err) = built.take_error() {
            return Err(err);
        }
        result?;
        Ok((r, kx, cv))
    }

    /// Bilinear elastoplastic spring with kinematic hardening.
    #[staticmethod]
    #[pyo3(signature = (i, j, k, fy, alpha))]
    fn bilinear(i: usize, j: Option<usize>, k: f64, fy: f64, alpha: f64) -> PyResult<Self> {
        guarded(|| Bilinear::new(i, j, k, fy, alpha).map_err(core_err))
            .map(|e| ElementSpec(Spec::Bilinear(e)))
    }

    /// Bouc-Wen smooth hysteretic spring on `d = x_i - x_j` (`j` None: to ground), its loop
    /// shaped by `(n, beta, gamma)`.
    #[staticmethod]
    #[pyo3(signature = (i, j, k, fy, alpha, shape))]
    fn bouc_wen(
        i: usize,
        j: Option<usize>,
        k: f64,
        fy: f64,
        alpha: f64,
        shape: (f64, f64, f64),
    ) -> PyResult<Self> {
        let (n, beta, gamma) = shape;
        guarded(|| {
            BoucWen::new(
                i,
                j,
                BoucWenParams {
                    k,
                    fy,
                    alpha,
                    n,
                    beta,
                    gamma,
                },
            )
            .map_err(core_err)
        })
        .map(|e| ElementSpec(Spec::BoucWen(e)))
    }

    /// Single friction pendulum bearing on two horizontal dofs, or on `dof_x` alone
    /// (`dof_y` None); `velocity = (mu_slow, rate)` for velocity-dependent friction.
    #[staticmethod]
    #[pyo3(signature = (dof_x, dof_y, radius, mu, weight, yield_displacement, velocity=None))]
    fn friction_pendulum(
        dof_x: usize,
        dof_y: Option<usize>,
        radius: f64,
        mu: f64,
        weight: f64,
        yield_displacement: f64,
        velocity: Option<(f64, f64)>,
    ) -> PyResult<Self> {
        let made = || {
            let e = match dof_y {
                Some(dof_y) => {
                    FrictionPendulum::new(dof_x, dof_y, radius, mu, weight, yield_displacement)
                }
                None => FrictionPendulum::uniaxial(dof_x, radius, mu, weight, yield_displacement),
            };
            e.and_then(|e| match velocity {
                Some((slow, rate)) => e.with_velocity(slow, rate),
                None => Ok(e),
            })
            .map_err(core_err)
        };
        guarded(made).map(|e| ElementSpec(Spec::FrictionPendulum(e)))
    }

    /// A device element of `devices.rs`: `kind` and its arguments (a tuple).
    #[staticmethod]
    fn device(kind: &str, args: &Bound<'_, PyAny>) -> PyResult<Self> {
        build_device(kind, args).map(|d| ElementSpec(Spec::Device(d)))
    }

    /// Lead-rubber bearing: coupled bidirectional Bouc-Wen on `(dof_x, dof_y)`, uniaxial on
    /// `dof_x` when `dof_y` is None; `strength = (k, fy, alpha)`, `shape = (eta, beta, gamma)`.
    #[staticmethod]
    #[pyo3(signature = (dof_x, dof_y, strength, shape))]
    fn lead_rubber(
        dof_x: usize,
        dof_y: Option<usize>,
        strength: (f64, f64, f64),
        shape: (f64, f64, f64),
    ) -> PyResult<Self> {
        guarded(|| LeadRubberBearing::new(dof_x, dof_y, strength, shape).map_err(core_err))
            .map(|e| ElementSpec(Spec::LeadRubber(e)))
    }

    /// Power-law viscous damper `c |v|^a sgn(v)`.
    #[staticmethod]
    #[pyo3(signature = (i, j, c, exponent, v0))]
    fn viscous_damper(
        i: usize,
        j: Option<usize>,
        c: f64,
        exponent: f64,
        v0: f64,
    ) -> PyResult<Self> {
        let made = || {
            ViscousDamper::new(i, j, c, exponent)
                .and_then(|d| d.with_v0(v0))
                .map_err(core_err)
        };
        guarded(made).map(|e| ElementSpec(Spec::ViscousDamper(e)))
    }

    /// Friction pendulum on `dofs = (dof_x, dof_z)` or `(dof_x, dof_y, dof_z)`, normal force
    /// from the axial stiffness `kv`; `velocity = (mu_slow, rate)`, `pressure = (area,
    /// delta_mu, alpha)` for velocity- and pressure-dependent friction.
    #[staticmethod]
    #[pyo3(signature = (dofs, radius, mu, nominal, kv, velocity=None, pressure=None))]
    fn friction_pendulum_axial(
        dofs: Vec<usize>,
        radius: f64,
        mu: f64,
        nominal: (f64, f64),
        kv: f64,
        velocity: Option<(f64, f64)>,
        pressure: Option<(f64, f64, f64)>,
    ) -> PyResult<Self> {
        let made = || AxialFrictionPendulum::on(&dofs, radius, mu, nominal, kv);
        let made = || made().and_then(|e| e.with_friction(velocity, pressure));
        guarded(|| made().map_err(core_err)).map(|e| ElementSpec(Spec::AxialPendulum(e)))
    }

    /// Power-law viscous damper `law = (c, exponent, v0)` in series with a brace `kb` (Maxwell).
    #[staticmethod]
    fn maxwell_damper(i: usize, j: Option<usize>, law: (f64, f64, f64), kb: f64) -> PyResult<Self> {
        let damper = || ViscousDamper::new(i, j, law.0, law.1).and_then(|d| d.with_v0(law.2));
        let made = || {
            damper()
                .and_then(|d| MaxwellDamper::new(d, kb))
                .map_err(core_err)
        };
        guarded(made).map(|e| ElementSpec(Spec::Maxwell(e)))
    }

    /// Element minus the local linear part `k0 x + c0 v` (row-major `n x n` matrices at its
    /// `n` dofs): the remainder of an element whose linear part is in the background.
    #[staticmethod]
    fn shifted(
        inner: &Bound<'_, ElementSpec>,
        k0: &Bound<'_, PyAny>,
        c0: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let k0 = vec_of(k0, "k0")?;
        let c0 = vec_of(c0, "c0")?;
        let n = inner.get().n_dofs();
        for (name, m) in [("k0", &k0), ("c0", &c0)] {
            if m.len() != n * n {
                return Err(PyValueError::new_err(format!(
                    "`{name}` must hold {n} x {n} = {} entries, got {}",
                    n * n,
                    m.len()
                )));
            }
        }
        Ok(ElementSpec(Spec::Shifted {
            inner: inner.clone().unbind(),
            k0,
            c0,
        }))
    }

    /// Compression-only contact.
    #[staticmethod]
    #[pyo3(signature = (i, j, gap, k))]
    fn gap(i: usize, j: Option<usize>, gap: f64, k: f64) -> PyResult<Self> {
        guarded(|| Gap::new(i, j, gap, k).map_err(core_err)).map(|e| ElementSpec(Spec::Gap(e)))
    }

    /// A Python function `fn(x, v, t) -> r` of the local state at `dofs`, with an optional
    /// `jacobian(x, v, t) -> (dr/dx, dr/dv)`; with `state` (the initial internal variables)
    /// `fn(x, v, t, state) -> (r, trial_state)` and `jacobian(x, v, t, state)`.
    #[staticmethod]
    #[pyo3(signature = (dofs, func, jacobian=None, state=None))]
    fn callable(
        dofs: Vec<usize>,
        func: Py<PyAny>,
        jacobian: Option<Py<PyAny>>,
        state: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        if let Some(bad) = state
            .as_ref()
            .and_then(|s| s.iter().find(|x| !x.is_finite()))
        {
            return Err(PyValueError::new_err(format!(
                "`state` must be finite, got {bad}"
            )));
        }
        Ok(ElementSpec(Spec::Callable {
            dofs,
            func,
            jacobian,
            state,
        }))
    }
}

impl ElementSpec {
    /// The global dofs the element acts on, in its local order.
    fn dof_list(&self) -> Vec<usize> {
        match &self.0 {
            Spec::Polynomial(e) => e.dofs().to_vec(),
            Spec::Spring(e) => e.dofs().to_vec(),
            Spec::Damper(e) => e.dofs().to_vec(),
            Spec::Contact(e) => e.dofs().to_vec(),
            Spec::Bilinear(e) => e.dofs().to_vec(),
            Spec::BoucWen(e) => e.dofs().to_vec(),
            Spec::FrictionPendulum(e) => e.dofs().to_vec(),
            Spec::LeadRubber(e) => e.dofs().to_vec(),
            Spec::ViscousDamper(e) => e.dofs().to_vec(),
            Spec::Maxwell(e) => e.dofs().to_vec(),
            Spec::AxialPendulum(e) => e.dofs().to_vec(),
            Spec::Gap(e) => e.dofs().to_vec(),
            Spec::Journal(e) => e.dofs().to_vec(),
            Spec::SpeedTable(e) => e.dofs().to_vec(),
            Spec::Crack(e) => e.dofs().to_vec(),
            Spec::Device(d) => d.dofs(),
            Spec::Callable { dofs, .. } => dofs.clone(),
            Spec::Shifted { inner, .. } => inner.get().dof_list(),
        }
    }

    /// The number of local dofs of the element.
    fn n_dofs(&self) -> usize {
        self.dof_list().len()
    }
}

/// A fresh core element from its spec (Python elements are also kept in `built.python`).
pub(crate) fn make(
    py: Python<'_>,
    spec: &ElementSpec,
    built: &mut Built,
) -> PyResult<Box<dyn Element>> {
    Ok(match &spec.0 {
        Spec::Polynomial(e) => Box::new(e.clone()),
        Spec::Spring(e) => Box::new(e.clone()),
        Spec::Damper(e) => Box::new(e.clone()),
        Spec::Contact(e) => Box::new(e.clone()),
        Spec::Bilinear(e) => Box::new(e.clone()),
        Spec::BoucWen(e) => Box::new(e.clone()),
        Spec::FrictionPendulum(e) => Box::new(e.clone()),
        Spec::LeadRubber(e) => Box::new(e.clone()),
        Spec::ViscousDamper(e) => Box::new(e.clone()),
        Spec::Maxwell(e) => Box::new(e.clone()),
        Spec::AxialPendulum(e) => Box::new(e.clone()),
        Spec::Gap(e) => Box::new(e.clone()),
        Spec::Journal(e) => Box::new(e.clone()),
        Spec::SpeedTable(e) => Box::new(e.clone()),
        Spec::Crack(e) => Box::new(e.clone()),
        Spec::Device(d) => d.fresh(),
        Spec::Callable {
            dofs,
            func,
            jacobian,
            state,
        } => {
            let element = std::sync::Arc::new(PyElement::new(
                dofs.clone(),
                func.clone_ref(py),
                jacobian.as_ref().map(|j| j.clone_ref(py)),
                state.clone(),
            ));
            built.python.push(element.clone());
            Box::new(ArcElement(element))
        }
        Spec::Shifted { inner, k0, c0 } => {
            let inner = make(py, inner.get(), built)?;
            Box::new(Shifted::new(inner, k0.clone(), c0.clone()).map_err(core_err)?)
        }
    })
}
