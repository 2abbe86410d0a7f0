//! Direct integrators: known discrete solutions and exactness properties.

use duhamel_core::direct::assembly::Matrix;
use duhamel_core::direct::{self, AlphaParams, DirectHistory, DirectProblem, Method};
use duhamel_core::elements::spring::Spring;
use duhamel_core::elements::Element;
use duhamel_core::loads::ModalForcing;
use duhamel_core::loads::{ModalLoad, TimeFunction};
use duhamel_core::{CoreError, Failure, Stats, Unattended};

/// A direct integration, unwatched.
fn integrate(
    p: &DirectProblem,
    forcing: Option<&mut dyn ModalForcing>,
) -> Result<(DirectHistory, Stats), Box<Failure<DirectHistory>>> {
    direct::integrate(p, forcing, &mut Unattended)
}

const NEWMARK: Method = Method::Alpha(AlphaParams {
    alpha_m: 0.0,
    alpha_f: 0.0,
    gamma: 0.5,
    beta: 0.25,
});

fn dense(n: usize, data: &[f64]) -> Matrix {
    Matrix::Dense {
        n,
        data: data.to_vec(),
    }
}

fn problem<'a>(
    m: &'a Matrix,
    k: &'a Matrix,
    x0: &'a [f64],
    v0: &'a [f64],
    loads: &'a [ModalLoad],
    out: &'a [usize],
    method: Method,
) -> DirectProblem<'a> {
    DirectProblem {
        m,
        k,
        c: None,
        k_fixed: None,
        scaled: &[],
        elements: &[],
        loads,
        mass: None,
        x0,
        v0,
        a0: None,
        t0: 0.0,
        dt: 0.3,
        n_steps: 40,
        save_every: 1,
        out_dofs: out,
        method,
        tol: 1e-12,
        max_iter: 20,
        energy: None,
    }
}

/// The average acceleration rule is the Cayley transform of the oscillator: from (1, 0) the
/// displacement is exactly cos(n theta), tan(theta / 2) = omega dt / 2.
#[test]
fn newmark_free_vibration_is_the_cayley_transform() {
    let (m, k) = (dense(1, &[2.0]), dense(1, &[8.0]));
    let p = problem(&m, &k, &[1.0], &[0.0], &[], &[0], NEWMARK);
    let (h, stats) = integrate(&p, None).unwrap();
    let theta = 2.0 * (2.0 * p.dt / 2.0f64).atan();
    for (n, x) in h.x.iter().enumerate() {
        assert!((x - (n as f64 * theta).cos()).abs() < 1e-13, "step {n}");
    }
    assert_eq!(stats.factorizations, 1);
    assert_eq!(stats.newton_iterations, 0);
}

/// A cubic trial function holds a constant-force rigid-body motion exactly.
#[test]
fn hermite_is_exact_for_a_constant_force_on_a_free_mass() {
    let (m, k) = (dense(1, &[4.0]), dense(1, &[0.0]));
    let loads = [ModalLoad {
        pattern: vec![2.0],
        time: TimeFunction::Step { t0: 0.0 },
    }];
    let p = problem(
        &m,
        &k,
        &[0.5],
        &[-1.0],
        &loads,
        &[0],
        Method::CubicHermite { points: 3 },
    );
    let (h, _) = integrate(&p, None).unwrap();
    for (n, (&x, &a)) in h.x.iter().zip(&h.a).enumerate() {
        let t = n as f64 * p.dt;
        assert!((x - (0.5 - t + 0.25 * t * t)).abs() < 1e-12, "step {n}");
        assert!((a - 0.5).abs() < 1e-14);
    }
}

/// A linear spring element gives the run of the same stiffness in K (one Newton correction
/// per step converges; dense and sparse assembly agree).
#[test]
fn linear_element_equals_stiffness_dense_and_sparse() {
    let m = dense(2, &[1.0, 0.0, 0.0, 2.0]);
    let k_all = dense(2, &[30.0, -10.0, -10.0, 10.0]);
    let k_part = dense(2, &[20.0, 0.0, 0.0, 0.0]);
    let k_sparse = Matrix::Csr {
        n: 2,
        indptr: vec![0, 1, 1],
        indices: vec![0],
        data: vec![20.0],
    };
    let spring = Spring::new(0, Some(1), 10.0, 0.0).unwrap();
    let elements: [&dyn Element; 1] = [&spring];
    let x0 = [0.1, -0.2];
    let v0 = [0.0, 0.3];
    let method = Method::Alpha(AlphaParams {
        alpha_m: 0.2,
        alpha_f: 0.4,
        gamma: 0.7,
        beta: 0.36,
    });
    let reference = integrate(&problem(&m, &k_all, &x0, &v0, &[], &[0, 1], method), None)
        .unwrap()
        .0;
    for k in [&k_part, &k_sparse] {
        let mut p = problem(&m, k, &x0, &v0, &[], &[0, 1], method);
        p.elements = &elements;
        let (h, stats) = integrate(&p, None).unwrap();
        assert!(stats.newton_iterations >= p.n_steps);
        for (a, b) in h.x.iter().zip(&reference.x) {
            assert!((a - b).abs() < 1e-13);
        }
    }
}

#[test]
fn bad_input_names_the_parameter() {
    let (m, k) = (dense(1, &[1.0]), dense(1, &[1.0]));
    let mut p = problem(&m, &k, &[1.0], &[0.0], &[], &[3], NEWMARK);
    let err = integrate(&p, None).unwrap_err().error;
    assert!(matches!(err, CoreError::InvalidInput { name: "dofs", .. }));
    p.out_dofs = &[0];
    p.method = Method::CubicHermite { points: 1 };
    let err = integrate(&p, None).unwrap_err().error;
    assert!(matches!(
        err,
        CoreError::InvalidInput { name: "points", .. }
    ));
    let wrong = dense(2, &[1.0; 4]);
    p.method = NEWMARK;
    p.k = &wrong;
    let err = integrate(&p, None).unwrap_err().error;
    assert!(matches!(err, CoreError::InvalidInput { name: "K", .. }));
}
