//! `canservo-sim`: simulated CiA 402 drives as their own process on a
//! real or virtual CAN interface, so the driver's SocketCAN path can be
//! tested end to end (hardware.md §6.12).

use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use clap::Parser;
use hal_canservo::bus::{Filters, SocketCanBus};
use hal_canservo::sim::{process, SimDrive, SimDriveConfig};
use hal_driver::plant::Switch;
use std::io::Write;

mod args;
use args::Args;

fn main() -> ExitCode {
    let args = Args::parse();
    let bus = match SocketCanBus::open(&args.iface, &Filters::everything()) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("canservo-sim: {e}");
            return ExitCode::from(2);
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    let slow = Arc::new(AtomicBool::new(false));
    for (sig, flag) in [
        (signal_hook::consts::SIGTERM, &stop),
        (signal_hook::consts::SIGINT, &stop),
        (signal_hook::consts::SIGUSR1, &slow),
    ] {
        if let Err(e) = signal_hook::flag::register(sig, flag.clone()) {
            eprintln!("canservo-sim: cannot handle signal {sig}: {e}");
            return ExitCode::from(2);
        }
    }
    let mut drives: Vec<SimDrive> = args
        .nodes
        .iter()
        .map(|&n| {
            let mut cfg = SimDriveConfig::new(n);
            cfg.home_switch = Some(Switch::at_or_above(args.home as f64));
            SimDrive::new(cfg)
        })
        .collect();
    let list: Vec<String> = args.nodes.iter().map(u8::to_string).collect();
    let mut out = std::io::stdout();
    // A closed stdout ends nothing: the drives run on regardless.
    let _ = writeln!(
        out,
        "canservo-sim: {} drive(s) on {} (nodes {})",
        drives.len(),
        args.iface,
        list.join(",")
    );
    let _ = out.flush();
    let pace = process::Pace {
        step: Duration::from_micros(args.step_us.max(1)),
        read_delay: Duration::from_micros(args.read_delay_us),
    };
    let sent = process::run(&bus, &mut drives, &stop, &slow, pace);
    for d in &drives {
        let _ = writeln!(
            out,
            "canservo-sim: node {}: controlword {:#06x}, {}",
            d.node(),
            d.controlword(),
            d.power_state().name()
        );
    }
    let _ = writeln!(out, "canservo-sim: stopped after sending {sent} frames");
    ExitCode::SUCCESS
}
