//! The host side: realtime components, threads and their executor.

pub mod clock;
mod funct;
mod host;
mod policy;
pub mod realtime;
mod reaper;
mod thread;

pub use funct::FunctCtx;
pub use host::{Host, HostConfig, RtComponentBuilder, DEFAULT_SHM_SIZE};
pub use policy::MissedDeadline;
pub use realtime::{RealtimeMode, TOP_PRIORITY};
