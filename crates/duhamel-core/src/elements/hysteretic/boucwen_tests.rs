//! Tests of `boucwen.rs`.

use super::*;

/// A grounded element at dof 0 of `[k, fy, alpha, n, beta, gamma]`.
pub(super) fn grounded([k, fy, alpha, n, beta, gamma]: [f64; 6]) -> Result<BoucWen, CoreError> {
    let params = BoucWenParams {
        k,
        fy,
        alpha,
        n,
        beta,
        gamma,
    };
    BoucWen::new(0, None, params)
}

#[test]
fn rk4_matches_the_exact_linear_flow() {
    // n = 1 integrated both ways, across the switch at w = 0 and into saturation
    for (beta, gamma) in [(0.5, 0.5), (0.25, 0.75), (0.8, 0.2), (1.0, -0.5)] {
        let e = grounded([1.0, 1.0, 0.0, 1.0, beta, gamma]).unwrap();
        for w0 in [-0.95 / (beta + gamma), -0.3, 0.0, 0.4] {
            for xi in [1e-3, 0.05, 0.3, 1.0, 2.5, 40.0] {
                let exact = e.flow.advance_linear(w0, xi);
                let rk4 = e.flow.advance_rk4(w0, xi).unwrap();
                assert!(
                    (exact - rk4).abs() < 1e-10,
                    "beta {beta} gamma {gamma} w0 {w0} xi {xi}: {exact} vs {rk4}"
                );
            }
        }
    }
}

#[test]
fn saturates_at_z_max_for_huge_increments() {
    for n in [1.0, 2.0, 2.5, 25.0] {
        let e = grounded([2.0, 1.0, 0.1, n, 0.3, 0.5]).unwrap();
        let (z, _, kt) = e.response(0.0, -0.2, 1e9).unwrap();
        assert!((z - e.z_max()).abs() < 1e-12, "n {n}: {z}");
        assert!((kt - 0.2).abs() < 1e-10, "n {n}: {kt}");
    }
}

/// The message of an `OutOfDomain` refusal (panics on anything else).
fn refusal(result: Result<(f64, f64, f64), CoreError>) -> String {
    match result {
        Err(CoreError::OutOfDomain { message, .. }) => message,
        other => panic!("expected a refusal, got {other:?}"),
    }
}

/// Parameters many orders of magnitude apart (issue 38: `fy = 1e-300, beta = 1e-300,
/// n = 1.66` took more than 30 s for a few steps, a million substeps per evaluation)
/// are refused naming the element and the count, on both branches and with the
/// adaptive substeps; ordinary parameters integrate the same huge increments.
#[test]
fn refuses_increments_beyond_the_substep_bound() {
    // the element unloading from saturation (beta ~ 0: g ~ 1e-12 there): z
    // leaves it exponentially (rate n / z_max) and saturates the other way, within
    // a few thousand substeps although the bound on the length to w = 0 is 1e12
    let e = grounded([1.0, 1e-300, 0.0, 1.66, 1e-300, 0.5]).unwrap();
    let (z, _, _) = e.response(0.0, (1.0 - 1e-12) * e.z_max(), -0.01).unwrap();
    assert!((z + e.z_max()).abs() < 1e-12, "{z}");
    // beta = gamma = 1e-300: z saturates at 3.5e180, beyond any substep budget, loading
    // (the positive branch) and unloading (g = 1 on the way to w = 0: w0 = -1e10)
    let e = grounded([1.0, 1e-300, 0.0, 1.66, 1e-300, 1e-300]).unwrap();
    for (z_c, u) in [(0.0, 0.01), (-1e10, 0.01)] {
        let msg = refusal(e.response(0.0, z_c, u));
        assert!(msg.starts_with("BoucWen (dofs [0])"), "{msg}");
        assert!(
            msg.contains("more than the bound of 1e6 RK4 substeps"),
            "{msg}"
        );
    }
    // n > 16: the adaptive substeps reach their bound instead of stopping short
    let e = grounded([1.0, 1e-300, 0.0, 20.0, 1e-30, 1e-30]).unwrap();
    let msg = refusal(e.response(0.0, 0.0, 0.01));
    assert!(msg.contains("bound of 200000 adaptive"), "{msg}");
    // an initial deformation beyond the bound: the first evaluation reports it
    let e = grounded([1.0, 1e-300, 0.0, 1.66, 1e-300, 1e-300]).unwrap();
    let mut state = [0.0; 2];
    e.initial_state(&[0.01], &[0.0], &mut state);
    assert!(state[1].is_nan());
    let (mut trial, mut r) = ([0.0; 2], [0.0]);
    let history = PathState {
        committed: &state,
        trial: &mut trial,
    };
    match e.eval_path(&[0.01], &[0.0], 0.5, history, &mut r, None) {
        Err(CoreError::OutOfDomain { time, .. }) => assert_eq!(time, 0.5),
        other => panic!("{other:?}"),
    }
    // ordinary parameters: huge increments stay within the bound
    for n in [1.5, 2.0, 16.0, 17.0, 64.0] {
        for (beta, gamma) in [(0.5, 0.5), (0.05, 0.005), (0.9, -0.5)] {
            let e = grounded([2.0, 1e-3, 0.1, n, beta, gamma]).unwrap();
            let zm = e.z_max();
            for (z_c, u) in [(0.0, 1e6), (0.99 * zm, -1e6), (-0.99 * zm, 1e3)] {
                assert!(
                    e.response(0.0, z_c, u).is_ok(),
                    "n {n} beta {beta} z_c {z_c}"
                );
            }
        }
    }
}

#[test]
fn validates_parameters() {
    let name = |e: CoreError| match e {
        CoreError::InvalidInput { name, .. } => name,
        other => panic!("{other:?}"),
    };
    let make = |n, beta, gamma| grounded([1.0, 1.0, 0.1, n, beta, gamma]);
    assert_eq!(name(make(0.5, 0.5, 0.5).unwrap_err()), "n");
    assert_eq!(name(make(f64::INFINITY, 0.5, 0.5).unwrap_err()), "n");
    assert_eq!(name(make(1.0, 0.0, 0.5).unwrap_err()), "beta");
    assert_eq!(name(make(1.0, 0.5, -0.5).unwrap_err()), "gamma");
    let e = grounded([1.0, 0.0, 0.1, 1.0, 0.5, 0.5]);
    assert_eq!(name(e.unwrap_err()), "fy");
}
