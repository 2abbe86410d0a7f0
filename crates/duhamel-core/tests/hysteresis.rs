//! Hysteretic and device elements under imposed displacements: closed-form bilinear loops,
//! Bouc-Wen loops against an independent fine RK4 integration of dz/du, the friction
//! pendulum's square loop and circular orbit, dissipated energies, the power-law damper and
//! the gap; consistent tangents against central differences of `eval_path`; trial/commit.

use duhamel_core::elements::hysteretic::bilinear::Bilinear;
use duhamel_core::elements::hysteretic::boucwen::{BoucWen, BoucWenParams};
use duhamel_core::elements::hysteretic::friction::FrictionPendulum;
use duhamel_core::elements::hysteretic::gap::Gap;
use duhamel_core::elements::hysteretic::viscous::ViscousDamper;
use duhamel_core::elements::{Element, PathState, Tangent};
use duhamel_core::CoreError;
use std::f64::consts::PI;

/// Deterministic uniform numbers in `[-1, 1)`.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Force, tangents and trial variables of one evaluation.
struct Out {
    r: Vec<f64>,
    kx: Vec<f64>,
    cv: Vec<f64>,
    trial: Vec<f64>,
}

/// A Bouc-Wen element of `[k, fy, alpha, n, beta, gamma]`.
fn boucwen(i: usize, j: Option<usize>, [k, fy, alpha, n, beta, gamma]: [f64; 6]) -> BoucWen {
    let params = BoucWenParams {
        k,
        fy,
        alpha,
        n,
        beta,
        gamma,
    };
    BoucWen::new(i, j, params).unwrap()
}

/// `eval_path` at `(x, v)` from `committed`.
fn eval_from(e: &dyn Element, committed: &[f64], x: &[f64], v: &[f64]) -> Out {
    let n = e.dofs().len();
    let mut out = Out {
        r: vec![0.0; n],
        kx: vec![0.0; n * n],
        cv: vec![0.0; n * n],
        trial: vec![f64::NAN; committed.len()],
    };
    let history = PathState {
        committed,
        trial: &mut out.trial,
    };
    let tangent = Tangent {
        kx: &mut out.kx,
        cv: &mut out.cv,
    };
    e.eval_path(x, v, 0.0, history, &mut out.r, Some(tangent))
        .unwrap();
    out
}

/// An element driven along a path: evaluate at each point and commit (one step each).
struct Driver<'a> {
    e: &'a dyn Element,
    committed: Vec<f64>,
}

impl<'a> Driver<'a> {
    fn new(e: &'a dyn Element, x0: &[f64]) -> Self {
        let mut committed = vec![0.0; e.state_len()];
        e.initial_state(x0, &vec![0.0; x0.len()], &mut committed);
        Driver { e, committed }
    }

    fn step(&mut self, x: &[f64]) -> Out {
        let out = eval_from(self.e, &self.committed, x, &vec![0.0; x.len()]);
        self.committed.copy_from_slice(&out.trial);
        out
    }
}

/// Triangle wave between `-a` and `a` starting at 0 upwards, `per_quarter` steps a quarter.
fn triangle(a: f64, per_quarter: usize, cycles: usize) -> Vec<f64> {
    let du = a / per_quarter as f64;
    let mut u = vec![0.0];
    let mut cur = 0.0;
    for _ in 0..cycles {
        for (n, dir) in [(1, 1.0), (2, -1.0), (1, 1.0)] {
            for _ in 0..n * per_quarter {
                cur += dir * du;
                // snap to the grid so that corners are hit exactly
                cur = (cur / du).round() * du;
                u.push(cur);
            }
        }
    }
    u
}

/// `sum F du` by the trapezoidal rule.
fn work(u: &[f64], f: &[f64]) -> f64 {
    (1..u.len())
        .map(|i| 0.5 * (f[i] + f[i - 1]) * (u[i] - u[i - 1]))
        .sum()
}

