//! Signal generators: `pwmgen` (software PWM/PDM) and `siggen` (test
//! waveforms).

pub mod pwmgen;
pub mod siggen;

use hal_core::ModuleDef;

/// The modules of this family.
pub fn modules() -> Vec<&'static ModuleDef> {
    vec![&pwmgen::MODULE, &siggen::MODULE]
}
