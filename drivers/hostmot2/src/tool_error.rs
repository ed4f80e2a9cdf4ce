//! The error of the crate's bring-up programs, `hal-board` and
//! `hm2-eth-sim`.
//!
//! It stands beside [`Hm2Error`] rather than inside it: [`Hm2Error`] is
//! the driver's LinuxCNC-worded, comparable (`Clone + Eq`) error, while
//! the programs also meet errors that are neither (system calls, PCI
//! access, the MOTENC and Servo-To-Go drivers the board list reaches,
//! HAL), and keep them as their sources.

use std::net::SocketAddr;
use std::path::PathBuf;

use hal_driver::params::NumberError;
use hal_driver::DriverError;

use crate::transport::TransportError;
use crate::Hm2Error;

/// What went wrong in `hal-board` or `hm2-eth-sim`.
#[derive(Debug, thiserror::Error)]
pub enum ToolError {
    /// The board's firmware, IDROM or configuration was refused.
    #[error(transparent)]
    Hm2(#[from] Hm2Error),
    /// A register transfer failed (a PCI window, an Ethernet board).
    #[error(transparent)]
    Transport(#[from] TransportError),
    /// Finding, enabling or mapping a PCI device failed.
    #[error(transparent)]
    Pci(#[from] DriverError),
    /// A MOTENC could not be identified.
    #[error(transparent)]
    Motenc(#[from] hal_motenc::MotencError),
    /// Probing for a Servo-To-Go failed.
    #[error(transparent)]
    Stg(#[from] hal_stg::StgError),
    /// `sim:NAME` names no simulated board.
    #[error("'{name}' is not a simulated board ({boards})")]
    NoSimBoard {
        /// The name given.
        name: String,
        /// The simulated boards there are, comma-separated.
        boards: String,
    },
    /// No HostMot2 board has this PCI address.
    #[error("no HostMot2 board at '{address}' under {} (see hal-board list)", root.display())]
    NoPciBoard {
        /// The address given.
        address: String,
        /// The sysfs PCI device directory searched.
        root: PathBuf,
    },
    /// A device matched the ID table but no board kind.
    #[error("unknown board kind")]
    UnknownKind,
    /// A register address is not a number in the register window.
    #[error("address '{text}': {source}")]
    BadAddress {
        /// The address given.
        text: String,
        /// Why it was refused.
        #[source]
        source: NumberError,
    },
    /// A register address that is not a multiple of 4.
    #[error("address '{text}': registers are 4-aligned")]
    Unaligned {
        /// The address given.
        text: String,
    },
    /// A register value is not a 32-bit number.
    #[error("value '{text}': {source}")]
    BadValue {
        /// The value given.
        text: String,
        /// Why it was refused.
        #[source]
        source: NumberError,
    },
    /// The firmware has no module of this name.
    #[error("the firmware has no module '{name}'")]
    NoModule {
        /// The name given.
        name: String,
    },
    /// `--board` names no simulated Ethernet board.
    #[error("--board {board}: not a simulated Ethernet board ({boards})")]
    NotAnEthBoard {
        /// The name given.
        board: String,
        /// The simulated Ethernet boards there are, comma-separated.
        boards: String,
    },
    /// `--remote 7i77` on a board with one Smart Serial channel.
    #[error("--remote 7i77 needs two channels: --board 7i96s")]
    RemoteNeedsTwoChannels,
    /// `--remote 7i76` or `7i77` given for a board without Smart Serial.
    #[error("--remote {remote}: --board {board} has no Smart Serial port (--remote none)")]
    NoSmartSerial {
        /// The remote asked for.
        remote: String,
        /// The board.
        board: String,
    },
    /// `--remote` names no remote card.
    #[error("--remote {remote}: 7i76, 7i77 or none")]
    NotARemote {
        /// The name given.
        remote: String,
    },
    /// A fault rate outside 0..=1.
    #[error("--{option} {value}: a probability is between 0 and 1")]
    NotAProbability {
        /// The option (`drop-requests`).
        option: &'static str,
        /// The value given.
        value: f64,
    },
    /// The simulator's UDP socket failed (binding or serving).
    #[error("{addr}: {source}")]
    Socket {
        /// The address bound or served.
        addr: SocketAddr,
        /// The system's answer.
        #[source]
        source: std::io::Error,
    },
    /// The simulator's server thread panicked.
    #[error("the server thread panicked")]
    ServerPanicked,
    /// The program could not catch the exit signals it stops on.
    #[error("catching the exit signals: {source}")]
    Signals {
        /// What HAL's signal set-up said.
        #[source]
        source: hal_core::HalError,
    },
    /// The HAL instance refused (attaching, the component).
    #[error(transparent)]
    Hal(#[from] hal_core::HalError),
}
