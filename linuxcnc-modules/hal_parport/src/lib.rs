//! `hal_parport.so`: the PC parallel-port driver for LinuxCNC's
//! `rtapi_app` (`loadrt hal_parport cfg="..."`), the same driver our host
//! loads ([`hal_parport::HalParport`]).

hal_driver::linuxcnc_module!(hal_parport::HalParport, hal_parport::hal_parport_params);
