//! Simulated machine parts for configurations without hardware:
//! sim_home_switch, sim_spindle, sphereprobe, sim_axis_hardware,
//! sim_parport; and steptest and axistest (axis motion for the
//! configuration wizards).

pub mod axis_test;
pub mod sim_axis_hardware;
pub mod sim_home_switch;
pub mod sim_parport;
pub mod sim_spindle;
pub mod sphereprobe;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &sim_home_switch::MODULE,
        &sim_spindle::MODULE,
        &sphereprobe::MODULE,
        &sim_axis_hardware::MODULE,
        &sim_parport::MODULE,
        &axis_test::STEPTEST,
        &axis_test::AXISTEST,
    ]
}
