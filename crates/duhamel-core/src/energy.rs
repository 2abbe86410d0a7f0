//! The energy balance accumulated during a run: an output stage a route feeds with the end
//! state of every step when the run asks for it (and never otherwise).
//!
//! The work integrals need the response between the saved instants, so they are integrated
//! here, step by step, and sampled at the saved instants; the state functions (kinetic and
//! strain energy) are exact at any saved instant and are left to the caller. Over a step
//! `[t0, t1]` with end states `0` and `1` (modal velocities `v`, modal external load `p`,
//! elements' local displacements `u` and forces `F`, ground accelerations `a_g`):
//!
//! * damping `int v^T C v dt ~ dt/2 (v0^T C v0 + v1^T C v1)` (`C` the modal damping matrix
//!   `Phi^T C Phi`);
//! * input (relative) `int v . p dt ~ dt/2 (v0 . p0 + v1 . p1)`;
//! * each element's work `int F . du ~ (F0 + F1)/2 . (u1 - u0)` (the trapezoid in the
//!   deformation: the loop integral of its force-deformation path);
//! * the ground velocity `v_g = v_g0 + int a_g dt`, exact for the step's load parabola;
//! * the absolute input less the relative one, per base excitation `b` with `w_b = Phi^T M
//!   r_b`: `int (w_b . v) a_g,b dt + int v_g,b d(w_b . v) + sum_b' r_b^T M r_b' int v_g,b
//!   a_g,b' dt` (trapezoids; the middle one a Stieltjes trapezoid, which needs no
//!   acceleration).
//!
//! Every rule is the trapezoid on the step's end states: second order in `dt`.

use crate::error::CoreError;

/// What the energy accumulator needs of the model, in modal coordinates.
#[derive(Debug, Clone, Copy)]
pub struct EnergySpec<'a> {
    /// The modal damping matrix `Phi^T C Phi`, `n_modes x n_modes` row-major; empty when
    /// the route gives the damping power itself (the direct integrators, with their
    /// physical `C`).
    pub damping: &'a [f64],
    /// For each base excitation, the index of the load whose time function is its ground
    /// acceleration.
    pub base_loads: &'a [usize],
    /// `w_b = Phi^T M r_b` of each base excitation, `n_bases x n_modes` row-major.
    pub base_w: &'a [f64],
    /// `r_b^T M r_b'`, `n_bases x n_bases` row-major.
    pub base_rr: &'a [f64],
    /// The ground velocities at the start of the run, one per base excitation.
    pub vg0: &'a [f64],
    /// The linear parts the background took over from the elements, whose forces the
    /// route's element record leaves out: per element of `w` local dofs, `k0` then `c0`
    /// (`w x w` each, row-major), the elements in order; empty: none.
    pub linear: &'a [f64],
}

impl EnergySpec<'_> {
    /// Checks the sizes against `n_modes` modes, `n_loads` loads and the elements' local
    /// `widths`.
    pub fn check(&self, n_modes: usize, n_loads: usize, widths: &[usize]) -> Result<(), CoreError> {
        let nb = self.base_loads.len();
        let linear: usize = widths.iter().map(|w| 2 * w * w).sum();
        let linear = if self.linear.is_empty() { 0 } else { linear };
        let damping = if self.damping.is_empty() {
            0
        } else {
            n_modes * n_modes
        };
        for (name, got, expected) in [
            ("energy linear parts", self.linear.len(), linear),
            ("energy damping matrix", self.damping.len(), damping),
            ("energy base directions", self.base_w.len(), nb * n_modes),
            ("energy base products", self.base_rr.len(), nb * nb),
            ("energy ground velocities", self.vg0.len(), nb),
        ] {
            if got != expected {
                return Err(CoreError::LengthMismatch {
                    name,
                    got,
                    expected,
                });
            }
        }
        if let Some(&l) = self.base_loads.iter().find(|&&l| l >= n_loads) {
            return Err(CoreError::InvalidInput {
                name: "energy",
                problem: format!("names load {l} of {n_loads} as a base excitation"),
            });
        }
        Ok(())
    }
}

/// The accumulated energies at the saved instants: `n_saved x n_cols`, the columns
/// `[damping, input, absolute - relative input, v_g (one per base), element work (one per
/// element)]`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EnergyRows {
    pub n_cols: usize,
    pub values: Vec<f64>,
}

