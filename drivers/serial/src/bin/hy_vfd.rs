//! `hy_vfd`: a Huanyang HY-series spindle VFD as a user-space HAL
//! component (see `hal_serial::vfd::hy`).

fn main() {
    // Arguments are text; one that is not is refused by position, never
    // a panic (std::env::args would panic on it).
    let mut args: Vec<String> = Vec::new();
    for (n, arg) in std::env::args_os().enumerate() {
        match arg.into_string() {
            Ok(a) => args.push(a),
            Err(raw) => {
                eprintln!("hy_vfd: argument {n} is not UTF-8 text: {raw:?}");
                std::process::exit(1);
            }
        }
    }
    std::process::exit(hal_serial::vfd::hy::main(&args));
}
