//! The object dictionary a CiA 402 drive shares on every fieldbus: the
//! CiA 301 communication objects and the CiA 402 drive objects it uses
//! (indices), the statusword and controlword bits, the standard commands
//! and the modes of operation (hardware.md §6.2 to §6.10). CANopen over
//! CAN and CoE over EtherCAT address the same objects. Named constants
//! only, plus [`describe_object`] for messages.

/// Object dictionary indices (CiA 301 communication profile and CiA 402).
pub mod obj {
    /// Device type (u32; low word 0x0192 for CiA 402).
    pub const DEVICE_TYPE: u16 = 0x1000;
    /// Error register (u8).
    pub const ERROR_REGISTER: u16 = 0x1001;
    /// Pre-defined error field (history).
    pub const ERROR_HISTORY: u16 = 0x1003;
    /// COB-ID SYNC.
    pub const COB_ID_SYNC: u16 = 0x1005;
    /// Communication cycle period (µs).
    pub const CYCLE_PERIOD: u16 = 0x1006;
    /// Manufacturer device name (string).
    pub const DEVICE_NAME: u16 = 0x1008;
    /// Manufacturer hardware version (string).
    pub const HW_VERSION: u16 = 0x1009;
    /// Manufacturer software version (string).
    pub const SW_VERSION: u16 = 0x100A;
    /// Store parameters.
    pub const STORE: u16 = 0x1010;
    /// Restore default parameters.
    pub const RESTORE: u16 = 0x1011;
    /// COB-ID EMCY.
    pub const COB_ID_EMCY: u16 = 0x1014;
    /// Inhibit time EMCY (100 µs).
    pub const EMCY_INHIBIT: u16 = 0x1015;
    /// Consumer heartbeat time (sub n: node << 16 | ms).
    pub const CONSUMER_HEARTBEAT: u16 = 0x1016;
    /// Producer heartbeat time (ms).
    pub const PRODUCER_HEARTBEAT: u16 = 0x1017;
    /// Identity (sub 1 vendor, 2 product, 3 revision, 4 serial).
    pub const IDENTITY: u16 = 0x1018;
    /// Synchronous counter overflow value.
    pub const SYNC_COUNTER_OVERFLOW: u16 = 0x1019;
    /// Error behaviour.
    pub const ERROR_BEHAVIOUR: u16 = 0x1029;
    /// SDO server parameter.
    pub const SDO_SERVER: u16 = 0x1200;
    /// RPDO1 communication parameter (RPDOn: + n − 1).
    pub const RPDO_COMM: u16 = 0x1400;
    /// RPDO1 mapping.
    pub const RPDO_MAP: u16 = 0x1600;
    /// TPDO1 communication parameter.
    pub const TPDO_COMM: u16 = 0x1800;
    /// TPDO1 mapping.
    pub const TPDO_MAP: u16 = 0x1A00;

