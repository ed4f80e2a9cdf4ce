//! Serial-line and Modbus drivers: a Modbus RTU master and LinuxCNC's
//! spindle VFD components `hy_vfd` (Huanyang HY series, their own
//! protocol) and `hy_gt_vfd` (Huanyang GT series, standard Modbus), with
//! a simulated drive so their configurations run without hardware; and
//! LinuxCNC's INI-driven Modbus master [`mb2hal`] (TCP and RTU).
//!
//! ```text
//! loadusr -Wn spindle-vfd hy_vfd -n spindle-vfd -d /dev/serial/by-id/usb-FTDI_...-if00-port0
//! loadusr -Wn hy_gt_vfd hy_gt_vfd -d sim -S 24000 -F 400 -f 120
//! loadusr -W mb2hal config=mb2hal.ini
//! ```
//!
//! # User-space components, as in LinuxCNC
//!
//! The components are programs that `loadusr` starts. They attach to the
//! instance `HAL_INSTANCE` names, export their pins, and loop: a cycle
//! of transactions on the line, then a sleep. No realtime thread ever
//! waits on the serial line; a slow or dead drive delays only its own
//! program's loop. SIGTERM (`unloadusr`, the end of `halrun`) stops the
//! spindle and removes the component; so does the host going away.
//!
//! # The driver anatomy
//!
//! * [`regs`]: the protocols as named constants (Modbus function and
//!   exception codes, the GT register map, the HY function codes,
//!   control and status bytes, PD parameter numbers).
//! * [`mod@line`]: the bus trait [`line::SerialLine`] in the driver layer's
//!   shape: `describe`, `settings`, an `errors()` count, the real
//!   backend [`line::TtyLine`] (the `serialport` crate: raw termios,
//!   speed and format, TIOCEXCL, reads in `poll` with a timeout) and the
//!   simulated [`line::SimLine`]. The line also owns time (the silence
//!   between frames, the timeouts), so the simulated line runs on
//!   simulated time and a test of timeouts takes no wall time.
//! * [`sim`]: the simulated drive: [`sim::VfdModel`] (ramps, and the
//!   spindle motor as the driver layer's `DcMotor` plant) under
//!   [`sim::VfdSim`], a byte-stream slave that speaks either protocol,
//!   drops frames with a bad CRC as a real bus does, and misbehaves on
//!   request ([`sim::Faults`]: silence, bad CRCs, wrong functions, cut
//!   replies, exceptions, late replies, a dead or unplugged line). It is
//!   reached in-process by a `SimLine`, or behind a pseudo-terminal by
//!   [`sim::PtyVfd`], which is what `-d sim` selects: the component then
//!   runs its real tty code against the kernel's pty.
//! * The HAL binding: [`vfd::hy`], [`vfd::gt`], with their command lines
//!   (`opts`: `getopt_long` forms and LinuxCNC's unique-prefix values)
//!   and the link-health pins ([`vfd::Link`], on the driver layer's
//!   `FaultLatch`).
//!
//! # The Modbus master
//!
//! [`modbus::Master`] runs one transaction at a time: it keeps the line
//! silent for 3.5 characters before a request (1.75 ms above 19 200
//! baud; the GT component keeps 10 characters, as LinuxCNC's does),
//! sends address, function, data and CRC (low byte first), and reads
//! the reply up to the length its function implies (fixed for writes,
//! from the count byte for reads and every HY reply, five bytes for an
//! exception), with a response timeout for the first byte and a byte
//! timeout within the reply. It checks CRC, address and function;
//! exception replies come back as [`SerialError::Exception`] with the
//! code by name. Lost, garbled or misdirected replies, and busy slaves
//! (exceptions 5 and 6), are retried; refusals are not. A read or write
//! error closes the device; the master reopens it by path every
//! `reopen_interval` and fails fast in between.
//!
//! Framing is written here, on `serialport`, rather than taken from a
//! Modbus crate: `tokio-modbus` needs an async runtime and offers no
//! hook for the HY protocol's reply lengths, `rmodbus` parses standard
//! Modbus only, and the HY protocol shares Modbus RTU's framing and CRC
//! but not its function codes, so one small framing layer serves both.
//! The CRC comes from the `crc` crate's catalogue (CRC-16/MODBUS).
//!
//! The data functions (coils, discrete inputs, holding and input
//! registers, read and written: [`modbus::functions`]) run on any
//! [`modbus::Transact`]: the RTU master, or `mb2hal`'s Modbus TCP client
//! ([`mb2hal::tcp`]: MBAP framing on a `TcpStream`, late replies skipped
//! by transaction id).
//!
//! # Health and faults
//!
//! Both components add three pins to LinuxCNC's: `modbus-ok` (every
//! transaction of the last cycle was answered), `fault` (the drive is
//! not answering or the line failed, or the GT drive reports a fault
//! code) and `last-error` (LinuxCNC's negative result code of the last
//! failure: an exception's code, −12 timeout, −11 write failure, −13
//! port failure, −16 bad CRC). While the drive is lost at-speed is held
//! false and the readings keep their last values; each change is said
//! once on stderr. A component cannot stop a spindle it cannot reach:
//! set the drive's own communication timeout so that it stops by itself.
//!
//! # Tests
//!
//! Frames byte for byte, timeouts, retries and exceptions run on the
//! simulated line in simulated time (`tests/master.rs`); every pin and
//! option of both components likewise (`tests/hy_vfd.rs`,
//! `tests/gt_vfd.rs`); the tty backend on a real pty
//! (`tests/pty_line.rs`); the real programs in their own processes on a
//! pty, unplugged and plugged back (`tests/real_tty.rs`, also run in the
//! VM rig by `.ci/run`); `mb2hal` against pymodbus over TCP and RTU
//! (`tests/mb2hal_pymodbus.rs`, ignored without pymodbus in
//! target/python-venv); `configs/sim/spindle-vfd.hal` as halrun runs
//! it (`tests/sim_config.rs`); and the `fuzzing` targets (feature `fuzzing`)
//! (`tests/fuzz_serial.rs`).

#![forbid(unsafe_code)]

pub mod crc;
mod error;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod line;
pub mod mb2hal;
pub mod modbus;
mod opts;
pub mod regs;
pub mod sim;
pub mod vfd;

pub use error::{code, ExceptionCode, Result, SerialError};
