//! The CiA 402 power state machine (hardware.md §6.8), written once for
//! the masters (CANopen, EtherCAT), the simulated drives and the
//! bring-up tools:
//!
//! * [`PowerState`]: the eight states, decoded from a statusword with
//!   the standard's masks, and the statusword a drive shows in each.
//! * [`Command`]: the controlword commands, decoded from a controlword
//!   the way a drive does, and their standard values.
//! * [`transition`]: where a command takes a state (the standard's
//!   numbered transitions 2 to 12, 15 and 16), the one table both the
//!   simulated drive and the master's planner ([`next_command`]) use.
//! * [`Power`]: the same machine with the states as types, for code that
//!   steps a drive through its states by hand (the bring-up tool, tests):
//!   each method exists only on the states the standard allows it from
//!   and returns the state it leads to, so a wrong order is a compile
//!   error, in the manner of EtherCrab's `SubDeviceGroup<PreOp>` →
//!   `into_op()`.
//!
//! ```compile_fail
//! # use hal_canservo::power::{Power, SwitchOnDisabled};
//! # fn f(p: Power<'_, SwitchOnDisabled>) {
//! // Enable operation needs Switched on first: this does not compile.
//! let _ = p.enable_operation();
//! # }
//! ```
//!
//! ```compile_fail
//! # use hal_canservo::power::{Power, OperationEnabled};
//! # fn f(p: Power<'_, OperationEnabled>) {
//! // A fault reset is only for a drive in Fault.
//! let _ = p.fault_reset();
//! # }
//! ```

use std::marker::PhantomData;
use std::time::{Duration, Instant};

use crate::objects::{cw, obj, sw};

/// Reading and writing a drive's objects (by SDO over CAN, CoE over
/// EtherCAT): what the typestate API needs of a fieldbus.
pub trait ObjectAccess {
    /// The error of a failed access.
    type Error;
    /// Reads a 16-bit object.
    fn read_u16(&self, index: u16, sub: u8) -> Result<u16, Self::Error>;
    /// Writes a 16-bit object.
    fn write_u16(&self, index: u16, sub: u8, value: u16) -> Result<(), Self::Error>;
    /// The error for a drive that did not show `state` within
    /// `timeout_ms`; `statusword` is the last one seen.
    fn state_timeout(&self, state: &'static str, timeout_ms: u64, statusword: u16) -> Self::Error;
}

/// A CiA 402 power state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PowerState {
    /// Not ready to switch on (self-test).
    NotReadyToSwitchOn,
    /// Switch on disabled.
    SwitchOnDisabled,
    /// Ready to switch on.
    ReadyToSwitchOn,
    /// Switched on.
    SwitchedOn,
    /// Operation enabled: the power stage follows the commands.
    OperationEnabled,
    /// Quick stop active.
    QuickStopActive,
    /// Fault reaction active.
    FaultReactionActive,
    /// Fault.
    Fault,
}

/// (state, mask, value, example statusword) per the standard's table.
const TABLE: [(PowerState, u16, u16, u16); 8] = [
    (PowerState::NotReadyToSwitchOn, 0x004F, 0x0000, 0x0000),
    (PowerState::SwitchOnDisabled, 0x004F, 0x0040, 0x0250),
    (PowerState::ReadyToSwitchOn, 0x006F, 0x0021, 0x0231),
    (PowerState::SwitchedOn, 0x006F, 0x0023, 0x0233),
    (PowerState::OperationEnabled, 0x006F, 0x0027, 0x0237),
    (PowerState::QuickStopActive, 0x006F, 0x0007, 0x0217),
    (PowerState::FaultReactionActive, 0x004F, 0x000F, 0x021F),
    (PowerState::Fault, 0x004F, 0x0008, 0x0218),
];

impl PowerState {
    /// The state a statusword shows; None for bit patterns the standard
    /// does not define.
    pub fn from_statusword(statusword: u16) -> Option<PowerState> {
        TABLE
            .iter()
            .find(|(_, mask, value, _)| statusword & mask == *value)
            .map(|(s, ..)| *s)
    }