/// The end of a step, as the accumulator reads it.
pub struct StepEnd<'a> {
    /// Modal velocities at the end.
    pub v: &'a [f64],
    /// The modal external load at the start and at the end of the step.
    pub p: (&'a [f64], &'a [f64]),
    /// The load basis `(p0, Dp, DDp)` of every load over the step (`n_loads` entries).
    pub load_basis: &'a [[f64; 3]],
    /// The elements' local displacements and forces at the end.
    pub elements: (&'a [f64], &'a [f64]),
    /// The damping power `v^T C v` at the end, when the route gives it (else from the
    /// spec's damping matrix).
    pub damping_power: Option<f64>,
}

/// The running integrals of a run (see the module docs).
#[derive(Debug, Clone)]
pub struct EnergyAccumulator {
    n: usize,
    damping_matrix: Vec<f64>,
    base_loads: Vec<usize>,
    base_w: Vec<f64>,
    base_rr: Vec<f64>,
    widths: Vec<usize>,
    // running totals
    damping: f64,
    input: f64,
    absolute: f64,
    vg: Vec<f64>,
    work: Vec<f64>,
    // the last step end
    v: Vec<f64>,
    power_c: f64,
    wv: Vec<f64>,
    u: Vec<f64>,
    f: Vec<f64>,
    started: bool,
    rows: EnergyRows,
}

impl EnergyAccumulator {
    /// An accumulator of `n` modes and elements of local widths `widths`, saving `n_saved`
    /// rows.
    pub fn new(spec: &EnergySpec, n: usize, widths: Vec<usize>, n_saved: usize) -> Self {
        let nb = spec.base_loads.len();
        let width: usize = widths.iter().sum();
        let n_cols = 3 + nb + widths.len();
        EnergyAccumulator {
            n,
            damping_matrix: spec.damping.to_vec(),
            base_loads: spec.base_loads.to_vec(),
            base_w: spec.base_w.to_vec(),
            base_rr: spec.base_rr.to_vec(),
            damping: 0.0,
            input: 0.0,
            absolute: 0.0,
            vg: spec.vg0.to_vec(),
            work: vec![0.0; widths.len()],
            widths,
            v: vec![0.0; n],
            power_c: 0.0,
            wv: vec![0.0; nb],
            u: vec![0.0; width],
            f: vec![0.0; width],
            started: false,
            rows: EnergyRows {
                n_cols,
                values: vec![0.0; n_saved * n_cols],
            },
        }
    }

    /// The total width of the elements' local dofs.
    pub fn element_width(&self) -> usize {
        self.u.len()
    }

    /// Whether the start state has been given.
    pub fn started(&self) -> bool {
        self.started
    }

    fn quadratic(&self, v: &[f64]) -> f64 {
        let n = self.n;
        if self.damping_matrix.is_empty() {
            return 0.0;
        }
        self.damping_matrix
            .chunks_exact(n.max(1))
            .zip(v)
            .map(|(row, &vi)| vi * crate::dense::dot(row, v))
            .sum()
    }

    fn base_products(&self, v: &[f64], out: &mut [f64]) {
        for (o, w) in out.iter_mut().zip(self.base_w.chunks_exact(self.n.max(1))) {
            *o = crate::dense::dot(w, v);
        }
    }

    /// Sets the state the integrals start from: modal velocities `v` and the elements'
    /// local displacements `u` and forces `f`.
    pub fn start(&mut self, v: &[f64], (u, f): (&[f64], &[f64])) {
        self.start_with(v, (u, f), None);
    }

    /// [`EnergyAccumulator::start`] with the damping power given (see
    /// [`StepEnd::damping_power`]).
    pub fn start_with(&mut self, v: &[f64], (u, f): (&[f64], &[f64]), power: Option<f64>) {
        self.v.copy_from_slice(v);
        self.power_c = power.unwrap_or_else(|| self.quadratic(v));
        let mut wv = std::mem::take(&mut self.wv);
        self.base_products(v, &mut wv);
        self.wv = wv;
        self.u.copy_from_slice(u);
        self.f.copy_from_slice(f);
        self.started = true;
    }

