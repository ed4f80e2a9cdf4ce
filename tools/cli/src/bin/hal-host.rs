//! The HAL host process for one instance (started by `halrun` and
//! `realtime start`; not usually run by hand).

use hal_core::userspace::instance_option;
use hal_core::{instance_from_env, HostConfig};

fn main() {
    let mut instance = instance_from_env();
    let args = hal_tools::stdio::args_or_exit("hal-host", 1);
    let mut i = 0;
    while i < args.len() {
        if let Some(found) = instance_option(&args, i, true) {
            let (name, words) = found.unwrap_or_else(|e| die(&e.to_string()));
            instance = name;
            i += words;
            continue;
        }
        match args[i].as_str() {
            "-h" | "--help" => {
                hal_tools::outln!("{}", hal_tools::usage::HAL_HOST);
                return;
            }
            "--version" => {
                hal_tools::outln!("{}", hal_core::userspace::version_line("hal-host"));
                return;
            }
            other if other.starts_with('-') => {
                die(&format!("unknown option '{other}' (see hal-host --help)"))
            }
            other => die(&format!(
                "unexpected argument '{other}' (see hal-host --help)"
            )),
        }
    }
    // Whoever started us polls the socket until it answers
    // (hal_lang::host_process).
    let result = hal_host::serve(HostConfig::new(&instance), || {});
    if let Err(e) = result {
        die(&e.to_string());
    }
}

fn die(msg: &str) -> ! {
    eprintln!("hal-host: {msg}");
    std::process::exit(1);
}