    /// The state bits (0..6, with bit 4 voltage enabled and bit 9 remote
    /// as in the standard's examples) a drive shows in this state.
    pub fn statusword_bits(self) -> u16 {
        TABLE
            .iter()
            .find(|(s, ..)| *s == self)
            .map_or(0, |(.., example)| *example)
    }

    /// The number shown on the `state` pin: 1..8 in the order of the
    /// standard's table (0 is kept for "unknown").
    pub fn number(self) -> i32 {
        TABLE
            .iter()
            .position(|(s, ..)| *s == self)
            .map_or(0, |i| i as i32 + 1)
    }

    /// The standard's name.
    pub fn name(self) -> &'static str {
        match self {
            PowerState::NotReadyToSwitchOn => "not ready to switch on",
            PowerState::SwitchOnDisabled => "switch on disabled",
            PowerState::ReadyToSwitchOn => "ready to switch on",
            PowerState::SwitchedOn => "switched on",
            PowerState::OperationEnabled => "operation enabled",
            PowerState::QuickStopActive => "quick stop active",
            PowerState::FaultReactionActive => "fault reaction active",
            PowerState::Fault => "fault",
        }
    }

    /// Whether the power stage is (or may be) energised.
    pub fn is_powered(self) -> bool {
        matches!(
            self,
            PowerState::OperationEnabled
                | PowerState::QuickStopActive
                | PowerState::FaultReactionActive
        )
    }
}

/// A controlword command (bits 7, 3, 2, 1, 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Command {
    /// Shutdown: 0 x 1 1 0.
    Shutdown,
    /// Switch on (also disable operation): 0 0 1 1 1.
    SwitchOn,
    /// Enable operation: 0 1 1 1 1.
    EnableOperation,
    /// Disable voltage: 0 x x 0 x.
    DisableVoltage,
    /// Quick stop: 0 x 0 1 x.
    QuickStop,
    /// Fault reset: bit 7 (acts on its rising edge).
    FaultReset,
}

impl Command {
    /// The command a controlword gives, as a drive decodes it.
    pub fn from_controlword(controlword: u16) -> Command {
        if controlword & cw::FAULT_RESET != 0 {
            Command::FaultReset
        } else if controlword & cw::ENABLE_VOLTAGE == 0 {
            Command::DisableVoltage
        } else if controlword & cw::QUICK_STOP == 0 {
            Command::QuickStop
        } else if controlword & cw::SWITCH_ON == 0 {
            Command::Shutdown
        } else if controlword & cw::ENABLE_OPERATION == 0 {
            Command::SwitchOn
        } else {
            Command::EnableOperation
        }
    }

    /// The standard's value of the command (bits 0..3 and 7 only).
    pub fn controlword(self) -> u16 {
        match self {
            Command::Shutdown => cw::SHUTDOWN,
            Command::SwitchOn => cw::SWITCH_ON_CMD,
            Command::EnableOperation => cw::ENABLE_OPERATION_CMD,
            Command::DisableVoltage => cw::DISABLE_VOLTAGE,
            Command::QuickStop => cw::QUICK_STOP_CMD,
            Command::FaultReset => cw::FAULT_RESET_CMD,
        }
    }
}

