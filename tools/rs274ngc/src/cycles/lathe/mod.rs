//! The lathe cycles G70 (finishing) and G71/G72 (roughing along Z and
//! along X), as LinuxCNC 2.9 has them: the geometry of the profile and
//! of the passes. The interpreter's side (reading the profile from its
//! subroutine, the words, the moves) is in `exec::g7x`.
//!
//! The geometry works in the ZX plane with points as complex numbers
//! (Z real, X imaginary) and rounds as LinuxCNC's does, so that the
//! moves print the same to the last digit.

pub(crate) mod complex;
pub(crate) mod finish;
pub(crate) mod profile;
pub(crate) mod rough;
pub(crate) mod segment;

pub(crate) use complex::C;
pub(crate) use finish::{finish, Finish};
pub(crate) use profile::Profile;
pub(crate) use rough::{rough, Pockets, Rough};
pub(crate) use segment::{Motion, Segment};
