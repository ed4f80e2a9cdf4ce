//! `hy_vfd`: a Huanyang HY-series spindle VFD as a user-space HAL
//! component (see `hal_serial::vfd::hy`).

fn main() {
    let args: Vec<String> = std::env::args().collect();
    std::process::exit(hal_serial::vfd::hy::main(&args));
}
