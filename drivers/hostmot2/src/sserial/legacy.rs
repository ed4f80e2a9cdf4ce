//! The two remote cards that predate self-description, the 8I20 drive
//! and the 7I64 I/O card (hostmot2-more.md 2.3): after a setup start they
//! name themselves but point at no tables (PTOC and GTOC 0), so their
//! process data and globals are known by name, as LinuxCNC knows them.
//!
//! The 8I20 (a 2.2 kW three-phase drive) takes a rotor angle and a
//! current command and reports its card temperature, bus voltage and two
//! 16-bit words of status and fault bits; its current scale is the
//! card's own maximum current, read from its memory at
//! [`EIGHT_I20_MAX_CURRENT_AT`] (in 0.01 A) at load. The 7I64 has 24
//! outputs, 24 inputs and two analog inputs.

use super::records::{data_type as t, dir, DataRecord};

/// Where an 8I20 keeps its maximum current (16 bits, 0.01 A) in RAM.
pub const EIGHT_I20_MAX_CURRENT_AT: u16 = 0x8E8;
/// The 8I20's name after a setup start (interface 1).
pub const EIGHT_I20: [u8; 4] = *b"8I20";
/// The 7I64's name after a setup start (interface 1).
pub const SEVEN_I64: [u8; 4] = *b"7I64";
/// Index of the 8I20's `current` record in [`process_data`].
pub const EIGHT_I20_CURRENT: usize = 1;

/// The tables of a card that does not describe itself.
#[derive(Debug, Clone, PartialEq)]
pub struct BuiltIn {
    /// Process data, in wire order.
    pub process: Vec<DataRecord>,
    /// Globals, with their addresses in the card's memory.
    pub globals: Vec<DataRecord>,
}

fn rec(
    bits: u8,
    ty: u8,
    d: u8,
    range: (f32, f32),
    addr: u16,
    unit: &str,
    name: &str,
) -> DataRecord {
    DataRecord {
        bits,
        data_type: ty,
        dir: d,
        min: range.0,
        max: range.1,
        addr,
        unit: unit.into(),
        name: name.into(),
    }
}

fn flag(name: &str) -> DataRecord {
    rec(1, t::BOOLEAN, dir::IN, (0.0, 0.0), 0, "none", name)
}

fn pad(bits: u8) -> DataRecord {
    rec(bits, t::PAD, dir::IN, (0.0, 0.0), 0, "pad", "pad")
}

/// The 8I20's status word, bit 0 first (`None` = unused bit).
pub const EIGHT_I20_STATUS: [Option<&str>; 16] = [
    Some("current-lim"),
    Some("brake-on"),
    Some("brake-old"),
    Some("bus-underv"),
    Some("wd-reset"),
    Some("sw-reset"),
    Some("ext-reset"),
    None,
    Some("no-enable"),
    Some("pid-on"),
    None,
    None,
    None,
    None,
    None,
    None,
];

/// The 8I20's fault word, bit 0 first (`None` = unused bit).
pub const EIGHT_I20_FAULT: [Option<&str>; 16] = [
    Some("watchdog"),
    Some("no-enable"),
    Some("overtemp"),
    None,
    Some("overcurrent"),
    Some("U-current"),
    Some("V-current"),
    Some("W-current"),
    Some("bus-underv"),
    Some("bus-high"),
    Some("bus-overv"),
    Some("module"),
    None,
    None,
    Some("overrun"),
    Some("framingr"),
];

/// One bit record per named bit of `word` (`<prefix>.<name>`), runs of
/// unused bits as padding.
fn bit_word(prefix: &str, word: &[Option<&str>; 16], out: &mut Vec<DataRecord>) {
    let mut gap = 0u8;
    for bit in word {
        match bit {
            Some(name) => {
                if gap > 0 {
                    out.push(pad(gap));
                    gap = 0;
                }
                out.push(flag(&format!("{prefix}.{name}")));
            }
            None => gap += 1,
        }
    }
    if gap > 0 {
        out.push(pad(gap));
    }
}

