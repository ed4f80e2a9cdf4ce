//! The HAL host: the process that owns an instance. It creates the
//! segment, serves requests on the instance's control socket
//! ([`serve`]), loads modules from the [`registry`] of every module this
//! suite provides (components, motion, every driver: the one crate that
//! depends on all of them), runs the threads, adopts the programs
//! `loadusr` starts, and brings everything to a safe state when it ends.
//!
//! A host can also run inside another process, reached through
//! [`InProcess`] instead of the socket (the fuzz targets and tests).

mod adopt;
mod error;
mod server;
mod setthread;
#[cfg(feature = "testing")]
pub mod testing;

pub use error::HostError;
pub use server::{registry, serve, InProcess};
