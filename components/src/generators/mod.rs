//! Signal generators: `pwmgen` (software PWM/PDM) and `siggen` (test
//! waveforms).

pub mod pwmgen;
pub mod siggen;

use hal_core::ModuleDef;

/// The modules of this family.
pub fn modules() -> Vec<&'static ModuleDef> {
    vec![&pwmgen::MODULE, &siggen::MODULE]
}

/// A HAL host on a private instance, for the family's tests.
#[cfg(test)]
pub(crate) use crate::testing::pin_names;
