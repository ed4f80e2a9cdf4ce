//! Signal generators: `pwmgen` (software PWM/PDM), `siggen` (test
//! waveforms) and `supply` (values from params).

pub mod pwmgen;
pub mod siggen;
pub mod supply;

use hal_core::ModuleDef;

/// The modules of this family.
pub fn modules() -> Vec<&'static ModuleDef> {
    vec![&pwmgen::MODULE, &siggen::MODULE, &supply::MODULE]
}
