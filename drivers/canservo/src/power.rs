//! The CiA 402 power state machine (hardware.md §6.8): the shared layer's
//! ([`hal_cia402::power`]), with its typestate API bound to canservo's
//! SDO client, so a drive on CAN is stepped through its states as
//! `Power<'_, SwitchOnDisabled>` → `shutdown()` → ... .

use crate::error::Error;
use crate::sdo::SdoClient;

pub use hal_cia402::power::{
    describe_statusword, next_command, transition, Command, Fault, Goal, ObjectAccess,
    OperationEnabled, PowerState, QuickStopActive, ReadyToSwitchOn, StateType, SwitchOnDisabled,
    SwitchedOn,
};

/// A drive on CAN known to be in state `S`.
pub type Power<'a, S> = hal_cia402::power::Power<'a, SdoClient<'a>, S>;
/// The state a drive on CAN is in now, as a typed handle.
pub type AnyPower<'a> = hal_cia402::power::AnyPower<'a, SdoClient<'a>>;
/// Where a quick stop leaves a drive on CAN.
pub type AfterQuickStop<'a> = hal_cia402::power::AfterQuickStop<'a, SdoClient<'a>>;

impl ObjectAccess for SdoClient<'_> {
    type Error = Error;

    fn read_u16(&self, index: u16, sub: u8) -> Result<u16, Error> {
        SdoClient::read_u16(self, index, sub)
    }

    fn write_u16(&self, index: u16, sub: u8, value: u16) -> Result<(), Error> {
        SdoClient::write_u16(self, index, sub, value)
    }

    fn state_timeout(&self, state: &'static str, timeout_ms: u64, statusword: u16) -> Error {
        Error::StateTimeout {
            node: self.node(),
            state,
            timeout_ms,
            statusword,
        }
    }
}
