//! The broken register images of LinuxCNC's `hm2_test` driver
//! (hardware.md 5.8, hostmot2-more.md 4): test pattern N (0 to 14) is a
//! board whose registration must fail at one particular check.

use crate::image::WINDOW_WORDS;
use crate::llio::Llio;
use crate::regs::{self, idrom as f};

/// Patterns that exist.
pub const PATTERNS: std::ops::RangeInclusive<u32> = 0..=14;

/// The `hm2_test` board of pattern `n`: its llio and register image, or
/// `None` for an unknown pattern.
pub fn pattern(n: u32) -> Option<(Llio, Vec<u32>)> {
    if !PATTERNS.contains(&n) {
        return None;
    }
    let mut llio = Llio {
        name: "hm2_test.0".into(),
        connectors: vec!["P99".into()],
        pins_per_connector: 24,
        num_leds: 0,
        fpga_part: "none".into(),
    };
    let mut img = vec![0u32; WINDOW_WORDS];
    let mut put = |addr: u32, v: u32| img[addr as usize / 4] = v;
    let idrom = regs::IDROM_DEFAULT_ADDR as u32;
    let field = |put: &mut dyn FnMut(u32, u32), off: usize, v: u32| put(idrom + off as u32, v);
    if n >= 1 {
        put(regs::COOKIE_ADDR as u32, regs::COOKIE);
    }
    if n >= 2 {
        put(regs::CONFIG_NAME_ADDR as u32, u32::from_le_bytes(*b"HOST"));
        put(
            regs::CONFIG_NAME_ADDR as u32 + 4,
            u32::from_le_bytes(*b"MOT2"),
        );
    }
    if n == 2 {
        // IDROM "at 0": its type word reads 0.
        return Some((llio, img));
    }
    put(regs::IDROM_OFFSET_ADDR as u32, idrom);
    let (ports, width, port_width, clock_low, clock_high) = match n {
        3 => {
            field(&mut put, f::TYPE, 0x1234);
            return Some((llio, img));
        }
        4 => (0, 0, 0, 0, 0),
        5 => (0, 0, 29, 0, 0),
        6 => (0, 0, 24, 0, 0),
        7 => (1, 99, 24, 0, 0),
        8 => (2, 48, 24, 0, 0),
        9 => (1, 24, 24, 12_345, 0),
        10 => (1, 24, 24, 2_000_000, 0),
        11 => {
            llio.connectors = ["P4", "P5", "P6", "P9", "P8", "P7"]
                .iter()
                .map(|s| s.to_string())
                .collect();
            (6, 144, 24, 2_000_000, 20_000_000)
        }
        12 => {
            llio.connectors = vec!["P3".into()];
            (1, 24, 24, 2_000_000, 20_000_000)
        }
        13 => {
            llio.pins_per_connector = 5;
            (1, 24, 24, 2_000_000, 20_000_000)
        }
        _ => {
            llio.pins_per_connector = 37;
            (0, 0, 37, 2_000_000, 20_000_000)
        }
    };
    let pd_offset = if n == 12 { 0x200 } else { 0x1C0 };
    field(&mut put, f::TYPE, 2);
    field(&mut put, f::OFFSET_TO_MODULES, 64);
    field(&mut put, f::OFFSET_TO_PIN_DESC, pd_offset);
    field(&mut put, f::IO_PORTS, ports);
    field(&mut put, f::IO_WIDTH, width);
    field(&mut put, f::PORT_WIDTH, port_width);
    field(&mut put, f::CLOCK_LOW, clock_low);
    field(&mut put, f::CLOCK_HIGH, clock_high);
    field(&mut put, f::INSTANCE_STRIDE0, 4);
    field(&mut put, f::INSTANCE_STRIDE1, 64);
    field(&mut put, f::REGISTER_STRIDE0, 256);
    field(&mut put, f::REGISTER_STRIDE1, 256);
    if n == 12 {
        for pin in 0..24 {
            put(idrom + pd_offset + 4 * pin, 0x0300_0000);
        }
    }
    Some((llio, img))
}

/// The message LinuxCNC logs for pattern `n` (the line its test looks
/// for; pattern 0 adds a second line, pattern 12 one pair per pin).
pub fn expected_message(n: u32) -> Option<&'static str> {
    Some(match n {
        0 => "invalid cookie, got 0x00000000, expected 0x55AACAFE",
        1 => "invalid config name, got '????????', expected 'HOSTMOT2'",
        2 => "invalid IDROM type 0, expected 2 or 3, aborting load",
        3 => "invalid IDROM type 4660, expected 2 or 3, aborting load",
        4 => "invalid IDROM PortWidth 0, this board has 24 pins per connector, aborting load",
        5 => "invalid IDROM PortWidth 29, this board has 24 pins per connector, aborting load",
        6 | 14 => "IDROM IOPorts is 0 but llio num_ioport_connectors is 1, driver and firmware are inconsistent, aborting driver load",
        7 => "IDROM IOWidth is 99, but IDROM IOPorts is 1 and IDROM PortWidth is 24 (inconsistent firmware), aborting driver load",
        8 => "IDROM IOPorts is 2 but llio num_ioport_connectors is 1, driver and firmware are inconsistent, aborting driver load",
        9 => "IDROM ClockLow is 12345, that's too low, aborting driver load",
        10 => "IDROM ClockHigh is 0, that's too low, aborting driver load",
        11 => "pin 0 primary tag is 0 (end-of-list sentinel), expected 144 pins!",
        12 => "hm2_set_pin_source: invalid pin number 0",
        13 => "invalid IDROM PortWidth 24, this board has 5 pins per connector, aborting load",
        _ => return None,
    })
}
