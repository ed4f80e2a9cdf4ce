//! `hm2_pci.so`: Mesa's PCI Anything I/O boards (or simulated ones, sim=5i25) for LinuxCNC's `rtapi_app`
//! (`loadrt hm2_pci ...`), the same driver our host loads
//! ([`hostmot2::hal::HalHm2Pci`]).

hal_driver::linuxcnc_module!(hostmot2::hal::HalHm2Pci, hostmot2::hm2_pci_params);
