//! The first-order (coupled) background against the uncoupled one.

use duhamel_core::background::first_order::{integrate, FirstOrderModes};
use duhamel_core::background::uncoupled;
use duhamel_core::loads::{ModalLoad, TimeFunction};
use duhamel_core::output::Outputs;
use duhamel_core::{ModalProblem, Unattended};
use num_complex::Complex64;

/// One damped oscillator `q'' + c q' + k q = p` in first-order modes (computed by hand)
/// gives the uncoupled engine's answer, loads and in-step jumps included.
#[test]
fn one_oscillator_matches_the_uncoupled_engine() {
    let (k, c) = ([4.0], [0.4]);
    let loads = [
        ModalLoad {
            pattern: vec![1.5],
            time: TimeFunction::Step { t0: 0.123 },
        },
        ModalLoad {
            pattern: vec![-0.7],
            time: TimeFunction::Harmonic {
                omega: 3.0,
                phase: 0.2,
            },
        },
    ];
    let problem = ModalProblem {
        k: &k,
        c: &c,
        q0: &[0.3],
        v0: &[-0.2],
        loads: &loads,
        t0: 0.0,
        step0: 0,
        dt: 0.05,
        n_steps: 200,
        save_every: 1,
        threads: Some(1),
    };
    // A = [[0, 1], [-k, -c]]: lambda = (-c + i sqrt(4k - c^2)) / 2, V = [[1, 1], [l, conj l]].
    let lam = Complex64::new(-c[0] / 2.0, (4.0 * k[0] - c[0] * c[0]).sqrt() / 2.0);
    let det = lam.conj() - lam; // det V
                                // row 0 of V^-1 = [conj l, -1] / det
    let w0 = lam.conj() / det;
    let w1 = Complex64::new(-1.0, 0.0) / det;
    let eta0 = w0 * 0.3 + w1 * -0.2;
    let modes = FirstOrderModes {
        lambda_re: &[lam.re],
        lambda_im: &[lam.im],
        gain_re: &[w1.re],
        gain_im: &[w1.im],
        eta0_re: &[eta0.re],
        eta0_im: &[eta0.im],
    };
    // [Re eta, Im eta] -> (q, v) = 2 Re(V_0 eta): q = 2 Re eta, v = 2 Re(l eta).
    let map = [2.0, 2.0 * lam.re, 0.0, -2.0 * lam.im];
    let outputs = Outputs {
        map: &map,
        loads: &[0.0; 4],
        n_cols: 2,
    };
    let (h, _) = integrate(
        &problem,
        &modes,
        Some(&outputs),
        None,
        None,
        &mut Unattended,
    )
    .unwrap();
    let reference = uncoupled::integrate(&problem, None, &mut Unattended).unwrap();
    assert_eq!(h.t, reference.t);
    for (s, row) in h.outputs.as_ref().unwrap().chunks_exact(2).enumerate() {
        assert!((row[0] - reference.q()[s]).abs() < 1e-14, "q at step {s}");
        assert!((row[1] - reference.v()[s]).abs() < 1e-13, "v at step {s}");
    }
}
