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
    for sig in [signal_hook::consts::SIGTERM, signal_hook::consts::SIGINT] {
        if let Err(e) = signal_hook::flag::register(sig, stop.clone()) {
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
    println!(
        "canservo-sim: {} drive(s) on {} (nodes {})",
        drives.len(),
        args.iface,
        list.join(",")
    );
    let sent = process::run(
        &bus,
        &mut drives,
        &stop,
        Duration::from_micros(args.step_us.max(1)),
    );
    println!("canservo-sim: stopped after sending {sent} frames");
    ExitCode::SUCCESS
}
