//! inivar: print one value of an INI file (LinuxCNC's `inivar`).

use hal_tools::conventions::print_version;
use hal_tools::inivar::{answer, parse_args};

fn main() {
    let args = hal_tools::stdio::args_or_exit("inivar", 1);
    match args.first().map(String::as_str) {
        Some("-h" | "--help") => {
            hal_tools::outln!("{}", hal_tools::usage::INIVAR);
            return;
        }
        Some("--version") => {
            print_version("inivar");
            return;
        }
        _ => {}
    }
    let outcome = match parse_args(&args) {
        Ok(query) => answer(&query, std::env::var("HOME").ok().as_deref()),
        Err(outcome) => outcome,
    };
    hal_tools::out!("{}", outcome.stdout);
    eprint!("{}", outcome.stderr);
    std::process::exit(outcome.status);
}
