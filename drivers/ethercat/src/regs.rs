//! The ESC (EtherCAT slave controller) register map: the addresses a
//! master reads and writes with physical commands, and their bits.
//! Named constants only; the simulator ([`crate::sim`]) gives them
//! behaviour.

/// ESC type (u8).
pub const TYPE: u16 = 0x0000;
/// ESC revision (u8).
pub const REVISION: u16 = 0x0001;
/// ESC build (u16).
pub const BUILD: u16 = 0x0002;
/// FMMUs supported (u8).
pub const FMMU_COUNT: u16 = 0x0004;
/// Sync managers supported (u8).
pub const SM_COUNT: u16 = 0x0005;
/// Process RAM size in KiB (u8).
pub const RAM_SIZE: u16 = 0x0006;
/// Port descriptor (u8): two bits per port.
pub const PORT_DESCRIPTOR: u16 = 0x0007;
/// ESC features supported (u16).
pub const FEATURES: u16 = 0x0008;
/// Configured station address (u16).
pub const STATION_ADDRESS: u16 = 0x0010;
/// Configured station alias (u16), loaded from SII word 4.
pub const STATION_ALIAS: u16 = 0x0012;
/// DL control (u32).
pub const DL_CONTROL: u16 = 0x0100;
/// DL status (u16).
pub const DL_STATUS: u16 = 0x0110;
/// AL control (u16).
pub const AL_CONTROL: u16 = 0x0120;
/// AL status (u16).
pub const AL_STATUS: u16 = 0x0130;
/// AL status code (u16).
pub const AL_STATUS_CODE: u16 = 0x0134;
/// PDI control (u8).
pub const PDI_CONTROL: u16 = 0x0140;
/// ESC configuration (u8).
pub const ESC_CONFIG: u16 = 0x0141;
/// ECAT event mask (u16).
pub const ECAT_EVENT_MASK: u16 = 0x0200;
/// AL event mask (u32).
pub const AL_EVENT_MASK: u16 = 0x0204;
/// ECAT event request (u16).
pub const ECAT_EVENT: u16 = 0x0210;
/// RX error counters, ports 0..3 (2 bytes each).
pub const RX_ERROR_COUNTERS: u16 = 0x0300;
/// Lost link counters, ports 0..3 (u8 each).
pub const LOST_LINK_COUNTERS: u16 = 0x0310;
/// Watchdog divider (u16).
pub const WATCHDOG_DIVIDER: u16 = 0x0400;
/// PDI watchdog time (u16).
pub const WATCHDOG_PDI: u16 = 0x0410;
/// Sync manager watchdog time (u16).
pub const WATCHDOG_SM: u16 = 0x0420;
/// Sync manager watchdog status (u16).
pub const WATCHDOG_SM_STATUS: u16 = 0x0440;
/// SII EEPROM configuration (u8).
pub const SII_CONFIG: u16 = 0x0500;
/// SII EEPROM PDI access state (u8).
pub const SII_ACCESS: u16 = 0x0501;
/// SII EEPROM control/status (u16).
pub const SII_CONTROL: u16 = 0x0502;
/// SII EEPROM word address (u32).
pub const SII_ADDRESS: u16 = 0x0504;
/// SII EEPROM data (4 or 8 bytes).
pub const SII_DATA: u16 = 0x0508;
/// First FMMU (16 bytes each).
pub const FMMU_BASE: u16 = 0x0600;
/// Bytes per FMMU.
pub const FMMU_LEN: u16 = 16;
/// First sync manager (8 bytes each).
pub const SM_BASE: u16 = 0x0800;
/// Bytes per sync manager.
pub const SM_LEN: u16 = 8;
/// DC receive time of port 0 (u32); a write latches all ports.
pub const DC_RECEIVE_TIME_PORT0: u16 = 0x0900;
/// DC receive time of port 1 (u32).
pub const DC_RECEIVE_TIME_PORT1: u16 = 0x0904;
/// DC system time (u64; a write feeds the drift control).
pub const DC_SYSTEM_TIME: u16 = 0x0910;
/// DC local receive time of the processing unit (u64).
pub const DC_RECEIVE_TIME_PU: u16 = 0x0918;
/// DC system time offset (u64).
pub const DC_SYSTEM_TIME_OFFSET: u16 = 0x0920;
/// DC system time transmission delay (u32).
pub const DC_SYSTEM_TIME_DELAY: u16 = 0x0928;
/// DC system time difference (u32, sign in bit 31).
pub const DC_SYSTEM_TIME_DIFFERENCE: u16 = 0x092C;
/// DC speed counter start (u16).
pub const DC_SPEED_COUNTER_START: u16 = 0x0930;
/// DC cyclic unit control (u8).
pub const DC_CYCLIC_UNIT_CONTROL: u16 = 0x0980;
/// DC activation (u8): cyclic operation, SYNC0, SYNC1.
pub const DC_ACTIVATION: u16 = 0x0981;
/// DC SYNC0 status (u8).
pub const DC_SYNC0_STATUS: u16 = 0x098E;
/// DC start time of cyclic operation (u64).
pub const DC_START_TIME: u16 = 0x0990;
/// DC SYNC0 cycle time (u32).
pub const DC_SYNC0_CYCLE: u16 = 0x09A0;
/// DC SYNC1 cycle time (u32).
pub const DC_SYNC1_CYCLE: u16 = 0x09A4;
/// First byte of process data RAM.
pub const PROCESS_RAM: u16 = 0x1000;

