//! `hy_gt_vfd`: a Huanyang GT-series spindle VFD over Modbus RTU as a
//! user-space HAL component (see `hal_serial::vfd::gt`).

fn main() {
    let mut args = vec!["hy_gt_vfd".to_string()];
    args.extend(hal_core::userspace::args_or_exit("hy_gt_vfd", 1));
    std::process::exit(hal_serial::vfd::gt::main(&args));
}