    /// Abort connection option code (s16).
    pub const ABORT_CONNECTION_OPTION: u16 = 0x6007;
    /// Error code (u16).
    pub const ERROR_CODE: u16 = 0x603F;
    /// Controlword (u16).
    pub const CONTROLWORD: u16 = 0x6040;
    /// Statusword (u16).
    pub const STATUSWORD: u16 = 0x6041;
    /// Quick stop option code (s16).
    pub const QUICK_STOP_OPTION: u16 = 0x605A;
    /// Shutdown option code (s16).
    pub const SHUTDOWN_OPTION: u16 = 0x605B;
    /// Disable operation option code (s16).
    pub const DISABLE_OPERATION_OPTION: u16 = 0x605C;
    /// Halt option code (s16).
    pub const HALT_OPTION: u16 = 0x605D;
    /// Fault reaction option code (s16).
    pub const FAULT_REACTION_OPTION: u16 = 0x605E;
    /// Modes of operation (s8).
    pub const MODES_OF_OPERATION: u16 = 0x6060;
    /// Modes of operation display (s8).
    pub const MODES_DISPLAY: u16 = 0x6061;
    /// Position demand value (s32).
    pub const POSITION_DEMAND: u16 = 0x6062;
    /// Position actual internal value (s32).
    pub const POSITION_INTERNAL: u16 = 0x6063;
    /// Position actual value (s32).
    pub const POSITION_ACTUAL: u16 = 0x6064;
    /// Following error window (u32).
    pub const FOLLOWING_ERROR_WINDOW: u16 = 0x6065;
    /// Following error time-out (u16 ms).
    pub const FOLLOWING_ERROR_TIMEOUT: u16 = 0x6066;
    /// Position window (u32).
    pub const POSITION_WINDOW: u16 = 0x6067;
    /// Position window time (u16 ms).
    pub const POSITION_WINDOW_TIME: u16 = 0x6068;
    /// Velocity demand value (s32).
    pub const VELOCITY_DEMAND: u16 = 0x606B;
    /// Velocity actual value (s32).
    pub const VELOCITY_ACTUAL: u16 = 0x606C;
    /// Velocity window (u16).
    pub const VELOCITY_WINDOW: u16 = 0x606D;
    /// Velocity window time (u16 ms).
    pub const VELOCITY_WINDOW_TIME: u16 = 0x606E;
    /// Velocity threshold (u16).
    pub const VELOCITY_THRESHOLD: u16 = 0x606F;
    /// Velocity threshold time (u16 ms).
    pub const VELOCITY_THRESHOLD_TIME: u16 = 0x6070;
    /// Target torque (s16).
    pub const TARGET_TORQUE: u16 = 0x6071;
    /// Max torque (u16).
    pub const MAX_TORQUE: u16 = 0x6072;
    /// Torque actual value (s16).
    pub const TORQUE_ACTUAL: u16 = 0x6077;
    /// Current actual value (s16).
    pub const CURRENT_ACTUAL: u16 = 0x6078;
    /// DC-link voltage (u32 mV).
    pub const DC_LINK_VOLTAGE: u16 = 0x6079;
    /// Target position (s32).
    pub const TARGET_POSITION: u16 = 0x607A;
    /// Home offset (s32).
    pub const HOME_OFFSET: u16 = 0x607C;
    /// Software position limit (sub 1 min, sub 2 max).
    pub const SOFTWARE_LIMIT: u16 = 0x607D;
    /// Polarity (u8).
    pub const POLARITY: u16 = 0x607E;
    /// Max profile velocity (u32).
    pub const MAX_PROFILE_VELOCITY: u16 = 0x607F;
    /// Max motor speed (u32).
    pub const MAX_MOTOR_SPEED: u16 = 0x6080;
    /// Profile velocity (u32).
    pub const PROFILE_VELOCITY: u16 = 0x6081;
    /// Profile acceleration (u32).
    pub const PROFILE_ACCELERATION: u16 = 0x6083;
    /// Profile deceleration (u32).
    pub const PROFILE_DECELERATION: u16 = 0x6084;
    /// Quick stop deceleration (u32).
    pub const QUICK_STOP_DECELERATION: u16 = 0x6085;
    /// Homing method (s8).
    pub const HOMING_METHOD: u16 = 0x6098;
    /// Homing speeds (sub 1 switch search, sub 2 zero search).
    pub const HOMING_SPEEDS: u16 = 0x6099;
    /// Homing acceleration (u32).
    pub const HOMING_ACCELERATION: u16 = 0x609A;
    /// Position offset (s32).
    pub const POSITION_OFFSET: u16 = 0x60B0;
    /// Velocity offset (s32).
    pub const VELOCITY_OFFSET: u16 = 0x60B1;
    /// Torque offset (s16).
    pub const TORQUE_OFFSET: u16 = 0x60B2;
    /// Interpolation time period (sub 1 value u8, sub 2 index s8).
    pub const INTERPOLATION_PERIOD: u16 = 0x60C2;
    /// Following error actual value (s32).
    pub const FOLLOWING_ERROR_ACTUAL: u16 = 0x60F4;
    /// Digital inputs (u32).
    pub const DIGITAL_INPUTS: u16 = 0x60FD;
    /// Digital outputs (sub 1 outputs, sub 2 mask).
    pub const DIGITAL_OUTPUTS: u16 = 0x60FE;
    /// Target velocity (s32).
    pub const TARGET_VELOCITY: u16 = 0x60FF;
    /// Supported drive modes (u32 bit mask).
    pub const SUPPORTED_MODES: u16 = 0x6502;