/// AL states (AL control request, AL status low nibble).
pub mod al {
    /// INIT.
    pub const INIT: u8 = 0x01;
    /// PRE-OPERATIONAL.
    pub const PREOP: u8 = 0x02;
    /// BOOTSTRAP.
    pub const BOOT: u8 = 0x03;
    /// SAFE-OPERATIONAL.
    pub const SAFEOP: u8 = 0x04;
    /// OPERATIONAL.
    pub const OP: u8 = 0x08;
    /// The state bits.
    pub const STATE_MASK: u8 = 0x0F;
    /// AL status: error indicated; AL control: error acknowledge.
    pub const ERROR: u8 = 0x10;

    /// The name IgH's `ethercat slaves` prints for a state.
    pub fn name(state: u8) -> &'static str {
        match state & STATE_MASK {
            INIT => "INIT",
            PREOP => "PREOP",
            BOOT => "BOOT",
            SAFEOP => "SAFEOP",
            OP => "OP",
            _ => "UNKNOWN",
        }
    }

    /// The state named `s` (INIT, PREOP, SAFEOP, OP, BOOT; any case).
    pub fn parse(s: &str) -> Option<u8> {
        match s.to_ascii_uppercase().replace('-', "").as_str() {
            "INIT" => Some(INIT),
            "PREOP" => Some(PREOP),
            "BOOT" => Some(BOOT),
            "SAFEOP" => Some(SAFEOP),
            "OP" => Some(OP),
            _ => None,
        }
    }
}

/// AL status codes (register 0x0134) and their meanings.
pub mod al_code {
    /// No error.
    pub const NONE: u16 = 0x0000;
    /// Unspecified error.
    pub const UNSPECIFIED: u16 = 0x0001;
    /// Invalid requested state change.
    pub const INVALID_STATE_CHANGE: u16 = 0x0011;
    /// Unknown requested state.
    pub const UNKNOWN_STATE: u16 = 0x0012;
    /// Bootstrap not supported.
    pub const BOOTSTRAP_NOT_SUPPORTED: u16 = 0x0013;
    /// Invalid mailbox configuration (PRE-OP).
    pub const INVALID_MAILBOX_CONFIG: u16 = 0x0016;
    /// Invalid sync manager configuration.
    pub const INVALID_SM_CONFIG: u16 = 0x0017;
    /// Sync manager watchdog.
    pub const SM_WATCHDOG: u16 = 0x001B;
    /// Invalid output configuration.
    pub const INVALID_OUTPUT_CONFIG: u16 = 0x001D;
    /// Invalid input configuration.
    pub const INVALID_INPUT_CONFIG: u16 = 0x001E;
    /// Slave restarted locally.
    pub const RESTARTED_LOCALLY: u16 = 0x0060;
    /// Invalid DC SYNC configuration.
    pub const INVALID_DC_SYNC: u16 = 0x0030;
    /// DC: invalid SYNC0 cycle time.
    pub const DC_SYNC0_CYCLE: u16 = 0x0036;

    /// What a code means (ETG.1000.6's table, the common ones).
    pub fn meaning(code: u16) -> &'static str {
        match code {
            0x0000 => "no error",
            0x0001 => "unspecified error",
            0x0002 => "no memory",
            0x0011 => "invalid requested state change",
            0x0012 => "unknown requested state",
            0x0013 => "bootstrap not supported",
            0x0014 => "no valid firmware",
            0x0015 => "invalid mailbox configuration (BOOT)",
            0x0016 => "invalid mailbox configuration (PREOP)",
            0x0017 => "invalid sync manager configuration",
            0x0018 => "no valid inputs available",
            0x0019 => "no valid outputs",
            0x001A => "synchronization error",
            0x001B => "sync manager watchdog",
            0x001C => "invalid sync manager types",
            0x001D => "invalid output configuration",
            0x001E => "invalid input configuration",
            0x001F => "invalid watchdog configuration",
            0x0020 => "slave needs cold start",
            0x0021 => "slave needs INIT",
            0x0022 => "slave needs PREOP",
            0x0023 => "slave needs SAFEOP",
            0x002C => "fatal sync error",
            0x0030 => "invalid DC SYNC configuration",
            0x0031 => "invalid DC latch configuration",
            0x0032 => "PLL error",
            0x0035 => "invalid DC cycle time",
            0x0036 => "invalid DC SYNC0 cycle time",
            0x0037 => "invalid DC SYNC1 cycle time",
            0x0043 => "mailbox CoE error",
            0x0050 => "EEPROM no access",
            0x0051 => "EEPROM error",
            0x0060 => "slave restarted locally",
            _ => "unknown AL status code",
        }
    }
}

