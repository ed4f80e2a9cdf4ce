//! The simulated PLX-bridged cards (`hm2_pci sim=5i20`, ...) and the
//! firmwares they can be loaded with.
//!
//! | `sim=` | card | part | connectors | LEDs | ClockLow / ClockHigh |
//! |---|---|---|---|---|---|
//! | `5i20` | 5i20 (PLX 9030) | 2s200pq208 | P2, P3, P4 | 8 | 33.33 / 100 MHz |
//! | `4i65` | 4i65 (PLX 9030) | 2s200pq208 | P1, P3, P4 | 8 | 33.33 / 100 MHz |
//! | `5i22`, `5i22-1.5` | 5i22-1.0M, -1.5M (PLX 9054) | 3s1000fg320, 3s1500fg320 | P2, P3, P4, P5 | 8 | 48 / 96 MHz |
//! | `5i23` | 5i23 (PLX 9054) | 3s400pq208 | P2, P3, P4 | 2 | 48 / 96 MHz |
//! | `4i68` | 4i68 (PLX 9054) | 3s400pq208 | P1, P2, P4 | 4 | 48 / 96 MHz |
//! | `3x20`, `3x20-1.5`, `3x20-2` | 3x20-1.0M, -1.5M, -2.0M (PLX 9056) | 3s1000fg456, ... | P4, P5, P6, P9, P8, P7 | 0 | 50 / 100 MHz |
//!
//! All have 24 pins per connector and no flash: the FPGA is empty until
//! `firmware=` loads it. The firmware is chosen by its file name, Mesa's
//! servo/stepper family: `SV<n>` (n servo channels) and `SVST<n>_<m>`
//! (n servo channels and m step generators), e.g. SVST8_4, SVST8_8, SV12,
//! SV16, SV24, SVST16_24. Servo channels come four to a connector, from
//! the first; per group of two channels (k+1, k) the pins are index,
//! index, B, B, A, A (encoder inputs), PWM, PWM, direction, direction,
//! /enable, /enable. Step generators fill the connectors after the
//! servos: six pins each (step, direction and four table outputs) where
//! they fit, two (step, direction) otherwise; the rest are GPIO. A name
//! ending in `_7I47` (SVST2_4_7I47, the Smithy machines' firmware) has
//! four encoders and its own layout (`seven_i47_pins`); Smithy's Smart
//! Serial firmware `SSSVST<s>_<n>_<m>[_V<k>]` (`sssvst2_2_4_v31`: s Smart
//! Serial channels, n servo channels, m step generators) has that layout
//! with the Smart Serial channels on the last two encoders' pins and an
//! 8I20 drive on channel 0 ([`crate::sim::sserial::eight_i20`]). Every
//! firmware has a watchdog, the IOPorts, encoders v2, PWM generators v0
//! (on ClockHigh), step generators v2 and the card's LEDs.
//!
//! With no `firmware_dir=` the simulator makes the bitfile of the named
//! design itself ([`super::plx::bitfile`]), so a LinuxCNC configuration
//! runs unchanged; the whole load (header check, /PROGRAM, the stream,
//! DONE) runs on the simulated bridge either way.

use std::sync::Arc;

use super::{machine, SimHm2};
use crate::error::Hm2Error;
use crate::fpga::Bridge;
use crate::image::{gpio, pd, FirmwareSpec, ModuleSpec};
use crate::pci::{self, PciBoard};
use crate::pins::PinDescriptor;
use crate::regs::gtag;
use crate::sim::sserial::{RemoteKind, RemoteSpec};

/// The `sim=` names of the PLX cards, with their PCI table names.
pub const PLX_PRESETS: &[(&str, &str)] = &[
    ("5i20", "5i20"),
    ("4i65", "4i65"),
    ("5i22", "5i22-1.0M"),
    ("5i22-1.5", "5i22-1.5M"),
    ("5i23", "5i23"),
    ("4i68", "4i68"),
    ("3x20", "3x20-1.0M"),
    ("3x20-1.5", "3x20-1.5M"),
    ("3x20-2", "3x20-2.0M"),
];

