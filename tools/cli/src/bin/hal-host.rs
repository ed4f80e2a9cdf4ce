//! The HAL host process for one instance (started by `halrun` and
//! `realtime start`; not usually run by hand).

use hal_core::userspace::instance_option;
use hal_core::{instance_from_env, HostConfig};

const USAGE: &str = "\
usage: hal-host [-i NAME]

Runs the HAL host of an instance until 'realtime stop', 'halrun -U' or a
signal: it creates the instance's shared memory, serves its control socket,
loads modules for loadrt and runs the realtime threads. halrun and
'realtime start' start it; it is not usually run by hand.

options:
  -i, --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help           print this help and exit
  --version            print the version and exit";

fn main() {
    let mut instance = instance_from_env();
    let args = hal_tools::stdio::args_or_exit("hal-host", 1);
    let mut i = 0;
    while i < args.len() {
        if let Some(found) = instance_option(&args, i, true) {
            let (name, words) = found.unwrap_or_else(|e| die(&e));
            instance = name;
            i += words;
            continue;
        }
        match args[i].as_str() {
            "-h" | "--help" => {
                hal_tools::outln!("{USAGE}");
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