/// Where `command` takes a drive in `state`, per the standard's
/// transitions; None when the command does nothing there. Quick stop
/// from Operation enabled leads to Quick stop active (11); what happens
/// next depends on the quick stop option code and is the drive's
/// business. A fault reset leads out of Fault (15) only on the edge and
/// only if the cause is gone, which the caller decides.
pub fn transition(state: PowerState, command: Command) -> Option<PowerState> {
    use Command as C;
    use PowerState as S;
    match (state, command) {
        (S::SwitchOnDisabled, C::Shutdown) => Some(S::ReadyToSwitchOn), // 2
        (S::ReadyToSwitchOn, C::SwitchOn) => Some(S::SwitchedOn),       // 3
        (S::ReadyToSwitchOn, C::EnableOperation) => Some(S::OperationEnabled), // 3 + 4
        (S::SwitchedOn, C::EnableOperation) => Some(S::OperationEnabled), // 4
        (S::OperationEnabled, C::SwitchOn) => Some(S::SwitchedOn),      // 5
        (S::SwitchedOn, C::Shutdown) => Some(S::ReadyToSwitchOn),       // 6
        (S::ReadyToSwitchOn, C::DisableVoltage | C::QuickStop) => Some(S::SwitchOnDisabled), // 7
        (S::OperationEnabled, C::Shutdown) => Some(S::ReadyToSwitchOn), // 8
        (S::OperationEnabled, C::DisableVoltage) => Some(S::SwitchOnDisabled), // 9
        (S::SwitchedOn, C::DisableVoltage | C::QuickStop) => Some(S::SwitchOnDisabled), // 10
        (S::OperationEnabled, C::QuickStop) => Some(S::QuickStopActive), // 11
        (S::QuickStopActive, C::DisableVoltage) => Some(S::SwitchOnDisabled), // 12
        (S::QuickStopActive, C::EnableOperation) => Some(S::OperationEnabled), // 16 (option 5..8)
        (S::Fault, C::FaultReset) => Some(S::SwitchOnDisabled),         // 15
        _ => None,
    }
}

/// What the master wants of a drive this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Goal {
    /// Power stage on, following the commands.
    Enabled,
    /// Power stage off (Switch on disabled), the motor free.
    Disabled,
    /// Stop now: quick stop, then disable voltage.
    QuickStop,
}

/// The controlword that moves a drive in `state` one step towards
/// `goal`: the planner behind the `enable` pin. Walking up it uses the
/// standard's path 2, 3, 4 (one step per cycle, since each needs the
/// drive to confirm the state in its statusword); walking down it
/// disables voltage at once, because the drive's own option codes
/// decide how it stops. Fault is left alone (a reset is the caller's
/// explicit edge); in Fault reaction active the drive must finish first.
pub fn next_command(state: Option<PowerState>, goal: Goal) -> u16 {
    use PowerState as S;
    let Some(state) = state else {
        return cw::DISABLE_VOLTAGE;
    };
    match goal {
        Goal::QuickStop => match state {
            S::OperationEnabled | S::QuickStopActive => cw::QUICK_STOP_CMD,
            _ => cw::DISABLE_VOLTAGE,
        },
        Goal::Disabled => cw::DISABLE_VOLTAGE,
        Goal::Enabled => match state {
            S::SwitchOnDisabled => cw::SHUTDOWN,
            S::ReadyToSwitchOn => cw::SWITCH_ON_CMD,
            S::SwitchedOn | S::OperationEnabled => cw::ENABLE_OPERATION_CMD,
            // A quick stop ends in Switch on disabled first.
            S::QuickStopActive => cw::QUICK_STOP_CMD,
            S::NotReadyToSwitchOn | S::FaultReactionActive | S::Fault => cw::DISABLE_VOLTAGE,
        },
    }
}

/// Decoded statusword bits, for displays.
pub fn describe_statusword(statusword: u16) -> String {
    let state = PowerState::from_statusword(statusword).map_or("undefined state", |s| s.name());
    let set: Vec<&str> = sw::NAMES
        .iter()
        .filter(|(b, _)| statusword & b != 0)
        .map(|(_, n)| *n)
        .collect();
    format!("{statusword:#06x} {state}: {}", set.join(" "))
}

// ---- The typestate API ----

/// Marker of a state type.
pub trait StateType {
    /// The state it stands for.
    const STATE: PowerState;
}