/// The PCI table entry and bridge of simulated card `name`.
pub fn card(name: &str) -> Option<(&'static PciBoard, Bridge)> {
    let (_, table) = PLX_PRESETS.iter().find(|(n, _)| *n == name)?;
    let board = pci::BOARDS.iter().find(|b| b.ids.name == *table)?;
    let bridge = Bridge::of_device(board.ids.vendor, board.ids.device)?;
    Some((board, bridge))
}

/// Servo channels and step generators of a firmware name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Design {
    /// Servo channels (encoder + PWM generator).
    pub servos: u32,
    /// Step generators.
    pub steppers: u32,
    /// Laid out for a 7I47 daughter card (`..._7I47`, `SSSVST...`).
    pub seven_i47: bool,
    /// Smart Serial channels (`SSSVST<s>_<n>_<m>`).
    pub sserial: u32,
}

/// The design a firmware name describes (`SVST8_4`, `sv12`, with or
/// without `.BIT`), if it is of the servo/stepper family.
pub fn design(name: &str) -> Option<Design> {
    let upper = name.to_ascii_uppercase();
    let stem = upper.strip_suffix(".BIT").unwrap_or(&upper);
    if let Some(rest) = stem.strip_prefix("SSSVST") {
        return smithy_sserial(rest);
    }
    if let Some(base) = stem.strip_suffix("_7I47") {
        return design(base).filter(|d| !d.seven_i47).map(|d| Design {
            seven_i47: true,
            ..d
        });
    }
    if let Some(rest) = stem.strip_prefix("SVST") {
        let (n, m) = rest.split_once('_')?;
        return Some(Design {
            servos: num(n)?,
            steppers: num(m)?,
            seven_i47: false,
            sserial: 0,
        });
    }
    let n = num(stem.strip_prefix("SV")?)?;
    Some(Design {
        servos: n,
        steppers: 0,
        seven_i47: false,
        sserial: 0,
    })
}

/// A count of one to three digits.
fn num(s: &str) -> Option<u32> {
    (!s.is_empty() && s.len() <= 3 && s.bytes().all(|b| b.is_ascii_digit()))
        .then(|| s.parse::<u32>().ok())
        .flatten()
}

/// Smithy's Smart Serial firmware after its `SSSVST`: `<s>_<n>_<m>`
/// (Smart Serial channels, servo channels, step generators) with an
/// optional version `_V<k>`, e.g. `sssvst2_2_4_v31`.
fn smithy_sserial(rest: &str) -> Option<Design> {
    let mut parts: Vec<&str> = rest.split('_').collect();
    if let Some(v) = parts.last().and_then(|p| p.strip_prefix('V')) {
        num(v)?;
        parts.pop();
    }
    let [s, n, m] = parts[..] else {
        return None;
    };
    Some(Design {
        servos: num(n)?,
        steppers: num(m)?,
        seven_i47: true,
        sserial: num(s)?,
    })
}

/// Why a firmware does not fit a simulated card.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unfit {
    /// The 7I47 layout needs three 24-pin connectors and has at most 2
    /// servo channels and 4 step generators.
    SevenI47,
    /// Neither servo channels nor step generators.
    Empty,
    /// Servo channels not a multiple of four.
    ServosNotByFour,
    /// More servo connectors than the card has.
    ServoConnectors {
        /// Servo channels the firmware has.
        servos: u32,
        /// Connectors they need.
        connectors: u32,
    },
    /// The step generators' pins do not fit what is left.
    StepgenPins {
        /// Step generators the firmware has.
        steppers: u32,
        /// Pins left after the servo connectors.
        left: u32,
    },
}

impl std::fmt::Display for Unfit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Unfit::SevenI47 => f.write_str(
                "the 7I47 layout has at most 2 servo channels, 4 step generators and \
                 2 Smart Serial channels, on a card of three 24-pin connectors",
            ),
            Unfit::Empty => f.write_str("it has neither servo channels nor step generators"),
            Unfit::ServosNotByFour => f.write_str("servo channels come four to a connector"),
            Unfit::ServoConnectors { servos, connectors } => {
                write!(f, "{servos} servo channels need {connectors} connectors")
            }
            Unfit::StepgenPins { steppers, left } => {
                write!(
                    f,
                    "{steppers} step generators do not fit the {left} pins left"
                )
            }
        }
    }
}

