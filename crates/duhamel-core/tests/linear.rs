//! The modal time loop against closed forms and against a naive step-by-step reference.

use duhamel_core::background::uncoupled;
use duhamel_core::loads::{ModalForcing, ModalLoad, TimeFunction};
use duhamel_core::{CoreError, Transfer};
use duhamel_core::{Failure, History, ModalProblem as LinearProblem, Unattended};

/// The uncoupled route, unwatched.
fn integrate(
    p: &LinearProblem,
    forcing: Option<&mut dyn ModalForcing>,
) -> Result<History, Box<Failure>> {
    uncoupled::integrate(p, forcing, &mut Unattended)
}

fn problem<'a>(
    k: &'a [f64],
    c: &'a [f64],
    q0: &'a [f64],
    v0: &'a [f64],
    loads: &'a [ModalLoad],
    dt: f64,
    n_steps: usize,
) -> LinearProblem<'a> {
    LinearProblem {
        k,
        c,
        q0,
        v0,
        loads,
        t0: 0.0,
        step0: 0,
        dt,
        n_steps,
        save_every: 1,
        threads: Some(1),
    }
}

fn q(h: &History, s: usize, mode: usize) -> f64 {
    h.q()[s * h.n_modes + mode]
}

#[test]
fn free_vibration_is_exact_at_every_step() {
    let w = 3.0_f64;
    let (k, c) = ([w * w], [0.0]);
    let h = integrate(&problem(&k, &c, &[1.0], &[0.0], &[], 0.7, 200), None).unwrap();
    for (s, &t) in h.t.iter().enumerate() {
        assert!((q(&h, s, 0) - (w * t).cos()).abs() < 1e-12, "t = {t}");
        assert!((h.v()[s] + w * (w * t).sin()).abs() < 1e-11, "t = {t}");
    }
}

#[test]
fn step_load_jumping_inside_a_step_is_exact() {
    // x'' + 2 z w x' + w^2 x = H(t - t0), from rest; t0 lies inside the third step.
    let (w, z, t0) = (2.0_f64, 0.1_f64, 1.234_f64);
    let (k, c) = ([w * w], [2.0 * z * w]);
    let loads = [ModalLoad {
        pattern: vec![1.0],
        time: TimeFunction::Step { t0 },
    }];
    let h = integrate(&problem(&k, &c, &[0.0], &[0.0], &loads, 0.5, 40), None).unwrap();
    let wd = w * (1.0 - z * z).sqrt();
    for (s, &t) in h.t.iter().enumerate() {
        let tau = t - t0;
        let exact = if tau <= 0.0 {
            0.0
        } else {
            (1.0 - (-z * w * tau).exp() * ((wd * tau).cos() + z * w / wd * (wd * tau).sin()))
                / (w * w)
        };
        assert!((q(&h, s, 0) - exact).abs() < 1e-14, "t = {t}");
    }
    assert_eq!(h.load_values[2], 0.0);
    assert_eq!(h.load_values[3], 1.0);
}

#[test]
fn divergence_is_located_at_the_exact_step_and_keeps_the_history() {
    // Negative damping: growth exp(5 t); two modes, the second stays bounded.
    let (k, c) = ([100.0, 1.0], [-10.0, 0.1]);
    let dt = 0.01;
    let err = integrate(
        &problem(&k, &c, &[1.0, 1.0], &[0.0, 0.0], &[], dt, 40_000),
        None,
    )
    .unwrap_err();
    // The naive reference: apply A step by step until the state is not finite.
    let tr = Transfer::new(k[0], c[0], dt);
    let (mut x, mut v) = (1.0_f64, 0.0_f64);
    let mut first_bad = 0;
    for n in 1..=40_000 {
        (x, v) = (
            tr.a[0][0] * x + tr.a[0][1] * v,
            tr.a[1][0] * x + tr.a[1][1] * v,
        );
        if !(x.is_finite() && v.is_finite()) {
            first_bad = n;
            break;
        }
    }
    assert!(first_bad > 0);
    match err.error {
        CoreError::NonFinite { step, time, .. } => {
            assert_eq!(step, first_bad);
            assert!((time - first_bad as f64 * dt).abs() < 1e-9);
        }
        other => panic!("unexpected error {other:?}"),
    }
    // Saved instants 0..first_bad-1 are kept, all finite.
    assert_eq!(err.partial.t.len(), first_bad);
    assert!(err.partial.q().iter().all(|u| u.is_finite()));
    assert_eq!(err.partial.q().len(), 2 * first_bad);
}