macro_rules! state_types {
    ($($(#[$m:meta])* $t:ident = $s:ident;)*) => {$(
        $(#[$m])*
        #[derive(Debug)]
        pub struct $t;
        impl StateType for $t {
            const STATE: PowerState = PowerState::$s;
        }
    )*};
}

state_types! {
    /// Switch on disabled.
    SwitchOnDisabled = SwitchOnDisabled;
    /// Ready to switch on.
    ReadyToSwitchOn = ReadyToSwitchOn;
    /// Switched on.
    SwitchedOn = SwitchedOn;
    /// Operation enabled.
    OperationEnabled = OperationEnabled;
    /// Quick stop active.
    QuickStopActive = QuickStopActive;
    /// Fault.
    Fault = Fault;
}

/// A drive known to be in state `S`, stepped through its states by SDO
/// writes of the controlword and reads of the statusword. Each method
/// waits until the drive shows the next state (or `timeout` passes; the
/// error then holds the statusword seen).
#[derive(Debug)]
pub struct Power<'a, A, S: StateType> {
    sdo: &'a A,
    timeout: Duration,
    _state: PhantomData<S>,
}

/// The state a drive is in now, as a typed handle.
#[derive(Debug)]
pub enum AnyPower<'a, A> {
    /// Switch on disabled.
    SwitchOnDisabled(Power<'a, A, SwitchOnDisabled>),
    /// Ready to switch on.
    ReadyToSwitchOn(Power<'a, A, ReadyToSwitchOn>),
    /// Switched on.
    SwitchedOn(Power<'a, A, SwitchedOn>),
    /// Operation enabled.
    OperationEnabled(Power<'a, A, OperationEnabled>),
    /// Quick stop active.
    QuickStopActive(Power<'a, A, QuickStopActive>),
    /// Fault.
    Fault(Power<'a, A, Fault>),
    /// Not ready to switch on or Fault reaction active past the
    /// time-out, or an undefined statusword: nothing can be commanded.
    NotReady(u16),
}

impl<'a, A: ObjectAccess> AnyPower<'a, A> {
    /// Reads the statusword and returns the typed handle for the state.
    /// The transient states (Not ready to switch on, Fault reaction
    /// active) are waited out, up to `timeout`.
    pub fn read(sdo: &'a A, timeout: Duration) -> Result<AnyPower<'a, A>, A::Error> {
        let end = Instant::now() + timeout;
        let mut statusword = sdo.read_u16(obj::STATUSWORD, 0)?;
        while matches!(
            PowerState::from_statusword(statusword),
            Some(PowerState::NotReadyToSwitchOn | PowerState::FaultReactionActive)
        ) && Instant::now() < end
        {
            std::thread::sleep(Duration::from_millis(2));
            statusword = sdo.read_u16(obj::STATUSWORD, 0)?;
        }
        Ok(match PowerState::from_statusword(statusword) {
            Some(PowerState::SwitchOnDisabled) => {
                AnyPower::SwitchOnDisabled(Power::new(sdo, timeout))
            }
            Some(PowerState::ReadyToSwitchOn) => {
                AnyPower::ReadyToSwitchOn(Power::new(sdo, timeout))
            }
            Some(PowerState::SwitchedOn) => AnyPower::SwitchedOn(Power::new(sdo, timeout)),
            Some(PowerState::OperationEnabled) => {
                AnyPower::OperationEnabled(Power::new(sdo, timeout))
            }
            Some(PowerState::QuickStopActive) => {
                AnyPower::QuickStopActive(Power::new(sdo, timeout))
            }
            Some(PowerState::Fault) => AnyPower::Fault(Power::new(sdo, timeout)),
            _ => AnyPower::NotReady(statusword),
        })
    }
}

impl<'a, A: ObjectAccess, S: StateType> Power<'a, A, S> {
    fn new(sdo: &'a A, timeout: Duration) -> Power<'a, A, S> {
        Power {
            sdo,
            timeout,
            _state: PhantomData,
        }
    }

    /// The state this handle stands for.
    pub fn state(&self) -> PowerState {
        S::STATE
    }

    /// Writes `controlword` and waits for state `T`.
    fn go<T: StateType>(self, controlword: u16) -> Result<Power<'a, A, T>, A::Error> {
        self.sdo.write_u16(obj::CONTROLWORD, 0, controlword)?;
        self.wait_for(&[T::STATE], T::STATE.name())?;
        Ok(Power::new(self.sdo, self.timeout))
    }

    /// Waits until the drive shows one of `states`; which one.
    fn wait_for(&self, states: &[PowerState], name: &'static str) -> Result<PowerState, A::Error> {
        let end = Instant::now() + self.timeout;
        loop {
            let statusword = self.sdo.read_u16(obj::STATUSWORD, 0)?;
            if let Some(s) = PowerState::from_statusword(statusword).filter(|s| states.contains(s))
            {
                return Ok(s);
            }
            if Instant::now() >= end {
                return Err(self.sdo.state_timeout(
                    name,
                    self.timeout.as_millis() as u64,
                    statusword,
                ));
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }
}

/// Where a quick stop leaves a drive: still in Quick stop active
/// (option codes 5..8, or while it decelerates) or, once stopped with
/// option codes 0..4, in Switch on disabled.
#[derive(Debug)]
pub enum AfterQuickStop<'a, A> {
    /// Quick stop active.
    Active(Power<'a, A, QuickStopActive>),
    /// Switch on disabled.
    Disabled(Power<'a, A, SwitchOnDisabled>),
}

impl<'a, A: ObjectAccess> Power<'a, A, SwitchOnDisabled> {
    /// Shutdown (2).
    pub fn shutdown(self) -> Result<Power<'a, A, ReadyToSwitchOn>, A::Error> {
        self.go(cw::SHUTDOWN)
    }
}

impl<'a, A: ObjectAccess> Power<'a, A, ReadyToSwitchOn> {
    /// Switch on (3).
    pub fn switch_on(self) -> Result<Power<'a, A, SwitchedOn>, A::Error> {
        self.go(cw::SWITCH_ON_CMD)
    }

    /// Disable voltage (7).
    pub fn disable_voltage(self) -> Result<Power<'a, A, SwitchOnDisabled>, A::Error> {
        self.go(cw::DISABLE_VOLTAGE)
    }
}

impl<'a, A: ObjectAccess> Power<'a, A, SwitchedOn> {
    /// Enable operation (4).
    pub fn enable_operation(self) -> Result<Power<'a, A, OperationEnabled>, A::Error> {
        self.go(cw::ENABLE_OPERATION_CMD)
    }

    /// Shutdown (6).
    pub fn shutdown(self) -> Result<Power<'a, A, ReadyToSwitchOn>, A::Error> {
        self.go(cw::SHUTDOWN)
    }

    /// Disable voltage (10).
    pub fn disable_voltage(self) -> Result<Power<'a, A, SwitchOnDisabled>, A::Error> {
        self.go(cw::DISABLE_VOLTAGE)
    }
}

impl<'a, A: ObjectAccess> Power<'a, A, OperationEnabled> {
    /// Disable operation (5).
    pub fn disable_operation(self) -> Result<Power<'a, A, SwitchedOn>, A::Error> {
        self.go(cw::SWITCH_ON_CMD)
    }

    /// Shutdown (8).
    pub fn shutdown(self) -> Result<Power<'a, A, ReadyToSwitchOn>, A::Error> {
        self.go(cw::SHUTDOWN)
    }

    /// Disable voltage (9): the motor coasts.
    pub fn disable_voltage(self) -> Result<Power<'a, A, SwitchOnDisabled>, A::Error> {
        self.go(cw::DISABLE_VOLTAGE)
    }

    /// Quick stop (11), and 12 when the drive's option code ends it in
    /// Switch on disabled.
    pub fn quick_stop(self) -> Result<AfterQuickStop<'a, A>, A::Error> {
        self.sdo
            .write_u16(obj::CONTROLWORD, 0, cw::QUICK_STOP_CMD)?;
        let states = [PowerState::QuickStopActive, PowerState::SwitchOnDisabled];
        Ok(
            match self.wait_for(&states, "quick stop active or switch on disabled")? {
                PowerState::QuickStopActive => {
                    AfterQuickStop::Active(Power::new(self.sdo, self.timeout))
                }
                _ => AfterQuickStop::Disabled(Power::new(self.sdo, self.timeout)),
            },
        )
    }
}

