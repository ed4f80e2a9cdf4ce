//! Control panel and pendant helpers: xhc_hb04_util.

pub mod xhc_hb04_util;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&xhc_hb04_util::MODULE]
}
