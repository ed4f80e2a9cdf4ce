//! `hal_stg.so`: the Servo-To-Go driver for LinuxCNC's `rtapi_app`
//! (`loadrt hal_stg ...`), the same driver our host loads
//! ([`hal_stg::hal::HalStg`]).

hal_driver::linuxcnc_module!(hal_stg::hal::HalStg, hal_stg::hal_stg_params);
