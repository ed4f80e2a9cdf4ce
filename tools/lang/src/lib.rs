//! The HAL command language: what halcmd reads and does, without any
//! driver or module behind it.
//!
//! - [`lexer`]: HAL file text to commands (continuations, comments,
//!   quoting, `$ENV` and `[SECTION]KEY` substitution).
//! - [`Session`]: runs commands against an instance (structure and values
//!   directly on the segment; `loadrt`, `addf`, `start` and the like on the
//!   instance's host, through a [`HostLink`]).
//! - [`format`]: `show`, `list`, `save`, `status`, `help`, byte for byte as
//!   LinuxCNC prints them; [`parse_value`]: values typed by the user.
//! - [`ini`]: LinuxCNC's INI files (`halcmd -i`, the launcher).
//! - [`haltcl`]: Tcl HAL files, each `hal` call run on a [`Session`].
//! - [`protocol`] and [`host_process`]: the client side of the host's
//!   control socket, and starting and stopping a host process.

mod error;
pub mod format;
pub mod haltcl;
pub mod host_process;
pub mod ini;
pub mod lexer;
mod lock;
pub mod protocol;
mod save;
pub mod session;
pub mod usr;
mod values;

pub use error::{LangError, Result};
pub use hal_core::cfmt::fmt_f;
pub use ini::{Ini, IniError};
pub use protocol::{Client, ClientError, HostLink};
pub use session::{CommandFilter, Options, Session, SharedFilter, Verdict};
pub use values::{parse_float, parse_value, ValueError};
