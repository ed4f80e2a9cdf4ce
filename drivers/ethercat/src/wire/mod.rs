//! The EtherCAT wire format: frames and datagrams ([`frame`]), the
//! mailbox and CoE with SDO and emergencies ([`coe`]), the SII EEPROM
//! layout ([`sii`]). Every parser checks lengths against the bytes there
//! and returns an [`Error`](crate::Error) naming what was wrong; none
//! panics on any input (fuzz bodies in [`crate::fuzzing`]).

pub mod coe;
pub mod frame;
pub mod sii;