/// What a card without flash offers the servo/stepper family: the PLX
/// cards' PCI table entries and the 7I43 (loaded through its CPLD).
#[derive(Debug, Clone, Copy)]
pub struct Card<'a> {
    /// Its type in HAL names (`5i20`, `7i43`).
    pub board: &'a str,
    /// The FPGA part.
    pub fpga_part: &'a str,
    /// Connector names, in I/O order.
    pub connectors: &'a [&'a str],
    /// Pins per connector.
    pub pins_per_connector: u32,
    /// LEDs.
    pub leds: u32,
}

impl<'a> From<&'a PciBoard> for Card<'a> {
    fn from(b: &'a PciBoard) -> Card<'a> {
        Card {
            board: b.board,
            fpga_part: b.fpga_part,
            connectors: b.connectors,
            pins_per_connector: b.pins_per_connector,
            leds: b.leds,
        }
    }
}

/// The 7I43 with FPGA `part` as a card of this family: two 24-pin
/// connectors (P4, P3) and 8 LEDs; loaded through its CPLD.
pub fn seven_i43(part: &str) -> Card<'_> {
    Card {
        board: "7i43",
        fpga_part: part,
        connectors: &["P4", "P3"],
        pins_per_connector: 24,
        leds: 8,
    }
}

/// The simulator's HostMot2 running `design_name` on `card`, with a
/// servo on each servo channel (motor leads swapped, as LinuxCNC's
/// hm2-servo samples expect) and a stepper axis on each step generator:
/// what a card runs once its FPGA is loaded.
pub fn running(card: &Card<'_>, design_name: &str) -> Result<Arc<SimHm2>, Hm2Error> {
    let spec = firmware(card, design_name)?;
    let shape = design(design_name).unwrap_or(Design {
        servos: 0,
        steppers: 0,
        seven_i47: false,
        sserial: 0,
    });
    let machine = machine::servo_stepper(shape.servos as usize, shape.steppers as usize);
    let (board, _) = crate::sim::board(spec, Box::new(machine));
    Ok(board)
}

/// Why firmware `d` does not fit simulated card `board`, if it does not.
pub fn unfit(board: &Card<'_>, d: Design) -> Option<Unfit> {
    let conns = board.connectors.len() as u32;
    let width = board.pins_per_connector;
    if d.seven_i47 {
        return (conns < 3 || width != 24 || d.servos > 2 || d.steppers > 4 || d.sserial > 2)
            .then_some(Unfit::SevenI47);
    }
    if d.servos == 0 && d.steppers == 0 {
        return Some(Unfit::Empty);
    }
    if d.servos % 4 != 0 {
        return Some(Unfit::ServosNotByFour);
    }
    let servo_conns = d.servos / 4;
    if servo_conns > conns {
        return Some(Unfit::ServoConnectors {
            servos: d.servos,
            connectors: servo_conns,
        });
    }
    let left = (conns - servo_conns) * width;
    if d.steppers * 2 > left {
        return Some(Unfit::StepgenPins {
            steppers: d.steppers,
            left,
        });
    }
    None
}

/// The pins of two servo channels `k + 1` and `k`.
fn servo_pair(k: u8) -> [PinDescriptor; 12] {
    let (hi, lo) = (k + 1, k);
    [
        pd(gtag::ENCODER, hi, 0x03),
        pd(gtag::ENCODER, lo, 0x03),
        pd(gtag::ENCODER, hi, 0x02),
        pd(gtag::ENCODER, lo, 0x02),
        pd(gtag::ENCODER, hi, 0x01),
        pd(gtag::ENCODER, lo, 0x01),
        pd(gtag::PWMGEN, hi, 0x81),
        pd(gtag::PWMGEN, lo, 0x81),
        pd(gtag::PWMGEN, hi, 0x82),
        pd(gtag::PWMGEN, lo, 0x82),
        pd(gtag::PWMGEN, hi, 0x83),
        pd(gtag::PWMGEN, lo, 0x83),
    ]
}

