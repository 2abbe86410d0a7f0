//! The substep rule of the pseudo-force route (stability and accuracy of a step that an
//! element stiffer than its background dominates) and the coupled route's limit; the levels
//! that take the substeps are [`super::subdivide`]'s.

use super::force::PseudoForce;
use super::local::DOMINANT;
use crate::error::CoreError;

/// The largest `omega_c dt` a (sub)step may take, `omega_c^2` the closed state's frequency
/// bound of [`super::local::ElementSpace::tangent_stiffness`] (elements that dominate the
/// modes they load). The pseudo-force step (scheme b, trapezoid) of an element much stiffer
/// than its background is the linear-acceleration method, stable up to
/// `omega_c dt = 2 sqrt(3) = 3.46`; with the background the limit is 3.30 - 3.32 for an
/// element as stiff as it and 3.21 - 3.30 for 0.3 of it (zeta 0 - 0.05; docs/nonlinear.md).
/// Steps are held below 2 and subdivided when the elements stiffen beyond: a hardening element
/// stiffens inside the step, and at 3 a stiff `Cubic` still grew (peak 2.5 times the
/// converged one at omega_c dt = 10 subdivided to <= 3; at <= 2 it is within 2 %).
pub(super) const STIFF_LIMIT: f64 = 2.0;

/// The `omega_c dt` of a substep the accuracy rule aims at (see [`depth_for`]).
pub(super) const ACCURATE_LIMIT: f64 = 1.0;

/// The largest change of the closed state's `ln omega_c^2` over a substep the accuracy rule
/// allows (see [`depth_for`]).
pub(super) const CHANGE_LIMIT: f64 = 2.0;

/// The largest `omega_c dt` the coupled (first-order) route, which does not subdivide,
/// steps at: measured on a stiff stop with non-classical damping (`Gap(k=1e8)` on two dofs
/// of 1e4, issue 23) its error was 0.011 of the peak at 0.45 (Newmark's 0.098) and 0.084 at
/// 0.89 (Newmark's 0.027). Beyond it the run stops, naming the element.
pub(crate) const COUPLED_LIMIT: f64 = 0.5;

/// The halvings that bring `x` within `limit`.
fn halvings_to(x: f64, limit: f64) -> usize {
    if x <= limit {
        0
    } else {
        (x / limit).log2().ceil().min(64.0) as usize
    }
}

/// The one substep rule, for a step of the run's `dt` at `omega_c dt = h` (`omega_c` of the
/// elements that dominate the modes they load, the larger at its ends; 0 when none does),
/// `peak` the largest `omega_c dt` of the run so far (see [`Watch`]) and `change` the change
/// of `ln omega_c^2` over the step, with `max_depth` levels of subdivision: `Ok(d)`, the step
/// is taken in `2^d` substeps, or `Err(d)` when stability needs `d > max_depth` halvings.
///
/// Stability: substeps of `omega_c dt <= STIFF_LIMIT`, or the run stops. Accuracy (as far as
/// `max_depth` allows; it never stops a run): substeps of `omega_c dt <= ACCURATE_LIMIT` at
/// the run's `peak` (beyond, the stiff state's phase error over many of its periods grew
/// larger than Newmark's at the same step: a `Cubic` 1e4 times its mode at `omega_c dt = 1`,
/// 0.61 of the peak against 0.24; docs/nonlinear.md, "Stiff elements"), and substeps over
/// which the closed state's stiffness changes by at most `e^CHANGE_LIMIT` (a gap closing, a
/// smoothed contact's ramp, a yield: a kink inside the step, where the trapezoid of the
/// pseudo-force erred 1.3 - 1.5 times more than Newmark at `omega_c dt = 0.1`, and a ramp
/// faster than the stiff state vibrates). Both limits are the largest that keep the whole
/// family within Newmark's error while the paper's Duffing oscillator (12 times its
/// background at the amplitude, `omega_c dt` 0.23 and 0.45 at 100 and 50 steps per period,
/// its stiffness changing by at most `e^0.64` per step) keeps its plain steps.
pub(super) fn depth_for(h: f64, peak: f64, change: f64, max_depth: usize) -> Result<usize, usize> {
    if h.is_nan() || h <= 0.0 {
        return Ok(0);
    }
    let stable = halvings_to(h, STIFF_LIMIT);
    if stable > max_depth {
        return Err(stable);
    }
    let accurate = halvings_to(peak.max(h), ACCURATE_LIMIT).max(halvings_to(change, CHANGE_LIMIT));
    Ok(stable.max(accurate.min(max_depth)))
}

