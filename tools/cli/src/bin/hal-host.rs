//! The HAL host process for one instance (started by `halrun` and
//! `realtime start`; not usually run by hand).

use hal_core::{instance_from_env, HostConfig};

fn main() {
    let mut instance = instance_from_env();
    let mut args = hal_tools::stdio::args_or_exit("hal-host", 1).into_iter();
    while let Some(a) = args.next() {
        match a.as_str() {
            "--instance" => match args.next() {
                Some(v) => instance = v,
                None => die("--instance needs a name"),
            },
            "-h" | "--help" => {
                hal_tools::outln!("usage: hal-host [--instance NAME]\nRuns the HAL host for an instance until 'realtime stop' or a signal.");
                return;
            }
            other => die(&format!("unknown argument '{other}'")),
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
