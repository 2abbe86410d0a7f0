//! Times the single-mode closed-form path on the paper's Duffing oscillator:
//! `cargo run --release --example duffing [steps] [auto|newton]`.

use duhamel_core::elements::polynomial::Polynomial;
use duhamel_core::elements::Element;
use duhamel_core::pseudo::{integrate, NonlinearProblem, Options, Quadrature, Scheme, Solver};
use duhamel_core::{ModalProblem, Unattended};

fn main() {
    let steps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let cubic = Polynomial::cubic(0, 4.0).expect("valid element");
    let elements: [&dyn Element; 1] = [&cubic];
    let dt = 2.0 * std::f64::consts::PI / 100.0;
    let only = std::env::args().nth(2);
    for (name, solver) in [("auto", Solver::Auto), ("newton", Solver::Newton)] {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let problem = NonlinearProblem {
            base: ModalProblem {
                k: &[1.0],
                c: &[0.0],
                q0: &[1.0],
                v0: &[0.0],
                loads: &[],
                t0: 0.0,
                step0: 0,
                dt,
                n_steps: steps,
                save_every: std::env::var("SAVE_EVERY")
                    .ok()
                    .and_then(|s| s.parse().ok())
                    .unwrap_or(1),
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
                tol: 1e-10,
                max_iter: 25,
                solver,
                subdivisions: 4,
                growth_limit: f64::INFINITY,
            },
            element_state: None,
            guard_state: None,
            energy: None,
        };
        let start = std::time::Instant::now();
        let (history, stats) = integrate(&problem, None, &mut Unattended).expect("runs");
        let ns = start.elapsed().as_secs_f64() * 1e9 / steps as f64;
        println!(
            "{name}: {ns:.1} ns/step, final x = {:.6}, newton iterations {}",
            history.q().last().copied().unwrap_or(f64::NAN),
            stats.newton_iterations
        );
    }
}
