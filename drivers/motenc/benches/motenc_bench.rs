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

use std::time::Duration;

use hal_core::{Host, HostConfig, Value};
use hal_driver::bench::{hal_functions, print_functions, run_cases};

const READS: [&str; 4] = ["encoder-read", "digital-in-read", "adc-read", "misc-update"];
const WRITES: [&str; 2] = ["dac-write", "digital-out-write"];

fn main() -> std::process::ExitCode {
    let cases = [("100", "MOTENC-100"), ("lite", "MOTENC-Lite")];
    run_cases(cases.map(|(k, t)| (t.to_string(), k)), |tag, kind| {
        bench(kind, tag)
    })
}

fn bench(kind: &str, tag: &str) -> hal_core::Result<()> {
    let name = format!("motenc-bench-{kind}-{}", std::process::id());
    let host = Host::create(HostConfig::new(&name))?;
    host.loadrt(
        &hal_motenc::MODULE,
        &["backend=sim".to_string(), format!("sim_boards={kind}")],
    )?;
    let inst = host.instance();
    // Every DAC drives its motor; outputs toggle between samples.
    for n in 0..8 {
        inst.set_pin(
            &format!("motenc.0.dac-{n:02}-value"),
            Value::Float(1.0 + n as f64),
        )?;
    }
    let functs: Vec<String> = READS
        .iter()
        .chain(&WRITES)
        .map(|f| format!("motenc.0.{f}"))
        .collect();
    let functs: Vec<&str> = functs.iter().map(String::as_str).collect();
    let times = hal_functions(&host, &functs, 100_000, Duration::from_secs(2), |round| {
        for n in (0..32).step_by(3) {
            let on = Value::Bit(round % 2 == 0);
            let _ = inst.set_pin(&format!("motenc.0.out-{n:02}"), on);
        }
    })?;
    print_functions(
        &format!(
            "hal_motenc, simulated {tag}, 100 us thread (realtime: {})",
            host.is_realtime()
        ),
        &times,
        READS.len(),
    );
    Ok(())
}
