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

/// What the HAL executor measured of one function while it ran.
#[derive(Debug, Clone, PartialEq)]
pub struct FunctTime {
    /// The function.
    pub name: String,
    /// Mean of its `.time` pin over the samples, ns.
    pub mean_ns: f64,
    /// Its `.tmax` param at the end, ns.
    pub max_ns: i32,
    /// How many samples were taken.
    pub samples: u64,
}

/// Runs `functs` in order in a new thread `bench` of `period_ns`,
/// samples their `.time` pins every 150 us for `duration`, calling
/// `between` before each round (to change the functions' inputs), and
/// stops the threads. The figures include the simulator's work when the
/// board is simulated.
pub fn hal_functions(
    host: &hal_core::Host,
    functs: &[&str],
    period_ns: i64,
    duration: std::time::Duration,
    mut between: impl FnMut(u64),
) -> hal_core::Result<Vec<FunctTime>> {
    use hal_core::Value;
    host.create_thread("bench", period_ns, true, None)?;
    for f in functs {
        host.addf(f, "bench", -1)?;
    }
    host.start()?;
    let inst = host.instance();
    let mut sums = vec![(0f64, 0u64); functs.len()];
    let end = Instant::now() + duration;
    let mut round = 0;
    while Instant::now() < end {
        between(round);
        round += 1;
        for (i, f) in functs.iter().enumerate() {
            if let Value::S32(ns) = inst.pin_value(&format!("{f}.time"))? {
                sums[i].0 += ns as f64;
                sums[i].1 += 1;
            }
        }
        std::thread::sleep(std::time::Duration::from_micros(150));
    }
    host.stop();
    functs
        .iter()
        .zip(sums)
        .map(|(f, (sum, n))| {
            let max_ns = match inst.param_value(&format!("{f}.tmax"))? {
                Value::S32(v) => v,
                _ => 0,
            };
            Ok(FunctTime {
                name: f.to_string(),
                mean_ns: sum / n.max(1) as f64,
                max_ns,
                samples: n,
            })
        })
        .collect()
}

/// Prints `times` under `title`, one line per function, then the totals
/// of the first `reads` (the read side) and of the rest (the write side).
pub fn print_functions(title: &str, times: &[FunctTime], reads: usize) {
    println!(
        "{title}, mean of {} samples",
        times.first().map_or(0, |t| t.samples)
    );
    let mut totals = [0.0; 2];
    for (i, t) in times.iter().enumerate() {
        totals[(i >= reads) as usize] += t.mean_ns;
        println!(
            "  {:<32} {:8.0} ns   (max {} ns)",
            t.name, t.mean_ns, t.max_ns
        );
    }
    println!(
        "  read total {:8.0} ns, write total {:8.0} ns",
        totals[0], totals[1]
    );
}

/// Runs `bench` for every case and says on stderr which failed and why.
/// A case that cannot run fails the benchmark (exit status 1): it is
/// never passed over as if it had been measured.
pub fn run_cases<C, E: std::fmt::Display>(
    cases: impl IntoIterator<Item = (String, C)>,
    mut bench: impl FnMut(&str, C) -> Result<(), E>,
) -> std::process::ExitCode {
    let mut failed = 0;
    for (label, case) in cases {
        if let Err(e) = bench(&label, case) {
            eprintln!("  {label}: failed: {e}");
            failed += 1;
        }
    }
    if failed == 0 {
        std::process::ExitCode::SUCCESS
    } else {
        std::process::ExitCode::FAILURE
    }
}
