//! halcmd: manipulate a running HAL instance.

use hal_core::{instance_from_env, Instance};
use hal_tools::cli::{halcmd_usage, parse_halcmd_args, run_halcmd};

fn main() {
    let args = hal_tools::stdio::args_or_exit("halcmd", 1);
    let parsed = match parse_halcmd_args(&args) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("halcmd: {e}");
            std::process::exit(1);
        }
    };
    if parsed.version {
        hal_tools::outln!("{}", hal_core::userspace::version_line("halcmd"));
        return;
    }
    if let Some(name) = &parsed.instance {
        if let Err(e) = hal_core::userspace::select_instance(name) {
            eprintln!("halcmd: --instance: {e}");
            std::process::exit(1);
        }
    }
    if let Some(topic) = &parsed.help {
        match topic {
            None => hal_tools::out!("{}", halcmd_usage()),
            Some(cmd) => match hal_lang::format::help(Some(cmd)) {
                Ok(text) => hal_tools::out!("{text}"),
                Err(e) => {
                    eprintln!("halcmd: {e}");
                    std::process::exit(1);
                }
            },
        }
        return;
    }
    let inst = match Instance::attach(&instance_from_env()) {
        Ok(i) => i,
        Err(e) => {
            eprintln!("halcmd: {e}");
            std::process::exit(1);
        }
    };
    std::process::exit(run_halcmd(inst, parsed, false));
}
