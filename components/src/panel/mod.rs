//! Control panel and pendant helpers: xhc_hb04_util, anglejog (jogging
//! two axes at an angle from one wheel), message (operator messages),
//! matrix_kb and sim_matrix_kb (matrix keypads).

pub mod anglejog;
pub mod matrix_kb;
pub mod message;
pub mod sim_matrix_kb;
pub mod xhc_hb04_util;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &xhc_hb04_util::MODULE,
        &anglejog::MODULE,
        &message::MODULE,
        &matrix_kb::MODULE,
        &sim_matrix_kb::MODULE,
    ]
}
