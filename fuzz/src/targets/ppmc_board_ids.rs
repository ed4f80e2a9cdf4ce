//! hal_ppmc's slot scan ([`hal_ppmc::fuzzing::board_ids`]): the ID
//! bytes the boards on an EPP bus answer.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "ppmc_board_ids",
    run: hal_ppmc::fuzzing::board_ids,
    dictionary: &[],
    generate: None,
};
