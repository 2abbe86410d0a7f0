use super::*;
use crate::elements::materials::testing::{cycles, drive, random_walk, tangent_error};

const FY: f64 = 355.0;
const E: f64 = 2.0e5;
const NO_HARDENING: [f64; 4] = [0.0, 1.0, 0.0, 1.0];

fn steel(b: f64, r0: f64, cr1: f64, a: [f64; 4], sig_init: f64) -> Steel02 {
    Steel02::new(FY, E, b, Transition { r0, cr1, cr2: 0.15 }, a, sig_init).unwrap()
}

/// Menegotto-Pinto's first branch: `s = fy (b x + (1 - b) x / (1 + |x|^R)^(1/R))`, `x =
/// e / ey`.
fn menegotto_pinto(e: f64, b: f64, r: f64) -> f64 {
    let x = e / (FY / E);
    FY * (b * x + (1.0 - b) * x / (1.0 + x.abs().powf(r)).powf(1.0 / r))
}

#[test]
fn monotonic_loading_follows_the_closed_form_first_branch() {
    let ey = FY / E;
    for (b, r0) in [(0.01, 20.0), (0.05, 10.0), (0.0, 18.0)] {
        let m = steel(b, r0, 0.925, NO_HARDENING, 0.0);
        for sign in [1.0, -1.0] {
            let us: Vec<f64> = (1..=400).map(|k| sign * k as f64 * 0.05 * ey).collect();
            let (_, out) = drive(&m, &us);
            for (&u, &(f, k)) in us.iter().zip(&out) {
                let exact = menegotto_pinto(u, b, r0);
                assert!(
                    (f - exact).abs() <= 1e-12 * FY,
                    "b {b} u {u}: {f} vs {exact}"
                );
                let x: f64 = u.abs() / ey;
                let dk = E * (b + (1.0 - b) / (1.0 + x.powf(r0)).powf(1.0 + 1.0 / r0));
                assert!((k - dk).abs() <= 1e-12 * E, "tangent at {u}: {k} vs {dk}");
            }
        }
    }
}

#[test]
fn isotropic_hardening_shifts_the_asymptote_by_the_closed_form() {
    // cR1 = 0 keeps R = R0 = 20: the curve meets its asymptote to round-off 10 ey past the
    // intersection, so the force there is the shifted asymptote
    let ey = FY / E;
    let b = 0.02;
    let (a3, a4) = (0.4, 2.0);
    let m = steel(b, 20.0, 0.0, [0.0, 1.0, a3, a4], 0.0);
    let plain = steel(b, 20.0, 0.0, NO_HARDENING, 0.0);
    let mut us: Vec<f64> = (1..=100).map(|k| -0.1 * k as f64 * ey).collect(); // to -10 ey
    us.extend((1..=600).map(|k| -10.0 * ey + 0.1 * k as f64 * ey)); // up to +50 ey
    let (_, out) = drive(&m, &us);
    let (_, out_plain) = drive(&plain, &us);
    let shift = 1.0 + a3 * ((ey - (-10.0 * ey)) / (2.0 * a4 * ey)).powf(0.8);
    let u = *us.last().unwrap();
    let asymptote = FY * shift + b * E * (u - ey * shift);
    let (f, k) = *out.last().unwrap();
    assert!((f - asymptote).abs() <= 1e-9 * FY, "{f} vs {asymptote}");
    assert!((k - b * E).abs() <= 1e-9 * E);
    let unshifted = FY + b * E * (u - ey);
    assert!((out_plain.last().unwrap().0 - unshifted).abs() <= 1e-9 * FY);
    assert!(f - unshifted > 0.1 * FY, "the hardening shift is visible");
}

#[test]
fn tangent_is_the_derivative_of_the_force() {
    let ey = FY / E;
    let histories = [
        cycles(&[0.5 * ey, 2.0 * ey, 5.0 * ey, 12.0 * ey], 25),
        random_walk(400, 1.5 * ey, 7),
    ];
    for a in [NO_HARDENING, [0.08, 1.0, 0.08, 1.0]] {
        for sig_init in [0.0, 0.3 * FY] {
            let m = steel(0.02, 20.0, 0.925, a, sig_init);
            for us in &histories {
                let (err, n) = tangent_error(&m, us, 1e-7 * ey, E);
                assert!(n > us.len() * 9 / 10, "compared {n} of {}", us.len());
                assert!(
                    err < 1e-5,
                    "tangent error {err} (a {a:?}, sig_init {sig_init})"
                );
            }
        }
    }
}

#[test]
fn tangent_stays_within_the_bound() {
    let ey = FY / E;
    let m = steel(0.02, 20.0, 0.925, [0.08, 1.0, 0.08, 1.0], 0.0);
    let bound = m.tangent_bound().unwrap();
    let (_, out) = drive(&m, &random_walk(2000, 3.0 * ey, 11));
    assert!(out
        .iter()
        .all(|&(_, k)| (0.0..=bound * (1.0 + 1e-14)).contains(&k)));
}

#[test]
fn initial_stress_is_kept_until_the_first_increment() {
    let m = steel(0.02, 20.0, 0.925, NO_HARDENING, 100.0);
    let (_, out) = drive(&m, &[0.0]);
    assert_eq!(out[0], (100.0, E));
}

#[test]
fn bad_parameters_are_named() {
    let ok =
        |fy, e, b, r0, cr1, cr2, a, s| Steel02::new(fy, e, b, Transition { r0, cr1, cr2 }, a, s);
    let name = |r: Result<Steel02, CoreError>| match r {
        Err(CoreError::InvalidInput { name, .. }) => name,
        other => panic!("expected an input error, got {other:?}"),
    };
    let a = NO_HARDENING;
    assert_eq!(name(ok(0.0, E, 0.1, 20.0, 0.9, 0.15, a, 0.0)), "fy");
    assert_eq!(name(ok(FY, f64::NAN, 0.1, 20.0, 0.9, 0.15, a, 0.0)), "E");
    assert_eq!(name(ok(FY, E, 1.0, 20.0, 0.9, 0.15, a, 0.0)), "b");
    assert_eq!(name(ok(FY, E, -0.1, 20.0, 0.9, 0.15, a, 0.0)), "b");
    assert_eq!(name(ok(FY, E, 0.1, 0.0, 0.9, 0.15, a, 0.0)), "R0");
    assert_eq!(name(ok(FY, E, 0.1, 20.0, 1.0, 0.15, a, 0.0)), "cR1");
    assert_eq!(name(ok(FY, E, 0.1, 20.0, 0.9, 0.0, a, 0.0)), "cR2");
    assert_eq!(
        name(ok(
            FY,
            E,
            0.1,
            20.0,
            0.9,
            0.15,
            [f64::INFINITY, 1.0, 0.0, 1.0],
            0.0
        )),
        "a1"
    );
    assert_eq!(
        name(ok(FY, E, 0.1, 20.0, 0.9, 0.15, [0.0, 0.0, 0.0, 1.0], 0.0)),
        "a2"
    );
    assert_eq!(
        name(ok(
            FY,
            E,
            0.1,
            20.0,
            0.9,
            0.15,
            [0.0, 1.0, f64::NAN, 1.0],
            0.0
        )),
        "a3"
    );
    assert_eq!(
        name(ok(FY, E, 0.1, 20.0, 0.9, 0.15, [0.0, 1.0, 0.0, -1.0], 0.0)),
        "a4"
    );
    assert_eq!(
        name(ok(FY, E, 0.1, 20.0, 0.9, 0.15, a, f64::NAN)),
        "sig_init"
    );
}
