//! realtime: start, stop or query the HAL host of the instance named by
//! `HAL_INSTANCE` (LinuxCNC's tests call it through `$REALTIME`).

use std::time::Duration;

use hal_core::{instance_from_env, Instance};
use hal_tools::launch::{start_host, stop_host};

fn main() {
    let instance = instance_from_env();
    let cmd = std::env::args().nth(1).unwrap_or_default();
    let code = match cmd.as_str() {
        "start" => start(&instance),
        "stop" => stop(&instance),
        "restart" => {
            let _ = stop(&instance);
            start(&instance)
        }
        "status" => {
            if Instance::attach(&instance).is_ok() {
                println!("realtime running for instance '{instance}'");
                0
            } else {
                println!("realtime not running for instance '{instance}'");
                1
            }
        }
        _ => {
            eprintln!("usage: realtime start|stop|restart|status");
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
            eprintln!(
                "realtime: started for instance '{instance}', messages go to {}",
                hal_tools::launch::log_path(instance)
                    .unwrap_or_default()
                    .display()
            );
            0
        }
        Err(e) => {
            eprintln!("realtime: {e}");
            1
        }
    }
}

fn stop(instance: &str) -> i32 {
    match stop_host(instance, Duration::from_secs(10)) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("realtime: {e}");
            1
        }
    }
}
