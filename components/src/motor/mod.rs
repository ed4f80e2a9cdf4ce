//! Motor control: bldc (commutation of three-phase brushless motors).

pub mod bldc;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&bldc::MODULE]
}
