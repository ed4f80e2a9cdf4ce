//! canservo's drive files of SDO writes
//! ([`hal_canservo::fuzzing::drive_file`]): an error names the file and a
//! line, an accepted file's writes are in line order, fit their types and
//! parse back the same when written out.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "canservo_drive_file",
    run,
    dictionary: &[
        "6098:00", "607C:00", "1017:00", " i8 ", " u8 ", " i16 ", " u16 ", " i32 ", " u32 ", "0x",
        "-2147483648", "4294967295", "#", "\n",
    ],
    generate: None,
};

/// The body returns the number of writes; only its panics matter.
fn run(input: &[u8]) {
    hal_canservo::fuzzing::drive_file(input);
}
