//! Plasma cutting: thc (torch height control from the arc voltage),
//! thcud (from up/down signals), ohmic (touch sensing through a THCAD),
//! plasmac (QtPlasmaC's cut controller).

pub mod ohmic;
pub mod plasmac;
pub mod thc;
pub mod thcud;
pub mod z_offset;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &thc::MODULE,
        &thcud::MODULE,
        &ohmic::MODULE,
        &plasmac::MODULE,
    ]
}
