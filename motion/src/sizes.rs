//! The controller's compile-time maxima (LinuxCNC's `EMCMOT_MAX_*`) and the
//! feed-override enable bits, shared by every layer.

/// Most joints (`EMCMOT_MAX_JOINTS`).
pub const MAX_JOINTS: usize = 16;
/// Most spindles (`EMCMOT_MAX_SPINDLES`).
pub const MAX_SPINDLES: usize = 8;
/// Most digital or analog I/O pairs (`EMCMOT_MAX_DIO`, `EMCMOT_MAX_AIO`).
pub const MAX_IO: usize = 64;
/// Most misc-error inputs (`EMCMOT_MAX_MISC_ERROR`).
pub const MAX_MISC_ERROR: usize = 64;

/// Spindle-scale enable bit (M51): also gates the inhibit inputs.
pub const SS_ENABLED: u8 = 0x01;
/// Feed-scale enable bit (M50).
pub const FS_ENABLED: u8 = 0x02;
/// Adaptive-feed enable bit (M52).
pub const AF_ENABLED: u8 = 0x04;
/// Feed-hold enable bit (M53).
pub const FH_ENABLED: u8 = 0x08;