    /// Adds the step of length `dt` that ends at `end`.
    pub fn step(&mut self, dt: f64, end: &StepEnd) {
        let half = 0.5 * dt;
        let (p0, p1) = end.p;
        let v1 = end.v;
        let power_c = end.damping_power.unwrap_or_else(|| self.quadratic(v1));
        self.damping += half * (self.power_c + power_c);
        self.power_c = power_c;
        self.input += half * (crate::dense::dot(&self.v, p0) + crate::dense::dot(v1, p1));
        // The elements' work: the trapezoid in their deformation.
        let (u1, f1) = end.elements;
        let mut at = 0;
        for (work, &w) in self.work.iter_mut().zip(&self.widths) {
            let mut sum = 0.0;
            for j in at..at + w {
                sum += 0.5 * (self.f[j] + f1[j]) * (u1[j] - self.u[j]);
            }
            *work += sum;
            at += w;
        }
        self.u.copy_from_slice(u1);
        self.f.copy_from_slice(f1);
        // The base excitations: the absolute input's extra terms and the ground velocity.
        let nb = self.base_loads.len();
        if nb > 0 {
            let mut wv1 = vec![0.0; nb];
            self.base_products(v1, &mut wv1);
            let ag = |l: usize| {
                let [b0, b1, b2] = end.load_basis[l];
                (b0, b0 + b1, dt * (b0 + 0.5 * b1 + (2.0 / 3.0) * b2))
            };
            let accel: Vec<(f64, f64, f64)> = self.base_loads.iter().map(|&l| ag(l)).collect();
            let vg1: Vec<f64> = self.vg.iter().zip(&accel).map(|(vg, a)| vg + a.2).collect();
            let mut extra = 0.0;
            for b in 0..nb {
                let (a0, a1, _) = accel[b];
                extra += half * (self.wv[b] * a0 + wv1[b] * a1);
                extra += 0.5 * (self.vg[b] + vg1[b]) * (wv1[b] - self.wv[b]);
                for (c, &(c0, c1, _)) in accel.iter().enumerate() {
                    let rr = self.base_rr[b * nb + c];
                    extra += rr * half * (self.vg[b] * c0 + vg1[b] * c1);
                }
            }
            self.absolute += extra;
            self.vg = vg1;
            self.wv = wv1;
        }
        self.v.copy_from_slice(v1);
    }

    /// Saves the integrals so far in row `slot`.
    pub fn save(&mut self, slot: usize) {
        let n_cols = self.rows.n_cols;
        let Some(row) = self.rows.values.get_mut(slot * n_cols..(slot + 1) * n_cols) else {
            return;
        };
        row[0] = self.damping;
        row[1] = self.input;
        row[2] = self.absolute;
        let nb = self.vg.len();
        row[3..3 + nb].copy_from_slice(&self.vg);
        row[3 + nb..].copy_from_slice(&self.work);
    }

    /// The saved rows.
    pub fn into_rows(self) -> EnergyRows {
        self.rows
    }
}

/// A function writing the elements' local displacements, velocities and forces at a modal
/// state and time into three rows (a route's element record).
pub type Record<'f> = dyn FnMut((&[f64], &[f64]), f64, (&mut [f64], &mut [f64], &mut [f64])) -> Result<(), CoreError>
    + 'f;

/// The accumulator as a modal route drives it: the step's start and end states, its loads,
/// and the route's element record.
#[derive(Debug, Clone)]
pub struct EnergyTap {
    pub acc: EnergyAccumulator,
    linear: Vec<f64>,
    widths: Vec<usize>,
    x: Vec<f64>,
    v: Vec<f64>,
    r: Vec<f64>,
    p1: Vec<f64>,
}

/// One step as a modal route sees it: its start and end times and states and its modal load
/// basis `(p0, Dp)` (the end load `p0 + Dp`).
pub struct ModalStep<'a> {
    pub dt: f64,
    pub t: (f64, f64),
    pub start: (&'a [f64], &'a [f64]),
    pub end: (&'a [f64], &'a [f64]),
    pub p: (&'a [f64], &'a [f64]),
    /// Every load's basis over the step.
    pub load_basis: &'a [[f64; 3]],
}

impl EnergyTap {
    /// The tap of `spec` for `n` modes, elements of local widths `widths`, `n_saved` rows.
    pub fn new(spec: &EnergySpec, n: usize, widths: Vec<usize>, n_saved: usize) -> Self {
        let acc = EnergyAccumulator::new(spec, n, widths.clone(), n_saved);
        let w = acc.element_width();
        EnergyTap {
            acc,
            linear: spec.linear.to_vec(),
            widths,
            x: vec![0.0; w],
            v: vec![0.0; w],
            r: vec![0.0; w],
            p1: vec![0.0; n],
        }
    }

