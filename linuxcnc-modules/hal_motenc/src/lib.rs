//! `hal_motenc.so`: the MOTENC-100/Lite driver for LinuxCNC's
//! `rtapi_app` (`loadrt hal_motenc ...`), the same driver our host loads
//! ([`hal_motenc::hal::HalMotenc`]).

hal_driver::linuxcnc_module!(hal_motenc::hal::HalMotenc, hal_motenc::hal_motenc_params);