/// The change of `ln omega_c^2` from `start` to `end` (`(omega_c^2, background)`, 0: no
/// element dominates; at least one of them dominated): an element that starts or stops
/// dominating changes the stiffness from its threshold, `DOMINANT + 1` times the background.
fn log_change(start: (f64, f64), end: (f64, f64)) -> f64 {
    let threshold = |b: f64| (DOMINANT + 1.0) * b;
    let (a, b) = if end.0 > 0.0 && start.0 > 0.0 {
        (end.0, start.0)
    } else if end.0 > 0.0 {
        (end.0, threshold(end.1))
    } else {
        (start.0, threshold(start.1))
    };
    if b > 0.0 {
        (a / b).ln().abs()
    } else {
        f64::INFINITY
    }
}

/// The refinement of the coupled route's quadrature over a step from `start` to `end`
/// (`(omega_c^2, background)` of its elements; [`super::first_order`]'s `kink.rs`): where an
/// element starts or stops dominating (a gap closing or opening, a contact touching or
/// leaving), the halvings that bring the change of `ln omega_c^2` from its threshold within
/// [`CHANGE_LIMIT`] per piece, at most `max`; 0 otherwise. A change while the elements keep
/// dominating (a smoothed contact's ramp) is left to the trapezoid: refining the quadrature
/// there without substeps of the state made a stiff `Contact` (kappa 1e4, `omega_c dt` 0.1,
/// coupled family of docs/nonlinear.md) 7 times less accurate (4.5e-4 of the peak against
/// 6.5e-5; Newmark 1.7e-4).
pub(crate) fn kink_depth(start: (f64, f64), end: (f64, f64), max: usize) -> usize {
    let onset = (start.0 > 0.0) != (end.0 > 0.0);
    if !onset || start.0.is_nan() || end.0.is_nan() {
        return 0;
    }
    halvings_to(log_change(start, end), CHANGE_LIMIT).min(max)
}

/// The number of halvings that bring `omega_c dt` (`h`) within [`STIFF_LIMIT`].
pub(super) fn halvings(h: f64) -> usize {
    halvings_to(h, STIFF_LIMIT)
}

/// A modal state `(q, v)` at `t`.
pub(super) type State<'s> = (&'s [f64], &'s [f64], f64);

/// The stiffness watch of a run: the closed state's `omega_c^2`
/// ([`super::local::ElementSpace::tangent_stiffness`]) at the start of the (sub)step, the
/// largest met so far and the largest accuracy depth needed so far, and the substep rule
/// ([`depth_for`]) on them. A dominated step is taken at least as finely as any before it:
/// a tangent that varies inside a contact (a smoothed `Contact`, a `Cubic`, the ramp into a
/// stop) would otherwise change the substep from step to step while the stiff state
/// vibrates, and each change costs the linear-acceleration step its energy balance
/// (measured: a stiff `Contact` at `omega_c dt = 1` in 2 and 3 levels: 9.5e-4 and 4.0e-3 of
/// the peak with the depth following the tangent, 1.2e-4 and 3.0e-5 in uniform substeps;
/// with the ramp taken finely and the rest coarser, 9.8e-3 against Newmark's 4.4e-3).
#[derive(Clone, Debug)]
pub(super) struct Watch {
    /// `omega_c^2` at the start of the (sub)step (0: no element dominates) and the
    /// background's modal stiffness it counted.
    start: (f64, f64),
    /// The largest `omega_c^2` met so far.
    peak: f64,
    /// The largest accuracy depth a dominated (sub)step has needed so far.
    held: std::cell::Cell<usize>,
}

impl Watch {
    /// The watch of a run whose initial state has `omega_c^2 = start.0` over a background
    /// of `start.1`.
    pub fn new(start: (f64, f64)) -> Self {
        Watch {
            start,
            peak: if start.0 > 0.0 { start.0 } else { 0.0 },
            held: std::cell::Cell::new(0),
        }
    }

