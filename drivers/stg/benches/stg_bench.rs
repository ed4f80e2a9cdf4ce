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

use std::time::Duration;

use hal_core::{Host, HostConfig, Value};
use hal_driver::bench::{hal_functions, print_functions, run_cases};

const READS: [&str; 3] = ["capture-position", "read-adcs", "di-read"];
const WRITES: [&str; 2] = ["write-dacs", "do-write"];

fn main() -> std::process::ExitCode {
    run_cases([1u8, 2].map(|m| (format!("Model {m}"), m)), |_, m| bench(m))
}

fn bench(model: u8) -> hal_core::Result<()> {
    let name = format!("stg-bench-{model}-{}", std::process::id());
    let host = Host::create(HostConfig::new(&name))?;
    host.loadrt(
        &hal_stg::MODULE,
        &["backend=sim".to_string(), format!("model={model}")],
    )?;
    let inst = host.instance();
    // Every DAC drives its motor, half the channels wait for an index,
    // outputs toggle between samples.
    for n in 0..8 {
        inst.set_pin(&format!("stg.{n}.dac-value"), Value::Float(1.0 + n as f64))?;
        inst.set_pin(&format!("stg.{n}.index-enable"), Value::Bit(n % 2 == 0))?;
    }
    let functs: Vec<String> = READS
        .iter()
        .chain(&WRITES)
        .map(|f| format!("stg.{f}"))
        .collect();
    let functs: Vec<&str> = functs.iter().map(String::as_str).collect();
    let times = hal_functions(&host, &functs, 100_000, Duration::from_secs(2), |round| {
        for n in (0..16).step_by(3) {
            let on = Value::Bit(round % 2 == 0);
            let _ = inst.set_pin(&format!("stg.out-{n:02}"), on);
        }
    })?;
    let m = if model == 1 { "I" } else { "II" };
    print_functions(
        &format!(
            "hal_stg, simulated Model {m}, 100 us thread (realtime: {})",
            host.is_realtime()
        ),
        &times,
        READS.len(),
    );
    Ok(())
}