impl<'a, A: ObjectAccess> Power<'a, A, QuickStopActive> {
    /// Disable voltage (12).
    pub fn disable_voltage(self) -> Result<Power<'a, A, SwitchOnDisabled>, A::Error> {
        self.go(cw::DISABLE_VOLTAGE)
    }

    /// Enable operation (16; only drives whose quick stop option code is
    /// 5..8 stay in Quick stop active to allow it).
    pub fn enable_operation(self) -> Result<Power<'a, A, OperationEnabled>, A::Error> {
        self.go(cw::ENABLE_OPERATION_CMD)
    }
}

impl<'a, A: ObjectAccess> Power<'a, A, Fault> {
    /// Fault reset (15): bit 7 low, then high; the drive leaves Fault
    /// only if the cause is gone.
    pub fn fault_reset(self) -> Result<Power<'a, A, SwitchOnDisabled>, A::Error> {
        self.sdo
            .write_u16(obj::CONTROLWORD, 0, cw::DISABLE_VOLTAGE)?;
        self.go(cw::FAULT_RESET_CMD)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn examples_decode_to_their_states() {
        for (state, _, _, example) in TABLE {
            assert_eq!(
                PowerState::from_statusword(example),
                Some(state),
                "{example:#x}"
            );
            assert_eq!(state.statusword_bits(), example);
        }
        // Other bits do not matter.
        assert_eq!(
            PowerState::from_statusword(0x1637),
            Some(PowerState::OperationEnabled)
        );
        assert_eq!(PowerState::from_statusword(0x0001), None);
        assert_eq!(PowerState::Fault.number(), 8);
    }

