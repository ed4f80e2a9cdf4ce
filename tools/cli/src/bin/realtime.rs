//! realtime: start, stop, restart or query the HAL host of the instance
//! named by `HAL_INSTANCE` (LinuxCNC's tests call it through `$REALTIME`).
//!
//! `stop` returns once the host has exited and released its segment,
//! socket and lock (or says it could not within its limit), so `start`
//! may follow at once; `restart` is the two in one.

use std::time::Duration;

use hal_core::{instance_from_env, Instance};
use hal_lang::host_process::{kill_host, start_host, stop_host};
use hal_lang::protocol::ClientError;

/// How long `stop` waits for the host to release everything.
const STOP_LIMIT: Duration = Duration::from_secs(20);

fn main() {
    use hal_tools::conventions::{common, print_version, Common};
    let args = hal_tools::stdio::args_or_exit("realtime", 2);
    let mut words = Vec::new();
    let mut i = 0;
    while i < args.len() {
        match common(&args, i, true) {
            Ok(Some(Common::Help)) => words.push("--help"),
            Ok(Some(Common::Version)) => {
                print_version("realtime");
                return;
            }
            Ok(Some(Common::Instance(_, n))) => {
                i += n;
                continue;
            }
            Ok(None) => words.push(args[i].as_str()),
            Err(e) => {
                eprintln!("realtime: {e}");
                std::process::exit(2);
            }
        }
        i += 1;
    }
    let instance = instance_from_env();
    let cmd = match words.as_slice() {
        [one] => *one,
        _ => "",
    };
    let code = match cmd {
        "start" => start(&instance),
        "stop" => stop(&instance, false),
        "restart" => match stop(&instance, true) {
            0 => start(&instance),
            failed => failed,
        },
        "status" => {
            if Instance::attach(&instance).is_ok() {
                hal_tools::outln!("realtime running for instance '{instance}'");
                0
            } else {
                hal_tools::outln!("realtime not running for instance '{instance}'");
                1
            }
        }
        "--help" => {
            hal_tools::outln!("{}", hal_tools::usage::REALTIME);
            0
        }
        option if option.starts_with('-') => {
            eprintln!("realtime: unknown option '{option}' (see realtime --help)");
            2
        }
        _ => {
            eprintln!("{}", hal_tools::usage::REALTIME);
            2
        }
    };
    std::process::exit(code);
}

fn start(instance: &str) -> i32 {
    match start_host(instance, true) {
        // The host lives on in its own session; we do not wait for it.
        Ok(child) => {
            std::mem::forget(child);
            let log = hal_lang::host_process::log_path(instance).unwrap_or_default();
            eprintln!(
                "realtime: started for instance '{instance}', messages go to {}",
                log.display()
            );
            0
        }
        Err(e) => {
            eprintln!("realtime: {e}");
            1
        }
    }
}

/// Stops the host; `quiet_if_stopped` makes "not running" a success. A
/// host that does not exit within [`STOP_LIMIT`] is killed, so `stop`
/// always ends it (and says so: its drivers had no safe state).
fn stop(instance: &str, quiet_if_stopped: bool) -> i32 {
    match stop_host(instance, STOP_LIMIT) {
        Ok(()) => 0,
        Err(ClientError::NotRunning { .. }) if quiet_if_stopped => 0,
        Err(e @ ClientError::StillRunning { pid: Some(pid), .. }) => {
            if kill_host(pid, Duration::from_secs(5)) {
                eprintln!(
                    "realtime: {e}; ended it (process {pid}) with SIGKILL: its drivers \
                     had no safe-state exit, check the machine"
                );
            } else {
                eprintln!("realtime: {e}; process {pid} did not end even on SIGKILL");
            }
            1
        }
        Err(e) => {
            eprintln!("realtime: {e}");
            1
        }
    }
}
