//! The built-in elements: one line each. Everything else about an element is in its own file
//! (its [`Definition`]); from this list come the enum a model holds ([`Defined`], serialised
//! with the element's name as its `"type"`), the enum the integrators evaluate ([`Runtime`],
//! each element called directly, without dynamic dispatch), and, through
//! [`for_each_element!`](crate::for_each_element), the binding's Python classes.

/// Calls the macro `$m` with the list of built-in elements, `Name: DefinitionType`.
#[macro_export]
macro_rules! for_each_element {
    ($m:ident) => {
        $m! {
            Bilinear: $crate::elements::hysteretic::bilinear::BilinearDef,
            BoucWen: $crate::elements::hysteretic::boucwen::BoucWenDef,
            BreathingCrack: $crate::elements::crack::BreathingCrackDef,
            Contact: $crate::elements::contact::ContactDef,
            Cubic: $crate::elements::polynomial::CubicDef,
            Damper: $crate::elements::spring::DamperDef,
            ElasticMultiLinear: $crate::elements::materials::elastic_multilinear::ElasticMultiLinearDef,
            FrictionPendulum: $crate::elements::hysteretic::pendulum::FrictionPendulumDef,
            Gap: $crate::elements::hysteretic::gap::GapDef,
            Hysteretic: $crate::elements::materials::hysteretic_def::HystereticDef,
            IMKBilin: $crate::elements::materials::imk_bilin_def::ImkBilinDef,
            JournalElement: $crate::elements::journal::JournalElementDef,
            LeadRubberBearing: $crate::elements::hysteretic::rubber::LeadRubberBearingDef,
            MinMax: $crate::elements::materials::minmax::MinMaxDef,
            ModIMKPeakOriented: $crate::elements::materials::imk_def::ModImkPeakOrientedDef,
            MultiLinear: $crate::elements::materials::multilinear::MultiLinearDef,
            Parallel: $crate::elements::materials::parallel::ParallelDef,
            Pinching4: $crate::elements::materials::pinching4_def::Pinching4Def,
            Polynomial: $crate::elements::polynomial::PolynomialDef,
            Series: $crate::elements::materials::series::SeriesDef,
            Spring: $crate::elements::spring::SpringDef,
            SpeedTableBearing: $crate::elements::table::SpeedTableBearingDef,
            Steel02: $crate::elements::materials::steel02::Steel02Def,
            Takeda: $crate::elements::materials::takeda::TakedaDef,
            TripleFrictionPendulum: $crate::elements::hysteretic::triple_model::TripleFrictionPendulumDef,
            ViscousDamper: $crate::elements::hysteretic::maxwell::ViscousDamperDef,
        }
    };
}

