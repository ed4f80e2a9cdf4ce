//! Laser cutting: laserpower (power scaled with the actual velocity).

pub mod laserpower;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&laserpower::MODULE]
}
