//! `xhc-hb04`: the XHC-HB04 wireless MPG pendant as a user-space HAL
//! component (see `hal_usb::xhc`).

fn main() {
    let mut args = vec!["xhc-hb04".to_string()];
    args.extend(hal_core::userspace::args_or_exit("xhc-hb04", 1));
    std::process::exit(hal_usb::xhc::main(&args));
}
