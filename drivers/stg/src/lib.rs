//! `hal_stg`: the Servo-To-Go ISA servo card, Model I and Model II,
//! compatible with LinuxCNC's driver.
//!
//! ```text
//! loadrt hal_stg                                  # search 0x3e0..0x200, detect the model
//! loadrt hal_stg base=0x300 num_chan=4 dio="IOIO"
//! loadrt hal_stg backend=sim model=1              # a simulated Model I at 0x300
//! addf stg.capture-position servo-thread
//! addf stg.write-dacs servo-thread
//! ```
//!
//! # Module parameters
//!
//! | parameter | meaning |
//! |---|---|
//! | `base` | base address, one of the jumper choices 0x200, 0x220, … 0x3e0; 0 (default) searches them from the top |
//! | `model` | 1 or 2 forces Model I or II; 0 (default) detects it from the board's signature |
//! | `num_chan` | channels exported, 1..8 (default 8) |
//! | `dio` | directions of ports A, B, C, D: `I` or `O` each (default `IIOO`) |
//! | `backend` | `ioperm` (default: `in`/`out` after `ioperm` on the board's two windows only; needs `CAP_SYS_RAWIO`), `sim` (a simulated board at `base`, default 0x300, of `model`, default II) or `devport`, which is refused with its reason (see below) |
//!
//! The board is found by the signature its board test register gives
//! one bit per read ([`probe`], usable alone for bring-up). With `base`
//! and no `model`, only that address is probed (LinuxCNC searched anyway
//! and replaced `base`). With a forced `model`, something must still
//! answer at the address; a signature that disagrees is a warning.
//!
//! `/dev/port` moves one byte per access, and the board's DACs and ADCs
//! take 16-bit accesses: a DAC written a byte at a time would output a
//! wrong voltage between the two writes. So `backend=devport` is refused
//! at `loadrt`; [`probe`] (8-bit reads only) works over
//! [`DevPortPorts`](hal_driver::bus::DevPortPorts).
//!
//! # Pins, parameters and functions
//!
//! LinuxCNC's (hardware.md §3.9):
//!
//! | name | type | dir | |
//! |---|---|---|---|
//! | `stg.<n>.counts`, `.position` | s32, float | out | counts since load or the index; counts / position-scale |
//! | `stg.<n>.position-scale` | float | param rw | counts per unit |
//! | `stg.<n>.index-enable` | bit | io | cleared when the index was taken |
//! | `stg.<n>.index-latch` | bit | out | the board's index latch was seen this period |
//! | `stg.<n>.index-polarity` | bit | in | Model I only: TRUE = index active high (default) |
//! | `stg.<n>.dac-value` | float | in | volts = (value − offset) × gain, ±10 V |
//! | `stg.<n>.dac-offset`, `.dac-gain` | float | param rw | |
//! | `stg.<n>.adc-value` | float | out | volts × gain − offset |
//! | `stg.<n>.adc-offset`, `.adc-gain` | float | param rw | |
//! | `stg.in-<NN>`, `stg.in-<NN>-not` | bit | out | input ports' lines, numbered on over the input ports in A B C D order |
//! | `stg.out-<NN>` | bit | in | output ports' lines, likewise |
//! | `stg.out-<NN>-invert` | bit | param rw | |
//!
//! Functions `stg.capture-position`, `stg.write-dacs`, `stg.read-adcs`
//! (floating point), `stg.di-read`, `stg.do-write`.
//!
//! Added by this driver: the canonical encoder's `stg.<n>.reset`,
//! `.rawcounts`, `.position-latched`, `.velocity`, `.velocity-rpm` and
//! `.vel-timeout`; the canonical analog input's `stg.<n>.adc-bit_weight`
//! and `.adc-hw_offset`; `stg.fault` (bit) and `stg.fault-code` (u32).
//!
//! # Digital input polarity
//!
//! `stg.in-NN` is TRUE while its line is **low** (a contact closed to
//! ground against the board's pull-up) and FALSE while it is high or
//! open; `stg.in-NN-not` is the opposite. LinuxCNC's user documentation
//! says the reverse; its driver, and this one, behave as written here,
//! so existing configurations keep working.
//!
//! # Defects of LinuxCNC's driver fixed here (hardware.md §3.10)
//!
//! * The 8259 "read IRR" command (OCW3 = 0x0a) goes to the board's
//!   interrupt controller at `base + 0x409`; LinuxCNC swapped the
//!   arguments and wrote 0x409 to I/O port 0x0a, the ISA DMA mask
//!   register. Nor does this driver write port 0x80 for delays: the ADC
//!   multiplexer's 4 µs settling is timed on the clock. No port outside
//!   the board's two windows is ever touched.
//! * `read-adcs` goes round the exported channels 0 … num_chan − 1;
//!   LinuxCNC's also started a conversion on channel `num_chan` (out of
//!   range) every sweep and threw it away.
//! * The digital input polarity is documented as the code behaves (above).
//! * The 24-bit counters are extended to 64 bits in software (the
//!   canonical encoder), so `counts` and `position` do not wrap at
//!   ±2^23 (LinuxCNC's FIXME).
//! * An invalid `dio` string, `base`, `model` or `num_chan` fails the load
//!   naming the parameter, with nothing left loaded.
//! * `base` without `model` probes only that address (above).
//!
//! # Index handling
//!
//! Model II: every period the driver enables the index of the axes whose
//! `index-enable` is TRUE (IDLEN), reads the latched flags (IDL) and
//! clears them at once, takes each armed flagged axis's count from its
//! latch as the index left it, then latches and reads every counter.
//! Model I can watch one axis pair at a time (INTC): the driver keeps the
//! watch on the pair of an axis waiting for its index, reads the pair's
//! latches before clearing them (LinuxCNC cleared, then sampled, so it
//! saw only an index still active at that instant), and sets the index
//! level from that axis's `index-polarity`. Axes on different pairs
//! waiting at once are watched in turn, so on a Model I home them one
//! pair at a time (HOME_SEQUENCE).
//!
//! # Faults and safe state
//!
//! `capture-position` checks every period that the board test register
//! still carries the model's signature (a board gone from the bus reads
//! 0xff, which no signature gives) and that no port access failed. The
//! first fault puts the board in its safe state in that same call: every
//! DAC to 0 V, every output at the level of `out` FALSE (the amplifier
//! enables off). The realtime log says which board and why (`stg (Model
//! II at 0x300): board stopped answering ...`), `stg.fault` goes TRUE and
//! `stg.fault-code` shows 1 (board gone) or 2 (readback failed); from
//! then on nothing is written until the driver is reloaded. The same safe
//! state is applied after a fault anywhere in the HAL, at unload and at
//! exit.
//!
//! # Crate layout
//!
//! * [`regs`]: the register map, chip commands and conversions.
//! * [`detect`]: signatures, [`probe`], the base address search.
//! * [`dio`]: the `dio` parameter.
//! * [`driver`]: register access ([`driver::Stg`]).
//! * [`sim`]: the register-level simulator with its motors.
//! * [`open`]: parameters, backends, opening the board.
//! * [`hal`]: the HAL binding and [`MODULE`].
//! * `fuzzing` (feature `fuzzing`): fuzz target bodies for the parsers of outside bytes.
//! * `error`: [`StgError`].

#![forbid(unsafe_code)]

pub mod detect;
pub mod dio;
pub mod driver;
mod error;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod hal;
pub mod open;
pub mod port_probe;
pub mod regs;
pub mod sim;

#[cfg(test)]
mod test_board;

pub use detect::{probe, Model};
pub use error::StgError;
pub use hal::MODULE;
