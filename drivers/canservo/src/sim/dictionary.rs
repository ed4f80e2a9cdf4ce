//! The simulated drive's object dictionary contents: the CiA 301
//! communication objects and the CiA 402 objects of hardware.md §6.6 and
//! §6.10, with their types, access, mappability and defaults. The PDO
//! defaults are CiA 402's predefined mappings (§6.7), all four PDOs of
//! each direction valid with transmission type 255, as many drives ship.

use super::od::{Access::*, Od, I16, I32, I8, U16, U32, U8};
use crate::regs::{mode, obj};

/// The identity and name a simulated drive reports.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Identity {
    /// 0x1000 device type.
    pub device_type: u32,
    /// 0x1018:1.
    pub vendor: u32,
    /// 0x1018:2.
    pub product: u32,
    /// 0x1018:3.
    pub revision: u32,
    /// 0x1018:4.
    pub serial: u32,
    /// 0x1008.
    pub name: String,
}

impl Identity {
    /// The simulator's identity for `node`: a CiA 402 servo drive
    /// (0x00020192), serial number = node.
    pub fn simulated(node: u8) -> Identity {
        Identity {
            device_type: 0x0002_0192,
            vendor: 0x0048_414C, // "HAL"
            product: 0x0000_0402,
            revision: 0x0001_0000,
            serial: u32::from(node),
            name: "canservo simulated CiA 402 servo drive".into(),
        }
    }
}

/// The modes the simulated drive supports (0x6502): PV, HM, CSP, CSV.
pub const SUPPORTED_MODES: u32 =
    (1 << (mode::PV - 1)) | (1 << (mode::HM - 1)) | (1 << (mode::CSP - 1)) | (1 << (mode::CSV - 1));

/// The dictionary of a drive with node id `node`.
pub fn build(node: u8, id: &Identity) -> Od {
    let n = i64::from(node);
    let mut od = Od::new();
    communication(&mut od, n, id);
    pdos(&mut od, n);
    device_profile(&mut od);
    od
}

/// The communication profile (0x1000..0x1FFF) but the PDOs.
fn communication(od: &mut Od, n: i64, id: &Identity) {
    od.add(
        obj::DEVICE_TYPE,
        0,
        U32,
        Const,
        false,
        i64::from(id.device_type),
    );
    od.add(obj::ERROR_REGISTER, 0, U8, Ro, true, 0);
    od.add(obj::ERROR_HISTORY, 0, U8, Rw, false, 0);
    for s in 1..=8 {
        od.add(obj::ERROR_HISTORY, s, U32, Ro, false, 0);
    }
    od.add(obj::COB_ID_SYNC, 0, U32, Rw, false, 0x80);
    od.add(obj::CYCLE_PERIOD, 0, U32, Rw, false, 0);
    od.add_str(obj::DEVICE_NAME, 0, Const, &id.name);
    od.add_str(obj::HW_VERSION, 0, Const, "sim-1");
    od.add_str(
        obj::SW_VERSION,
        0,
        Const,
        concat!("canservo-sim ", env!("CARGO_PKG_VERSION")),
    );
    od.add(obj::STORE, 0, U8, Const, false, 1);
    od.add(obj::STORE, 1, U32, Rw, false, 1);
    od.add(obj::RESTORE, 0, U8, Const, false, 1);
    od.add(obj::RESTORE, 1, U32, Rw, false, 1);
    od.add(obj::COB_ID_EMCY, 0, U32, Rw, false, 0x80 + n);
    od.add(obj::EMCY_INHIBIT, 0, U16, Rw, false, 0);
    od.add(obj::CONSUMER_HEARTBEAT, 0, U8, Const, false, 4);
    for s in 1..=4 {
        od.add(obj::CONSUMER_HEARTBEAT, s, U32, Rw, false, 0);
    }
    od.add(obj::PRODUCER_HEARTBEAT, 0, U16, Rw, false, 0);
    od.add(obj::IDENTITY, 0, U8, Const, false, 4);
    od.add(obj::IDENTITY, 1, U32, Ro, false, i64::from(id.vendor));
    od.add(obj::IDENTITY, 2, U32, Ro, false, i64::from(id.product));
    od.add(obj::IDENTITY, 3, U32, Ro, false, i64::from(id.revision));
    od.add(obj::IDENTITY, 4, U32, Ro, false, i64::from(id.serial));
    od.add(obj::SYNC_COUNTER_OVERFLOW, 0, U8, Rw, false, 0);
    od.add(obj::ERROR_BEHAVIOUR, 0, U8, Const, false, 1);
    od.add(obj::ERROR_BEHAVIOUR, 1, U8, Rw, false, 0);
    od.limit(obj::ERROR_BEHAVIOUR, 1, 0, 2);
    od.add(obj::SDO_SERVER, 0, U8, Const, false, 2);
    od.add(obj::SDO_SERVER, 1, U32, Ro, false, 0x600 + n);
    od.add(obj::SDO_SERVER, 2, U32, Ro, false, 0x580 + n);
}