    /// A PDO mapping entry: `index << 16 | sub << 8 | bits`.
    pub const fn map_entry(index: u16, sub: u8, bits: u8) -> u32 {
        (index as u32) << 16 | (sub as u32) << 8 | bits as u32
    }

    /// The CiA 402 profile number in 0x1000's low word.
    pub const PROFILE_402: u32 = 0x0192;
    /// COB-ID bit 31: the PDO (or EMCY, SYNC consumer) is not valid.
    pub const COB_INVALID: u32 = 0x8000_0000;
    /// COB-ID bit 30: no RTR allowed on this PDO.
    pub const COB_NO_RTR: u32 = 0x4000_0000;
    /// COB-ID bit 30 of 0x1005: this device produces SYNC.
    pub const COB_SYNC_PRODUCER: u32 = 0x4000_0000;
    /// 0x1010 signature "save".
    pub const SIGNATURE_SAVE: u32 = 0x6576_6173;
    /// 0x1011 signature "load".
    pub const SIGNATURE_LOAD: u32 = 0x6461_6F6C;
}

/// Statusword (0x6041) bits.
pub mod sw {
    /// Ready to switch on.
    pub const READY_TO_SWITCH_ON: u16 = 1 << 0;
    /// Switched on.
    pub const SWITCHED_ON: u16 = 1 << 1;
    /// Operation enabled.
    pub const OPERATION_ENABLED: u16 = 1 << 2;
    /// Fault.
    pub const FAULT: u16 = 1 << 3;
    /// Voltage enabled.
    pub const VOLTAGE_ENABLED: u16 = 1 << 4;
    /// Quick stop (0 = quick stop active).
    pub const QUICK_STOP: u16 = 1 << 5;
    /// Switch on disabled.
    pub const SWITCH_ON_DISABLED: u16 = 1 << 6;
    /// Warning.
    pub const WARNING: u16 = 1 << 7;
    /// Manufacturer specific.
    pub const MANUFACTURER_8: u16 = 1 << 8;
    /// Remote: the controlword is processed.
    pub const REMOTE: u16 = 1 << 9;
    /// Target reached (mode dependent).
    pub const TARGET_REACHED: u16 = 1 << 10;
    /// Internal limit active.
    pub const INTERNAL_LIMIT: u16 = 1 << 11;
    /// Mode specific: CSP/CSV "follows the command", PV speed zero, HM
    /// homing attained.
    pub const MODE_12: u16 = 1 << 12;
    /// Mode specific: CSP following error, HM homing error.
    pub const MODE_13: u16 = 1 << 13;

    /// The bits with their names (the `status.<name>` pins, displays).
    pub const NAMES: [(u16, &str); 13] = [
        (READY_TO_SWITCH_ON, "ready-to-switch-on"),
        (SWITCHED_ON, "switched-on"),
        (OPERATION_ENABLED, "operation-enabled"),
        (FAULT, "fault"),
        (VOLTAGE_ENABLED, "voltage-enabled"),
        (QUICK_STOP, "quick-stop"),
        (SWITCH_ON_DISABLED, "switch-on-disabled"),
        (WARNING, "warning"),
        (REMOTE, "remote"),
        (TARGET_REACHED, "target-reached"),
        (INTERNAL_LIMIT, "internal-limit"),
        (MODE_12, "mode-bit-12"),
        (MODE_13, "mode-bit-13"),
    ];
}

