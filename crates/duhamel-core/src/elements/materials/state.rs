//! Named internal variables kept in a material's state slice.
//!
//! [`material_state!`] declares a struct of `f64` fields (flags and counters are stored as
//! exact small integers) with `LEN`, `load` from and `store` into the slice, in the order the
//! fields are written. A material loads its committed variables, works on the copy as
//! OpenSees' `setTrialStrain` works on its trial members, and stores the copy as the trial.

/// Declares a struct of named `f64` internal variables stored in declaration order.
macro_rules! material_state {
    ($(#[$meta:meta])* $name:ident { $($(#[$fmeta:meta])* $field:ident),* $(,)? }) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        pub(crate) struct $name {
            $($(#[$fmeta])* pub(crate) $field: f64,)*
        }

        impl $name {
            /// The number of variables.
            pub(crate) const LEN: usize = [$(stringify!($field)),*].len();

            /// The variables from `s` (`s.len() >= LEN`).
            #[inline]
            pub(crate) fn load(s: &[f64]) -> Self {
                // one copy of LEN values (a field-by-field iterator was 3 % of a
                // ModIMKPeakOriented step)
                let s = &s[..Self::LEN];
                let values: [f64; Self::LEN] = std::array::from_fn(|k| s[k]);
                let [$($field),*] = values;
                Self { $($field,)* }
            }

            /// Writes the variables into `s` (`s.len() >= LEN`).
            #[inline]
            pub(crate) fn store(&self, s: &mut [f64]) {
                let values = [$(self.$field),*];
                s[..Self::LEN].copy_from_slice(&values);
            }
        }
    };
}

pub(crate) use material_state;

/// `true` stored as 1, `false` as 0.
#[inline]
pub(crate) fn flag(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// A parameter check: `ok`, or `InvalidInput` naming `name` with `problem` and the value.
pub(crate) fn require(
    ok: bool,
    name: &'static str,
    value: f64,
    problem: &str,
) -> Result<(), crate::error::CoreError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(crate::error::CoreError::InvalidInput {
            name,
            problem: format!("must be finite and {problem}, got {value}"),
        })
    }
}
