//! The Modbus command file the hm2_modbus burst test and the modbus
//! bench share: device 7, holding registers 2 and 3 read into two U32
//! pins, registers 10 and 11 written from two, at 115200 baud.
//! (Included by the bench with `#[path]`.)

use hostmot2::modbus::mbccb::{format, Command, HalType, Mbccb, ModbusType, PinSpec};

pub fn u32_pin(name: &str, regofs: u8) -> PinSpec {
    PinSpec {
        name: name.into(),
        htype: HalType::U32,
        mtype: ModbusType(0),
        flags: 0,
        regofs,
    }
}

/// Reads holding registers 2 and 3 of device 7, writes registers 10 and
/// 11 from two pins.
pub fn file() -> Mbccb {
    let cmd = |func: u8, addr: u16, pins: Vec<PinSpec>| Command {
        mbid: 7,
        func,
        flags: 0,
        addr,
        regcnt: 2,
        interval_us: 0,
        timeout_us: 50_000,
        pins,
    };
    Mbccb {
        baudrate: 115_200,
        format: format::PARITY_EN,
        txdelay: 0,
        rxdelay: 0,
        drvdelay: 0,
        icdelay: 0,
        inits: Vec::new(),
        commands: vec![
            cmd(3, 2, vec![u32_pin("in.a", 0), u32_pin("in.b", 1)]),
            cmd(16, 10, vec![u32_pin("out.a", 0), u32_pin("out.b", 1)]),
        ],
        warnings: Vec::new(),
    }
}
