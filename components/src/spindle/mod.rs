//! Spindle helpers: gearchange (speed scaling and limits per gear),
//! orient (the position command for M19 spindle orientation), spindle
//! (speed control with ramps and gears, in `speed`), spindle_monitor
//! (at-speed and under-speed).

pub mod gearchange;
pub mod orient;
pub mod speed;
pub mod spindle_monitor;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &gearchange::MODULE,
        &orient::MODULE,
        &speed::MODULE,
        &spindle_monitor::MODULE,
    ]
}