macro_rules! registry {
    ($($name:ident: $def:ty),* $(,)?) => {
        /// A built-in element as a model holds it: its definition.
        // A definition is made once per element of a model, never per step: the size of the
        // largest (Pinching4's 39 parameters) costs nothing where it matters.
        #[allow(clippy::large_enum_variant)]
        #[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
        #[serde(tag = "type")]
        pub enum Defined {
            $(
                #[doc = concat!("`", stringify!($name), "`")]
                $name($def),
            )*
        }

        $(
            impl From<$def> for Defined {
                fn from(d: $def) -> Self {
                    Defined::$name(d)
                }
            }
        )*

        /// A built-in element as the integrators evaluate it.
        #[derive(Clone, Debug)]
        pub enum Runtime {
            $(
                #[doc = concat!("`", stringify!($name), "`")]
                $name(<$def as Definition>::Runtime),
            )*
        }

        /// Per built-in element: `(name, signature, documentation, legacy positional names)`.
        pub const ELEMENTS: &[(&str, &str, &str, &[&str])] = &[
            $((<$def>::NAME, <$def>::SIGNATURE, <$def>::DOC, <$def>::LEGACY),)*
        ];

        impl Defined {
            /// The element's class name.
            pub fn name(&self) -> &'static str {
                match self { $(Defined::$name(_) => <$def>::NAME,)* }
            }

            /// The engine element, checked.
            pub fn build(&self) -> Result<Runtime, CoreError> {
                match self { $(Defined::$name(d) => d.build().map(Runtime::$name),)* }
            }

            /// [`Definition::passive`].
            pub fn passive(&self) -> bool {
                match self { $(Defined::$name(d) => d.passive(),)* }
            }

            /// [`Definition::linear_stiffness`].
            pub fn linear_stiffness(&self) -> Option<Vec<f64>> {
                match self { $(Defined::$name(d) => d.linear_stiffness(),)* }
            }

            /// [`Definition::without_linear`].
            pub fn without_linear(&self) -> Option<Defined> {
                match self { $(Defined::$name(d) => d.without_linear().map(Defined::$name),)* }
            }

            /// [`Definition::tangent_bound`].
            pub fn tangent_bound(&self) -> Option<(f64, f64)> {
                match self { $(Defined::$name(d) => d.tangent_bound(),)* }
            }

            /// [`Definition::directions`].
            pub fn directions(&self) -> Option<Vec<Pair>> {
                match self { $(Defined::$name(d) => d.directions(),)* }
            }

            /// [`Definition::stored_energy`].
            pub fn stored_energy(&self, u: &[f64], f: &[f64]) -> f64 {
                match self { $(Defined::$name(d) => d.stored_energy(u, f),)* }
            }

            /// [`Definition::linear`].
            pub fn linear(&self) -> Result<(Vec<f64>, Vec<f64>), String> {
                match self { $(Defined::$name(d) => d.linear(),)* }
            }

            /// [`Definition::material`].
            pub fn material(&self) -> Option<Result<Box<dyn Material>, CoreError>> {
                match self { $(Defined::$name(d) => d.material(),)* }
            }

            /// [`Definition::rename`] of the element `name`.
            pub fn rename(name: &str, old: &str) -> Option<(&'static str, Option<usize>)> {
                match name {
                    $(n if n == <$def>::NAME => <$def>::rename(old),)*
                    _ => None,
                }
            }
        }

        impl Runtime {
            #[inline(always)]
            fn get(&self) -> &dyn Element {
                match self { $(Runtime::$name(e) => e,)* }
            }
        }

        impl Element for Runtime {
            fn dofs(&self) -> &[usize] {
                self.get().dofs()
            }

            #[inline]
            fn eval(
                &self,
                x: &[f64],
                v: &[f64],
                t: f64,
                r: &mut [f64],
                tangent: Option<Tangent<'_>>,
            ) -> Result<(), CoreError> {
                match self { $(Runtime::$name(e) => e.eval(x, v, t, r, tangent),)* }
            }

            fn polynomial_degree(&self) -> Option<u32> {
                self.get().polynomial_degree()
            }

            fn uses_velocity(&self) -> bool {
                self.get().uses_velocity()
            }

            fn has_tangent(&self) -> bool {
                self.get().has_tangent()
            }

            fn state_len(&self) -> usize {
                self.get().state_len()
            }

            fn initial_state(&self, x: &[f64], v: &[f64], state: &mut [f64]) {
                self.get().initial_state(x, v, state)
            }

            fn initial_time(&self, t0: f64, state: &mut [f64]) {
                self.get().initial_time(t0, state)
            }

            #[inline(always)]
            fn eval_path(
                &self,
                x: &[f64],
                v: &[f64],
                t: f64,
                history: PathState<'_>,
                r: &mut [f64],
                tangent: Option<Tangent<'_>>,
            ) -> Result<(), CoreError> {
                match self {
                    $(Runtime::$name(e) => e.eval_path(x, v, t, history, r, tangent),)*
                }
            }

            fn modal_cubic(&self, phi: &[f64]) -> Option<ModalCubic> {
                self.get().modal_cubic(phi)
            }

            fn path_reads(&self) -> Option<(bool, bool)> {
                self.get().path_reads()
            }

            fn restarts_exactly(&self) -> bool {
                self.get().restarts_exactly()
            }

            fn resolution(&self) -> f64 {
                self.get().resolution()
            }

            fn as_any(&self) -> Option<&dyn std::any::Any> {
                Some(self)
            }
        }
    };
}

use super::definition::{Definition, Pair};
use super::element::{Element, ModalCubic, PathState, Tangent};
use super::materials::material::Material;
use crate::error::CoreError;

crate::for_each_element!(registry);

impl Defined {
    /// The definition of the element `name` from its parameters `params` (a JSON object of
    /// the serde field names); errors name the missing or invalid parameter.
    pub fn from_params(
        name: &str,
        mut params: serde_json::Map<String, serde_json::Value>,
    ) -> Result<Self, serde_json::Error> {
        params.insert("type".into(), serde_json::Value::String(name.into()));
        serde_json::from_value(serde_json::Value::Object(params))
    }

    /// The parameters as a JSON object (without the `"type"` tag).
    pub fn params(&self) -> serde_json::Map<String, serde_json::Value> {
        match serde_json::to_value(self) {
            Ok(serde_json::Value::Object(mut map)) => {
                map.remove("type");
                map
            }
            // a definition is a struct of numbers, strings and sequences: always an object
            _ => serde_json::Map::new(),
        }
    }
}

/// A scalar two-node law whose force and tangent on the deformation `u` follow from the
/// committed `(u_c, F_c)` alone (what [`Element::eval_path`] computes): the element space
/// evaluates such an element directly on its deformation (`Evaluation::evaluate_deformation`).
pub(crate) trait ScalarLaw {
    /// `(F, dF/du)` at deformation `u` from the committed `(u_c, F_c)`.
    fn path_response(&self, committed: (f64, f64), u: f64) -> (f64, f64);
}

impl Runtime {
    /// The element's [`ScalarLaw`], where it has one (the `Bilinear`), else None.
    #[inline(always)]
    pub(crate) fn scalar_law(&self) -> Option<&(impl ScalarLaw + '_)> {
        match self {
            Runtime::Bilinear(b) => Some(b),
            _ => None,
        }
    }
}
