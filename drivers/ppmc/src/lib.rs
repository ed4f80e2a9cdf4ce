//! `hal_ppmc`: the Pico Systems boards on EPP parallel ports, compatible
//! with LinuxCNC's driver: the PPMC set (encoder, DAC and digital I/O
//! boards), the Universal Stepper Controller (USC) and the Universal PWM
//! Controller (UPC).
//!
//! ```text
//! loadrt hal_ppmc                                  # the boards on the port at 0x378
//! loadrt hal_ppmc port_addr=0x378 timestamp=0x00   # timestamp velocity on the board in slot 0
//! loadrt hal_ppmc sim=upc                          # a simulated UPC instead of the port
//! addf ppmc.0.read servo-thread
//! addf ppmc.0.write servo-thread
//! ```
//!
//! # Module parameters
//!
//! | parameter | meaning |
//! |---|---|
//! | `port_addr` | up to 3 ports, one EPP bus each (`ppmc.0`, `ppmc.1`, `ppmc.2`): an I/O address, or a port number 0..15 that Linux lists; -1 leaves an item unused; default 0x378 |
//! | `extradac` | bus/slot codes `0xBS` of USC/UPC boards whose extra port drives the 8-bit spindle DAC |
//! | `extradout` | bus/slot codes of USC/UPC boards whose extra port is 8 more digital outputs |
//! | `timestamp` | bus/slot codes of encoder boards or UPCs (revision 4+) whose counters' timestamps give the velocity |
//! | `enc_clock` | `0xFBS`: the input filter clock F (1, 2 for 2.5, 5, `a` for 10 MHz) of the encoder board (revision 4+) at bus B, slot S |
//! | `epp_dir` | per bus: 0 (default) turns the data lines for each read, 1 leaves them (some old ports) |
//! | `sim` | per bus: simulated boards instead of the port (see [`sim::SimSpec`]): `ppmc` (encoder + DAC + DIO), `usc`, `upc`, or boards joined by `+`, each with an optional revision (`upc:2`) |
//!
//! In a bus/slot code, B is the bus (the item's position in `port_addr`)
//! and S the board's first slot on it (its address switches). A code
//! that names no board, or a board without the feature (an extra port on
//! a UPC before revision 2, timestamps before revision 4, `extradac` and
//! `extradout` on one board), fails the load naming the parameter and
//! the board; LinuxCNC printed some of these and went on without the
//! feature.
//!
//! # Pins, parameters and functions
//!
//! Channels are numbered per kind across a bus in slot order, from 00:
//! the first board's encoders are 00..03, the next board's 04..07.
//!
//! | name | type | dir | boards |
//! |---|---|---|---|
//! | `ppmc.<b>.encoder.<n>.position`, `.count`, `.delta`, `.velocity`, `.index` | float, s32, s32, float, bit | out | encoder, USC, UPC |
//! | `ppmc.<b>.encoder.<n>.index-enable` | bit | io | revision 2+ |
//! | `ppmc.<b>.encoder.<n>.scale` | float param rw | | counts per unit |
//! | `ppmc.<b>.encoder.<n>.min-speed-estimate` | float param rw | | with `timestamp` |
//! | `ppmc.<b>.DAC.<n>.value`, `.scale` | float in, param | | DAC: volts = value / scale, ±10 V |
//! | `ppmc.<b>.stepgen.<n>.enable`, `.velocity` | bit, float | in | USC |
//! | `ppmc.<b>.stepgen.<n>.scale`, `.max-vel` (rw), `.freq` (ro) | float params | | USC |
//! | `ppmc.<b>.stepgen.<n>-<n+3>.setup-time-ns`, `.pulse-width-ns`, `.pulse-space-min-ns` | u32 params rw | | USC, 100 ns steps |
//! | `ppmc.<b>.pwm.<n>.enable`, `.value` | bit, float | in | UPC |
//! | `ppmc.<b>.pwm.<n>.scale`, `.max-dc`, `.min-dc`, `.bootstrap` (rw), `.duty-cycle` (ro) | params | | UPC |
//! | `ppmc.<b>.pwm.<n>-<n+3>.freq` | float param rw | | UPC carrier, Hz; 0 (default) = off |
//! | `ppmc.<b>.din.<n>.in`, `.in-not` | bit | out | DIO, USC, UPC |
//! | `ppmc.<b>.dout.<n>.out` | bit | in | DIO, USC, UPC, extra port |
//! | `ppmc.<b>.dout.<n>.invert` (DIO, extra port), `ppmc.<b>.dout.<n>-invert` (USC/UPC) | bit param rw | | |
//! | `ppmc.<b>.din.estop.in`, `.in-not`, `ppmc.<b>.din.fault.in`, `.in-not` | bit | out | first DIO board |
//! | `ppmc.<b>.dout.Estop.out`, `ppmc.<b>.dout.Estop.invert` | bit in, param | | first DIO board |
//! | `ppmc.<b>.DAC8.<n>.value`, `.scale` | float in, param | | with `extradac`: 0..10 V from \|value / scale\| |
//!
//! Functions `ppmc.<b>.read` and `ppmc.<b>.write` (floating point).
//! Added by this driver: `ppmc.<b>.fault` (bit).
//!
//! # The estop circuit
//!
//! A USC or UPC drives its outputs only while its estop output (output
//! 7) is on and its safety chain is closed; its estop input (input 15)
//! reads TRUE only then. The DIO board's `din.estop.in` reads TRUE while
//! the board is in estop. LinuxCNC's sample configurations chain these
//! through `estop_latch` and work unchanged. The first board with
//! digital I/O on a bus holds the estop circuit; the driver makes every
//! later one its slave at load, as LinuxCNC's does (a DIO board through
//! its estop register, a USC/UPC through its slave register).
//!
//! # Differences from LinuxCNC's driver
//!
//! * `count` is extended from the 24-bit counters by the signed step
//!   between readings, so it never jumps at the counter's wrap; an index
//!   clear is recognised even when the pulse came in the first periods
//!   after `index-enable` was set (LinuxCNC ignored those for 3 periods
//!   and then lost its count extension).
//! * `min-speed-estimate` is used: a timestamp velocity estimate below
//!   it reads 0 (LinuxCNC exported it and ignored it).
//! * The PWM carrier `freq` reads back the frequency made from the
//!   board's clock (40 MHz from revision 3); LinuxCNC read it back as if
//!   the clock were 10 MHz.
//! * The safe state (a fault anywhere, unload, exit) turns every estop
//!   output off first and puts the DACs at 0 V; LinuxCNC's unload wrote
//!   0 to every register, which is -10 V on a DAC.
//! * EPP timeouts in two periods running trip `ppmc.<b>.fault` and the
//!   safe state; a period with a timeout publishes nothing. LinuxCNC
//!   read 0xFF and went on.
//! * Bad options fail the load (above).
//!
//! # Crate layout
//!
//! * [`regs`]: the register map and conversions.
//! * [`epp`]: EPP address and data cycles over the shared port bus.
//! * [`scan`]: board IDs and the slot scan.
//! * [`params`]: the module parameters.
//! * [`open`]: opening the ports, checking the options, setting the
//!   boards up, the safe state.
//! * [`sim`]: the simulated port and boards, with motors.
//! * [`hal`]: the HAL binding and [`MODULE`].
//! * `fuzzing` (feature `fuzzing`): fuzz target bodies.
//! * `error`: [`PpmcError`].

#![forbid(unsafe_code)]

pub mod epp;
mod error;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod hal;
pub mod open;
pub mod params;
pub mod regs;
pub mod scan;
pub mod sim;

pub use error::PpmcError;
pub use hal::MODULE;
