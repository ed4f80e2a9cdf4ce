//! The protocol maps as named constants: Modbus RTU function and
//! exception codes, the Huanyang GT-series register map, and the codes of
//! the older Huanyang (HY) protocol that LinuxCNC's `hy_vfd` speaks
//! (hardware.md §7.3).

/// Modbus RTU (the public function codes this crate uses).
pub mod modbus {
    /// Read coils: start address, count (1..=2000); the reply packs the
    /// bits eight to a byte, lowest address in bit 0.
    pub const READ_COILS: u8 = 0x01;
    /// Read discrete inputs: as [`READ_COILS`].
    pub const READ_DISCRETE_INPUTS: u8 = 0x02;
    /// Read holding registers: start address, count (1..=125).
    pub const READ_HOLDING_REGISTERS: u8 = 0x03;
    /// Read input registers: start address, count (1..=125).
    pub const READ_INPUT_REGISTERS: u8 = 0x04;
    /// Write single register: address, value; the reply echoes both.
    pub const WRITE_SINGLE_REGISTER: u8 = 0x06;
    /// Write single coil: address, 0xFF00 (on) or 0x0000 (off); the reply
    /// echoes both.
    pub const WRITE_SINGLE_COIL: u8 = 0x05;
    /// Write multiple coils: address, count (1..=1968), byte count, the
    /// bits packed as [`READ_COILS`] replies them; the reply carries
    /// address and count.
    pub const WRITE_MULTIPLE_COILS: u8 = 0x0F;
    /// Write multiple registers: address, count (1..=123), byte count,
    /// values; the reply carries address and count.
    pub const WRITE_MULTIPLE_REGISTERS: u8 = 0x10;
    /// Set in the function code of an exception reply.
    pub const EXCEPTION_FLAG: u8 = 0x80;
    /// Most registers one read may ask for.
    pub const MAX_READ_COUNT: u16 = 125;
    /// Most bits one read of coils or discrete inputs may ask for.
    pub const MAX_READ_BITS: u16 = 2000;
    /// Most coils one multiple write may carry.
    pub const MAX_WRITE_BITS: u16 = 1968;
    /// The coil value of "on" in a single-coil write.
    pub const COIL_ON: u16 = 0xFF00;
    /// Most registers one multiple write may carry.
    pub const MAX_WRITE_COUNT: u16 = 123;
    /// The broadcast address: every slave obeys, none replies.
    pub const BROADCAST: u8 = 0;
    /// Highest unicast slave address.
    pub const MAX_SLAVE: u8 = 247;
    /// Longest RTU frame on the line (address, PDU of up to 253 bytes, CRC).
    pub const MAX_FRAME: usize = 256;

    /// Exception codes (the byte after `function | 0x80`).
    pub mod exception {
        /// The function code is not supported.
        pub const ILLEGAL_FUNCTION: u8 = 0x01;
        /// The register address is not valid.
        pub const ILLEGAL_DATA_ADDRESS: u8 = 0x02;
        /// A value in the request is not valid.
        pub const ILLEGAL_DATA_VALUE: u8 = 0x03;
        /// The slave failed while doing it.
        pub const SERVER_DEVICE_FAILURE: u8 = 0x04;
        /// Accepted, will take long: poll later.
        pub const ACKNOWLEDGE: u8 = 0x05;
        /// Busy with a long command: retry later.
        pub const SERVER_DEVICE_BUSY: u8 = 0x06;
        /// Memory parity error in a file record.
        pub const MEMORY_PARITY_ERROR: u8 = 0x08;
        /// A gateway found no path to the target.
        pub const GATEWAY_PATH_UNAVAILABLE: u8 = 0x0A;
        /// A gateway's target did not answer.
        pub const GATEWAY_TARGET_FAILED: u8 = 0x0B;
    }
}

/// The Huanyang GT series over standard Modbus (LinuxCNC's `hy_gt_vfd`).
pub mod gt {
    /// Control command register (write single register).
    pub const CONTROL: u16 = 0x1000;
    /// Control value: run forward.
    pub const RUN_FORWARD: u16 = 1;
    /// Control value: run reverse.
    pub const RUN_REVERSE: u16 = 2;
    /// Control value: jog forward.
    pub const JOG_FORWARD: u16 = 3;
    /// Control value: jog reverse.
    pub const JOG_REVERSE: u16 = 4;
    /// Control value: stop (ramp down).
    pub const STOP: u16 = 5;
    /// Control value: coast to a stop.
    pub const COAST_STOP: u16 = 6;
    /// Control value: reset a fault.
    pub const FAULT_RESET: u16 = 7;
    /// Frequency command, in 1/100 % of the maximum frequency (0..=10000).
    pub const FREQUENCY: u16 = 0x2000;
    /// Full scale of [`FREQUENCY`]: 100.00 %.
    pub const FREQUENCY_FULL_SCALE: u16 = 10_000;
    /// Output frequency, 0.01 Hz.
    pub const OUTPUT_FREQUENCY: u16 = 0x3000;
    /// Frequency set point, 0.01 Hz.
    pub const SET_FREQUENCY: u16 = 0x3001;
    /// DC bus voltage, 0.1 V.
    pub const DC_BUS_VOLTAGE: u16 = 0x3002;
    /// Output voltage, V.
    pub const OUTPUT_VOLTAGE: u16 = 0x3003;
    /// Output current, A.
    pub const OUTPUT_CURRENT: u16 = 0x3004;
    /// Motor speed, rpm.
    pub const SPEED: u16 = 0x3005;
    /// Output power, W.
    pub const OUTPUT_POWER: u16 = 0x3006;
    /// Input terminal states.
    pub const INPUT_TERMINAL: u16 = 0x300A;
    /// Output terminal states.
    pub const OUTPUT_TERMINAL: u16 = 0x300B;
    /// Analog input 1.
    pub const AI1: u16 = 0x300C;
    /// Analog input 2.
    pub const AI2: u16 = 0x300D;
    /// HDI pulse input frequency.
    pub const HDI_FREQUENCY: u16 = 0x3010;
    /// External counter.
    pub const EXTERNAL_COUNTER: u16 = 0x3014;
    /// Fault code (0: no fault).
    pub const FAULT_INFO: u16 = 0x5000;
}