    /// The depth ([`depth_for`]) of a (sub)step from the last accepted state to one whose
    /// elements' `omega_c^2` is `end.0` over a background `end.1`, the (sub)step `fraction`
    /// of the run's `dt`, with `max_depth` levels. An element that starts or stops
    /// dominating changes the stiffness from its threshold, `DOMINANT + 1` times the
    /// background.
    pub fn depth(
        &self,
        end: (f64, f64),
        dt: f64,
        fraction: f64,
        max_depth: usize,
    ) -> Result<usize, usize> {
        let lambda = end.0.max(self.start.0);
        if lambda.is_nan() || lambda <= 0.0 {
            return Ok(0);
        }
        let change = log_change(self.start, end) / fraction;
        let peak = self.peak.max(lambda);
        let need = depth_for(dt * lambda.sqrt(), dt * peak.sqrt(), change, max_depth)?;
        self.held.set(self.held.get().max(need));
        Ok(need.max(self.held.get().min(max_depth)))
    }

    /// The depth of a run's step from `ends.0` to its trial end `ends.1` (`(q, v, t)`),
    /// `max_depth` levels available: 0 (the trial is kept, and accepted), the substeps'
    /// depth, or the failure naming the element when stability needs more levels.
    pub fn decide(
        &mut self,
        pf: &mut PseudoForce,
        ends: (State, State),
        dt: f64,
        max_depth: usize,
    ) -> Result<usize, CoreError> {
        let ((q0, v0, t0), (q1, v1, t1)) = ends;
        let (lambda, worst) = pf.tangent_stiffness(q1, v1, t1)?;
        let end = (lambda, pf.space().background());
        match self.depth(end, dt, 1.0, max_depth) {
            Ok(0) => {
                self.accept(end);
                Ok(0)
            }
            Ok(need) => Ok(need),
            Err(_) => {
                let start = self.start.0;
                let at = if lambda >= start {
                    (lambda, worst)
                } else {
                    pf.tangent_stiffness(q0, v0, t0).unwrap_or((start, worst))
                };
                Err(too_stiff(pf, at, dt, 0))
            }
        }
    }

    /// An accepted (sub)step ends at `omega_c^2 = end.0` over a background `end.1`.
    pub fn accept(&mut self, end: (f64, f64)) {
        self.start = end;
        if end.0 > self.peak {
            self.peak = end.0;
        }
    }
}

/// The failure of a step whose elements are too stiff for it even at the deepest level
/// (`depth` halvings; `lambda` their modal stiffness, `worst` the element adding most).
pub(super) fn too_stiff(
    pf: &PseudoForce,
    (lambda, worst): (f64, usize),
    dt: f64,
    depth: usize,
) -> CoreError {
    let h = dt * lambda.sqrt();
    let dofs = pf.space().element_dofs(worst);
    let step = dt * 2f64.powi(depth as i32);
    CoreError::TooStiff {
        message: format!(
            "element {worst} (on dofs {dofs:?}) is too stiff for the step: with its tangent \
             the modes it loads (dominating them) vibrate at omega_c^2 = {lambda:.4e} \
             (rad/s)^2, omega_c dt = {h:.4} in steps of {dt:e} after {depth} halvings of \
             dt = {step:e} (`subdivisions`), and the pseudo-force step is held below \
             omega_c dt = {STIFF_LIMIT} (unstable beyond 2 sqrt(3) = 3.46); reduce `dt` below \
             {:.4e} or raise `subdivisions` to {}",
            STIFF_LIMIT * 2f64.powi(depth as i32) / lambda.sqrt(),
            depth + halvings(h)
        ),
        time: 0.0,
        step: 0,
        last_good_time: None,
    }
}

#[cfg(test)]
mod tests {
    use super::{depth_for, kink_depth, Watch, ACCURATE_LIMIT, CHANGE_LIMIT, STIFF_LIMIT};

