//! `hostmot2.so`: the Mesa HostMot2 driver core for LinuxCNC's `rtapi_app`
//! (`loadrt hostmot2 ...`), the same driver our host loads
//! ([`hostmot2::hal::HalHostmot2`]).

hal_driver::linuxcnc_module!(hostmot2::hal::HalHostmot2, hostmot2::hostmot2_params);
