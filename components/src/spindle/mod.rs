//! Spindle helpers: gearchange (speed scaling and limits per gear),
//! orient (the position command for M19 spindle orientation).

pub mod gearchange;
pub mod orient;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&gearchange::MODULE, &orient::MODULE]
}
