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

const USAGE: &str = "usage: realtime start|stop|restart|status";

fn main() {
    let instance = instance_from_env();
    let args: Vec<std::ffi::OsString> = std::env::args_os().skip(1).collect();
    let cmd = match args.as_slice() {
        [one] => one.to_str().unwrap_or(""),
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
        "-h" | "--help" => {
            hal_tools::outln!("{USAGE}");
            0
        }
        _ => {
            eprintln!("{USAGE}");
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
