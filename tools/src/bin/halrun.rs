//! halrun: start a HAL instance, run halcmd on it, then tear it down.

use hal_core::{instance_from_env, Instance};
use hal_tools::cli::{parse_halcmd_args, run_halcmd};
use hal_tools::launch::{start_host, stop_host};

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let instance = instance_from_env();
    let mut interactive = false;
    if args.first().map(String::as_str) == Some("-I") {
        interactive = true;
        args.remove(0);
    }
    if args.first().map(String::as_str) == Some("-U") {
        let _ = stop_host(&instance, std::time::Duration::from_secs(10));
        return;
    }
    if args.iter().any(|a| a == "-h" || a == "--help") {
        println!("usage: halrun [-I] [halcmd options] [-f FILE | COMMAND]\n       halrun -U");
        return;
    }
    let parsed = match parse_halcmd_args(&args) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("halrun: {e}");
            std::process::exit(1);
        }
    };
    let mut host = match start_host(&instance, false) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("halrun: {e}");
            std::process::exit(1);
        }
    };
    let status = match Instance::attach(&instance) {
        Ok(inst) => run_halcmd(inst, parsed, interactive),
        Err(e) => {
            eprintln!("halrun: {e}");
            1
        }
    };
    if let Err(e) = stop_host(&instance, std::time::Duration::from_secs(10)) {
        eprintln!("halrun: stopping realtime: {e}");
        let _ = host.kill();
    }
    let _ = host.wait();
    std::process::exit(status);
}