    /// Starts the integrals at the modal state `(q, v)` at `t`; `record` gives the
    /// elements' rows there (a hysteretic element's from its committed variables, so this
    /// comes before the first step is committed).
    pub fn start(
        &mut self,
        (q, v): (&[f64], &[f64]),
        t: f64,
        record: &mut Record,
    ) -> Result<(), CoreError> {
        if !self.x.is_empty() {
            record((q, v), t, (&mut self.x, &mut self.v, &mut self.r))?;
            self.add_linear();
        }
        self.acc.start(v, (&self.x, &self.r));
        Ok(())
    }

    /// Adds the step `s`; `record` gives the elements' rows at a state (the start state's
    /// too, when [`EnergyTap::start`] could not be done before the first step).
    pub fn step(&mut self, s: &ModalStep, record: &mut Record) -> Result<(), CoreError> {
        let has_elements = !self.x.is_empty();
        if !self.acc.started() {
            self.start(s.start, s.t.0, record)?;
        }
        if has_elements {
            record(s.end, s.t.1, (&mut self.x, &mut self.v, &mut self.r))?;
            self.add_linear();
        }
        for ((e, a), b) in self.p1.iter_mut().zip(s.p.0).zip(s.p.1) {
            *e = a + b;
        }
        let end = StepEnd {
            v: s.end.1,
            p: (s.p.0, &self.p1),
            load_basis: s.load_basis,
            elements: (&self.x, &self.r),
            damping_power: None,
        };
        self.acc.step(s.dt, &end);
        Ok(())
    }

    /// Adds the linear parts `k0 x + c0 v` to the recorded forces.
    fn add_linear(&mut self) {
        if self.linear.is_empty() {
            return;
        }
        let (mut at, mut off) = (0, 0);
        for &w in &self.widths {
            let (k0, c0) = self.linear[off..off + 2 * w * w].split_at(w * w);
            let (x, v) = (&self.x[at..at + w], &self.v[at..at + w]);
            for (i, r) in self.r[at..at + w].iter_mut().enumerate() {
                let row = i * w..(i + 1) * w;
                *r += crate::dense::dot(&k0[row.clone()], x) + crate::dense::dot(&c0[row], v);
            }
            at += w;
            off += 2 * w * w;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{EnergyAccumulator, EnergySpec, StepEnd};

    /// One mode moving at `v = t` under the load `p = 2`, damping `c = 3`, a one-dof
    /// element with `u = t^2 / 2` and `F = t`, and a base excitation of constant ground
    /// acceleration 1 (`w = 1`, `r^T M r = 1`): every integral has its closed form, and the
    /// trapezoids are exact where the integrand is linear in `t`.
    #[test]
    fn integrals_of_a_known_motion() {
        let spec = EnergySpec {
            damping: &[3.0],
            base_loads: &[0],
            base_w: &[1.0],
            base_rr: &[1.0],
            vg0: &[0.0],
            linear: &[],
        };
        let dt = 0.01;
        let steps = 100;
        let mut acc = EnergyAccumulator::new(&spec, 1, vec![1], 2);
        acc.start(&[0.0], (&[0.0], &[0.0]));
        acc.save(0);
        for k in 1..=steps {
            let t = k as f64 * dt;
            let end = StepEnd {
                v: &[t],
                p: (&[2.0], &[2.0]),
                load_basis: &[[1.0, 0.0, 0.0]],
                elements: (&[0.5 * t * t], &[t]),
                damping_power: None,
            };
            acc.step(dt, &end);
        }
        acc.save(1);
        let row = &acc.into_rows().values[5..];
        let t: f64 = 1.0;
        // damping int 3 t^2: the trapezoid's error 3 t dt^2 / 6 exactly
        assert!(
            (row[0] - (t.powi(3) + 0.5 * t * dt * dt)).abs() < 1e-12,
            "{}",
            row[0]
        );
        assert!((row[1] - t * t).abs() < 1e-12, "input {}", row[1]); // int 2 t
                                                                     // absolute: int (w v) a_g + int v_g d(w v) + int v_g a_g = t^2/2 + t^2/2 + t^2/2
        assert!((row[2] - 1.5 * t * t).abs() < 1e-12, "absolute {}", row[2]);
        assert!((row[3] - t).abs() < 1e-12, "v_g {}", row[3]);
        // element: int F du = int t * t dt = t^3 / 3, the trapezoid in u: - t dt^2 / 12
        let work = t.powi(3) / 3.0 - t * dt * dt / 12.0;
        assert!((row[4] - work).abs() < 1e-12, "work {}", row[4]);
    }
}
