//! z_level_compensation: LinuxCNC's Z level compensation user component
//! (see `hal_launcher::zlevel`).

use hal_tools::conventions::{common, print_version, Common};

fn main() {
    let args = hal_tools::stdio::args_or_exit("z_level_compensation", 2);
    let mut rest = Vec::new();
    let mut i = 0;
    while i < args.len() {
        match common(&args, i, false) {
            Ok(Some(Common::Help)) => {
                hal_tools::outln!("{}", hal_launcher::zlevel::USAGE);
                return;
            }
            Ok(Some(Common::Version)) => {
                print_version("z_level_compensation");
                return;
            }
            Ok(Some(Common::Instance(_, n))) => {
                i += n;
                continue;
            }
            Ok(None) => rest.push(args[i].clone()),
            Err(e) => {
                eprintln!("z_level_compensation: {e}");
                std::process::exit(2);
            }
        }
        i += 1;
    }
    std::process::exit(hal_launcher::zlevel::main(&rest));
}
