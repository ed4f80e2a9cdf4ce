//! The CiA 402 drive layer that every fieldbus driver of the suite
//! shares: `canservo` speaks it over CANopen (SDO and PDOs on SocketCAN),
//! `hal-ethercat` over CoE (mailbox SDOs and process data). What a drive
//! does with its objects is the same on both, so it is written once:
//!
//! * [`objects`]: object indices, statusword and controlword bits, modes
//!   of operation, [`objects::describe_object`] for messages.
//! * [`codes`]: SDO abort codes and CANopen error codes with meanings.
//! * [`power`]: the power state machine ([`power::PowerState`],
//!   [`power::transition`], the planner [`power::next_command`]) and a
//!   typestate API for stepping a drive by hand over any
//!   [`power::ObjectAccess`].
//! * [`drive`]: one drive's realtime control: fault latch and log line,
//!   the planner behind `enable`, the fault-reset sequence, homing
//!   through the drive, PP's set-point handshake, tracking of the
//!   position command ([`drive::DriveControl`]); the fieldbus adds its
//!   supervision ([`drive::LinkSupervision`]) and its frames.
//! * [`faults`]: the drive-side faults; [`shared`]: what the realtime
//!   side shares with a fieldbus's helper thread; [`units`]: counts.

#![forbid(unsafe_code)]

pub mod codes;
pub mod drive;
pub mod faults;
pub mod objects;
pub mod power;
pub mod shared;
pub mod units;

pub use drive::{DriveControl, DriveInputs, Feedback, LinkSupervision, Plan, Restarting};
pub use power::PowerState;
pub use shared::{DriveShared, Restart};

use objects::{mode, obj};

/// The control mode a drive runs in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Cyclic synchronous position (8): the default.
    Csp,
    /// Profile velocity (3).
    Pv,
    /// Cyclic synchronous velocity (9).
    Csv,
    /// Profile position (1): the drive's own profile generator moves to
    /// each new target (set-point handshake on controlword bit 4).
    Pp,
}

impl Mode {
    /// The mode named `s` (`csp`, `pv`, `csv`, `pp`).
    pub fn parse(s: &str) -> Option<Mode> {
        match s.to_ascii_lowercase().as_str() {
            "csp" => Some(Mode::Csp),
            "pv" => Some(Mode::Pv),
            "csv" => Some(Mode::Csv),
            "pp" => Some(Mode::Pp),
            _ => None,
        }
    }

    /// 0x6060's value.
    pub fn number(self) -> i8 {
        match self {
            Mode::Csp => mode::CSP,
            Mode::Pv => mode::PV,
            Mode::Csv => mode::CSV,
            Mode::Pp => mode::PP,
        }
    }

    /// The object the process data carries as target.
    pub fn target_object(self) -> u16 {
        match self {
            Mode::Csp | Mode::Pp => obj::TARGET_POSITION,
            Mode::Pv | Mode::Csv => obj::TARGET_VELOCITY,
        }
    }

    /// Whether the target is a position.
    pub fn is_position(self) -> bool {
        matches!(self, Mode::Csp | Mode::Pp)
    }
}
