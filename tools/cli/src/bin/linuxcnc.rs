//! linuxcnc: run a LinuxCNC machine configuration (its INI file) headless.
//! See `hal_launcher`.

use hal_launcher::{parse_args, run, USAGE};

fn main() {
    let args = hal_tools::stdio::args_or_exit("linuxcnc", 1);
    if args.iter().any(|a| a == "-h" || a == "--help") {
        hal_tools::outln!("{USAGE}");
        return;
    }
    match parse_args(&args) {
        Ok(opts) => std::process::exit(run(&opts)),
        Err(e) => {
            eprintln!("linuxcnc: {e}\n{USAGE}");
            std::process::exit(2);
        }
    }
}
