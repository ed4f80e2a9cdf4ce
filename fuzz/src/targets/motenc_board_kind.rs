//! hal_motenc's `sim_boards` items ([`hal_motenc::fuzzing::board_kind_item`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "motenc_board_kind",
    run: hal_motenc::fuzzing::board_kind_item,
    dictionary: &["100", "lite", "LITE", "motenc-100", "motenc-lite", "Motenc-Lite"],
    generate: None,
};