/// Four receive and four transmit PDOs with their default mappings.
fn pdos(od: &mut Od, n: i64) {
    let rpdo_maps: [&[u32]; 4] = [
        &[obj::map_entry(0x6040, 0, 16)],
        &[obj::map_entry(0x6040, 0, 16), obj::map_entry(0x6060, 0, 8)],
        &[obj::map_entry(0x6040, 0, 16), obj::map_entry(0x607A, 0, 32)],
        &[obj::map_entry(0x6040, 0, 16), obj::map_entry(0x60FF, 0, 32)],
    ];
    let tpdo_maps: [&[u32]; 4] = [
        &[obj::map_entry(0x6041, 0, 16)],
        &[obj::map_entry(0x6041, 0, 16), obj::map_entry(0x6061, 0, 8)],
        &[obj::map_entry(0x6041, 0, 16), obj::map_entry(0x6064, 0, 32)],
        &[obj::map_entry(0x6041, 0, 16), obj::map_entry(0x606C, 0, 32)],
    ];
    for p in 0..4u16 {
        let (rc, rm, tc, tm) = (
            obj::RPDO_COMM + p,
            obj::RPDO_MAP + p,
            obj::TPDO_COMM + p,
            obj::TPDO_MAP + p,
        );
        od.add(rc, 0, U8, Const, false, 2);
        od.add(rc, 1, U32, Rw, false, i64::from(0x200 + 0x100 * p) + n);
        od.add(rc, 2, U8, Rw, false, 255);
        od.add(tc, 0, U8, Const, false, 6);
        od.add(tc, 1, U32, Rw, false, i64::from(0x180 + 0x100 * p) + n);
        od.add(tc, 2, U8, Rw, false, 255);
        od.add(tc, 3, U16, Rw, false, 0);
        od.add(tc, 5, U16, Rw, false, 0);
        od.add(tc, 6, U8, Rw, false, 0);
        for (index, maps) in [(rm, rpdo_maps[p as usize]), (tm, tpdo_maps[p as usize])] {
            od.add(index, 0, U8, Rw, false, maps.len() as i64);
            od.limit(index, 0, 0, 8);
            for s in 1..=8u8 {
                let v = maps.get(usize::from(s) - 1).copied().unwrap_or(0);
                od.add(index, s, U32, Rw, false, i64::from(v));
            }
        }
    }
}

