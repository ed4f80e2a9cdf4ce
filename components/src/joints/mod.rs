//! Joint-level helpers that map axis positions to motors in HAL instead
//! of in a kinematics module: gantry, differential, corexy_by_hal.

pub mod corexy_by_hal;
pub mod differential;
pub mod gantry;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &gantry::MODULE,
        &differential::MODULE,
        &corexy_by_hal::MODULE,
    ]
}
