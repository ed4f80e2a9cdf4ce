//! The HAL core: one HAL instance in shared memory that a host process, its
//! realtime components and tools in other processes share.
//!
//! * [`Host`] creates the instance, runs realtime components and threads.
//! * [`Instance`] is any process's view: components, pins, params, signals,
//!   links, aliases, regions, and snapshots for display.
//! * [`Pin`] and [`Param`] are the typed realtime handles; [`HalHost`],
//!   [`PinFactory`] and [`Ours`] let code be written once for this HAL
//!   and a foreign one (LinuxCNC's, in the driver layer).
//! * [`RingWriter`]/[`RingReader`] and [`SeqLockWriter`]/[`SeqLockReader`]
//!   are the lock-free channels between realtime code and other processes.
//!
//! Module overview: `shm` (the segment: layout, lock, journal, allocator),
//! `objects` (the HAL objects and their rules), `handles` (realtime access),
//! `exec` (host, threads, executor), `ring` and `seqlock` (channels),
//! `userspace` (helpers for user-space component processes).

pub mod cfmt;
mod error;
mod exec;
pub mod files;
pub mod handles;
mod hosted;
pub mod instances;
pub mod module;
pub mod name;
mod objects;
pub mod paths;
mod port;
mod ring;
mod rtlog;
mod seqlock;
pub(crate) mod shm;
pub mod stdio;
mod types;
pub mod userspace;

pub use error::{HalError, Result};
pub use exec::clock;
pub use exec::realtime;
pub use exec::{
    FunctCtx, Host, HostConfig, MissedDeadline, RealtimeMode, RtComponentBuilder, DEFAULT_SHM_SIZE,
    TOP_PRIORITY,
};
pub use handles::{
    CellReader, Direction, In, Io, Out, Param, ParamAccess, Pin, RawParam, RawPin, Ro, Rw, Writable,
};
pub use hosted::{HalHost, HostParam, HostPin, Ours, PinFactory};
pub use module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind, Registry};
pub use objects::{
    instance_from_env, lock_bits, validate_instance_name, AliasKind, Component, ComponentInfo,
    ComponentKind, FunctInfo, HalStatistics, Instance, ParamInfo, PinInfo, Region, RegionInfo,
    SignalInfo, ThreadInfo, ValueKind, ValueSet,
};
pub use port::{PortIn, PortOut, MAX_PORT_SIZE};
pub use ring::{RingReader, RingWriter, MAX_TYPED_COLUMNS};
pub use rtlog::{MsgLevel, RtLog};
pub use seqlock::{SeqLockReader, SeqLockWriter};
pub use shm::{latency_bucket, latency_bucket_floor_us};
pub use types::{HalType, ParamDir, PinDir, PinValue, Value};
