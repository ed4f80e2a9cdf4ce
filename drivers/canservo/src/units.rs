//! Conversions between user units and drive counts: the shared CiA 402
//! layer's ([`hal_cia402::units`]).

pub use hal_cia402::units::counts;
