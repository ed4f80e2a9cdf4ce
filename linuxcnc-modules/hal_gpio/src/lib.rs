//! `hal_gpio.so`: Linux GPIO lines through the GPIO character device for
//! LinuxCNC's `rtapi_app` (`loadrt hal_gpio inputs=... outputs=...`),
//! the same driver our host loads ([`hal_gpio::hal::HalGpio`]).

hal_driver::linuxcnc_module!(hal_gpio::hal::HalGpio, hal_gpio::hal_gpio_params);