/// The firmware `design_name` on simulated card `board`, or why not.
pub fn firmware(board: &Card<'_>, design_name: &str) -> Result<FirmwareSpec, Hm2Error> {
    let d = design(design_name).ok_or_else(|| Hm2Error::SimUnknownFirmware {
        design: design_name.into(),
    })?;
    if let Some(why) = unfit(board, d) {
        return Err(Hm2Error::SimFirmwareUnfit {
            design: design_name.into(),
            board: board.board.into(),
            why,
        });
    }
    let total = board.connectors.len() * board.pins_per_connector as usize;
    let (pins, encoders) = if d.seven_i47 {
        // Smart Serial channels take the last two encoders' pins.
        (seven_i47_pins(d, total), if d.sserial > 0 { 2 } else { 4 })
    } else {
        (family_pins(d, total), d.servos)
    };
    let mut modules = vec![
        ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
        ModuleSpec::standard(gtag::IOPORT, 0, board.connectors.len() as u8),
    ];
    if encoders > 0 {
        modules.push(ModuleSpec::standard(gtag::ENCODER, 2, encoders as u8));
    }
    if d.servos > 0 {
        modules.push(ModuleSpec::standard(gtag::PWMGEN, 0, d.servos as u8));
    }
    if d.steppers > 0 {
        modules.push(ModuleSpec::standard(gtag::STEPGEN, 2, d.steppers as u8));
    }
    if d.sserial > 0 {
        modules.push(ModuleSpec::standard(gtag::SSERIAL, 0, 1));
    }
    if board.leds > 0 {
        modules.push(ModuleSpec::standard(gtag::LED, 0, 1));
    }
    let (clock_low, clock_high) = clocks(board.board);
    let mut board_name = *b"MESA    ";
    let short = board.board.to_ascii_uppercase();
    let n = short.len().min(4);
    board_name[4..4 + n].copy_from_slice(&short.as_bytes()[..n]);
    Ok(FirmwareSpec {
        board: board.board.into(),
        board_name,
        fpga_part: board.fpga_part.into(),
        fpga_size: 0,
        fpga_pins: 0,
        connectors: board.connectors.iter().map(|c| c.to_string()).collect(),
        port_width: board.pins_per_connector,
        leds: board.leds,
        clock_low,
        clock_high,
        modules,
        pins,
        // The Smithy machines' 8I20 spindle drive on the first channel.
        remotes: if d.sserial > 0 {
            vec![RemoteSpec {
                port: 0,
                channel: 0,
                kind: RemoteKind::EightI20,
                unit: 0x0820,
            }]
        } else {
            Vec::new()
        },
    })
}

/// The family's pin-out: servo pairs from the first pin, then the step
/// generators (six pins each where they fit, else two), then GPIO.
pub(crate) fn family_pins(d: Design, total: usize) -> Vec<PinDescriptor> {
    let mut pins = Vec::with_capacity(total);
    for k in (0..d.servos as u8).step_by(2) {
        pins.extend(servo_pair(k));
    }
    let left = total - pins.len();
    let per = if d.steppers as usize * 6 <= left {
        6
    } else {
        2
    };
    for k in 0..d.steppers as u8 {
        for p in 1..=per {
            pins.push(pd(gtag::STEPGEN, k, 0x80 | p));
        }
    }
    pins.resize(total, gpio());
    pins
}