/// Controlword (0x6040) bits and the standard commands (§6.8).
pub mod cw {
    /// Switch on.
    pub const SWITCH_ON: u16 = 1 << 0;
    /// Enable voltage.
    pub const ENABLE_VOLTAGE: u16 = 1 << 1;
    /// Quick stop (0 = request quick stop).
    pub const QUICK_STOP: u16 = 1 << 2;
    /// Enable operation.
    pub const ENABLE_OPERATION: u16 = 1 << 3;
    /// Mode specific bit 4: HM start homing, PP new set-point.
    pub const MODE_4: u16 = 1 << 4;
    /// Mode specific bit 5: PP change set immediately.
    pub const CHANGE_SET_IMMEDIATELY: u16 = 1 << 5;
    /// Fault reset (on the 0 → 1 edge).
    pub const FAULT_RESET: u16 = 1 << 7;
    /// Halt.
    pub const HALT: u16 = 1 << 8;

    /// Shutdown (transitions 2, 6, 8).
    pub const SHUTDOWN: u16 = 0x0006;
    /// Switch on (3) and disable operation (5).
    pub const SWITCH_ON_CMD: u16 = 0x0007;
    /// Switch on + enable operation (3 + 4), enable operation (4, 16).
    pub const ENABLE_OPERATION_CMD: u16 = 0x000F;
    /// Disable voltage (7, 9, 10, 12).
    pub const DISABLE_VOLTAGE: u16 = 0x0000;
    /// Quick stop (7, 10, 11).
    pub const QUICK_STOP_CMD: u16 = 0x0002;
    /// Fault reset (15), on the edge.
    pub const FAULT_RESET_CMD: u16 = 0x0080;
}

/// Modes of operation (0x6060 / 0x6061) and their 0x6502 bits.
pub mod mode {
    /// Profile position.
    pub const PP: i8 = 1;
    /// Profile velocity.
    pub const PV: i8 = 3;
    /// Homing.
    pub const HM: i8 = 6;
    /// Cyclic synchronous position.
    pub const CSP: i8 = 8;
    /// Cyclic synchronous velocity.
    pub const CSV: i8 = 9;

    /// The 0x6502 bit of a mode, if it has one.
    pub const fn supported_bit(mode: i8) -> Option<u32> {
        match mode {
            1..=4 => Some(1 << (mode - 1)),
            6..=10 => Some(1 << (mode - 1)),
            _ => None,
        }
    }

    /// The mode's short name.
    pub fn name(mode: i8) -> &'static str {
        match mode {
            0 => "none",
            1 => "pp",
            2 => "vl",
            3 => "pv",
            4 => "pt",
            6 => "hm",
            7 => "ip",
            8 => "csp",
            9 => "csv",
            10 => "cst",
            m if m < 0 => "manufacturer",
            _ => "reserved",
        }
    }
}

