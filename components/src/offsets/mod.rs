//! Offsets applied to joint positions from HAL: moveoff.

pub mod moveoff;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&moveoff::MODULE]
}
