//! SDO abort codes and CANopen error codes with their meanings: the
//! shared CiA 402 layer's ([`hal_cia402::codes`]), the same on CAN and
//! EtherCAT.

pub use hal_cia402::codes::{AbortCode, ErrorCode};
