//! `hm2_eth.so`: Mesa's Ethernet Anything I/O boards for LinuxCNC's `rtapi_app`
//! (`loadrt hm2_eth ...`), the same driver our host loads
//! ([`hostmot2::eth::hal::HalHm2Eth`]).

hal_driver::linuxcnc_module!(hostmot2::eth::hal::HalHm2Eth, hostmot2::hm2_eth_params);
