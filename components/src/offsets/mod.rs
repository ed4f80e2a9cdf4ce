//! Offsets applied from HAL: moveoff (joint offsets while paused),
//! eoffset_per_angle (external offsets computed from an angle).

pub mod eoffset_per_angle;
pub mod moveoff;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&moveoff::MODULE, &eoffset_per_angle::MODULE]
}
