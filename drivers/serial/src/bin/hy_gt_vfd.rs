//! `hy_gt_vfd`: a Huanyang GT-series spindle VFD over Modbus RTU as a
//! user-space HAL component (see `hal_serial::vfd::gt`).

fn main() {
    let args: Vec<String> = std::env::args().collect();
    std::process::exit(hal_serial::vfd::gt::main(&args));
}
