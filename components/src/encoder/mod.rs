//! Encoder family: `encoder` (software quadrature / pulse counter),
//! `sim_encoder` (simulated quadrature output) and `encoder_ratio`
//! (electronic-gearbox error between two encoders).
//!
//! The counting logic lives in plain structs ([`quadrature::QuadDecoder`],
//! [`encoder::Counter`], [`encoder::Capture`], [`sim_encoder::PulseGen`],
//! [`encoder_ratio::RatioSampler`], ...) that know nothing of pins, so they
//! can be driven and tested without a HAL host; each module's HAL glue
//! reads pins, calls them and writes pins.

// Each module is named after the component it implements, `encoder` too.
#[allow(clippy::module_inception)]
pub mod encoder;
pub mod encoder_ratio;
pub mod quadrature;
pub mod sim_encoder;

use hal_core::module::{ParamDecl, ParamKind};
use hal_core::ModuleDef;

/// Most channels one load of these modules creates.
pub const MAX_CHAN: usize = 8;

/// The module parameter table shared by the three modules: `num_chan=` and
/// `names=` (an array of [`MAX_CHAN`] strings), read by
/// [`crate::halcomp::channel_names`].
pub const CHANNEL_PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "num_chan",
        kind: ParamKind::Int,
        help: "number of channels (1-8)",
    },
    ParamDecl {
        name: "names",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "names of the channels, comma separated",
    },
];

/// Every module of this family.
pub fn modules() -> Vec<&'static ModuleDef> {
    vec![
        &encoder::MODULE,
        &sim_encoder::MODULE,
        &encoder_ratio::MODULE,
    ]
}
