//! Motor control: bldc (commutation of three-phase brushless motors);
//! clarke2, clarke3, clarkeinv (three-phase transforms).

pub mod bldc;
pub mod clarke;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &bldc::MODULE,
        &clarke::CLARKE2,
        &clarke::CLARKE3,
        &clarke::CLARKEINV,
    ]
}