#[test]
fn bilinear_follows_the_closed_form_loop() {
    let (k, fy, alpha) = (200.0, 3.0, 0.05);
    let uy = fy / k;
    let a = 3.7 * uy;
    let fa = fy + alpha * k * (a - uy);
    let per_cycle = 4 * 37;
    for j in [None, Some(1)] {
        let e = Bilinear::new(0, j, k, fy, alpha).unwrap();
        let mut d = Driver::new(&e, if j.is_some() { &[0.0, 0.0] } else { &[0.0] });
        for n in 1..=3 * per_cycle {
            let phase = 2.0 * PI * n as f64 / per_cycle as f64;
            let u = a * phase.sin();
            let shift = 0.3 * phase.cos(); // node j moves too
            let x = if j.is_some() {
                vec![u + shift, shift]
            } else {
                vec![u]
            };
            let out = d.step(&x);
            let quarter = n as f64 / per_cycle as f64 * 4.0;
            let expected = if quarter <= 1.0 {
                // virgin loading
                (k * u).min(alpha * k * u + (1.0 - alpha) * fy)
            } else if phase.cos() < 0.0 {
                // unloading from +a
                let lower = alpha * k * u - (1.0 - alpha) * fy;
                if u >= a - 2.0 * uy {
                    fa - k * (a - u)
                } else {
                    lower
                }
            } else {
                // loading from -a
                if u <= -a + 2.0 * uy {
                    -fa + k * (u + a)
                } else {
                    alpha * k * u + (1.0 - alpha) * fy
                }
            };
            assert!(
                (out.r[0] - expected).abs() < 1e-12 * fy,
                "j {j:?} n {n}: {} vs {expected}",
                out.r[0]
            );
            if j.is_some() {
                assert_eq!(out.r[1], -out.r[0]);
            }
        }
    }
}

#[test]
fn bilinear_dissipates_the_closed_form_energy() {
    for alpha in [0.0, 0.1, -0.05] {
        let (k, fy) = (50.0, 2.0);
        let uy = fy / k;
        let e = Bilinear::new(0, None, k, fy, alpha).unwrap();
        // 300 steps a quarter; the corners (u = a - 2 uy) fall on the grid
        let a = 3.0 * uy;
        let u = triangle(a, 300, 2);
        let mut d = Driver::new(&e, &[0.0]);
        let f: Vec<f64> = u.iter().map(|&ui| d.step(&[ui]).r[0]).collect();
        // second cycle: a closed loop
        let start = 4 * 300;
        let energy = work(&u[start..], &f[start..]);
        let expected = 4.0 * (1.0 - alpha) * fy * (a - uy);
        assert!(
            (energy - expected).abs() < 1e-10 * expected,
            "alpha {alpha}: {energy} vs {expected}"
        );
    }
}

