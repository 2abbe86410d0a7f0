//! The transfer matrices of a model's modes over a step, made once per content: a
//! prepared model's runs (a study's, `Prepared.run`) step the same modes with the same step
//! (and its subdivisions), and [`Transfer::new`] per mode and level is a few microseconds of
//! every short run. The matrices are a pure function of `(k, c, dt)`, so a run given the
//! kept ones computes exactly what it would have made itself.

use std::sync::{Arc, Mutex};

use super::oscillator::Transfer;

/// Sets of matrices kept (the oldest dropped first).
const KEPT: usize = 16;

/// Modes above which a set is made each time and not kept (its size bounds the memory kept,
/// `KEPT * MODES` matrices of 112 bytes; making it is then a small part of a run anyway).
const MODES: usize = 4096;

/// One set: its step and modes (their bits: the exact content, signed zeros and NaNs told
/// apart) and the matrices.
struct Entry {
    dt: u64,
    k: Vec<u64>,
    c: Vec<u64>,
    transfers: Arc<[Transfer]>,
}

static MEMO: Mutex<Vec<Entry>> = Mutex::new(Vec::new());

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

/// `Transfer::new(k[m], c[m], dt)` for every mode `m` (`k` and `c` of one length: the
/// caller checked them), the set made once for the same `k`, `c` and `dt`.
pub fn transfers(k: &[f64], c: &[f64], dt: f64) -> Arc<[Transfer]> {
    let make = || -> Arc<[Transfer]> {
        k.iter()
            .zip(c)
            .map(|(&k, &c)| Transfer::new(k, c, dt))
            .collect()
    };
    if k.len() > MODES {
        return make();
    }
    let same = |e: &Entry| {
        e.dt == dt.to_bits()
            && e.k.len() == k.len()
            && e.c.len() == c.len()
            && e.k.iter().zip(k).all(|(a, b)| *a == b.to_bits())
            && e.c.iter().zip(c).all(|(a, b)| *a == b.to_bits())
    };
    {
        let memo = MEMO.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(e) = memo.iter().find(|e| same(e)) {
            return Arc::clone(&e.transfers);
        }
    }
    let made = make();
    let mut memo = MEMO.lock().unwrap_or_else(|p| p.into_inner());
    if !memo.iter().any(same) {
        if memo.len() >= KEPT {
            memo.remove(0);
        }
        memo.push(Entry {
            dt: dt.to_bits(),
            k: bits(k),
            c: bits(c),
            transfers: Arc::clone(&made),
        });
    }
    made
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kept_sets_are_the_matrices_made_afresh() {
        let (k, c) = ([4.0, 0.0, 2.5e3, f64::INFINITY], [0.1, 0.0, 1.0, 3.0]);
        for dt in [0.01, 0.005, 0.01] {
            let first = transfers(&k, &c, dt);
            let again = transfers(&k, &c, dt);
            assert!(Arc::ptr_eq(&first, &again));
            for (m, t) in first.iter().enumerate() {
                assert!(*t == Transfer::new(k[m], c[m], dt));
            }
        }
        // another step or other modes: another set
        let other = transfers(&k, &c, 0.02);
        assert!(other[0] == Transfer::new(4.0, 0.1, 0.02));
        let c2 = [0.1, -0.0, 1.0, 3.0];
        let signed = transfers(&k, &c2, 0.01);
        assert!(!Arc::ptr_eq(&signed, &transfers(&k, &c, 0.01)));
    }
}
