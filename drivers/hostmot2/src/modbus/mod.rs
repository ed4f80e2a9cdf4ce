//! hm2_modbus: LinuxCNC's Modbus RTU master over a Mesa PktUART. A
//! compiled command file (`.mbccb`, [`mbccb`]) lists the init commands
//! sent once and the commands run in a loop; [`engine`] runs them one
//! step per servo period (send, wait for the reply within the command's
//! timeout, parse, next) and maps the replies to and from pin values
//! ([`values`], [`pins`]).
//!
//! # Register traffic per servo period
//!
//! `hm2_modbus.N.process` never reaches the board itself: no immediate
//! register access (on hm2_eth each would be a UDP round trip inside the
//! servo thread). At load the PktUART is set up directly (not realtime)
//! and attached to its board as a [`PktUartLink`]; from then on its
//! traffic rides in the board's one read and one write burst per period,
//! as LinuxCNC's hm2 modules get theirs:
//!
//! 1. the board's `read` burst carries, after the TRAM regions, the
//!    transmitter's and receiver's mode/status words, then the reads the
//!    engine asked for one period before (the receive-count pop of a
//!    waiting frame, or, once its size is known, up to 64 of its data
//!    words);
//! 2. `process` steps the engine on those words (transmitter busy,
//!    frames waiting, the frame fetched) and stages what it sends: a
//!    request's data words and count, an init's line settings, the
//!    clear after a timeout;
//! 3. the board's `write` burst carries the staged writes, in order.
//!
//! So a request built in period k leaves in k's write burst; its reply,
//! seen waiting in the status of period j, has its count word in j + 1
//! and its data in j + 2, when it is parsed onto the pins. Each answered
//! exchange takes those two periods more than with immediate reads
//! (`cargo bench -p hostmot2 --bench modbus_bench` prints the figures).
//! Timeouts count the same periods as before: a reply not seen waiting
//! within its command's timeout is a timeout; one seen in time is
//! fetched even if the timeout runs out meanwhile. A period whose read
//! burst did not arrive (board stopped, packet lost) starts nothing, and
//! a frame whose words a lost burst carried counts as an I/O error
//! (`EIO`), as a failed transfer did before. On a network board a burst
//! is one datagram of limited size: the PktUART's reads and writes that
//! do not fit wait for the next period's, so they never make the board's
//! own transfer fail.
//!
//! [`PktUartLink`]: crate::pktuart::PktUartLink

pub mod encode;
pub mod engine;
pub mod frame;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod hal;
pub mod line;
pub mod mbccb;
pub mod mbccs;
pub mod pins;
pub mod rtu;
pub mod values;
