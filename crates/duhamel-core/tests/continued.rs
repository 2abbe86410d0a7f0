//! A run continued from an intermediate state at grid point `step0` reproduces the
//! uninterrupted run bit for bit (the hooks of checkpointed, streamed runs).

use duhamel_core::elements::polynomial::Polynomial;
use duhamel_core::elements::spring::Spring;
use duhamel_core::elements::Element;
use duhamel_core::loads::{ModalLoad, TimeFunction};
use duhamel_core::pseudo::{integrate, NonlinearProblem, Options, Quadrature, Scheme, Solver};
use duhamel_core::{History, ModalProblem, Unattended};

const K: [f64; 3] = [1.0, 7.3, 30.0];
const C: [f64; 3] = [0.02, 0.1, 0.3];
const PHI: [f64; 9] = [0.5, 0.4, 0.3, 0.6, -0.2, 0.5, 0.7, 0.1, -0.6];

fn run(
    loads: &[ModalLoad],
    elements: &[&dyn Element],
    (q0, v0): (&[f64], &[f64]),
    (step0, n_steps): (usize, usize),
) -> History {
    let problem = NonlinearProblem {
        base: ModalProblem {
            k: &K,
            c: &C,
            q0,
            v0,
            loads,
            t0: 0.37,
            step0,
            dt: 0.013,
            n_steps,
            save_every: 1,
            threads: Some(1),
        },
        phi: &PHI,
        n_dof: 3,
        elements,
        coupling_k: None,
        coupling_c: None,
        scaled: &[],
        mass: None,
        options: Options {
            scheme: Scheme::B,
            quadrature: Quadrature::Trapezoid,
            tol: 1e-12,
            max_iter: 25,
            solver: Solver::Auto,
            subdivisions: 4,
            growth_limit: f64::INFINITY,
        },
        element_state: None,
        guard_state: None,
        energy: None,
    };
    integrate(&problem, None, &mut Unattended).expect("runs").0
}

#[test]
fn a_continued_run_is_the_uninterrupted_run() {
    let cubic = Polynomial::cubic(0, 40.0).expect("valid");
    let link = Spring::new(1, Some(2), 3.0, 200.0).expect("valid");
    let elements: [&dyn Element; 2] = [&cubic, &link];
    let loads = [ModalLoad {
        pattern: vec![1.0, -0.5, 0.25],
        time: TimeFunction::Harmonic {
            omega: 2.3,
            phase: 0.4,
        },
    }];
    let (q0, v0) = ([0.1, -0.05, 0.02], [0.0, 0.3, -0.1]);
    let (n, split) = (400, 157);
    let whole = run(&loads, &elements, (&q0, &v0), (0, n));
    let first = run(&loads, &elements, (&q0, &v0), (0, split));
    let m = K.len();
    let (qs, vs) = (&first.q()[split * m..], &first.v()[split * m..]);
    let rest = run(&loads, &elements, (qs, vs), (split, n - split));
    // times on the original grid, bit for bit
    assert_eq!(rest.t[..], whole.t[split..]);
    assert_eq!(rest.q()[..], whole.q()[split * m..]);
    assert_eq!(rest.v()[..], whole.v()[split * m..]);
    let pseudo = |h: &History| h.pseudo.clone().expect("a corrector route");
    assert_eq!(pseudo(&rest)[..], pseudo(&whole)[split * m..]);
}
