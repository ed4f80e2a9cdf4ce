//! Prints what the `hal_stg` functions cost on a fully populated
//! simulated board (8 channels turning, 16 inputs, 16 outputs, every
//! DAC and ADC), Model I and Model II, measured by the HAL executor's
//! per-function timing in a 100 us thread and averaged over every sample
//! taken.
//!
//! `cargo bench -p hal-stg`. The simulator's own work (the board model
//! behind a lock, the motors advanced once per `capture-position`) is
//! part of the figures. On the ISA bus every port access takes about a
//! microsecond, so hardware costs are of another order: a capture of 8
//! channels makes about 40 accesses.

use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, Value};

const READS: [&str; 3] = ["capture-position", "read-adcs", "di-read"];
const WRITES: [&str; 2] = ["write-dacs", "do-write"];

fn main() {
    for model in [1, 2] {
        if let Err(e) = bench(model) {
            println!("  Model {model}: skipped ({e})");
        }
    }
}

fn bench(model: u8) -> hal_core::Result<()> {
    let name = format!("stg-bench-{model}-{}", std::process::id());
    let host = Host::create(HostConfig::new(&name))?;
    host.loadrt(
        &hal_stg::MODULE,
        &["backend=sim".to_string(), format!("model={model}")],
    )?;
    let inst = host.instance();
    for n in 0..8 {
        inst.set_pin(&format!("stg.{n}.dac-value"), Value::Float(1.0 + n as f64))?;
        inst.set_pin(&format!("stg.{n}.index-enable"), Value::Bit(n % 2 == 0))?;
    }
    host.create_thread("t", 100_000, true, None)?;
    for f in READS.iter().chain(&WRITES) {
        host.addf(&format!("stg.{f}"), "t", -1)?;
    }
    host.start()?;
    let mut sums = vec![(0f64, 0u64); READS.len() + WRITES.len()];
    let end = Instant::now() + Duration::from_secs(2);
    let mut toggle = false;
    while Instant::now() < end {
        toggle = !toggle;
        for n in (0..16).step_by(3) {
            let _ = inst.set_pin(&format!("stg.out-{n:02}"), Value::Bit(toggle));
        }
        for (i, f) in READS.iter().chain(&WRITES).enumerate() {
            if let Value::S32(ns) = inst.pin_value(&format!("stg.{f}.time"))? {
                sums[i].0 += ns as f64;
                sums[i].1 += 1;
            }
        }
        std::thread::sleep(Duration::from_micros(150));
    }
    host.stop();
    println!(
        "hal_stg, simulated Model {}, 100 us thread (realtime: {}), mean of {} samples",
        if model == 1 { "I" } else { "II" },
        host.is_realtime(),
        sums[0].1
    );
    let mut totals = [0.0; 2];
    for (i, f) in READS.iter().chain(&WRITES).enumerate() {
        let mean = sums[i].0 / sums[i].1.max(1) as f64;
        let tmax = match inst.param_value(&format!("stg.{f}.tmax"))? {
            Value::S32(v) => v,
            _ => 0,
        };
        totals[(i >= READS.len()) as usize] += mean;
        println!("  stg.{f:<20} {mean:8.0} ns   (max {tmax} ns)");
    }
    println!(
        "  read total {:8.0} ns, write total {:8.0} ns",
        totals[0], totals[1]
    );
    Ok(())
}
