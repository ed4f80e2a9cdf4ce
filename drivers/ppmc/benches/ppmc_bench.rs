//! Prints what the `hal_ppmc` functions cost on fully used simulated
//! buses (a PPMC set: 4 counters, 4 DACs, 16 inputs, 8 outputs and the
//! estop circuit; a USC and a UPC with their extra ports: 8 counters,
//! 4 step and 4 PWM generators, 32 inputs, 24 outputs), measured by the
//! HAL executor's per-function timing in a 100 us thread and averaged
//! over every sample taken.
//!
//! `cargo bench -p hal-ppmc`. The simulator's work (the port model
//! behind a lock, the motors advanced once per `read`) is part of the
//! figures. On a real port every EPP cycle takes about a microsecond:
//! the PPMC set's read is 24 cycles (and a status read per address
//! cycle), its write 15.

use std::time::Duration;

use hal_core::{Host, HostConfig, Value};
use hal_driver::bench::{hal_functions, print_functions, run_cases};

fn main() -> std::process::ExitCode {
    let cases = [
        ("PPMC set", &["sim=ppmc"][..]),
        (
            "USC + UPC",
            &[
                "sim=usc+upc",
                "extradout=0x00",
                "extradac=0x02",
                "timestamp=0x02",
            ],
        ),
    ];
    run_cases(cases.map(|(l, a)| (l.to_string(), a)), bench)
}

fn bench(label: &str, args: &[&str]) -> hal_core::Result<()> {
    let name = format!("ppmc-bench-{}-{}", label.len(), std::process::id());
    let host = Host::create(HostConfig::new(&name))?;
    host.loadrt(&hal_ppmc::MODULE, args)?;
    let inst = host.instance();
    // Everything that exists moves: DACs, step and PWM generators out of
    // estop, half the counters waiting for an index.
    for n in 0..8 {
        let _ = inst.set_pin(&format!("ppmc.0.DAC.{n:02}.value"), Value::Float(0.5));
        let _ = inst.set_pin(
            &format!("ppmc.0.stepgen.{n:02}.velocity"),
            Value::Float(100.0),
        );
        let _ = inst.set_pin(&format!("ppmc.0.stepgen.{n:02}.enable"), Value::Bit(true));
        let _ = inst.set_pin(&format!("ppmc.0.pwm.{n:02}.value"), Value::Float(0.5));
        let _ = inst.set_pin(&format!("ppmc.0.pwm.{n:02}.enable"), Value::Bit(true));
        let _ = inst.set_pin(
            &format!("ppmc.0.encoder.{n:02}.index-enable"),
            Value::Bit(n % 2 == 0),
        );
    }
    let _ = inst.set_param("ppmc.0.pwm.00-03.freq", Value::Float(20_000.0));
    let _ = inst.set_pin("ppmc.0.dout.07.out", Value::Bit(true));
    let _ = inst.set_pin("ppmc.0.dout.Estop.out", Value::Bit(true));
    let functs = ["ppmc.0.read", "ppmc.0.write"];
    let times = hal_functions(&host, &functs, 100_000, Duration::from_secs(2), |round| {
        for n in (0..8).step_by(3) {
            let _ = inst.set_pin(
                &format!("ppmc.0.dout.{n:02}.out"),
                Value::Bit(round % 2 == 0),
            );
        }
    })?;
    print_functions(
        &format!(
            "hal_ppmc, simulated {label}, 100 us thread (realtime: {})",
            host.is_realtime()
        ),
        &times,
        1,
    );
    Ok(())
}
