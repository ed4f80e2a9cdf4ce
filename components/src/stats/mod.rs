//! Statistics for diagnostic scripts: histobins (value histogram, for
//! hal-histogram), latencybins (thread latency histogram, for
//! latency-histogram).

pub mod histobins;
pub mod latencybins;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&histobins::MODULE, &latencybins::MODULE]
}
