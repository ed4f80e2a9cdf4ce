//! halcmd: manipulate a running HAL instance.

use hal_core::{instance_from_env, Instance};
use hal_tools::cli::{parse_halcmd_args, run_halcmd};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let parsed = match parse_halcmd_args(&args) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("halcmd: {e}");
            std::process::exit(1);
        }
    };
    let inst = match Instance::attach(&instance_from_env()) {
        Ok(i) => i,
        Err(e) => {
            eprintln!("halcmd: {e}");
            std::process::exit(1);
        }
    };
    std::process::exit(run_halcmd(inst, parsed, false));
}