/// The 7I47 layout (this simulator's, shaped by the Smithy machines'
/// HAL files): on the first connector step generators 0 and 1 (step,
/// direction) at I/O 0 to 3, encoders 0 and 1 (A, B, index) at 4 to 9,
/// PWM generators 0 and 1 (PWM, direction, /enable) at 10 to 15, step
/// generators 2 and 3 at 16 to 19; encoders 2 and 3 on the last six pins
/// of the third connector, or in the Smart Serial designs (`SSSVST`)
/// Smart Serial channels 0 and 1 (RX, TX, TX enable); the rest GPIO.
fn seven_i47_pins(d: Design, total: usize) -> Vec<PinDescriptor> {
    let step = |k: u8| [pd(gtag::STEPGEN, k, 0x81), pd(gtag::STEPGEN, k, 0x82)];
    let enc = |k: u8| (1..=3).map(move |f| pd(gtag::ENCODER, k, f));
    let mut pins = Vec::with_capacity(total);
    pins.extend(step(0));
    pins.extend(step(1));
    pins.extend(enc(0).chain(enc(1)));
    for k in 0..2u8 {
        pins.extend((0x81..=0x83).map(|f| pd(gtag::PWMGEN, k, f)));
    }
    pins.extend(step(2));
    pins.extend(step(3));
    pins.resize(total - 6, gpio());
    if d.sserial > 0 {
        for c in 0..2u8 {
            pins.extend([
                pd(gtag::SSERIAL, 0, 0x01 + c),
                pd(gtag::SSERIAL, 0, 0x81 + c),
                pd(gtag::SSERIAL, 0, 0x91 + c),
            ]);
        }
    } else {
        pins.extend(enc(2).chain(enc(3)));
    }
    // Modules the design lacks leave their pins to GPIO.
    for p in &mut pins {
        let unit = p.sec_unit as u32;
        let absent = (p.sec_tag == gtag::STEPGEN && unit >= d.steppers)
            || (p.sec_tag == gtag::PWMGEN && unit >= d.servos)
            || (p.sec_tag == gtag::SSERIAL && (p.sec_pin & 0x0F) as u32 > d.sserial);
        if absent {
            *p = gpio();
        }
    }
    pins
}

/// The firmware clocks of a card type (hardware.md 5.3).
fn clocks(board: &str) -> (u32, u32) {
    match board {
        "5i20" | "4i65" => (33_333_333, 100_000_000),
        "3x20" | "7i43" => (50_000_000, 100_000_000),
        _ => (48_000_000, 96_000_000),
    }
}

