//! Smart Serial (SSLBP) as both sides see it (hostmot2-more.md 2): the
//! module's registers and commands, the LBP commands sent to remote
//! cards, their self-description records ([`records`]) and how process
//! data is packed and scaled ([`data`]). The driver's module is
//! [`modules::sserial`](crate::modules::sserial); the simulated firmware
//! and remote cards are [`sim::sserial`](crate::sim::sserial).

pub mod data;
pub mod legacy;
pub mod records;
pub mod report;

/// Register indices of the module (register stride apart); the port's
/// instance stride (0x40) and, for per-channel registers, 4 × channel
/// are added.
pub mod reg {
    /// Command register (per port).
    pub const COMMAND: usize = 0;
    /// Data register (per port).
    pub const DATA: usize = 1;
    /// Control/status register (per channel).
    pub const CS: usize = 2;
    /// Interface register 0 (per channel); 1 and 2 follow.
    pub const INTERFACE0: usize = 3;
    /// Interface registers per channel of a Smart Serial (0xC1) module.
    pub const INTERFACES: usize = 3;
}

/// Most channels of a port.
pub const MAX_CHANNELS: usize = 8;
/// Most ports (`sserial_port_0..3`).
pub const MAX_PORTS: usize = 4;
/// Data bits per channel and direction of a Smart Serial module.
pub const MAX_DATA_BITS: usize = 32 * reg::INTERFACES;

/// Commands written to the command register.
pub mod cmd {
    /// Bit 31: ignored by the firmware; written when nothing may start.
    pub const NOTHING: u32 = 0x8000_0000;
    /// Resets the SSLBP processor.
    pub const RESET: u32 = 0x4000;
    /// Stops the channels in the low byte (0: all).
    pub const STOP: u32 = 0x0800;
    /// Starts the channels in the low byte in normal (process-data) mode.
    pub const START_NORMAL: u32 = 0x0900;
    /// Starts the channels in the low byte in setup mode.
    pub const START_SETUP: u32 = 0x0F00;
    /// One transfer on the channels in the low byte.
    pub const DOIT: u32 = 0x1000;
    /// Reads local parameter byte (low 11 bits) into the data register.
    pub const READ_LOCAL: u32 = 0x2000;
    /// Writes the data register's low byte to local parameter (low 11 bits).
    pub const WRITE_LOCAL: u32 = 0xA000;
}

/// Local parameter bytes of the SSLBP processor.
pub mod local {
    /// Interface type.
    pub const INTERFACE_TYPE: u16 = 0;
    /// Interface width (channels).
    pub const INTERFACE_WIDTH: u16 = 1;
    /// Major revision.
    pub const MAJOR_REV: u16 = 2;
    /// Minor revision.
    pub const MINOR_REV: u16 = 3;
    /// Start of the per-channel blocks.
    pub const CHANNEL_START: u16 = 4;
    /// Bytes per channel block.
    pub const CHANNEL_STRIDE: u16 = 5;
    /// Processor type.
    pub const PROCESSOR_TYPE: u16 = 6;
    /// Channels.
    pub const CHANNELS: u16 = 7;
    /// In a channel block: the baud rate (u32).
    pub const BAUD_RATE: u16 = 42;
    /// The SSLBP clock (u32).
    pub const CLOCK: u16 = 0x230;
}

/// The baud rates a remote's `NVBaudRate` global selects, by index (the
/// cards' manuals; mesaflash prints the global with this table).
pub const BAUD_RATES: [u32; 12] = [
    9_600, 19_200, 38_400, 57_600, 115_200, 230_400, 460_800, 921_600, 1_250_000, 2_500_000,
    5_000_000, 10_000_000,
];

/// LBP command bytes sent to a remote (CS bits 31..24 in setup mode).
pub mod lbp {
    /// Read 1, 2, 4 or 8 bytes (+ 0..3) at the address in CS bits 15..0.
    pub const READ: u8 = 0x44;
    /// Read one byte with increment (descriptor reads).
    pub const READ_BYTE: u8 = 0x4C;
    /// Write 1, 2, 4 or 8 bytes (+ 0..3) from interface 0 (and 1).
    pub const WRITE: u8 = 0x64;
    /// Non-volatile access: interface 0 = 1 for EEPROM, 0 for RAM.
    pub const NONVOLATILE: u8 = 0xEC;
    /// Write 8 bytes (flash data, from interfaces 0 and 1).
    pub const WRITE_DOUBLE: u8 = 0x67;
    /// Write 4 bytes.
    pub const WRITE_LONG: u8 = 0x66;
    /// Write 1 byte.
    pub const WRITE_BYTE: u8 = 0x64;
    /// Special read: the cookie (0x5A when the card is in step).
    pub const COOKIE: u8 = 0xDF;
}

/// A remote's flash controller in flash access mode: its registers in
/// the remote's address space and its command bytes.
pub mod flash {
    /// The flash address (u32) the next erase or write acts on.
    pub const ADDR: u16 = 0x8000;
    /// log2 of the erase block size (byte).
    pub const ERASE_SIZE: u16 = 0x8004;
    /// log2 of the write size (byte).
    pub const WRITE_SIZE: u16 = 0x8005;
    /// The command byte.
    pub const COMMAND: u16 = 0x8007;
    /// Command: erase the block at [`ADDR`].
    pub const ERASE: u8 = 0xFE;
    /// Command: program the written bytes at [`ADDR`].
    pub const WRITE: u8 = 0xFD;
    /// What the cookie read answers when the remote is in step.
    pub const COOKIE: u8 = 0x5A;
}

/// What interface 0 selects with [`lbp::NONVOLATILE`].
pub mod access {
    /// The card's RAM (normal).
    pub const RAM: u32 = 0;
    /// Its EEPROM (non-volatile globals).
    pub const EEPROM: u32 = 1;
    /// Its firmware flash.
    pub const FLASH: u32 = 2;
}