/// The CiA 402 device profile (0x6000..).
fn device_profile(od: &mut Od) {
    od.add(obj::ABORT_CONNECTION_OPTION, 0, I16, Rw, false, 1);
    od.limit(obj::ABORT_CONNECTION_OPTION, 0, 0, 3);
    od.add(obj::ERROR_CODE, 0, U16, Ro, true, 0);
    od.add(obj::CONTROLWORD, 0, U16, Rw, true, 0);
    od.add(obj::STATUSWORD, 0, U16, Ro, true, 0);
    for (index, default) in [
        (obj::QUICK_STOP_OPTION, 2),
        (obj::SHUTDOWN_OPTION, 0),
        (obj::DISABLE_OPERATION_OPTION, 1),
        (obj::HALT_OPTION, 1),
        (obj::FAULT_REACTION_OPTION, 2),
    ] {
        od.add(index, 0, I16, Rw, false, default);
    }
    od.limit(obj::QUICK_STOP_OPTION, 0, 0, 8);
    od.limit(obj::SHUTDOWN_OPTION, 0, 0, 1);
    od.limit(obj::DISABLE_OPERATION_OPTION, 0, 0, 1);
    od.limit(obj::HALT_OPTION, 0, 1, 4);
    od.limit(obj::FAULT_REACTION_OPTION, 0, 0, 4);
    od.add(obj::MODES_OF_OPERATION, 0, I8, Rw, true, 0);
    od.add(obj::MODES_DISPLAY, 0, I8, Ro, true, 0);
    for index in [
        obj::POSITION_DEMAND,
        obj::POSITION_INTERNAL,
        obj::POSITION_ACTUAL,
        obj::VELOCITY_DEMAND,
        obj::VELOCITY_ACTUAL,
        obj::FOLLOWING_ERROR_ACTUAL,
    ] {
        od.add(index, 0, I32, Ro, true, 0);
    }
    od.add(obj::FOLLOWING_ERROR_WINDOW, 0, U32, Rw, false, 20_000);
    od.add(obj::FOLLOWING_ERROR_TIMEOUT, 0, U16, Rw, false, 10);
    od.add(obj::POSITION_WINDOW, 0, U32, Rw, false, 100);
    od.add(obj::POSITION_WINDOW_TIME, 0, U16, Rw, false, 10);
    od.add(obj::VELOCITY_WINDOW, 0, U16, Rw, false, 1000);
    od.add(obj::VELOCITY_WINDOW_TIME, 0, U16, Rw, false, 10);
    od.add(obj::VELOCITY_THRESHOLD, 0, U16, Rw, false, 100);
    od.add(obj::VELOCITY_THRESHOLD_TIME, 0, U16, Rw, false, 10);
    od.add(obj::TARGET_TORQUE, 0, I16, Rw, true, 0);
    od.add(obj::MAX_TORQUE, 0, U16, Rw, false, 3000);
    od.add(obj::TORQUE_ACTUAL, 0, I16, Ro, true, 0);
    od.add(obj::CURRENT_ACTUAL, 0, I16, Ro, true, 0);
    od.add(obj::DC_LINK_VOLTAGE, 0, U32, Ro, true, 48_000);
    od.add(obj::TARGET_POSITION, 0, I32, Rw, true, 0);
    od.add(obj::HOME_OFFSET, 0, I32, Rw, false, 0);
    od.add(obj::SOFTWARE_LIMIT, 0, U8, Const, false, 2);
    od.add(obj::SOFTWARE_LIMIT, 1, I32, Rw, false, 0);
    od.add(obj::SOFTWARE_LIMIT, 2, I32, Rw, false, 0);
    od.add(obj::POLARITY, 0, U8, Rw, false, 0);
    od.add(obj::MAX_PROFILE_VELOCITY, 0, U32, Rw, false, 500_000);
    od.add(obj::MAX_MOTOR_SPEED, 0, U32, Rw, false, 500_000);
    od.add(obj::PROFILE_VELOCITY, 0, U32, Rw, false, 100_000);
    od.add(obj::PROFILE_ACCELERATION, 0, U32, Rw, false, 1_000_000);
    od.add(obj::PROFILE_DECELERATION, 0, U32, Rw, false, 1_000_000);
    od.add(obj::QUICK_STOP_DECELERATION, 0, U32, Rw, false, 10_000_000);
    od.add(obj::HOMING_METHOD, 0, I8, Rw, false, 35);
    od.add(obj::HOMING_SPEEDS, 0, U8, Const, false, 2);
    od.add(obj::HOMING_SPEEDS, 1, U32, Rw, false, 20_000);
    od.add(obj::HOMING_SPEEDS, 2, U32, Rw, false, 2_000);
    od.add(obj::HOMING_ACCELERATION, 0, U32, Rw, false, 1_000_000);
    od.add(obj::POSITION_OFFSET, 0, I32, Rw, true, 0);
    od.add(obj::VELOCITY_OFFSET, 0, I32, Rw, true, 0);
    od.add(obj::TORQUE_OFFSET, 0, I16, Rw, true, 0);
    od.add(obj::INTERPOLATION_PERIOD, 0, U8, Const, false, 2);
    od.add(obj::INTERPOLATION_PERIOD, 1, U8, Rw, false, 1);
    od.add(obj::INTERPOLATION_PERIOD, 2, I8, Rw, false, -3);
    od.limit(obj::INTERPOLATION_PERIOD, 2, -6, 0);
    od.add(obj::DIGITAL_INPUTS, 0, U32, Ro, true, 0);
    od.add(obj::DIGITAL_OUTPUTS, 0, U8, Const, false, 2);
    od.add(obj::DIGITAL_OUTPUTS, 1, U32, Rw, true, 0);
    od.add(obj::DIGITAL_OUTPUTS, 2, U32, Rw, false, 0);
    od.add(obj::TARGET_VELOCITY, 0, I32, Rw, true, 0);
    od.add(
        obj::SUPPORTED_MODES,
        0,
        U32,
        Const,
        false,
        i64::from(SUPPORTED_MODES),
    );
}
