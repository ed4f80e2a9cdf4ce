//! `hal_ppmc.so`: the Pico Systems PPMC/USC/UPC driver for LinuxCNC's
//! `rtapi_app` (`loadrt hal_ppmc ...`), the same driver our host loads
//! ([`hal_ppmc::hal::HalPpmc`]).

hal_driver::linuxcnc_module!(hal_ppmc::hal::HalPpmc, hal_ppmc::hal_ppmc_params);
