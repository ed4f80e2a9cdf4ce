//! halui: LinuxCNC's HAL user interface, a client of the launcher's task
//! (see `hal_launcher::halui`).

use hal_tools::conventions::{common, print_version, Common};

fn main() {
    let args = hal_tools::stdio::args_or_exit("halui", 2);
    let mut rest = Vec::new();
    let mut i = 0;
    while i < args.len() {
        match common(&args, i, false) {
            Ok(Some(Common::Help)) => {
                hal_tools::outln!("{}", hal_launcher::halui::USAGE);
                return;
            }
            Ok(Some(Common::Version)) => {
                print_version("halui");
                return;
            }
            Ok(Some(Common::Instance(_, n))) => {
                i += n;
                continue;
            }
            Ok(None) => rest.push(args[i].clone()),
            Err(e) => {
                eprintln!("halui: {e}");
                std::process::exit(2);
            }
        }
        i += 1;
    }
    std::process::exit(hal_launcher::halui::main(&rest));
}
