//! `hm2_test.so`: LinuxCNC's HostMot2 test driver for LinuxCNC's `rtapi_app`
//! (`loadrt hm2_test ...`), the same driver our host loads
//! ([`hostmot2::hal::HalHm2Test`]).

hal_driver::linuxcnc_module!(hostmot2::hal::HalHm2Test, hostmot2::hm2_test_params);