    /// The rule: stability first (an error when the levels cannot reach it), then accuracy
    /// as far as the levels allow; nothing for a step no element dominates.
    #[test]
    fn one_rule_for_stability_and_accuracy() {
        assert_eq!((ACCURATE_LIMIT, CHANGE_LIMIT), (1.0, 2.0));
        assert_eq!(depth_for(0.0, 10.0, f64::INFINITY, 4), Ok(0));
        assert_eq!(depth_for(f64::NAN, 0.0, 0.0, 4), Ok(0));
        // within both limits: the plain step
        assert_eq!(
            depth_for(ACCURATE_LIMIT, ACCURATE_LIMIT, CHANGE_LIMIT, 4),
            Ok(0)
        );
        // accuracy: omega_c dt 2 -> 1 in one halving, capped by the levels, never an error
        assert_eq!(depth_for(2.0, 2.0, 0.0, 4), Ok(1));
        assert_eq!(depth_for(2.0, 2.0, 0.0, 0), Ok(0));
        // the run's peak, not the current stiffness, sets the accuracy depth
        assert_eq!(depth_for(0.1, 4.0, 0.0, 4), Ok(2));
        // a fast change of the stiffness: e^8 over the step -> 2 halvings to e^2
        assert_eq!(depth_for(0.1, 0.1, 8.0, 4), Ok(2));
        assert_eq!(depth_for(0.1, 0.1, f64::INFINITY, 4), Ok(4));
        // stability: 2^3 substeps bring 10 to 1.25; with 2 levels the run stops
        assert_eq!(depth_for(10.0, 10.0, 0.0, 2), Err(3));
        assert_eq!(depth_for(2.0 * STIFF_LIMIT, 0.0, 0.0, 1), Ok(1));
        assert_eq!(depth_for(10.0, 10.0, 0.0, 6), Ok(4));
    }

    /// The coupled route's kinks: only where an element starts or stops dominating, as
    /// many halvings as bring the change from the threshold within e^2, capped.
    #[test]
    fn kink_depth_refines_onset_and_offset_only() {
        // a gap closing at 1e6 x a background of 1: ln(1e6 / 3) = 12.7 -> 3 halvings
        assert_eq!(kink_depth((0.0, 1.0), (1e6, 1.0), 4), 3);
        assert_eq!(kink_depth((1e6, 1.0), (0.0, 1.0), 4), 3);
        assert_eq!(kink_depth((0.0, 1.0), (1e6, 1.0), 2), 2);
        // just dominating: within e^2 of the threshold
        assert_eq!(kink_depth((0.0, 1.0), (5.0, 1.0), 4), 0);
        // dominating at both ends, however fast it changes; dominating at neither
        assert_eq!(kink_depth((10.0, 1.0), (1e6, 1.0), 4), 0);
        assert_eq!(kink_depth((0.0, 1.0), (0.0, 1.0), 4), 0);
        assert_eq!(kink_depth((f64::NAN, 1.0), (1e6, 1.0), 4), 0);
    }

    /// The watch: an element that starts dominating changes the stiffness from its
    /// threshold (3 times the background); the peak and the depth it needed are kept.
    #[test]
    fn watch_counts_onset_from_the_threshold_and_keeps_the_depth() {
        let dt = 0.01;
        let mut w = Watch::new((0.0, 1.0));
        // just dominating (3.1 x a background of 1): no change worth a substep
        assert_eq!(w.depth((3.1, 1.0), dt, 1.0, 4), Ok(0));
        // a gap closing at 1e4 x its background: ln(1e4 / 3) = 8.1 -> 3 halvings to e^2
        assert_eq!(w.depth((1e4, 1.0), dt, 1.0, 4), Ok(3));
        w.accept((1e4, 1.0));
        // closed and steady at omega_c dt = 1: no substep needed, the depth is held
        assert_eq!(w.depth((1e4, 1.0), dt, 1.0, 4), Ok(3));
        // fewer levels available: as many as there are
        assert_eq!(w.depth((1e4, 1.0), dt, 1.0, 2), Ok(2));
        w.accept((0.0, 0.0));
        // open: the plain step
        assert_eq!(w.depth((0.0, 0.0), dt, 1.0, 4), Ok(0));
        // a fresh watch: steady at omega_c dt = 2, one halving, also for a half substep
        let mut fresh = Watch::new((4e4, 1.0));
        assert_eq!(fresh.depth((4e4, 1.0), dt, 1.0, 4), Ok(1));
        fresh.accept((4e4, 1.0));
        assert_eq!(fresh.depth((4e4, 1.0), dt, 0.5, 4), Ok(1));
    }
}