/// The stem of a `firmware=` name: `hm2/5i20/SVST8_4.BIT` → `SVST8_4`.
pub fn design_of_path(name: &str) -> &str {
    let file = name.rsplit('/').next().unwrap_or(name);
    match file.rfind('.') {
        Some(dot) if dot > 0 => &file[..dot],
        _ => file,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::idrom;
    use crate::image::ImageTransport;

    #[test]
    fn the_family_names_parse() {
        assert_eq!(
            design("SVST8_4.BIT"),
            Some(Design {
                servos: 8,
                steppers: 4,
                seven_i47: false,
                sserial: 0,
            })
        );
        assert_eq!(
            design("sv12"),
            Some(Design {
                servos: 12,
                steppers: 0,
                seven_i47: false,
                sserial: 0,
            })
        );
        assert_eq!(
            design("SVST2_4_7I47.BIT"),
            Some(Design {
                servos: 2,
                steppers: 4,
                seven_i47: true,
                sserial: 0,
            })
        );
        assert_eq!(
            design("sssvst2_2_4_v31.bit"),
            Some(Design {
                servos: 2,
                steppers: 4,
                seven_i47: true,
                sserial: 2,
            })
        );
        assert_eq!(design("SSSVST1_2_4").map(|d| d.sserial), Some(1));
        for bad in [
            "SSSVST2_4",
            "SSSVST2_2_4_V",
            "SSSVST2_2_4_Vx",
            "SSSVST2_2_4_5_6",
        ] {
            assert_eq!(design(bad), None, "{bad}");
        }
        assert_eq!(design("SVST2_4_7I47_7I47"), None);
        for bad in ["7i77x2", "SVST8", "SV", "SVST_4", "SV1234", "SVSTx_4"] {
            assert_eq!(design(bad), None, "{bad}");
        }
        assert_eq!(design_of_path("hm2/5i20/SVST8_4.BIT"), "SVST8_4");
        assert_eq!(design_of_path("SV12"), "SV12");
    }

    #[test]
    fn every_card_takes_its_configs_firmwares_and_the_images_load() {
        for (name, fw) in [
            ("5i20", "SVST8_4"),
            ("5i20", "SV12"),
            ("4i65", "SVST8_4"),
            ("5i22", "SVST8_8"),
            ("5i22-1.5", "SV16"),
            ("5i23", "SVST8_4"),
            ("4i68", "SVST8_4"),
            ("3x20", "SV24"),
            ("3x20", "SVST16_24"),
            ("5i20", "SVST2_4_7I47"),
            ("5i20", "sssvst2_2_4_v31"),
        ] {
            let (board, _) = card(name).unwrap();
            let spec = firmware(&board.into(), fw).unwrap();
            assert_eq!(spec.pins.len(), board.connectors.len() * 24, "{name} {fw}");
            let llio = board.llio(0);
            let mut t = ImageTransport::new(spec.image(), &llio.name);
            idrom::check_identity(&mut t).unwrap();
            idrom::read_header(&mut t, &llio).unwrap();
        }
    }

    #[test]
    fn firmwares_that_do_not_fit_say_why() {
        let (board, _) = card("5i20").unwrap();
        let e = firmware(&board.into(), "SV16").unwrap_err();
        assert!(
            e.to_string()
                .contains("16 servo channels need 4 connectors"),
            "{e}"
        );
        let e = firmware(&board.into(), "7i77x2").unwrap_err();
        assert!(e.to_string().contains("does not know"), "{e}");
        let e = firmware(&board.into(), "SVST8_30").unwrap_err();
        assert!(e.to_string().contains("30 step generators"), "{e}");
    }

    #[test]
    fn svst8_4_puts_the_steppers_on_p4_six_pins_apart() {
        let (board, _) = card("5i20").unwrap();
        let spec = firmware(&board.into(), "SVST8_4").unwrap();
        assert_eq!(spec.pins[48], pd(gtag::STEPGEN, 0, 0x81));
        assert_eq!(spec.pins[49], pd(gtag::STEPGEN, 0, 0x82));
        assert_eq!(spec.pins[54], pd(gtag::STEPGEN, 1, 0x81));
        assert_eq!(spec.pins[25], pd(gtag::ENCODER, 4, 0x03));
    }

    #[test]
    fn smithys_sserial_firmware_has_an_8i20_on_channel_0() {
        let (board, _) = card("5i20").unwrap();
        let spec = firmware(&board.into(), "sssvst2_2_4_v31").unwrap();
        assert_eq!(spec.pins[66], pd(gtag::SSERIAL, 0, 0x01));
        assert_eq!(spec.pins[67], pd(gtag::SSERIAL, 0, 0x81));
        assert_eq!(spec.pins[71], pd(gtag::SSERIAL, 0, 0x92));
        assert_eq!(spec.module(gtag::SSERIAL).unwrap().instances, 1);
        assert_eq!(spec.module(gtag::ENCODER).unwrap().instances, 2);
        assert_eq!(spec.module(gtag::STEPGEN).unwrap().instances, 4);
        // The GPIO the 1240combined machines use stay free.
        for io in [22, 24, 29, 35, 39, 41, 43, 45] {
            assert_eq!(spec.pins[io], gpio(), "I/O {io}");
        }
        assert_eq!(spec.remotes.len(), 1);
        assert_eq!(spec.remotes[0].kind, RemoteKind::EightI20);
        let one = firmware(&board.into(), "sssvst1_2_4").unwrap();
        assert_eq!(one.pins[69], gpio(), "no channel 1");
        let e = firmware(&board.into(), "sssvst3_2_4").unwrap_err();
        assert!(e.to_string().contains("2 Smart Serial channels"), "{e}");
    }

    #[test]
    fn the_7i47_layout_leaves_the_smithy_machines_gpio_free() {
        let (board, _) = card("5i20").unwrap();
        let spec = firmware(&board.into(), "SVST2_4_7I47").unwrap();
        assert_eq!(spec.pins[0], pd(gtag::STEPGEN, 0, 0x81));
        assert_eq!(spec.pins[18], pd(gtag::STEPGEN, 3, 0x81));
        assert_eq!(spec.pins[66], pd(gtag::ENCODER, 2, 0x01));
        for io in [22, 24, 39, 40, 46, 64] {
            assert_eq!(spec.pins[io], gpio(), "I/O {io}");
        }
        assert_eq!(spec.module(gtag::ENCODER).unwrap().instances, 4);
        let e = firmware(&board.into(), "SVST4_4_7I47").unwrap_err();
        assert!(e.to_string().contains("7I47 layout"), "{e}");
    }
}
