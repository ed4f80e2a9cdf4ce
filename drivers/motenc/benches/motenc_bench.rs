//! Prints what the `hal_motenc` functions cost on fully populated
//! simulated boards (a MOTENC-100: 8 encoders turning, 68 inputs, 32
//! outputs, 8 DACs, 8 ADCs; and a MOTENC-Lite), measured by the HAL
//! executor's per-function timing in a 100 us thread and averaged over
//! every sample taken.
//!
//! `cargo bench -p hal-motenc`. The simulator's own work (the board
//! model behind a lock, the motors advanced once per `encoder-read`) is
//! part of the figures, so hardware costs differ: a real PCI read is
//! about 0.5 to 1 us, a posted write far less.

use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, Value};

const READS: [&str; 4] = ["encoder-read", "digital-in-read", "adc-read", "misc-update"];
const WRITES: [&str; 2] = ["dac-write", "digital-out-write"];

fn main() {
    for (kind, tag) in [("100", "MOTENC-100"), ("lite", "MOTENC-Lite")] {
        if let Err(e) = bench(kind, tag) {
            println!("  {tag}: skipped ({e})");
        }
    }
}

fn bench(kind: &str, tag: &str) -> hal_core::Result<()> {
    let name = format!("motenc-bench-{kind}-{}", std::process::id());
    let host = Host::create(HostConfig::new(&name))?;
    host.loadrt(
        &hal_motenc::MODULE,
        &["backend=sim".to_string(), format!("sim_boards={kind}")],
    )?;
    let inst = host.instance();
    // Every DAC drives its motor, every output toggles each call.
    for n in 0..8 {
        inst.set_pin(
            &format!("motenc.0.dac-{n:02}-value"),
            Value::Float(1.0 + n as f64),
        )?;
    }
    host.create_thread("t", 100_000, true, None)?;
    for f in READS.iter().chain(&WRITES) {
        host.addf(&format!("motenc.0.{f}"), "t", -1)?;
    }
    host.start()?;
    let mut sums = vec![(0f64, 0u64); READS.len() + WRITES.len()];
    let end = Instant::now() + Duration::from_secs(2);
    let mut toggle = false;
    while Instant::now() < end {
        toggle = !toggle;
        for n in (0..32).step_by(3) {
            let _ = inst.set_pin(&format!("motenc.0.out-{n:02}"), Value::Bit(toggle));
        }
        for (i, f) in READS.iter().chain(&WRITES).enumerate() {
            if let Value::S32(ns) = inst.pin_value(&format!("motenc.0.{f}.time"))? {
                sums[i].0 += ns as f64;
                sums[i].1 += 1;
            }
        }
        std::thread::sleep(Duration::from_micros(150));
    }
    host.stop();
    println!(
        "hal_motenc, simulated {tag}, 100 us thread (realtime: {}), mean of {} samples",
        host.is_realtime(),
        sums[0].1
    );
    let mut totals = [0.0; 2];
    for (i, f) in READS.iter().chain(&WRITES).enumerate() {
        let mean = sums[i].0 / sums[i].1.max(1) as f64;
        let tmax = inst.param_value(&format!("motenc.0.{f}.tmax"))?;
        let tmax = match tmax {
            Value::S32(v) => v,
            _ => 0,
        };
        totals[(i >= READS.len()) as usize] += mean;
        println!("  motenc.0.{f:<20} {mean:8.0} ns   (max {tmax} ns)");
    }
    println!(
        "  read total {:8.0} ns, write total {:8.0} ns",
        totals[0], totals[1]
    );
    Ok(())
}