/// Status bits of a channel's CS register.
pub mod status {
    /// CRC error.
    pub const CRC: u32 = 1 << 0;
    /// Invalid cookie.
    pub const COOKIE: u32 = 1 << 1;
    /// Overrun.
    pub const OVERRUN: u32 = 1 << 2;
    /// Timeout: the remote did not answer.
    pub const TIMEOUT: u32 = 1 << 3;
    /// Extra character.
    pub const EXTRA: u32 = 1 << 4;
    /// Serial break.
    pub const BREAK: u32 = 1 << 5;
    /// The remote reports a fault (bits 24..31 say which).
    pub const REMOTE_FAULT: u32 = 1 << 8;
    /// Communication error.
    pub const COMM_ERROR: u32 = 1 << 13;
    /// No remote ID.
    pub const NO_ID: u32 = 1 << 14;
    /// Communication not ready.
    pub const NOT_READY: u32 = 1 << 15;
    /// Remote: its watchdog tripped.
    pub const WATCHDOG: u32 = 1 << 24;
    /// Remote: no enable.
    pub const NO_ENABLE: u32 = 1 << 25;
    /// Remote: over temperature.
    pub const OVER_TEMPERATURE: u32 = 1 << 26;
    /// Remote: over current.
    pub const OVER_CURRENT: u32 = 1 << 27;
    /// Remote: over voltage.
    pub const OVER_VOLTAGE: u32 = 1 << 28;
    /// Remote: under voltage.
    pub const UNDER_VOLTAGE: u32 = 1 << 29;
    /// Remote: illegal mode.
    pub const ILLEGAL_MODE: u32 = 1 << 30;
    /// Remote: LBPCOM fault.
    pub const LBPCOM: u32 = 1 << 31;
    /// The bits about the link (shown when the port stops).
    pub const LOCAL_MASK: u32 = 0xE0FF;
    /// The bits a remote reports.
    pub const REMOTE_MASK: u32 = 0xFF00_0100;

    /// What a status bit means.
    pub fn describe(bit: u32) -> Option<&'static str> {
        Some(match bit {
            0 => "CRC error",
            1 => "invalid cookie",
            2 => "overrun",
            3 => "timeout",
            4 => "extra character",
            5 => "serial break",
            8 => "remote fault",
            13 => "communication error",
            14 => "no remote ID",
            15 => "communication not ready",
            24 => "watchdog fault",
            25 => "no enable",
            26 => "over temperature",
            27 => "over current",
            28 => "over voltage",
            29 => "under voltage",
            30 => "illegal remote mode",
            31 => "LBPCOM fault",
            _ => return None,
        })
    }
}

/// Remote type codes (interface 0 bits 31..24 after a setup start).
pub mod remote_type {
    /// 7I76 (I/O and spindle).
    pub const SEVEN_I76: u8 = 0x10;
    /// 7I77 analog channel.
    pub const SEVEN_I77_ANALOG: u8 = 0x11;
    /// 7I77 I/O channel.
    pub const SEVEN_I77_IO: u8 = 0x12;
}

/// The pin of a port's channel: RX (input), TX and TX enable (outputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PinRole {
    /// Receive data of channel n.
    Rx(u8),
    /// Transmit data of channel n.
    Tx(u8),
    /// Transmit enable of channel n.
    TxEnable(u8),
    /// Inverted transmit enable of channel n.
    TxEnableNot(u8),
}

impl PinRole {
    /// Decodes a pin descriptor's SecPin (`rx0..7` 0x01..0x08, `tx`
    /// 0x81.., `txen` 0x91.., `ntxen` 0xA1..; the firmware allows 15
    /// channels, the driver 8).
    pub fn of(sec_pin: u8) -> Option<PinRole> {
        let n = (sec_pin & 0x0F).checked_sub(1)?;
        Some(match sec_pin & 0xF0 {
            0x00 => PinRole::Rx(n),
            0x80 => PinRole::Tx(n),
            0x90 => PinRole::TxEnable(n),
            0xA0 => PinRole::TxEnableNot(n),
            _ => return None,
        })
    }

    /// The channel.
    pub fn channel(self) -> u8 {
        match self {
            PinRole::Rx(n) | PinRole::Tx(n) | PinRole::TxEnable(n) | PinRole::TxEnableNot(n) => n,
        }
    }
}

/// The HAL name of a remote: its interface-1 name with the second
/// character lower-cased (`7I76` → `7i76`), non-printables dropped.
pub fn remote_name(raw: u32) -> String {
    raw.to_le_bytes()
        .iter()
        .enumerate()
        .filter(|(_, b)| b.is_ascii_graphic())
        .map(|(i, &b)| {
            if i == 1 {
                b.to_ascii_lowercase() as char
            } else {
                b as char
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_roles() {
        assert_eq!(remote_name(u32::from_le_bytes(*b"7I76")), "7i76");
        assert_eq!(remote_name(u32::from_le_bytes(*b"8I20")), "8i20");
        assert_eq!(remote_name(u32::from_le_bytes([b'7', 0, b'7', 0x7F])), "77");
        assert_eq!(PinRole::of(0x01), Some(PinRole::Rx(0)));
        assert_eq!(PinRole::of(0x83), Some(PinRole::Tx(2)));
        assert_eq!(PinRole::of(0x98), Some(PinRole::TxEnable(7)));
        assert_eq!(PinRole::of(0xA1), Some(PinRole::TxEnableNot(0)));
        assert_eq!(PinRole::of(0x80), None);
        assert_eq!(PinRole::of(0xC1), None);
        assert_eq!(status::describe(3), Some("timeout"));
    }
}
