//! The backbone of [`ModImkPeakOriented`](super::imk::ModImkPeakOriented): elastic, hardening
//! to the capping point, post-capping (negative) slope to the residual strength, residual
//! plateau, fracture at the ultimate deformation — OpenSees' `envelPosCap2` /
//! `envelNegCap2`, line for line (including their 1e-7 "zero" slopes and the 1e-10 force at
//! fracture).

/// One side of the current (deteriorated) backbone.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Side {
    /// Yield force (signed: negative on the negative side).
    pub fy: f64,
    /// Hardening ratio (of `elstk`).
    pub alpha: f64,
    /// Post-capping slope ratio (of `elstk`; negative on the positive side).
    pub alpha_cap: f64,
    /// Capping deformation.
    pub cp: f64,
    /// Elastic stiffness.
    pub elstk: f64,
    /// The initial yield force (the residual strength is `resfac` times it).
    pub fyield: f64,
    /// Residual strength ratio.
    pub resfac: f64,
    /// Fracture (ultimate) deformation, signed.
    pub frac: f64,
}

/// The slope OpenSees puts on its flat branches.
const FLAT: f64 = 1.0e-7;

impl Side {
    /// Positive side at `d`: `(f, ek)`; past the fracture deformation `d` is set to it and
    /// `flag_stop` to 1 (OpenSees' `envelPosCap2`).
    pub(crate) fn pos(&self, d: &mut f64, flag_stop: &mut f64) -> (f64, f64) {
        let Side {
            fy,
            alpha,
            alpha_cap,
            cp,
            elstk,
            fyield,
            resfac,
            frac,
        } = *self;
        let dy = fy / elstk;
        let (mut f, mut ek);
        if dy <= cp {
            let res = resfac * fyield;
            let rcap = fy + alpha * elstk * (cp - dy);
            let dres = cp + (res - rcap) / (alpha_cap * elstk);
            if *d < 0.0 {
                (f, ek) = (0.0, FLAT);
            } else if *d <= dy {
                ek = elstk;
                f = ek * *d;
            } else if *d <= cp {
                ek = elstk * alpha;
                f = fy + ek * (*d - dy);
            } else if *d <= dres {
                ek = alpha_cap * elstk;
                f = rcap + ek * (*d - cp);
            } else {
                ek = FLAT;
                f = res + *d * ek;
            }
        } else if dy > cp {
            let rcap = elstk * cp;
            let res = resfac * rcap;
            let dres = cp + (res - rcap) / (alpha_cap * elstk);
            if *d < 0.0 {
                (f, ek) = (0.0, FLAT);
            } else if *d <= cp {
                ek = elstk;
                f = ek * *d;
            } else if *d <= dres {
                ek = alpha_cap * elstk;
                f = rcap + ek * (*d - cp);
            } else {
                ek = FLAT;
                f = res + *d * ek;
            }
        } else {
            // NaN dy or cp: OpenSees leaves f and ek as they were; the caller's finite
            // check names the failure
            return (f64::NAN, f64::NAN);
        }
        if *d >= frac {
            ek = FLAT;
            f = 1.0e-10;
            *d = frac;
            *flag_stop = 1.0;
        }
        (f, ek)
    }

    /// Negative side at `d` (OpenSees' `envelNegCap2`; `frac` negative).
    pub(crate) fn neg(&self, d: &mut f64, flag_stop: &mut f64) -> (f64, f64) {
        let Side {
            fy,
            alpha,
            alpha_cap,
            cp,
            elstk,
            fyield,
            resfac,
            frac,
        } = *self;
        let dy = fy / elstk;
        let (mut f, mut ek);
        if dy >= cp {
            let res = resfac * fyield;
            let rcap = fy + alpha * elstk * (cp - dy);
            let dres = cp + (res - rcap) / (alpha_cap * elstk);
            if *d > 0.0 {
                (f, ek) = (0.0, FLAT);
            } else if *d >= dy {
                ek = elstk;
                f = ek * *d;
            } else if *d >= cp {
                ek = elstk * alpha;
                f = fy + ek * (*d - dy);
            } else if *d >= dres {
                ek = elstk * alpha_cap;
                f = rcap + ek * (*d - cp);
            } else {
                ek = FLAT;
                f = res + ek * *d;
            }
        } else if dy < cp {
            let rcap = elstk * cp;
            let res = resfac * rcap;
            let dres = cp + (res - rcap) / (alpha_cap * elstk);
            if *d > 0.0 {
                (f, ek) = (0.0, FLAT);
            } else if *d >= cp {
                ek = elstk;
                f = ek * *d;
            } else if *d >= dres {
                ek = elstk * alpha_cap;
                f = rcap + ek * (*d - cp);
            } else {
                ek = FLAT;
                f = res + ek * *d;
            }
        } else {
            return (f64::NAN, f64::NAN);
        }
        if *d <= frac {
            ek = FLAT;
            f = 1.0e-10;
            *d = frac;
            *flag_stop = 1.0;
        }
        (f, ek)
    }
}
