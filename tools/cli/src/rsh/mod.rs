//! linuxcncrsh: LinuxCNC's text protocol for remote control over TCP,
//! answered from this suite's task. [`vocab`] holds the words,
//! [`parse`] takes a line apart, [`session`] answers it for one
//! connection, [`stat`] reads task's status snapshot.

pub mod fuzz;
pub mod parse;
pub mod reply;
pub mod server;
pub mod session;
pub mod stat;
pub mod vocab;