#[test]
fn threads_and_chunks_do_not_change_the_result() {
    let n = 203; // not a multiple of the chunk or lane width
    let k: Vec<f64> = (0..n).map(|i| (1.0 + i as f64).powi(2)).collect();
    let c: Vec<f64> = k.iter().map(|k| 0.02 * k.sqrt()).collect();
    let q0: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
    let v0 = vec![0.5; n];
    let loads = [ModalLoad {
        pattern: (0..n).map(|i| 1.0 / (1.0 + i as f64)).collect(),
        time: TimeFunction::Harmonic {
            omega: 7.0,
            phase: 0.2,
        },
    }];
    let mut p = problem(&k, &c, &q0, &v0, &loads, 0.003, 3000);
    p.save_every = 7;
    let one = integrate(&p, None).unwrap();
    p.threads = Some(2);
    let two = integrate(&p, None).unwrap();
    assert_eq!(one, two);
    assert_eq!(one.t.len(), 3000 / 7 + 2);
    assert!((one.t.last().unwrap() - 9.0).abs() < 1e-12);
}

struct Sine;

impl ModalForcing for Sine {
    fn modal_loads(&mut self, times: &[f64], out: &mut [f64]) -> Result<(), CoreError> {
        let n = out.len() / times.len();
        for (j, &t) in times.iter().enumerate() {
            for m in 0..n {
                out[j * n + m] = (m as f64 + 1.0) * (7.0 * t + 0.2).sin();
            }
        }
        Ok(())
    }
}

#[test]
fn external_forcing_matches_the_builtin_load() {
    let k = [4.0, 25.0, 400.0];
    let c = [0.1, 0.2, 0.3];
    let zeros = [0.0; 3];
    let loads = [ModalLoad {
        pattern: vec![1.0, 2.0, 3.0],
        time: TimeFunction::Harmonic {
            omega: 7.0,
            phase: 0.2,
        },
    }];
    let builtin = integrate(&problem(&k, &c, &zeros, &zeros, &loads, 0.01, 2500), None).unwrap();
    let mut sine = Sine;
    let external = integrate(
        &problem(&k, &c, &zeros, &zeros, &[], 0.01, 2500),
        Some(&mut sine),
    )
    .unwrap();
    for (a, b) in builtin.q().iter().zip(external.q()) {
        assert!((a - b).abs() <= 1e-13 * (1.0 + a.abs()));
    }
    assert_eq!(
        external.forcing.as_ref().map_or(0, Vec::len),
        external.q().len()
    );
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let k = [1.0];
    let err = |p: &LinearProblem| integrate(p, None).unwrap_err().error;
    let base = problem(&k, &[0.0], &[0.0], &[0.0], &[], 0.1, 10);
    assert!(matches!(
        err(&LinearProblem {
            dt: 0.0,
            ..base.clone()
        }),
        CoreError::InvalidInput { name: "dt", .. }
    ));
    assert!(matches!(
        err(&LinearProblem {
            n_steps: 0,
            ..base.clone()
        }),
        CoreError::InvalidInput { name: "t_end", .. }
    ));
    assert!(matches!(
        err(&LinearProblem {
            c: &[0.0, 1.0],
            ..base.clone()
        }),
        CoreError::LengthMismatch { name: "c", .. }
    ));
    assert!(matches!(
        err(&LinearProblem {
            k: &[-1.0],
            ..base.clone()
        }),
        CoreError::InvalidInput { name: "omega2", .. }
    ));
    let bad_table = [ModalLoad {
        pattern: vec![1.0],
        time: TimeFunction::Table {
            t: vec![0.0, 0.0],
            v: vec![1.0, 2.0],
            hold: false,
        },
    }];
    assert!(matches!(
        err(&LinearProblem {
            loads: &bad_table,
            ..base
        }),
        CoreError::InvalidInput { name: "t", .. }
    ));
}