/// A readable name of object `index:sub`, for messages: "0x1A00:01
/// (TPDO1 mapping entry 1)".
pub fn describe_object(index: u16, sub: u8) -> String {
    let name: Option<String> = match index {
        0x1000 => Some("device type".into()),
        0x1001 => Some("error register".into()),
        0x1003 => Some("error history".into()),
        0x1005 => Some("COB-ID SYNC".into()),
        0x1006 => Some("communication cycle period".into()),
        0x1008 => Some("device name".into()),
        0x1009 => Some("hardware version".into()),
        0x100A => Some("software version".into()),
        0x1010 => Some("store parameters".into()),
        0x1011 => Some("restore default parameters".into()),
        0x1014 => Some("COB-ID EMCY".into()),
        0x1015 => Some("EMCY inhibit time".into()),
        0x1016 => Some("consumer heartbeat time".into()),
        0x1017 => Some("producer heartbeat time".into()),
        0x1018 => Some(
            match sub {
                1 => "identity: vendor-ID",
                2 => "identity: product code",
                3 => "identity: revision",
                4 => "identity: serial number",
                _ => "identity",
            }
            .into(),
        ),
        0x1019 => Some("synchronous counter overflow".into()),
        0x1029 => Some("error behaviour".into()),
        0x1400..=0x15FF => Some(pdo_part("RPDO", index - 0x1400, "communication", sub)),
        0x1600..=0x17FF => Some(pdo_part("RPDO", index - 0x1600, "mapping", sub)),
        0x1800..=0x19FF => Some(pdo_part("TPDO", index - 0x1800, "communication", sub)),
        0x1A00..=0x1BFF => Some(pdo_part("TPDO", index - 0x1A00, "mapping", sub)),
        0x6007 => Some("abort connection option code".into()),
        0x603F => Some("error code".into()),
        0x6040 => Some("controlword".into()),
        0x6041 => Some("statusword".into()),
        0x605A => Some("quick stop option code".into()),
        0x605E => Some("fault reaction option code".into()),
        0x6060 => Some("modes of operation".into()),
        0x6061 => Some("modes of operation display".into()),
        0x6064 => Some("position actual value".into()),
        0x6065 => Some("following error window".into()),
        0x6066 => Some("following error time-out".into()),
        0x606C => Some("velocity actual value".into()),
        0x607A => Some("target position".into()),
        0x607C => Some("home offset".into()),
        0x607D => Some("software position limit".into()),
        0x6083 => Some("profile acceleration".into()),
        0x6084 => Some("profile deceleration".into()),
        0x6085 => Some("quick stop deceleration".into()),
        0x6098 => Some("homing method".into()),
        0x6099 => Some("homing speeds".into()),
        0x609A => Some("homing acceleration".into()),
        0x60C2 => Some("interpolation time period".into()),
        0x60FD => Some("digital inputs".into()),
        0x60FF => Some("target velocity".into()),
        0x6502 => Some("supported drive modes".into()),
        _ => None,
    };
    match name {
        Some(n) => format!("{index:#06X}:{sub:02X} ({n})").replacen("0X", "0x", 1),
        None => format!("{index:#06X}:{sub:02X}").replacen("0X", "0x", 1),
    }
}

fn pdo_part(kind: &str, n: u16, part: &str, sub: u8) -> String {
    match (part, sub) {
        ("mapping", 0) => format!("{kind}{} number of mapped objects", n + 1),
        ("mapping", s) => format!("{kind}{} mapping entry {s}", n + 1),
        (_, 1) => format!("{kind}{} COB-ID", n + 1),
        (_, 2) => format!("{kind}{} transmission type", n + 1),
        (_, 3) => format!("{kind}{} inhibit time", n + 1),
        (_, 5) => format!("{kind}{} event timer", n + 1),
        (_, 6) => format!("{kind}{} SYNC start value", n + 1),
        _ => format!("{kind}{} {part} parameter", n + 1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_bits() {
        assert_eq!(mode::supported_bit(mode::CSP), Some(1 << 7));
        assert_eq!(mode::supported_bit(mode::PV), Some(1 << 2));
        assert_eq!(mode::supported_bit(mode::HM), Some(1 << 5));
        assert_eq!(mode::supported_bit(5), None);
        assert_eq!(obj::map_entry(0x6040, 0, 16), 0x6040_0010);
    }

    #[test]
    fn object_names() {
        assert_eq!(
            describe_object(0x1A00, 1),
            "0x1A00:01 (TPDO1 mapping entry 1)"
        );
        assert_eq!(describe_object(0x1000, 0), "0x1000:00 (device type)");
        assert_eq!(describe_object(0x2001, 3), "0x2001:03");
    }
}
