//! `hal_motenc`: the Vital Systems MOTENC-100 and MOTENC-Lite PCI servo
//! cards, compatible with LinuxCNC's driver.
//!
//! ```text
//! loadrt hal_motenc                      # every MOTENC on the PCI bus
//! loadrt hal_motenc backend=sim          # one simulated MOTENC-100, ID 0
//! loadrt hal_motenc backend=sim sim_boards=100,lite sim_ids=0,2
//! addf motenc.0.encoder-read servo-thread
//! addf motenc.0.dac-write servo-thread
//! ```
//!
//! # Boards
//!
//! The driver finds every PCI device 10b5:3001 (LinuxCNC matches vendor
//! and device only), up to four, enables it, maps BAR 2 and reads
//! boardVersion (0: MOTENC-100 with two FPGAs, 1: MOTENC-Lite with one)
//! and the board ID jumpers. `<id>` in every name below is that jumper ID;
//! a board whose ID an earlier board already has gets the lowest free ID,
//! with a warning. A board that reads all ones, or a boardVersion that is
//! neither 0 nor 1, fails the `loadrt` naming the board (LinuxCNC logs
//! the latter and carries on with no FPGA). [`identify`] is the
//! identification alone, for bring-up tools.
//!
//! # Module parameters
//!
//! LinuxCNC's driver takes none. This one adds:
//!
//! | parameter | meaning |
//! |---|---|
//! | `backend` | `pci` (default) or `sim`: simulated boards ([`sim`]), no hardware |
//! | `sim_boards` | with `sim`: `100` or `lite` per board, up to 4 (default one `100`) |
//! | `sim_ids` | with `sim`: each board's ID jumpers, 0..3 (default 0, 1, 2, 3) |
//!
//! # Pins, parameters and functions
//!
//! LinuxCNC's, `NN` two digits (hardware.md §4.4):
//!
//! | name | type | dir | |
//! |---|---|---|---|
//! | `motenc.<id>.enc-NN-count`, `-position` | s32, float | out | 8 channels (Lite: 4) |
//! | `motenc.<id>.enc-NN-index` | bit | out | live index input |
//! | `motenc.<id>.enc-NN-index-enable` | bit | io | cleared when the board cleared the count at an index |
//! | `motenc.<id>.enc-NN-reset` | bit | in | count 0 while TRUE |
//! | `motenc.<id>.enc-NN-scale` | float | param rw | counts per unit |
//! | `motenc.<id>.dac-NN-value` | float | in | volts = (value − offset) × gain, ±10 V |
//! | `motenc.<id>.dac-NN-offset`, `-gain` | float | param rw | |
//! | `motenc.<id>.adc-NN-value` | float | out | volts × gain − offset |
//! | `motenc.<id>.adc-NN-offset`, `-gain` | float | param rw | |
//! | `motenc.<id>.in-NN`, `in-NN-not` | bit | out | 68 inputs (Lite: 32) |
//! | `motenc.<id>.out-NN`, `out-NN-invert` | bit | in, param rw | 32 outputs (Lite: 16) |
//! | `motenc.<id>.estop-in`, `estop-in-not` | bit | out | E-stop input |
//! | `motenc.<id>.watchdog-reset` | bit | io | TRUE restarts the watchdog once |
//! | `motenc.<id>.watchdog-control` | u32 | param rw | bit 0: 16 ms (else 8 ms), bit 2: enable, bit 4: DAC writes restart it |
//!
//! Functions `motenc.<id>.encoder-read`, `.dac-write`, `.adc-read`
//! (floating point), `.digital-in-read`, `.digital-out-write`,
//! `.misc-update`.
//!
//! Added by this driver: the canonical encoder's
//! `enc-NN-rawcounts`, `-position-latched`, `-velocity`, `-velocity-rpm`
//! and `-vel-timeout`; the canonical analog input's `adc-NN-bit_weight`
//! and `-hw_offset`; `motenc.<id>.fault` (bit) and `.fault-code` (u32).
//!
//! # Behaviour
//!
//! As LinuxCNC's driver, with these differences:
//!
//! * Counts are extended to 64 bits in software (the canonical
//!   encoder). The board clears its counter at an armed index and keeps
//!   no record of the count it had there: `count` (counts since the
//!   index) is exact, while `rawcounts`, `position-latched` and the
//!   velocity of that one period take the last count read before the
//!   index as its position.
//! * The arm register of an encoder is written only when
//!   `index-enable` changes (LinuxCNC writes it every period).
//! * `enc-NN-reset` zeroes the count in software, not the board's
//!   counter, so `rawcounts` keeps counting.
//!
//! # Faults and safe state
//!
//! `encoder-read` checks every period that the board answers (a status
//! that reads all ones is confirmed on boardVersion), that no bus access
//! failed, and that the watchdog, when enabled, was restarted within its
//! timeout (the driver times it on the board's clock: the thread's, or
//! the simulator's). The first fault puts the board in its safe state in
//! that same call, so within the servo period: every DAC to 0 V, every
//! output at the level of `out` FALSE (the amplifier enables off). The
//! realtime log says which board and why (`motenc.0 (MOTENC-100 PCI
//! 0000:03:00.0): watchdog bit ...`), `fault` goes TRUE and `fault-code`
//! shows 1 (board gone), 2 (readback failed) or 3 (watchdog). While
//! faulted, `dac-write` and `digital-out-write` write nothing. A
//! watchdog fault clears with `watchdog-reset`; the others need a
//! reload. The same safe state is applied after a fault anywhere in the
//! HAL, at unload and at exit.
//!
//! What the real board does when its watchdog bites is not documented;
//! the simulator assumes it holds DACs at 0 V and outputs off.
//!
//! # Crate layout
//!
//! * [`regs`]: the register map and conversions.
//! * [`board`]: identification and register access ([`board::Motenc`]).
//! * [`sim`]: the register-level simulator with its motors.
//! * [`open`]: backends, PCI discovery, board IDs.
//! * [`hal`]: the HAL binding and [`MODULE`].
//! * `fuzzing` (feature `fuzzing`): fuzz target bodies for the parsers of outside bytes.
//! * `error`: [`MotencError`].

#![forbid(unsafe_code)]

pub mod board;
mod error;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod hal;
pub mod open;
pub mod regs;
pub mod sim;

pub use board::{identify, BoardKind, Identity};
pub use error::MotencError;
pub use hal::MODULE;