fn eight_i20() -> BuiltIn {
    let mut process = vec![
        rec(16, t::UNSIGNED, dir::OUT, (0.0, 1.0), 0, "degrees", "angle"),
        rec(16, t::SIGNED, dir::OUT, (-10.0, 10.0), 0, "amps", "current"),
        rec(
            16,
            t::UNSIGNED,
            dir::IN,
            (0.0, 65535.0),
            0,
            "Deg C",
            "card-temp",
        ),
        rec(
            16,
            t::UNSIGNED,
            dir::IN,
            (0.0, 655.35),
            0,
            "volts",
            "bus-voltage",
        ),
    ];
    bit_word("status", &EIGHT_I20_STATUS, &mut process);
    bit_word("fault", &EIGHT_I20_FAULT, &mut process);
    let nv =
        |addr, max, unit, name| rec(16, t::NV_UNSIGNED, dir::OUT, (0.0, max), addr, unit, name);
    let globals = vec![
        rec(
            16,
            t::UNSIGNED,
            dir::IN,
            (0.0, 0.0),
            2164,
            "none",
            "swrevision",
        ),
        rec(
            32,
            t::UNSIGNED,
            dir::IN,
            (0.0, 0.0),
            2344,
            "none",
            "unitnumber",
        ),
        nv(2, 32.768, "amps", "nvmaxcurrent"),
        nv(36, 0.0, "volts", "nvbusundervmax"),
        nv(34, 0.0, "volts", "nvbusundervmin"),
        nv(38, 0.0, "volts", "nvbusoverv"),
        nv(40, 0.0, "volts", "nvbrakeonv"),
        nv(42, 0.0, "volts", "nvbrakeoffv"),
        nv(6, 0.0, "bps", "nvrembaudrate"),
        nv(10, 0.0, "none", "nvkqp"),
        nv(14, 0.0, "none", "nvkqihi"),
        nv(12, 0.0, "none", "nvkqilo"),
        nv(16, 0.0, "none", "nvkqil"),
        nv(18, 0.0, "none", "nvkdp"),
        nv(22, 0.0, "none", "nvkdihi"),
        nv(20, 0.0, "none", "nvkdilo"),
        nv(24, 0.0, "none", "nvkdil"),
    ];
    BuiltIn { process, globals }
}

fn seven_i64() -> BuiltIn {
    BuiltIn {
        process: vec![
            rec(24, t::BITS, dir::OUT, (0.0, 0.0), 0, "none", "output"),
            rec(24, t::BITS, dir::IN, (0.0, 0.0), 0, "none", "input"),
            pad(8),
            rec(16, t::UNSIGNED, dir::IN, (0.0, 3.3), 0, "volts", "analog0"),
            rec(16, t::UNSIGNED, dir::IN, (0.0, 3.3), 0, "volts", "analog1"),
        ],
        globals: Vec::new(),
    }
}

/// The tables of the card named `raw_name` (interface 1 after a setup
/// start) if it is one that does not describe itself.
pub fn built_in(raw_name: u32) -> Option<BuiltIn> {
    match raw_name.to_le_bytes() {
        EIGHT_I20 => Some(eight_i20()),
        SEVEN_I64 => Some(seven_i64()),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn widths(b: &BuiltIn) -> (u32, u32) {
        let sum = |f: fn(&DataRecord) -> bool| {
            b.process
                .iter()
                .filter(|r| f(r))
                .map(|r| r.bits as u32)
                .sum()
        };
        (sum(DataRecord::is_in), sum(DataRecord::is_out))
    }

    #[test]
    fn the_8i20_moves_64_bits_in_and_32_out() {
        let b = built_in(u32::from_le_bytes(EIGHT_I20)).unwrap();
        assert_eq!(widths(&b), (64, 32));
        assert_eq!(b.process[EIGHT_I20_CURRENT].name, "current");
        let names: Vec<&str> = b.process.iter().map(|r| r.name.as_str()).collect();
        assert!(names.contains(&"fault.U-current"), "{names:?}");
        assert!(names.contains(&"status.pid-on"), "{names:?}");
        // The fault word starts at bit 16 of the second input register.
        let before: u32 = b
            .process
            .iter()
            .take_while(|r| r.name != "fault.watchdog")
            .filter(|r| r.is_in())
            .map(|r| r.bits as u32)
            .sum();
        assert_eq!(before, 48);
        assert!(b
            .globals
            .iter()
            .any(|g| g.name == "nvbusoverv" && g.addr == 38));
    }

    #[test]
    fn the_7i64_and_unknown_names() {
        let b = built_in(u32::from_le_bytes(SEVEN_I64)).unwrap();
        assert_eq!(widths(&b), (64, 24));
        assert!(built_in(u32::from_le_bytes(*b"7I76")).is_none());
        assert!(built_in(0).is_none());
    }
}
