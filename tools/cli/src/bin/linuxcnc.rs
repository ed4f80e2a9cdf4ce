//! linuxcnc: run a LinuxCNC machine configuration (its INI file) headless.
//! See `hal_launcher`.

use hal_launcher::{parse_args, run, USAGE};
use hal_tools::conventions::{common, print_version, Common};

/// linuxcnc's options that take a value (the value is never one of the
/// suite's common options).
const TAKES_VALUE: [&str; 3] = ["-t", "-m", "-H"];

fn main() {
    let args = hal_tools::stdio::args_or_exit("linuxcnc", 1);
    // The suite's common options come out first; the rest are LinuxCNC's.
    let mut rest = Vec::new();
    let mut i = 0;
    while i < args.len() {
        match common(&args, i, true) {
            Ok(Some(Common::Help)) => {
                hal_tools::outln!("{USAGE}");
                return;
            }
            Ok(Some(Common::Version)) => {
                print_version("linuxcnc");
                return;
            }
            Ok(Some(Common::Instance(_, n))) => {
                i += n;
                continue;
            }
            Ok(None) => {}
            Err(e) => {
                eprintln!("linuxcnc: {e}\n{USAGE}");
                std::process::exit(2);
            }
        }
        rest.push(args[i].clone());
        if TAKES_VALUE.contains(&args[i].as_str()) {
            if let Some(v) = args.get(i + 1) {
                rest.push(v.clone());
                i += 1;
            }
        }
        i += 1;
    }
    match parse_args(&rest) {
        Ok(opts) => std::process::exit(run(&opts)),
        Err(e) => {
            eprintln!("linuxcnc: {e}\n{USAGE}");
            std::process::exit(2);
        }
    }
}
