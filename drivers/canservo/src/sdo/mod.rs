//! SDO (service data objects, hardware.md §6.5): the client the master
//! and the tools use, and the server the simulated drive runs.

mod client;
mod server;

pub use client::{SdoClient, DEFAULT_MAX_UPLOAD};
pub use server::{ObjectAccess, SdoServer, MAX_DOWNLOAD, TRANSFER_TIMEOUT_NS};
