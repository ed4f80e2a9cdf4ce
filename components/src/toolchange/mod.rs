//! Tool changers: carousel.

pub mod carousel;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&carousel::MODULE]
}
