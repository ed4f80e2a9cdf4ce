//! `lcec.so`: the EtherCAT master with linuxcnc-ethercat's configuration
//! and pins, for LinuxCNC's `rtapi_app` (`loadrt lcec config=FILE ...`),
//! the same driver our host loads ([`hal_ethercat::hal::Lcec`]). Inside
//! LinuxCNC the configuration is always `config=`: our `lcec_conf`'s
//! hand-over lives in our host's instance.

hal_driver::linuxcnc_module!(hal_ethercat::hal::Lcec, hal_ethercat::lcec_params);
