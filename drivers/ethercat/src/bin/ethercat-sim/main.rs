//! `ethercat-sim`: a simulated EtherCAT segment, described by a file, as
//! its own process on a network interface (one end of a veth pair), so
//! the master's raw-socket path and third-party masters (SOEM) can be
//! tested end to end. Fault commands arrive on standard input.

use std::io::BufRead;
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

use clap::Parser;
use hal_ethercat::link::RawSocket;
use hal_ethercat::sim::control::{serve, Control};
use hal_ethercat::sim::file;

mod args;
use args::Args;

fn main() -> ExitCode {
    let args = Args::parse();
    let spec = match file::read(&args.file) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("ethercat-sim: {e}");
            return ExitCode::from(2);
        }
    };
    let segment = match spec.build() {
        Ok(s) => Arc::new(Mutex::new(s)),
        Err(e) => {
            eprintln!("ethercat-sim: {e}");
            return ExitCode::from(2);
        }
    };
    let mut link = match RawSocket::open(&args.iface) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("ethercat-sim: {e}");
            return ExitCode::from(2);
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGTERM, signal_hook::consts::SIGINT] {
        if let Err(e) = signal_hook::flag::register(sig, stop.clone()) {
            eprintln!("ethercat-sim: cannot handle signal {sig}: {e}");
            return ExitCode::from(2);
        }
    }
    let control = segment.clone();
    // Fault commands: a thread of their own, so a quiet standard input
    // never holds up the frames. It ends with standard input.
    let _commands = std::thread::Builder::new()
        .name("ethercat-sim-stdin".into())
        .spawn(move || {
            for line in std::io::stdin().lock().lines() {
                let Ok(line) = line else { break };
                if line.trim().is_empty() {
                    continue;
                }
                let r = Control::parse(&line).and_then(|c| match control.lock() {
                    Ok(mut s) => c.apply(&mut s),
                    Err(p) => c.apply(&mut p.into_inner()),
                });
                match r {
                    Ok(None) => println!("ethercat-sim: {}", line.trim()),
                    Ok(Some(said)) => println!("ethercat-sim: {said}"),
                    Err(e) => eprintln!("ethercat-sim: {e}"),
                }
            }
        });
    println!(
        "ethercat-sim: {} slave(s) from {} on {}",
        spec.slaves.len(),
        args.file.display(),
        args.iface
    );
    match serve(&mut link, &segment, &stop) {
        Ok(n) => {
            println!("ethercat-sim: stopped after answering {n} frames");
            ExitCode::SUCCESS
        }
        Err(e) => {
            // The whole chain: the OS error says why the link failed.
            let mut line = format!("ethercat-sim: {e}");
            let mut cause = std::error::Error::source(&e);
            while let Some(c) = cause {
                line.push_str(&format!(": {c}"));
                cause = c.source();
            }
            eprintln!("{line}");
            ExitCode::from(1)
        }
    }
}