/// Bouc-Wen reference: RK4 in u on dz/du with `sub` substeps per segment.
fn bouc_wen_reference(
    (uy, n, beta, gamma): (f64, f64, f64, f64),
    u: &[f64],
    sub: usize,
) -> (Vec<f64>, f64) {
    let mut z = vec![0.0];
    let mut zint = 0.0; // integral of z du
    for w in u.windows(2) {
        let h = (w[1] - w[0]) / sub as f64;
        let sgn = h.signum();
        let rhs = |z: f64| {
            let s = (sgn * z).signum();
            (1.0 - z.abs().powf(n) * (beta * s + gamma)) / uy
        };
        let mut zc = *z.last().unwrap();
        for _ in 0..sub {
            // augmented state (z, integral z du)
            let k1 = rhs(zc);
            let k2 = rhs(zc + 0.5 * h * k1);
            let k3 = rhs(zc + 0.5 * h * k2);
            let k4 = rhs(zc + h * k3);
            let (i1, i2, i3, i4) = (zc, zc + 0.5 * h * k1, zc + 0.5 * h * k2, zc + h * k3);
            zint += h / 6.0 * (i1 + 2.0 * i2 + 2.0 * i3 + i4);
            zc += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        z.push(zc);
    }
    (z, zint)
}

#[test]
fn bouc_wen_follows_an_independent_fine_integration() {
    let (k, fy, alpha) = (100.0, 2.0, 0.1);
    let uy = fy / k;
    // (n, beta, gamma, tolerance on z)
    let cases = [
        (1.0, 0.5, 0.5, 1e-9),
        (1.0, 0.25, 0.75, 1e-9),
        (1.0, 0.75, 0.25, 1e-9),
        (2.0, 0.5, 0.5, 1e-9),
        (3.0, 0.9, -0.3, 1e-9),
        (1.5, 0.5, 0.5, 1e-7),
        (10.0, 0.5, 0.5, 1e-9),
    ];
    for (n, beta, gamma, tol) in cases {
        let e = boucwen(0, Some(1), [k, fy, alpha, n, beta, gamma]);
        // 40 steps a cycle (|du| up to 0.5 uy), 2.5 cycles growing then decaying
        let per_cycle = 40;
        let u: Vec<f64> = (0..=100)
            .map(|i| {
                let p = 2.0 * PI * i as f64 / per_cycle as f64;
                3.0 * uy * (1.0 + 0.3 * (0.3 * p).sin()) * p.sin()
            })
            .collect();
        let (z_ref, _) = bouc_wen_reference((uy, n, beta, gamma), &u, 20_000);
        let mut d = Driver::new(&e, &[0.0, 0.0]);
        let mut worst: f64 = 0.0;
        for (i, &ui) in u.iter().enumerate().skip(1) {
            let out = d.step(&[ui - 0.1, -0.1]);
            let z = d.committed[1];
            worst = worst.max((z - z_ref[i]).abs());
            let f = alpha * k * ui + (1.0 - alpha) * fy * z_ref[i];
            assert!((out.r[0] - f).abs() < tol * fy + 1e-12 * fy);
        }
        assert!(worst < tol, "n {n} beta {beta} gamma {gamma}: {worst:e}");
    }
}

#[test]
fn bouc_wen_energy_per_cycle() {
    let (k, fy, alpha) = (10.0, 1.0, 0.05);
    let uy = fy / k;
    for (n, beta, gamma) in [(1.0, 0.5, 0.5), (2.0, 0.3, 0.6)] {
        let e = boucwen(0, None, [k, fy, alpha, n, beta, gamma]);
        let u = triangle(4.0 * uy, 4000, 2);
        let (_, zint_all) = bouc_wen_reference((uy, n, beta, gamma), &u[..=32000], 20);
        let (_, zint_first) = bouc_wen_reference((uy, n, beta, gamma), &u[..=16000], 20);
        let reference = (1.0 - alpha) * fy * (zint_all - zint_first);
        let mut d = Driver::new(&e, &[0.0]);
        let f: Vec<f64> = u.iter().map(|&ui| d.step(&[ui]).r[0]).collect();
        // Simpson's rule over the second cycle (the reversals fall on even panels)
        let du = u[1] - u[0];
        let energy: f64 = (16000..32000)
            .step_by(2)
            .map(|i| {
                let sign = (u[i + 2] - u[i]).signum();
                sign * du / 3.0 * (f[i] + 4.0 * f[i + 1] + f[i + 2])
            })
            .sum();
        assert!(
            (energy - reference).abs() < 1e-8 * reference,
            "n {n}: {energy} vs {reference}"
        );
        // a stable loop of a saturated model dissipates about 4 fy a (1 - alpha), less
        assert!(energy > 0.0 && energy < 4.0 * (1.0 - alpha) * fy * 4.0 * uy * e.z_max());
    }
}

#[test]
fn friction_pendulum_square_loop() {
    let (radius, mu, weight, y) = (2.0, 0.06, 1000.0, 2.5e-4);
    let e = FrictionPendulum::new(3, 7, radius, mu, weight, y).unwrap();
    let f_max = mu * weight;
    let a = 0.1;
    let per_cycle = 400;
    let mut d = Driver::new(&e, &[0.0, 0.0]);
    let (mut u_prev, mut u_rev) = (0.0, 0.0);
    let mut checked = 0;
    for n in 1..=2 * per_cycle {
        let phase = 2.0 * PI * n as f64 / per_cycle as f64;
        let u = a * phase.sin();
        let out = d.step(&[u, 0.0]);
        let v = u - u_prev;
        let pendulum = weight / radius * u;
        assert!(out.r[1] == 0.0);
        assert!((out.r[0] - pendulum).abs() <= f_max * (1.0 + 1e-14));
        // sliding once the displacement since the reversal exceeds the pre-sliding zone
        if (u - u_rev).abs() > 2.0 * y {
            let expected = pendulum + f_max * v.signum();
            assert!((out.r[0] - expected).abs() < 1e-12 * f_max, "n {n}");
            checked += 1;
        }
        if n % (per_cycle / 2) == per_cycle / 4 {
            u_rev = u; // the peaks: the motion reverses after them
        }
        u_prev = u;
    }
    assert!(checked > 2 * per_cycle - 40, "{checked}");

    // energy of a closed cycle: elastic-perfectly plastic with yield displacement Y
    let u = triangle(a, 4000, 2);
    let mut d = Driver::new(&e, &[0.0, 0.0]);
    let f: Vec<f64> = u.iter().map(|&ui| d.step(&[ui, 0.0]).r[0]).collect();
    let energy = work(&u[16000..], &f[16000..]);
    let expected = 4.0 * f_max * (a - y);
    assert!(
        (energy - expected).abs() < 1e-9 * expected,
        "{energy} {expected}"
    );
}

#[test]
fn friction_pendulum_circular_orbit() {
    let (radius, mu, weight, y) = (3.0, 0.05, 2.0e4, 2.5e-4);
    let e = FrictionPendulum::new(0, 1, radius, mu, weight, y).unwrap();
    let f_max = mu * weight;
    let rho = 0.2;
    let per_turn = 2000;
    let dtheta = 2.0 * PI / per_turn as f64;
    let mut d = Driver::new(&e, &[rho, 0.0]);
    let mut worst_angle: f64 = 0.0;
    for n in 1..=3 * per_turn {
        let theta = n as f64 * dtheta;
        let u = [rho * theta.cos(), rho * theta.sin()];
        let out = d.step(&u);
        let f = [
            out.r[0] - weight / radius * u[0],
            out.r[1] - weight / radius * u[1],
        ];
        if n > per_turn {
            // sliding: |f| = mu W, along the velocity (restoring: the LHS force is +f)
            assert!((f[0].hypot(f[1]) - f_max).abs() < 1e-12 * f_max);
            let t = [-theta.sin(), theta.cos()];
            let cross = (f[0] * t[1] - f[1] * t[0]) / f_max;
            assert!(f[0] * t[0] + f[1] * t[1] > 0.0);
            worst_angle = worst_angle.max(cross.abs().asin());
        }
    }
    // the lag behind the tangent: about Y / rho, plus half a step's rotation of the chord
    assert!(worst_angle < 1.5 * y / rho + dtheta, "{worst_angle}");
}

#[test]
fn viscous_damper_power_law_and_regularisation() {
    let c = 40.0;
    for a in [0.2, 0.5, 1.0, 1.8] {
        let e = ViscousDamper::new(2, Some(5), c, a).unwrap();
        let v0 = e.v0();
        for v in [-1.3, -0.2, 1e-3, 0.05, 0.7, 2.0] {
            let out = eval_from(&e, &[], &[0.3, -0.4], &[v + 0.1, 0.1]);
            let f = c * v.abs().powf(a) * v.signum();
            let df = c * a * v.abs().powf(a - 1.0);
            assert!((out.r[0] - f).abs() < 1e-13 * f.abs() && out.r[1] == -out.r[0]);
            let expected_cv = [df, -df, -df, df];
            for (got, want) in out.cv.iter().zip(expected_cv) {
                assert!((got - want).abs() < 1e-12 * df, "a {a} v {v}");
            }
            assert!(out.kx.iter().all(|&k| k == 0.0));
        }
        if a < 1.0 {
            // C^1 at the regularisation boundary, finite slope at rest, odd and monotone
            for side in [-1.0, 1.0] {
                let (fi, dfi) = e.force(side * v0 * (1.0 - 1e-12));
                let (fo, dfo) = e.force(side * v0 * (1.0 + 1e-12));
                assert!((fi - fo).abs() < 1e-9 * fo.abs(), "a {a}");
                assert!((dfi - dfo).abs() < 1e-9 * dfo, "a {a}");
            }
            let (f0, df0) = e.force(0.0);
            assert!(f0 == 0.0 && (df0 - c * v0.powf(a - 1.0) * (3.0 - a) / 2.0).abs() < 1e-9 * df0);
            let mut last = f64::NEG_INFINITY;
            for i in -200..=200 {
                let (f, df) = e.force(i as f64 / 100.0 * v0);
                assert!(f > last && df > 0.0);
                assert_eq!(e.force(-(i as f64) / 100.0 * v0).0, -f);
                last = f;
            }
        }
    }
    let e = ViscousDamper::new(0, None, 1.0, 0.3)
        .unwrap()
        .with_v0(1e-3)
        .unwrap();
    assert_eq!(e.v0(), 1e-3);
    assert!(e.uses_velocity() && e.state_len() == 0);
}

#[test]
fn gap_open_and_closed() {
    let (gap, k) = (0.02, 1e6);
    let e = Gap::new(0, Some(1), gap, k).unwrap();
    // open: i moved towards j by less than the gap, or away from it
    for u in [0.5, 0.0, -0.019, -gap] {
        let out = eval_from(&e, &[], &[u, 0.0], &[0.0, 0.0]);
        assert!(out.r == [0.0, 0.0] && out.kx == [0.0; 4], "u {u}");
    }
    // closed: pushes i back (+x, the force on the left-hand side is negative) and j away
    let out = eval_from(&e, &[], &[-0.025 + 1.0, 1.0], &[0.0, 0.0]);
    assert!((out.r[0] - k * (-0.005)).abs() < 1e-6 && out.r[1] == -out.r[0]);
    assert_eq!(out.kx, vec![k, -k, -k, k]);
    // grounded: a stop at -gap
    let e = Gap::new(0, None, gap, k).unwrap();
    let out = eval_from(&e, &[], &[-0.03], &[5.0]);
    assert!((out.r[0] + k * 0.01).abs() < 1e-6 && out.kx == [k] && out.cv == [0.0]);
    assert!(Gap::new(0, None, -0.1, k).is_err() && Gap::new(0, None, 0.0, 0.0).is_err());
}

/// Drives `e` along a random path (committing), then returns the committed variables.
fn random_history(e: &dyn Element, rng: &mut Lcg, scale: f64, steps: usize) -> Vec<f64> {
    let nl = e.dofs().len();
    let mut d = Driver::new(e, &vec![0.0; nl]);
    let mut x = vec![0.0; nl];
    for _ in 0..steps {
        for xi in x.iter_mut() {
            *xi += scale * rng.next();
        }
        d.step(&x);
    }
    d.committed
}

/// Central differences of `eval_path` against the analytic tangents at random trial states
/// from random committed states; stencils across a kink (one-sided differences that
/// disagree) are skipped. Returns the number of entries checked.
fn check_tangents(e: &dyn Element, scale: f64, h: f64, seed: u64) -> usize {
    let mut rng = Lcg(seed);
    let nl = e.dofs().len();
    let mut checked = 0;
    for _ in 0..200 {
        let committed = random_history(e, &mut rng, scale, 5);
        let x: Vec<f64> = (0..nl).map(|_| 3.0 * scale * rng.next()).collect();
        let v: Vec<f64> = (0..nl).map(|_| rng.next()).collect();
        let out = eval_from(e, &committed, &x, &v);
        let shifted = |which: usize, j: usize, delta: f64| {
            let (mut xs, mut vs) = (x.clone(), v.clone());
            if which == 0 {
                xs[j] += delta;
            } else {
                vs[j] += delta;
            }
            eval_from(e, &committed, &xs, &vs).r
        };
        for which in 0..2 {
            for j in 0..nl {
                let (rp, rm) = (shifted(which, j, h), shifted(which, j, -h));
                let tangent = if which == 0 { &out.kx } else { &out.cv };
                let scale_r = tangent.iter().fold(1e-300_f64, |m, t| m.max(t.abs()));
                for i in 0..nl {
                    let forward = (rp[i] - out.r[i]) / h;
                    let backward = (out.r[i] - rm[i]) / h;
                    if (forward - backward).abs() > 1e-3 * scale_r {
                        continue; // a kink inside the stencil
                    }
                    let central = (rp[i] - rm[i]) / (2.0 * h);
                    let got = tangent[i * nl + j];
                    assert!(
                        (got - central).abs() < 1e-6 * scale_r,
                        "{which} ({i},{j}): {got} vs {central}, x {x:?} committed {committed:?}"
                    );
                    checked += 1;
                }
            }
        }
    }
    checked
}

#[test]
fn tangents_match_central_differences() {
    let uy = 0.01;
    let elements: Vec<(Box<dyn Element>, f64, f64)> = vec![
        (
            Box::new(Bilinear::new(0, Some(1), 100.0, 1.0, 0.1).unwrap()),
            uy,
            1e-7,
        ),
        (
            Box::new(Bilinear::new(0, None, 100.0, 1.0, -0.05).unwrap()),
            uy,
            1e-7,
        ),
        (
            Box::new(boucwen(0, Some(1), [100.0, 1.0, 0.1, 1.0, 0.5, 0.5])),
            uy,
            1e-7,
        ),
        (
            Box::new(boucwen(0, None, [100.0, 1.0, 0.0, 1.0, 0.2, 0.8])),
            uy,
            1e-7,
        ),
        (
            Box::new(boucwen(0, None, [100.0, 1.0, 0.05, 2.0, 0.5, 0.5])),
            uy,
            1e-6,
        ),
        (
            Box::new(boucwen(1, Some(0), [100.0, 1.0, 0.05, 5.0, 0.7, 0.1])),
            uy,
            1e-6,
        ),
        (
            Box::new(FrictionPendulum::new(0, 1, 2.0, 0.05, 100.0, 1e-3).unwrap()),
            2e-3,
            1e-8,
        ),
        (
            Box::new(ViscousDamper::new(0, Some(1), 3.0, 0.35).unwrap()),
            1.0,
            1e-7,
        ),
        (
            Box::new(
                ViscousDamper::new(0, None, 3.0, 0.35)
                    .unwrap()
                    .with_v0(0.5)
                    .unwrap(),
            ),
            1.0,
            1e-7,
        ),
        (
            Box::new(ViscousDamper::new(0, None, 3.0, 1.6).unwrap()),
            1.0,
            1e-7,
        ),
        (Box::new(Gap::new(0, Some(1), 0.01, 1e4).unwrap()), uy, 1e-7),
    ];
    for (k, (e, scale, h)) in elements.iter().enumerate() {
        let checked = check_tangents(e.as_ref(), *scale, *h, 17 + k as u64);
        let n = e.dofs().len();
        // most stencils are smooth
        assert!(checked > 200 * 2 * n * n * 3 / 4, "element {k}: {checked}");
    }
}

#[test]
fn trial_evaluations_do_not_accumulate_and_commits_continue_the_path() {
    let elements: Vec<(Box<dyn Element>, f64)> = vec![
        (
            Box::new(Bilinear::new(0, None, 100.0, 1.0, 0.1).unwrap()),
            0.01,
        ),
        (
            Box::new(boucwen(0, None, [100.0, 1.0, 0.1, 1.0, 0.5, 0.5])),
            0.01,
        ),
        (
            Box::new(boucwen(0, None, [100.0, 1.0, 0.1, 3.0, 0.5, 0.5])),
            0.01,
        ),
        (
            Box::new(FrictionPendulum::new(0, 1, 2.0, 0.05, 100.0, 1e-3).unwrap()),
            2e-3,
        ),
    ];
    let mut rng = Lcg(5);
    for (e, scale) in &elements {
        let e = e.as_ref();
        let nl = e.dofs().len();
        let committed = random_history(e, &mut rng, *scale, 7);
        let (x2, x3): (Vec<f64>, Vec<f64>) = (0..nl)
            .map(|_| (3.0 * scale * rng.next(), 3.0 * scale * rng.next()))
            .unzip();
        let v = vec![0.0; nl];
        // Newton iterates inside a step: each evaluation starts from the committed state
        let first = eval_from(e, &committed, &x3, &v);
        let _ = eval_from(e, &committed, &x2, &v);
        let again = eval_from(e, &committed, &x3, &v);
        assert_eq!(first.r, again.r);
        assert_eq!(first.kx, again.kx);
        assert_eq!(first.trial, again.trial);
        // committing at x2, then evaluating at x3, continues the path from x2
        let at_x2 = eval_from(e, &committed, &x2, &v);
        let continued = eval_from(e, &at_x2.trial, &x3, &v);
        let mut d = Driver {
            e,
            committed: committed.clone(),
        };
        d.step(&x2);
        assert_eq!(d.step(&x3).r, continued.r);
        // a path through the yield band: the history matters
        assert!(first.r != continued.r || first.trial == continued.trial);
    }
}

#[test]
fn initial_state_is_virgin_monotonic_loading_and_eval_is_the_backbone() {
    let elements: Vec<Box<dyn Element>> = vec![
        Box::new(Bilinear::new(0, Some(1), 100.0, 1.0, 0.1).unwrap()),
        Box::new(boucwen(0, Some(1), [100.0, 1.0, 0.1, 1.0, 0.5, 0.5])),
        Box::new(boucwen(0, Some(1), [100.0, 1.0, 0.1, 2.5, 0.5, 0.5])),
        Box::new(FrictionPendulum::new(0, 1, 2.0, 0.05, 100.0, 1e-3).unwrap()),
    ];
    for e in &elements {
        let e = e.as_ref();
        for x0 in [[0.0, 0.0], [0.004, -0.001], [-0.05, 0.02]] {
            let mut state = vec![f64::NAN; e.state_len()];
            e.initial_state(&x0, &[0.0, 0.0], &mut state);
            let mut virgin = vec![f64::NAN; e.state_len()];
            e.initial_state(&[0.0, 0.0], &[0.0, 0.0], &mut virgin);
            let loaded = eval_from(e, &virgin, &x0, &[0.0, 0.0]);
            assert_eq!(loaded.trial, state);
            // staying at the initial state keeps the variables
            assert_eq!(eval_from(e, &state, &x0, &[0.0, 0.0]).trial, state);
            let mut r = [0.0; 2];
            e.eval(&x0, &[0.0, 0.0], 0.0, &mut r, None).unwrap();
            assert_eq!(r.to_vec(), loaded.r);
        }
    }
}

#[test]
fn constructors_name_the_bad_parameter_and_non_finite_states_are_errors() {
    let name = |e: CoreError| match e {
        CoreError::InvalidInput { name, .. } => name,
        other => panic!("{other:?}"),
    };
    let fp = |r, mu, w, y| FrictionPendulum::new(0, 1, r, mu, w, y).map(|_| ());
    assert_eq!(name(fp(0.0, 0.05, 1.0, 1e-3).unwrap_err()), "radius");
    assert_eq!(name(fp(1.0, -0.05, 1.0, 1e-3).unwrap_err()), "mu");
    assert_eq!(name(fp(1.0, 0.05, f64::NAN, 1e-3).unwrap_err()), "weight");
    assert_eq!(
        name(fp(1.0, 0.05, 1.0, 0.0).unwrap_err()),
        "yield_displacement"
    );
    let same = FrictionPendulum::new(4, 4, 1.0, 0.05, 1.0, 1e-3);
    assert_eq!(name(same.unwrap_err()), "dof_y");
    assert_eq!(name(Gap::new(0, None, f64::NAN, 1.0).unwrap_err()), "gap");
    assert_eq!(name(Gap::new(1, Some(1), 0.0, 1.0).unwrap_err()), "j");

    let elements: Vec<Box<dyn Element>> = vec![
        Box::new(Bilinear::new(0, Some(1), 100.0, 1.0, 0.1).unwrap()),
        Box::new(boucwen(0, Some(1), [100.0, 1.0, 0.1, 1.0, 0.5, 0.5])),
        Box::new(boucwen(0, Some(1), [100.0, 1.0, 0.1, 2.5, 0.5, 0.5])),
        Box::new(FrictionPendulum::new(0, 1, 2.0, 0.05, 100.0, 1e-3).unwrap()),
        Box::new(ViscousDamper::new(0, Some(1), 3.0, 0.35).unwrap()),
        Box::new(Gap::new(0, Some(1), 0.01, 1e4).unwrap()),
    ];
    for e in &elements {
        for bad in [f64::NAN, f64::INFINITY] {
            let committed = vec![0.0; e.state_len()];
            let mut trial = committed.clone();
            let mut r = [0.0; 2];
            let history = PathState {
                committed: &committed,
                trial: &mut trial,
            };
            let err = e.eval_path(&[bad, 0.0], &[bad, 0.0], 1.5, history, &mut r, None);
            assert!(matches!(err, Err(CoreError::NonFinite { .. })), "{err:?}");
        }
    }
}

/// A bilinear SDOF (`q'' + c q' + k_e q + F(q) = p sin(omega t)`, one mode) on the
/// semi-analytic integrator: final displacement at time steps `dt`.
fn bilinear_sdof(dt: f64) -> f64 {
    use duhamel_core::loads::{ModalLoad, TimeFunction};
    use duhamel_core::pseudo::{integrate, NonlinearProblem, Options, Quadrature, Scheme, Solver};
    use duhamel_core::{ModalProblem, Unattended};
    let bilinear = Bilinear::new(0, None, 30.0, 0.6, 0.05).unwrap(); // uy = 0.02
    let elements: [&dyn Element; 1] = [&bilinear];
    let loads = [ModalLoad {
        pattern: vec![2.0],
        time: TimeFunction::Harmonic {
            omega: 4.0,
            phase: 0.0,
        },
    }];
    let n_steps = (4.0 / dt).round() as usize;
    let problem = NonlinearProblem {
        base: ModalProblem {
            k: &[10.0],
            c: &[0.2],
            q0: &[0.0],
            v0: &[0.0],
            loads: &loads,
            t0: 0.0,
            step0: 0,
            dt,
            n_steps,
            save_every: n_steps,
            threads: Some(1),
        },
        phi: &[1.0],
        n_dof: 1,
        elements: &elements,
        coupling_k: None,
        coupling_c: None,
        scaled: &[],
        mass: None,
        options: Options {
            scheme: Scheme::B,
            quadrature: Quadrature::Trapezoid,
            tol: 1e-13,
            max_iter: 50,
            solver: Solver::Auto,
            subdivisions: 4,
            growth_limit: f64::INFINITY,
        },
        element_state: None,
        guard_state: None,
        energy: None,
    };
    let history = integrate(&problem, None, &mut Unattended).expect("runs").0;
    *history.q().last().unwrap()
}

#[test]
fn bilinear_sdof_converges_at_second_order() {
    let reference = bilinear_sdof(0.02 / 256.0);
    let dts = [0.04, 0.02, 0.01, 0.005, 0.0025];
    let err: Vec<f64> = dts
        .iter()
        .map(|&dt| (bilinear_sdof(dt) - reference).abs())
        .collect();
    // yielded well beyond uy = 0.02
    assert!(reference.abs() > 0.1);
    // the yield events fall anywhere inside their steps, so the error constant wanders:
    // the least-squares slope of log(error) against log(dt)
    let (x, y): (Vec<f64>, Vec<f64>) = dts.iter().zip(&err).map(|(d, e)| (d.ln(), e.ln())).unzip();
    let (mx, my) = (x.iter().sum::<f64>() / 5.0, y.iter().sum::<f64>() / 5.0);
    let slope = x
        .iter()
        .zip(&y)
        .map(|(a, b)| (a - mx) * (b - my))
        .sum::<f64>()
        / x.iter().map(|a| (a - mx) * (a - mx)).sum::<f64>();
    assert!(slope > 1.8, "slope {slope}, errors {err:?}");
}