/// SII control/status (0x0502) bits.
pub mod sii {
    /// ECAT write enable.
    pub const WRITE_ENABLE: u16 = 1 << 0;
    /// Read size: 8 bytes (else 4).
    pub const READ_8: u16 = 1 << 6;
    /// Command: read.
    pub const CMD_READ: u16 = 0x0100;
    /// Command: write.
    pub const CMD_WRITE: u16 = 0x0200;
    /// Command: reload.
    pub const CMD_RELOAD: u16 = 0x0400;
    /// The command bits.
    pub const CMD_MASK: u16 = 0x0700;
    /// Checksum error at load.
    pub const CHECKSUM_ERROR: u16 = 1 << 11;
    /// Command error (unknown command, address out of range).
    pub const COMMAND_ERROR: u16 = 1 << 13;
    /// Write error (write without enable).
    pub const WRITE_ERROR: u16 = 1 << 14;
    /// Busy.
    pub const BUSY: u16 = 1 << 15;
}

/// Sync manager register bytes (offsets in an SM's 8 bytes) and bits.
pub mod sm {
    /// Physical start address (u16).
    pub const START: u16 = 0;
    /// Length (u16).
    pub const LENGTH: u16 = 2;
    /// Control (u8).
    pub const CONTROL: u16 = 4;
    /// Status (u8).
    pub const STATUS: u16 = 5;
    /// Activate (u8).
    pub const ACTIVATE: u16 = 6;
    /// PDI control (u8).
    pub const PDI_CONTROL: u16 = 7;
    /// Control: mailbox mode (else 3-buffer).
    pub const MODE_MAILBOX: u8 = 0x02;
    /// Control: mode bits.
    pub const MODE_MASK: u8 = 0x03;
    /// Control: written by the master (outputs, mailbox out).
    pub const DIR_WRITE: u8 = 0x04;
    /// Control: direction bits.
    pub const DIR_MASK: u8 = 0x0C;
    /// Status: mailbox full.
    pub const STATUS_FULL: u8 = 0x08;
    /// Activate: enable.
    pub const ENABLE: u8 = 0x01;
    /// Activate: repeat request.
    pub const REPEAT: u8 = 0x02;
    /// PDI control: repeat acknowledge.
    pub const REPEAT_ACK: u8 = 0x02;
}

/// FMMU register bytes (offsets in an FMMU's 16 bytes) and types.
pub mod fmmu {
    /// Logical start address (u32).
    pub const LOGICAL_START: u16 = 0;
    /// Length in bytes (u16).
    pub const LENGTH: u16 = 4;
    /// Logical start bit (u8).
    pub const LOGICAL_START_BIT: u16 = 6;
    /// Logical stop bit (u8).
    pub const LOGICAL_STOP_BIT: u16 = 7;
    /// Physical start address (u16).
    pub const PHYSICAL_START: u16 = 8;
    /// Physical start bit (u8).
    pub const PHYSICAL_START_BIT: u16 = 10;
    /// Type (u8): bit 0 read, bit 1 write.
    pub const TYPE: u16 = 11;
    /// Activate (u8).
    pub const ACTIVATE: u16 = 12;
    /// Type: the master reads (inputs).
    pub const READ: u8 = 0x01;
    /// Type: the master writes (outputs).
    pub const WRITE: u8 = 0x02;
}

/// DL status (0x0110) bits.
pub mod dl_status {
    /// PDI operational (EEPROM loaded).
    pub const PDI_OPERATIONAL: u16 = 1 << 0;
    /// Physical link on port `p`.
    pub const fn link(p: u16) -> u16 {
        1 << (4 + p)
    }
    /// Loop of port `p` closed.
    pub const fn loop_closed(p: u16) -> u16 {
        1 << (8 + 2 * p)
    }
    /// Communication established on port `p`.
    pub const fn communication(p: u16) -> u16 {
        1 << (9 + 2 * p)
    }
}

/// ESC features (0x0008) bits.
pub mod features {
    /// Distributed clocks.
    pub const DC: u16 = 1 << 2;
    /// 64-bit DC time.
    pub const DC_64: u16 = 1 << 3;
    /// Fixed FMMU/SM configuration not required.
    pub const FMMU_BIT_OPERATION: u16 = 1 << 0;
    /// Enhanced DC sync activation (0x0981..0x0984 usable): SYNC0/SYNC1.
    pub const ENHANCED_DC_SYNC: u16 = 1 << 8;
}

/// DC activation (0x0981) bits.
pub mod dc {
    /// Cyclic operation enabled.
    pub const CYCLIC: u8 = 0x01;
    /// SYNC0 generation.
    pub const SYNC0: u8 = 0x02;
    /// SYNC1 generation.
    pub const SYNC1: u8 = 0x04;
}
