//! linuxcnc: run a LinuxCNC machine configuration (its INI file) headless.
//! See `hal_tools::launcher`.

use hal_tools::launcher::{parse_args, run, USAGE};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "-h" || a == "--help") {
        println!("{USAGE}");
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
