//! Force elements: known values, exact tangents against central differences, additivity of
//! `eval`, and parameter validation.

use duhamel_core::elements::contact::Contact;
use duhamel_core::elements::polynomial::Polynomial;
use duhamel_core::elements::spring::{Damper, Spring};
use duhamel_core::elements::{Element, Tangent};
use duhamel_core::CoreError;

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

struct Eval {
    r: Vec<f64>,
    kx: Vec<f64>,
    cv: Vec<f64>,
}

fn eval(e: &dyn Element, x: &[f64], v: &[f64]) -> Eval {
    let n = e.dofs().len();
    let mut out = Eval {
        r: vec![0.0; n],
        kx: vec![0.0; n * n],
        cv: vec![0.0; n * n],
    };
    let tangent = Tangent {
        kx: &mut out.kx,
        cv: &mut out.cv,
    };
    e.eval(x, v, 0.3, &mut out.r, Some(tangent)).unwrap();
    out
}

fn force(e: &dyn Element, x: &[f64], v: &[f64]) -> Vec<f64> {
    let mut r = vec![0.0; e.dofs().len()];
    e.eval(x, v, 0.3, &mut r, None).unwrap();
    r
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Central differences of the force with steps `hx` (displacements) and `hv` (velocities);
/// every entry must agree to `tol` relative to the largest entry of its matrix, or to `floor`
/// (a natural stiffness scale of the element) when that is larger: a tangent that passes
/// through zero cannot be differenced to a relative accuracy of its own size.
fn check_tangents(e: &dyn Element, x: &[f64], v: &[f64], hx: f64, hv: f64, floor: f64) {
    let tol = 1e-6;
    let n = e.dofs().len();
    let a = eval(e, x, v);
    assert_eq!(a.r, force(e, x, v), "force without tangent differs");
    for (h, analytic, which) in [(hx, &a.kx, "kx"), (hv, &a.cv, "cv")] {
        let mut fd = vec![0.0; n * n];
        for b in 0..n {
            let (mut xp, mut xm, mut vp, mut vm) = (x.to_vec(), x.to_vec(), v.to_vec(), v.to_vec());
            if which == "kx" {
                xp[b] += h;
                xm[b] -= h;
            } else {
                vp[b] += h;
                vm[b] -= h;
            }
            let (fp, fm) = (force(e, &xp, &vp), force(e, &xm, &vm));
            for a in 0..n {
                fd[a * n + b] = (fp[a] - fm[a]) / (2.0 * h);
            }
        }
        let scale = max_abs(analytic).max(max_abs(&fd)).max(floor);
        for idx in 0..n * n {
            let err = (analytic[idx] - fd[idx]).abs();
            assert!(
                err <= tol * scale || scale == 0.0 && err == 0.0,
                "{which}[{idx}]: analytic {} vs fd {} (scale {scale}) at x={x:?} v={v:?}",
                analytic[idx],
                fd[idx]
            );
        }
    }
}

fn assert_invalid<T: std::fmt::Debug>(res: Result<T, CoreError>, expected: &str) {
    match res {
        Err(CoreError::InvalidInput { name, .. }) => assert_eq!(name, expected),
        other => panic!("expected InvalidInput naming {expected}, got {other:?}"),
    }
}

fn contact(mu: f64) -> Contact {
    // 1 mm clearance, 1e7 N/m, eps = 1e-3 clearance, v_eps = 1e-4 m/s.
    Contact::new(0, 1, 1e-3, 1e7, mu, 1e-6, 1e-4).unwrap()
}

/// A shaft position at radius `rho` and angle `phi`.
fn at(rho: f64, phi: f64) -> [f64; 2] {
    [rho * phi.cos(), rho * phi.sin()]
}

#[test]
fn polynomial_values_degree_and_tangent() {
    let p = Polynomial::new(4, vec![0.5, -2.0, 1.0, 3.0, 0.0]).unwrap();
    assert_eq!(p.dofs(), &[4]);
    assert_eq!(p.polynomial_degree(), Some(3));
    assert!(!p.uses_velocity());
    let x = -1.3_f64;
    let r = force(&p, &[x], &[0.0]);
    assert!((r[0] - (0.5 - 2.0 * x + x * x + 3.0 * x.powi(3))).abs() < 1e-12);

    let cubic = Polynomial::cubic(0, -2.5).unwrap();
    assert_eq!(cubic.polynomial_degree(), Some(3));
    assert!((force(&cubic, &[0.8], &[0.0])[0] + 2.5 * 0.512).abs() < 1e-14);

    for empty in [vec![], vec![0.0, 0.0]] {
        let z = Polynomial::new(0, empty).unwrap();
        assert_eq!(z.polynomial_degree(), Some(0));
        let e = eval(&z, &[2.0], &[0.0]);
        assert_eq!((e.r[0], e.kx[0]), (0.0, 0.0));
    }
    assert_eq!(
        Polynomial::new(0, vec![7.0]).unwrap().polynomial_degree(),
        Some(0)
    );

    let mut rng = Lcg(1);
    for _ in 0..20 {
        let x = 3.0 * rng.next();
        check_tangents(&p, &[x], &[0.0], 1e-5, 1e-5, 1.0);
        check_tangents(&cubic, &[x], &[0.0], 1e-5, 1e-5, 1.0);
    }
}

#[test]
fn spring_to_ground_and_between_dofs() {
    let (k, k3) = (150.0, -40.0);
    let g = Spring::new(2, None, k, k3).unwrap();
    assert_eq!(g.dofs(), &[2]);
    assert_eq!(g.polynomial_degree(), Some(3));
    assert!(!g.uses_velocity());
    let x = 0.37_f64;
    assert!((force(&g, &[x], &[0.0])[0] - (k * x + k3 * x.powi(3))).abs() < 1e-12);

    let s = Spring::new(1, Some(3), k, k3).unwrap();
    assert_eq!(s.dofs(), &[1, 3]);
    let r = force(&s, &[0.9, 0.2], &[0.0, 0.0]);
    let d = 0.7_f64;
    assert!((r[0] - (k * d + k3 * d.powi(3))).abs() < 1e-12);
    assert_eq!(r[0], -r[1]);

    let lin = Spring::new(0, Some(1), -5.0, 0.0).unwrap();
    assert_eq!(lin.polynomial_degree(), Some(1));

    let mut rng = Lcg(2);
    for _ in 0..20 {
        let (a, b) = (2.0 * rng.next(), 2.0 * rng.next());
        check_tangents(&g, &[a], &[b], 1e-5, 1e-5, k);
        check_tangents(&s, &[a, b], &[0.0, 0.0], 1e-5, 1e-5, k);
        check_tangents(&lin, &[a, b], &[0.0, 0.0], 1e-5, 1e-5, 5.0);
    }
}

#[test]
fn damper_values_and_tangent() {
    let d = Damper::new(0, Some(1), 3.0).unwrap();
    assert_eq!(d.polynomial_degree(), Some(1));
    assert!(d.uses_velocity());
    let e = eval(&d, &[5.0, -1.0], &[0.4, 0.1]);
    assert!((e.r[0] - 0.9).abs() < 1e-15 && (e.r[1] + 0.9).abs() < 1e-15);
    assert_eq!(e.kx, vec![0.0; 4]);
    assert_eq!(e.cv, vec![3.0, -3.0, -3.0, 3.0]);
    let g = Damper::new(5, None, 2.0).unwrap();
    assert_eq!(force(&g, &[1.0], &[-0.5]), vec![-1.0]);
    check_tangents(&g, &[0.3], &[0.2], 1e-5, 1e-5, 0.0);
    check_tangents(&d, &[0.3, 0.1], &[0.2, -0.7], 1e-5, 1e-5, 0.0);
}

#[test]
fn contact_known_values() {
    let c = contact(0.3);
    assert_eq!(c.dofs(), &[0, 1]);
    assert_eq!(c.polynomial_degree(), None);
    assert!(c.uses_velocity());
    assert!(!contact(0.0).uses_velocity());
    let (k, g, eps) = (1e7, 1e-3, 1e-6);

    // Deep inside the clearance: no force.
    for rho in [0.0, 1e-5, 0.5e-3, g - 30.0 * eps] {
        let r = force(&c, &at(rho, 0.7), &[0.3, -0.2]);
        assert!(max_abs(&r) < k * eps * 1e-10, "rho = {rho}: {r:?}");
    }

    // Deep penetration, no tangential velocity: F_n = k (rho - g) along n.
    let (rho, phi) = (g + 2e-4, 2.1);
    let p = at(rho, phi);
    let r = force(&c, &p, &[0.0, 0.0]);
    let f = k * (rho - g);
    assert!((r[0] - f * phi.cos()).abs() < 1e-9 * f);
    assert!((r[1] - f * phi.sin()).abs() < 1e-9 * f);

    // Friction opposes the whirl velocity: the LHS force has the sign of v_t along t.
    let t = [-phi.sin(), phi.cos()];
    for sign in [1.0, -1.0] {
        let v = [sign * 0.5 * t[0], sign * 0.5 * t[1]]; // v_t = 0.5 sign, fully sliding
        let r = force(&c, &p, &v);
        let along_t = r[0] * t[0] + r[1] * t[1];
        let along_n = r[0] * p[0] / rho + r[1] * p[1] / rho;
        assert!((along_t - sign * 0.3 * f).abs() < 1e-9 * f, "{along_t}");
        assert!((along_n - f).abs() < 1e-9 * f);
        let (f_n, f_t) = c.normal_and_friction(p, v);
        assert!((f_n - f).abs() < 1e-9 * f && (f_t - sign * 0.3 * f).abs() < 1e-9 * f);
    }

    // Centred shaft: zero force, finite tangent.
    let e = eval(
        &Contact::new(0, 1, 0.0, 1e7, 0.2, 1e-9, 1e-4).unwrap(),
        &[0.0, 0.0],
        &[1.0, 2.0],
    );
    assert_eq!(e.r, vec![0.0, 0.0]);
    assert!((e.kx[0] - 0.5e7).abs() < 1e-6 && e.kx[1] == 0.0 && e.kx[3] == e.kx[0]);
    assert_eq!(e.cv, vec![0.0; 4]);
}

#[test]
fn contact_tangents_match_finite_differences() {
    let (g, eps, veps) = (1e-3, 1e-6, 1e-4);
    let mut rng = Lcg(3);
    for mu in [0.0, 0.15] {
        let c = contact(mu);
        // inactive, transition (|delta| ~ eps), active, deep.
        for delta in [-20.0 * eps, -2.0 * eps, 0.0, 0.7 * eps, 3.0 * eps, 1e-4] {
            // whirl velocity: sliding both ways, near stick, plus a radial component.
            for vt in [-0.3, -0.5 * veps, 0.0, 2.0 * veps, 0.3] {
                let phi = std::f64::consts::PI * rng.next();
                let p = at(g + delta, phi);
                let vr = 0.05 * rng.next();
                let v = [
                    vr * phi.cos() - vt * phi.sin(),
                    vr * phi.sin() + vt * phi.cos(),
                ];
                check_tangents(&c, &p, &v, 1e-3 * eps, 1e-3 * veps, 0.0);
            }
        }
    }
    // Zero clearance, small radius.
    let c = Contact::new(3, 7, 0.0, 2e6, 0.4, 1e-9, 1e-3).unwrap();
    for _ in 0..20 {
        let p = at(1e-8 * (1.5 + rng.next()), 3.0 * rng.next());
        let v = [2e-3 * rng.next(), 2e-3 * rng.next()];
        check_tangents(&c, &p, &v, 1e-12, 1e-6, 0.0);
    }
}

/// An element with a state `(x, v)` to evaluate it at.
type Case = (Box<dyn Element>, Vec<f64>, Vec<f64>);

#[test]
fn eval_adds_into_outputs() {
    let elements: Vec<Case> = vec![
        (
            Box::new(Polynomial::new(0, vec![1.0, 2.0, 3.0]).unwrap()),
            vec![0.4],
            vec![0.0],
        ),
        (
            Box::new(Spring::new(0, Some(1), 2.0, 5.0).unwrap()),
            vec![0.4, -0.1],
            vec![0.0; 2],
        ),
        (
            Box::new(Spring::new(0, None, 2.0, 5.0).unwrap()),
            vec![0.4],
            vec![0.0],
        ),
        (
            Box::new(Damper::new(0, Some(1), 2.0).unwrap()),
            vec![0.0; 2],
            vec![0.4, -0.1],
        ),
        (
            Box::new(contact(0.2)),
            at(1.0005e-3, 0.4).to_vec(),
            vec![0.02, 0.03],
        ),
    ];
    for (e, x, v) in &elements {
        let once = eval(e.as_ref(), x, v);
        let n = x.len();
        let (mut r, mut kx, mut cv) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; n * n]);
        for _ in 0..2 {
            let tangent = Tangent {
                kx: &mut kx,
                cv: &mut cv,
            };
            e.eval(x, v, 0.0, &mut r, Some(tangent)).unwrap();
        }
        let twice = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| *b == 2.0 * a);
        assert!(twice(&once.r, &r) && twice(&once.kx, &kx) && twice(&once.cv, &cv));
        assert!(max_abs(&once.r) > 0.0);
    }
}

