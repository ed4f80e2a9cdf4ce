//! `pca9685.so`: the NXP PCA9685 PWM driver for LinuxCNC's `rtapi_app`
//! (`loadrt pca9685 ...`), the same driver our host loads
//! ([`hal_i2c::hal::pca9685::HalPca9685`]).

hal_driver::linuxcnc_module!(hal_i2c::hal::pca9685::HalPca9685, hal_i2c::pca9685_params);
