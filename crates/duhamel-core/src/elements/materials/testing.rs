//! Test helpers shared by the materials' unit tests: drive a material along a deformation
//! history (a commit after each point, as OpenSees' `setStrain`) and compare its tangents
//! with finite differences of its force.

use super::Material;

/// The committed state after driving `m` from its virgin state through `us`, and the
/// `(F, dF/du)` at each point.
pub(crate) fn drive(m: &dyn Material, us: &[f64]) -> (Vec<f64>, Vec<(f64, f64)>) {
    let mut c = vec![0.0; m.state_len()];
    m.initial_state(&mut c);
    let mut t = c.clone();
    let mut out = Vec::with_capacity(us.len());
    for &u in us {
        out.push(m.response(u, 0.0, &c, &mut t).expect("response"));
        c.copy_from_slice(&t);
    }
    (c, out)
}

/// The force at `u` from the committed state `c`.
pub(crate) fn force(m: &dyn Material, c: &[f64], u: f64) -> f64 {
    let mut t = c.to_vec();
    m.response(u, 0.0, c, &mut t).expect("response").0
}

/// Along `us`, at each point reached from the previous committed state, the tangent
/// against the central difference of the force (step `h`), where both one-sided
/// differences agree (no kink within `h`); returns the largest difference relative to
/// `scale` and the number of points compared.
pub(crate) fn tangent_error(m: &dyn Material, us: &[f64], h: f64, scale: f64) -> (f64, usize) {
    let mut c = vec![0.0; m.state_len()];
    m.initial_state(&mut c);
    let mut t = c.clone();
    let (mut worst, mut compared) = (0.0_f64, 0);
    for &u in us {
        let (f, k) = m.response(u, 0.0, &c, &mut t).expect("response");
        let (fp, fm) = (force(m, &c, u + h), force(m, &c, u - h));
        let (right, left) = ((fp - f) / h, (f - fm) / h);
        if (right - left).abs() <= 1e-4 * scale {
            worst = worst.max((k - 0.5 * (right + left)).abs() / scale);
            compared += 1;
        }
        c.copy_from_slice(&t);
    }
    (worst, compared)
}

/// A deformation history: cycles of amplitudes `amps` (each up, down and back), `n` points
/// per quarter cycle.
pub(crate) fn cycles(amps: &[f64], n: usize) -> Vec<f64> {
    let mut out = Vec::new();
    for &a in amps {
        for q in 0..4 {
            for k in 1..=n {
                let x = k as f64 / n as f64;
                out.push(match q {
                    0 => a * x,
                    1 => a * (1.0 - x),
                    2 => -a * x,
                    _ => -a * (1.0 - x),
                });
            }
        }
    }
    out
}

/// A reproducible pseudo-random walk of `n` points, steps up to `step`.
pub(crate) fn random_walk(n: usize, step: f64, seed: u64) -> Vec<f64> {
    let mut state = seed;
    let mut u = 0.0;
    (0..n)
        .map(|_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = (state >> 11) as f64 / (1u64 << 53) as f64;
            u += step * (2.0 * r - 1.0);
            u
        })
        .collect()
}