#[test]
fn invalid_parameters_are_named() {
    assert_invalid(Polynomial::new(0, vec![1.0, f64::NAN]), "coefficients");
    assert_invalid(Polynomial::cubic(0, f64::INFINITY), "k3");
    assert_invalid(Spring::new(1, Some(1), 1.0, 0.0), "j");
    assert_invalid(Spring::new(0, None, f64::NAN, 0.0), "k");
    assert_invalid(Spring::new(0, None, 1.0, f64::NEG_INFINITY), "k3");
    assert_invalid(Damper::new(2, Some(2), 1.0), "j");
    assert_invalid(Damper::new(0, None, -1.0), "c");
    assert_invalid(Damper::new(0, None, f64::NAN), "c");
    let ok = (0, 1, 1e-3, 1e7, 0.1, 1e-6, 1e-4);
    let mk = |a: (usize, usize, f64, f64, f64, f64, f64)| {
        Contact::new(a.0, a.1, a.2, a.3, a.4, a.5, a.6)
    };
    assert!(mk(ok).is_ok());
    assert!(mk((0, 1, 0.0, 1e7, 0.0, 1e-9, 1e-4)).is_ok());
    assert_invalid(mk((1, 1, 1e-3, 1e7, 0.1, 1e-6, 1e-4)), "dof_y");
    assert_invalid(mk((0, 1, -1e-3, 1e7, 0.1, 1e-6, 1e-4)), "clearance");
    assert_invalid(mk((0, 1, f64::NAN, 1e7, 0.1, 1e-6, 1e-4)), "clearance");
    assert_invalid(mk((0, 1, 1e-3, 0.0, 0.1, 1e-6, 1e-4)), "stiffness");
    assert_invalid(mk((0, 1, 1e-3, -1e7, 0.1, 1e-6, 1e-4)), "stiffness");
    assert_invalid(mk((0, 1, 1e-3, 1e7, -0.1, 1e-6, 1e-4)), "friction");
    assert_invalid(mk((0, 1, 1e-3, 1e7, 0.1, 0.0, 1e-4)), "smoothing");
    assert_invalid(
        mk((0, 1, 1e-3, 1e7, 0.1, 1e-6, f64::INFINITY)),
        "velocity_smoothing",
    );
}
