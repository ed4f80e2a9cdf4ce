//! `canservo.so`: the CANopen CiA 402 servo-drive master for LinuxCNC's
//! `rtapi_app` (`loadrt canservo ...`), the same driver our host loads
//! ([`hal_canservo::hal::Canservo`]).

hal_driver::linuxcnc_module!(hal_canservo::hal::Canservo, hal_canservo::canservo_params);
