//! `hal_parport`: the PC parallel-port driver, compatible with LinuxCNC's.
//!
//! ```text
//! loadrt hal_parport cfg="0x378 out 1 in"
//! addf parport.0.read base-thread
//! addf parport.0.write base-thread
//! ```
//!
//! # Configuration
//!
//! The `cfg` module parameter takes LinuxCNC's syntax unchanged (see
//! [`cfg`](mod@cfg)): `<addr> [<type>]` per port, up to 8 ports, tokens separated
//! by whitespace or `_`; addresses are hex, values below 16 are Linux
//! parport numbers; types `in`, `out` (default), `epp`, `x`, recognised by
//! their first letter.
//!
//! This driver adds an optional **backend token** per port, after the
//! address and before or after the type:
//!
//! | token | backend |
//! |---|---|
//! | `ppdev` | `/dev/parportN` through ppdev ioctls: needs only access to the device node (group `lp`, udev rule `KERNEL=="parport[0-9]*", GROUP="lp", MODE="0660"`) |
//! | `raw` | `ioperm` + `inb`/`outb`: needs `CAP_SYS_RAWIO` (`setcap cap_sys_rawio+ep` on the host binary) |
//! | `sim` | the register-level simulator ([`sim`]): no hardware |
//! | `simloop` | the simulator with the loopback plug [`sim::Plug::loopback`] in the connector |
//!
//! For example `cfg="0 sim"` or `cfg="0x378 in simloop 0x278 x raw"`.
//! The tokens start with letters that are neither hex digits nor type
//! letters, so they cannot change the meaning of a LinuxCNC cfg string.
//!
//! Without a token the backend is chosen as [`select`] describes: ppdev
//! when a `/dev/parportN` matches the port (by number, or for an address
//! through `/proc/sys/dev/parport/parport*/base-addr`), otherwise raw I/O;
//! `x` and `epp` ports always use raw I/O, because ppdev cannot read live
//! control lines or write the ECR. Combinations that cannot work (`x` or
//! `epp` on ppdev, raw I/O without permission, a missing `/dev/parportN`,
//! `in` on a port that is not bidirectional, one port named twice, e.g.
//! as `0` and by its address) are refused at `loadrt` with the port and
//! the reason, and nothing stays loaded.
//!
//! # Behaviour
//!
//! Pins, parameters and functions are LinuxCNC's ([`hal`]); reading,
//! writing and the DoubleStep `reset` follow LinuxCNC's algorithm exactly
//! ([`driver`]): the 0x80/0x0B inversion corrections, writes only when a
//! byte changed, the `reset-time` clamp to a quarter period written back
//! into the parameter, and the busy-wait before a reset.
//!
//! # Crate layout
//!
//! * [`regs`]: the register map and the DB-25 pin assignment.
//! * [`port`]: the [`port::PortIo`] bus trait and its ppdev and raw
//!   backends.
//! * [`sim`]: the register-level simulator (also a `PortIo`).
//! * [`cfg`](mod@cfg): the cfg string. [`select`]: backend choice and opening.
//! * [`driver`]: the read/write/reset algorithm on a `PortIo`.
//! * [`hal`]: the HAL binding and [`MODULE`].
//! * [`clock`]: the time source of write/reset timing.
//! * [`speaker`]: `hal_speaker`, LinuxCNC's PC-speaker driver, on the
//!   same port layer (its own module, [`speaker::MODULE`]).

pub mod cfg;
pub mod clock;
pub mod driver;
pub mod hal;
pub mod port;
pub mod regs;
pub mod select;
pub mod sim;
pub mod speaker;
pub mod tool;
pub mod tool_args;

pub use hal::{load_cfg, HalParport, OpenedPorts, MODULE};
pub use port::PortError;
