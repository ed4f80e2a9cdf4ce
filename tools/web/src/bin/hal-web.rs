//! hal-web: a running HAL instance and its machine in a browser. See
//! `hal_web`.

use hal_web::{parse, run, Command, USAGE};

fn main() {
    let args = hal_tools::stdio::args_or_exit("hal-web", 1);
    let code = match parse(&args) {
        Ok(Command::Help) => {
            hal_tools::outln!("{USAGE}");
            0
        }
        Ok(Command::Version) => {
            hal_tools::conventions::print_version("hal-web");
            0
        }
        Ok(Command::Serve(options)) => match run(&options) {
            Ok(()) => 0,
            Err(e) => {
                eprintln!("hal-web: {e}");
                1
            }
        },
        Err(e) => {
            eprintln!("hal-web: {e}");
            2
        }
    };
    std::process::exit(code);
}
