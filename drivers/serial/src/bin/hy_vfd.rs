//! `hy_vfd`: a Huanyang HY-series spindle VFD as a user-space HAL
//! component (see `hal_serial::vfd::hy`).

fn main() {
    let mut args = vec!["hy_vfd".to_string()];
    args.extend(hal_core::userspace::args_or_exit("hy_vfd", 1));
    std::process::exit(hal_serial::vfd::hy::main(&args));
}
