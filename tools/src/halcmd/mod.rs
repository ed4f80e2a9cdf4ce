//! halcmd's language: reading HAL files and executing their commands
//! against an instance (directly on the segment) and its host (over the
//! control socket).

pub mod cfmt;
pub mod format;
pub use crate::ini;
pub mod lexer;
pub mod lock;
pub mod save;
pub mod session;
pub mod usr;
pub mod values;

pub use session::{Options, Session};
