//! For drivers' benchmark binaries (`cargo bench`, `harness = false`):
//! one way to time a call and print the figure, so every driver's
//! benchmark reads the same.

use std::time::Instant;

/// Runs `f(i)` `n / 10` times to warm up, then `n` times timed, prints
/// `  <what>  <ns> ns` and returns the mean nanoseconds per call.
pub fn per_call(what: &str, n: u64, mut f: impl FnMut(u64)) -> f64 {
    for i in 0..n / 10 {
        f(i);
    }
    let t = Instant::now();
    for i in 0..n {
        f(i);
    }
    let ns = t.elapsed().as_nanos() as f64 / n.max(1) as f64;
    println!("  {what:<48} {ns:8.1} ns");
    ns
}
