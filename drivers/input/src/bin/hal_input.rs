//! `hal_input`: Linux input devices as HAL pins (see `hal_input::run`).

fn main() {
    let args = hal_core::userspace::args_or_exit("hal_input", 1);
    std::process::exit(hal_input::run::main(&args));
}