/// The Huanyang HY protocol: Modbus RTU framing and CRC, its own
/// function codes; after address and function every frame carries a
/// length byte, then that many data bytes.
pub mod hy {
    /// Read a function parameter PDnnn: length 3, PD number, 0, 0.
    pub const FUNCTION_READ: u8 = 0x01;
    /// Write a function parameter: length 3, PD number, value (big-endian).
    pub const FUNCTION_WRITE: u8 = 0x02;
    /// Write the control word CNTR: length 1, command; the reply carries CNST.
    pub const WRITE_CONTROL: u8 = 0x03;
    /// Read a status value: length 1, index; reply length 3, index, value.
    pub const READ_STATUS: u8 = 0x04;
    /// Write the frequency: length 2, 0.01 Hz (big-endian).
    pub const WRITE_FREQUENCY: u8 = 0x05;

    /// CNTR command: run forward.
    pub const CNTR_RUN_FORWARD: u8 = 0x01;
    /// CNTR command: run reverse.
    pub const CNTR_RUN_REVERSE: u8 = 0x11;
    /// CNTR command: stop.
    pub const CNTR_STOP: u8 = 0x08;

    /// CNST bit: run command active.
    pub const CNST_RUN: u8 = 0x01;
    /// CNST bit: jog command active.
    pub const CNST_JOG: u8 = 0x02;
    /// CNST bit: commanded direction is reverse.
    pub const CNST_COMMAND_RF: u8 = 0x04;
    /// CNST bit: the output is running.
    pub const CNST_RUNNING: u8 = 0x08;
    /// CNST bit: jogging.
    pub const CNST_JOGGING: u8 = 0x10;
    /// CNST bit: running in reverse.
    pub const CNST_RUNNING_RF: u8 = 0x20;
    /// CNST bit: braking.
    pub const CNST_BRAKING: u8 = 0x40;
    /// CNST bit: track start.
    pub const CNST_TRACK_START: u8 = 0x80;

    /// Status index: frequency set point, 0.01 Hz.
    pub const STATUS_SET_F: u8 = 0;
    /// Status index: output frequency, 0.01 Hz.
    pub const STATUS_OUT_F: u8 = 1;
    /// Status index: output current, 0.1 A.
    pub const STATUS_OUT_A: u8 = 2;
    /// Status index: rotation speed, rpm.
    pub const STATUS_ROTT: u8 = 3;
    /// Status index: DC bus voltage, V.
    pub const STATUS_DCV: u8 = 4;
    /// Status index: AC output voltage, V.
    pub const STATUS_ACV: u8 = 5;
    /// Status index: counter.
    pub const STATUS_CONT: u8 = 6;
    /// Status index: temperature, °C.
    pub const STATUS_TMP: u8 = 7;
    /// Number of status indices.
    pub const STATUS_COUNT: u8 = 8;

    /// PD001: source of run commands (2: communication port).
    pub const PD_RUN_SOURCE: u8 = 1;
    /// PD002: source of the operating frequency (2: communication port).
    pub const PD_FREQUENCY_SOURCE: u8 = 2;
    /// PD004: base frequency, 0.01 Hz.
    pub const PD_BASE_FREQUENCY: u8 = 4;
    /// PD005: maximum operating frequency, 0.01 Hz.
    pub const PD_MAX_FREQUENCY: u8 = 5;
    /// PD011: frequency lower limit, 0.01 Hz.
    pub const PD_MIN_FREQUENCY: u8 = 11;
    /// PD141: rated motor voltage, 0.1 V.
    pub const PD_MOTOR_VOLTAGE: u8 = 141;
    /// PD142: rated motor current, 0.1 A.
    pub const PD_MOTOR_CURRENT: u8 = 142;
    /// PD143: number of motor poles.
    pub const PD_MOTOR_POLES: u8 = 143;
    /// PD144: rated motor speed at 50 Hz, rpm.
    pub const PD_MOTOR_RPM_AT_50HZ: u8 = 144;
    /// PD163: communication address.
    pub const PD_ADDRESS: u8 = 163;
    /// PD164: baud rate code.
    pub const PD_BAUD: u8 = 164;
    /// PD165: data format code (3: 8N1 RTU).
    pub const PD_FORMAT: u8 = 165;
    /// Highest PD number `--regdump` prints.
    pub const PD_LAST: u8 = 183;
}