    #[test]
    fn commands_decode_as_a_drive_does() {
        for c in [
            Command::Shutdown,
            Command::SwitchOn,
            Command::EnableOperation,
            Command::DisableVoltage,
            Command::QuickStop,
            Command::FaultReset,
        ] {
            assert_eq!(Command::from_controlword(c.controlword()), c);
        }
        // "x" bits.
        assert_eq!(Command::from_controlword(0x000E), Command::Shutdown);
        assert_eq!(Command::from_controlword(0x000D), Command::DisableVoltage);
        assert_eq!(Command::from_controlword(0x000B), Command::QuickStop);
    }

    #[test]
    fn the_planner_walks_the_standard_path() {
        let mut s = PowerState::SwitchOnDisabled;
        let mut path = vec![s];
        for _ in 0..5 {
            let c = Command::from_controlword(next_command(Some(s), Goal::Enabled));
            if let Some(n) = transition(s, c) {
                s = n;
                path.push(s);
            }
        }
        assert_eq!(
            path,
            vec![
                PowerState::SwitchOnDisabled,
                PowerState::ReadyToSwitchOn,
                PowerState::SwitchedOn,
                PowerState::OperationEnabled
            ]
        );
        let c = Command::from_controlword(next_command(Some(s), Goal::QuickStop));
        assert_eq!(transition(s, c), Some(PowerState::QuickStopActive));
        let c = Command::from_controlword(next_command(
            Some(PowerState::QuickStopActive),
            Goal::Disabled,
        ));
        assert_eq!(
            transition(PowerState::QuickStopActive, c),
            Some(PowerState::SwitchOnDisabled)
        );
        assert_eq!(
            next_command(Some(PowerState::Fault), Goal::Enabled),
            cw::DISABLE_VOLTAGE,
            "a fault is never reset by enable"
        );
    }

    #[test]
    fn statusword_description() {
        let d = describe_statusword(0x0237);
        assert!(d.starts_with("0x0237 operation enabled:"), "{d}");
        assert!(d.contains("remote") && d.contains("voltage-enabled"));
    }
}
