//! `ads1115.so`: the TI ADS1115 ADC driver for LinuxCNC's `rtapi_app`
//! (`loadrt ads1115 ...`), the same driver our host loads
//! ([`hal_i2c::hal::ads1115::HalAds1115`]).

hal_driver::linuxcnc_module!(hal_i2c::hal::ads1115::HalAds1115, hal_i2c::ads1115_params);
