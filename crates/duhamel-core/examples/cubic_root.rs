//! Times `cubic::nearest_root` on Duffing-like cubics: `cargo run --release --example cubic_root`.
fn main() {
    let n = 10_000_000;
    let mut acc = 0.0;
    let start = std::time::Instant::now();
    for i in 0..n {
        let l = 1e-3 * (i % 1000) as f64;
        // u + w u^3 = L around the predictor: one real root near 0
        let c = [-l * 1e-3, 1.0 + 0.01 * l, 0.003, 1e-4];
        acc += duhamel_core::cubic::nearest_root(c, 0.0).unwrap_or(0.0);
    }
    let ns = start.elapsed().as_secs_f64() * 1e9 / n as f64;
    println!("{ns:.1} ns per root (checksum {acc:.6})");
}
