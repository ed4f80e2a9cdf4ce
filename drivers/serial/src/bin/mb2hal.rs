//! `mb2hal`: LinuxCNC's INI-driven Modbus master as a user-space HAL
//! component (see `hal_serial::mb2hal`).

fn main() {
    let args = hal_core::userspace::args_or_exit("mb2hal", 1);
    std::process::exit(hal_serial::mb2hal::main(&args));
}
