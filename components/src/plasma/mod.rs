//! Plasma cutting: thc (torch height control from the arc voltage).

pub mod thc;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&thc::MODULE]
}
