//! The simulated boards `hm2_pci sim=...` offers, each a firmware of the
//! kind Mesa ships for it (the descriptors are this simulator's, not a
//! dump of a real bitfile):
//!
//! | name | board | connectors | firmware |
//! |---|---|---|---|
//! | `5i25` | 5i25, 7i76-style pin-out | P3, P2 × 17 | per connector 5 step generators (step/dir on DB-25 pins 1, 14, 2, 15, ...), 1 encoder (A, B, index), 4 GPIO; watchdog, 2 LEDs |
//! | `6i25` | 6i25, servo pin-out | P3, P2 × 17 | P3: 4 encoders with probe (A, B, index), 5 GPIO; P2: 4 PWM generators with dither (PWM, dir, /enable), 5 GPIO |
//! | `5i24` | 5i24 | P4, P3, P2 × 24 | P4: 8 encoders; P3: 8 PWM generators; P2: 8 step generators with index/probe latch (0xC2), 8 GPIO |
//! | `5i25-7i77` | 5i25 | P3, P2 × 17 | P3: Smart Serial port 0 with 2 channels and a simulated 7I77 on them (I/O, analog), 1 encoder, 8 GPIO; P2: 5 step generators, 1 encoder, 4 GPIO |
//! | `5i25-pktuart` | 5i25 | P3, P2 × 17 | P3: 2 PktUARTs v3 (TX, TX enable, RX each; `hm2_modbus`), 1 encoder, 8 GPIO; P2: 5 step generators, 1 encoder, 4 GPIO. Nothing is on the PktUARTs' lines until a test plugs a peer in ([`SimPktUart::attach`](crate::sim::pktuart::SimPktUart::attach)) |
//!
//! and the Ethernet boards the `hm2-eth-sim` tool serves ([`ETH_PRESETS`]):
//!
//! | name | space-7 name | connectors | firmware |
//! |---|---|---|---|
//! | `7i96s` | `7I96S` | P1, TB1, TB2 × 17 | P1: Smart Serial port 0 with 2 channels (RX, TX, TX enable each), 3 PWM generators (PWM, dir, /enable), 2 GPIO; TB1: 5 step generators (step/dir), encoder 0 (A, B, index), 4 GPIO; TB2: 11 GPIO (the isolated inputs), encoders 1 and 2; one PktUART v3 on the RS-422/485 port (`hm2_7i96s.0.pktuart.0`, no connector pins; nothing on its line until a test plugs a peer in) |
//! | `7i76e` | `7I76E-16` | P1, P2, P3 × 17 | P1 (the on-card 7i76): 5 step generators, Smart Serial port 0 channel 0, 1 encoder, 1 GPIO; P2, P3: GPIO |
//! | `7i93` | `7I93` | P2, P1 × 24 | the PCI cards' SVST4_8 layout ([`super::plx_boards`]): P2: 4 servo channels (encoder A, B, index; PWM, dir, /enable, paired); P1: 8 step generators (step/dir), 8 GPIO |
//! | `7i92` | `7I92` | P2, P1 × 17 | the `5i25` firmware: per header 5 step generators, 1 encoder, 4 GPIO |
//! | `7i95` | `7I95` | P1, TB1 × 29 | P1: 6 step generators, 3 encoders, 5 GPIO; TB1: 29 GPIO |
//!
//! The 7i96s's three PWM generators and two extra encoders are more than
//! the card's own firmware has: LinuxCNC's hm2-servo sample for it asks
//! for three servo channels. The 7i93, 7i92 and 7i95 pin-outs are this
//! simulator's.
//!
//! A simulated 7I76 is plugged into channel 0 of the 7i96s's and 7i76e's
//! Smart Serial port ([`seven_i76_on`]; [`seven_i77_on`] gives a 7I77);
//! the 7i93, 7i92 and 7i95 have no Smart Serial.
//! All run ClockLow at 100 MHz and ClockHigh at 200 MHz, except the 6i25
//! whose ClockLow is 66.67 MHz. Every board has a watchdog and 2 LEDs
//! (the Ethernet ones 4).

use crate::image::{gpio, pd, FirmwareSpec, ModuleSpec};
use crate::pins::PinDescriptor;
use crate::regs::gtag;
use crate::sim::sserial::{RemoteKind, RemoteSpec};

/// The PCI board names [`preset`] knows.
pub const PRESETS: &[&str] = &["5i25", "6i25", "5i24", "5i25-7i77", "5i25-pktuart"];

/// The Ethernet board names [`preset`] knows.
pub const ETH_PRESETS: &[&str] = &["7i96s", "7i76e", "7i93", "7i92", "7i95"];

/// Every `hm2_pci sim=` name: the presets, then the PLX cards.
pub fn pci_sim_names() -> String {
    let plx = super::plx_boards::PLX_PRESETS.iter().map(|(n, _)| *n);
    PRESETS
        .iter()
        .copied()
        .chain(plx)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The firmware of a simulated board, by name.
pub fn preset(name: &str) -> Option<FirmwareSpec> {
    match name {
        "5i25" => Some(five_i25()),
        "6i25" => Some(six_i25()),
        "5i24" => Some(five_i24()),
        "5i25-7i77" => Some(five_i25_7i77()),
        "5i25-pktuart" => Some(five_i25_pktuart()),
        "7i96s" => Some(seven_i96s()),
        "7i76e" => Some(seven_i76e()),
        "7i93" => Some(seven_i93()),
        "7i92" => Some(seven_i92()),
        "7i95" => Some(seven_i95()),
        _ => None,
    }
}

/// The space-7 name of an Ethernet preset (`7I96S`).
pub fn eth_name(name: &str) -> Option<&'static str> {
    match name {
        "7i96s" => Some("7I96S"),
        "7i76e" => Some("7I76E-16"),
        "7i93" => Some("7I93"),
        "7i92" => Some("7I92"),
        "7i95" => Some("7I95"),
        _ => None,
    }
}

/// A simulated 7I76 on Smart Serial `port`, `channel`.
pub fn seven_i76_on(port: u8, channel: u8) -> RemoteSpec {
    RemoteSpec {
        port,
        channel,
        kind: RemoteKind::SevenI76,
        unit: 0x1234 + channel as u32,
    }
}

/// A simulated 7I77 on Smart Serial `port`: its I/O on `channel`, its
/// analog outputs on the next one.
pub fn seven_i77_on(port: u8, channel: u8) -> [RemoteSpec; 2] {
    [
        RemoteSpec {
            port,
            channel,
            kind: RemoteKind::SevenI77Io,
            unit: 0x7700 + channel as u32,
        },
        RemoteSpec {
            port,
            channel: channel + 1,
            kind: RemoteKind::SevenI77Analog,
            unit: 0x7701 + channel as u32,
        },
    ]
}

/// The pins of Smart Serial port `port` channel `chan`: RX, TX, TX enable.
fn sserial_channel(port: u8, chan: u8) -> [PinDescriptor; 3] {
    [
        pd(gtag::SSERIAL, port, 0x01 + chan),
        pd(gtag::SSERIAL, port, 0x81 + chan),
        pd(gtag::SSERIAL, port, 0x91 + chan),
    ]
}

/// An Ethernet board's firmware: watchdog, 3 IOPorts, 1 encoder, 5 step
/// generators, 1 Smart Serial port with a 7I76 on channel 0, 4 LEDs.
fn eth_firmware(id: Identity, pins: Vec<PinDescriptor>) -> FirmwareSpec {
    let mut fw = firmware(
        id,
        vec![
            ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
            ModuleSpec::standard(gtag::IOPORT, 0, 3),
            ModuleSpec::standard(gtag::ENCODER, 2, 1),
            ModuleSpec::standard(gtag::STEPGEN, 2, 5),
            ModuleSpec::standard(gtag::SSERIAL, 0, 1),
            ModuleSpec::standard(gtag::LED, 0, 1),
        ],
        pins,
    );
    fw.leds = 4;
    fw.remotes = vec![seven_i76_on(0, 0)];
    fw
}

/// 5i25 with a Smart Serial port and a 7I77 on it.
fn five_i25_7i77() -> FirmwareSpec {
    let mut pins = Vec::new();
    pins.extend(sserial_channel(0, 0));
    pins.extend(sserial_channel(0, 1));
    for f in 1..=3 {
        pins.push(pd(gtag::ENCODER, 0, f));
    }
    pins.extend(std::iter::repeat_n(gpio(), 8));
    for k in 0..5u8 {
        pins.push(pd(gtag::STEPGEN, k, 0x81));
        pins.push(pd(gtag::STEPGEN, k, 0x82));
    }
    for f in 1..=3 {
        pins.push(pd(gtag::ENCODER, 1, f));
    }
    pins.extend(std::iter::repeat_n(gpio(), 4));
    let mut fw = firmware(
        FIVE_I25,
        vec![
            ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
            ModuleSpec::standard(gtag::IOPORT, 0, 2),
            ModuleSpec::standard(gtag::ENCODER, 2, 2),
            ModuleSpec::standard(gtag::STEPGEN, 2, 5),
            ModuleSpec::standard(gtag::SSERIAL, 0, 1),
            ModuleSpec::standard(gtag::LED, 0, 1),
        ],
        pins,
    );
    fw.remotes = seven_i77_on(0, 0).to_vec();
    fw
}

/// 5i25 with two PktUARTs on P3 (the 5i25-7i77 pin-out with PktUARTs
/// where the Smart Serial channels are).
fn five_i25_pktuart() -> FirmwareSpec {
    let mut fw = five_i25_7i77();
    fw.board = "5i25".into();
    fw.remotes.clear();
    let sserial_pins = fw.pins.iter_mut().filter(|p| p.sec_tag == gtag::SSERIAL);
    for (io, p) in sserial_pins.enumerate() {
        // Per channel (RX, TX, TX enable): PktUART unit = channel.
        let unit = (io / 3) as u8;
        *p = match io % 3 {
            0 => pd(gtag::PKTUART_RX, unit, 0x01),
            1 => pd(gtag::PKTUART_TX, unit, 0x81),
            _ => pd(gtag::PKTUART_TX, unit, 0x82),
        };
    }
    for m in fw.modules.iter_mut().filter(|m| m.gtag == gtag::SSERIAL) {
        *m = ModuleSpec::standard(gtag::PKTUART_TX, 3, 2);
    }
    fw.modules
        .push(ModuleSpec::standard(gtag::PKTUART_RX, 3, 2));
    fw
}

/// 7i96S: Smart Serial and three PWM generators on P1, steppers and an
/// encoder on TB1, I/O and two more encoders on TB2.
fn seven_i96s() -> FirmwareSpec {
    let mut pins = Vec::new();
    pins.extend(sserial_channel(0, 0));
    pins.extend(sserial_channel(0, 1));
    for k in 0..3u8 {
        pins.extend((0x81..=0x83).map(|f| pd(gtag::PWMGEN, k, f)));
    }
    pins.extend(std::iter::repeat_n(gpio(), 2));
    for k in 0..5u8 {
        pins.push(pd(gtag::STEPGEN, k, 0x81));
        pins.push(pd(gtag::STEPGEN, k, 0x82));
    }
    for f in 1..=3 {
        pins.push(pd(gtag::ENCODER, 0, f));
    }
    pins.extend(std::iter::repeat_n(gpio(), 4 + 11));
    for k in 1..3u8 {
        pins.extend((1..=3).map(|f| pd(gtag::ENCODER, k, f)));
    }
    let mut fw = eth_firmware(
        Identity {
            board: "7i96s",
            idrom_name: "MESA7I96",
            fpga_part: "T20F256",
            fpga_size: 20,
            fpga_pins: 256,
            connectors: &["P1", "TB1", "TB2"],
            port_width: 17,
            clock_low: 100_000_000,
        },
        pins,
    );
    for m in fw.modules.iter_mut().filter(|m| m.gtag == gtag::ENCODER) {
        *m = ModuleSpec::standard(gtag::ENCODER, 2, 3);
    }
    let led = fw.modules.len() - 1;
    fw.modules
        .insert(led, ModuleSpec::standard(gtag::PWMGEN, 0, 3));
    // The card's RS-422/485 port: one PktUART (v3), as Mesa's 7I96S
    // firmware has for `hm2_modbus`. Its transceiver is wired on the
    // card, so no connector pin is given to it here.
    fw.modules
        .push(ModuleSpec::standard(gtag::PKTUART_TX, 3, 1));
    fw.modules
        .push(ModuleSpec::standard(gtag::PKTUART_RX, 3, 1));
    fw
}

/// 7i76E: the on-card 7i76's steppers, Smart Serial and encoder on P1.
fn seven_i76e() -> FirmwareSpec {
    let mut pins = Vec::new();
    for k in 0..5u8 {
        pins.push(pd(gtag::STEPGEN, k, 0x81));
        pins.push(pd(gtag::STEPGEN, k, 0x82));
    }
    pins.extend(sserial_channel(0, 0));
    for f in 1..=3 {
        pins.push(pd(gtag::ENCODER, 0, f));
    }
    pins.extend(std::iter::repeat_n(gpio(), 1 + 34));
    eth_firmware(
        Identity {
            board: "7i76e",
            idrom_name: "MESA7I76",
            fpga_part: "XC6SLX16",
            fpga_size: 16,
            fpga_pins: 256,
            connectors: &["P1", "P2", "P3"],
            port_width: 17,
            clock_low: 100_000_000,
        },
        pins,
    )
}

/// A board without Smart Serial: watchdog, IOPorts, `encoders` encoders
/// v2, `pwmgens` PWM generators v0, `stepgens` step generators v2 and 4
/// LEDs (the Ethernet boards'), on `pins`.
fn plain_eth_firmware(
    id: Identity,
    encoders: u8,
    pwmgens: u8,
    stepgens: u8,
    pins: Vec<PinDescriptor>,
) -> FirmwareSpec {
    let mut modules = vec![
        ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
        ModuleSpec::standard(gtag::IOPORT, 0, id.connectors.len() as u8),
    ];
    for (tag, version, n) in [
        (gtag::ENCODER, 2, encoders),
        (gtag::PWMGEN, 0, pwmgens),
        (gtag::STEPGEN, 2, stepgens),
    ] {
        if n > 0 {
            modules.push(ModuleSpec::standard(tag, version, n));
        }
    }
    modules.push(ModuleSpec::standard(gtag::LED, 0, 1));
    let mut fw = firmware(id, modules, pins);
    fw.leds = 4;
    fw
}

/// 7I93: two 50-pin headers with the PCI cards' servo/stepper family
/// pin-out for SVST4_8 ([`super::plx_boards`]): four servo channels
/// (encoder and PWM generator) on P2, eight step generators (step,
/// direction) and 8 GPIO on P1.
fn seven_i93() -> FirmwareSpec {
    let design = super::plx_boards::Design {
        servos: 4,
        steppers: 8,
        seven_i47: false,
        sserial: 0,
    };
    plain_eth_firmware(
        Identity {
            board: "7i93",
            idrom_name: "MESA7I93",
            fpga_part: "6slx9tqg144",
            fpga_size: 9,
            fpga_pins: 144,
            connectors: &["P2", "P1"],
            port_width: 24,
            clock_low: 100_000_000,
        },
        4,
        4,
        8,
        super::plx_boards::family_pins(design, 48),
    )
}

/// 7I92: the 5i25's 7i76-style firmware on its two 26-pin headers (per
/// header 5 step generators, 1 encoder, 4 GPIO).
fn seven_i92() -> FirmwareSpec {
    let mut fw = five_i25();
    let pins = std::mem::take(&mut fw.pins);
    plain_eth_firmware(
        Identity {
            board: "7i92",
            idrom_name: "MESA7I92",
            fpga_part: "6slx9tqg144",
            fpga_size: 9,
            fpga_pins: 144,
            connectors: &["P2", "P1"],
            port_width: 17,
            clock_low: 100_000_000,
        },
        2,
        0,
        10,
        pins,
    )
}

/// 7I95: on the first connector 6 step generators (step, direction), 3
/// encoders (A, B, index) and 5 GPIO; the second (the isolated inputs,
/// outputs and expansion) all GPIO.
fn seven_i95() -> FirmwareSpec {
    let mut pins = Vec::new();
    for k in 0..6u8 {
        pins.push(pd(gtag::STEPGEN, k, 0x81));
        pins.push(pd(gtag::STEPGEN, k, 0x82));
    }
    for k in 0..3u8 {
        pins.extend((1..=3).map(|f| pd(gtag::ENCODER, k, f)));
    }
    pins.resize(2 * 29, gpio());
    plain_eth_firmware(
        Identity {
            board: "7i95",
            idrom_name: "MESA7I95",
            fpga_part: "6slx9tqg144",
            fpga_size: 9,
            fpga_pins: 144,
            connectors: &["P1", "TB1"],
            port_width: 29,
            clock_low: 100_000_000,
        },
        3,
        0,
        6,
        pins,
    )
}

/// What distinguishes one board from another.
pub(crate) struct Identity {
    pub(crate) board: &'static str,
    pub(crate) idrom_name: &'static str,
    pub(crate) fpga_part: &'static str,
    pub(crate) fpga_size: u32,
    pub(crate) fpga_pins: u32,
    pub(crate) connectors: &'static [&'static str],
    pub(crate) port_width: u32,
    pub(crate) clock_low: u32,
}

/// The 5i25's identity, shared by its two personalities.
const FIVE_I25: Identity = Identity {
    board: "5i25",
    idrom_name: "MESA5I25",
    fpga_part: "6slx9tqg144",
    fpga_size: 9,
    fpga_pins: 144,
    connectors: &["P3", "P2"],
    port_width: 17,
    clock_low: 100_000_000,
};

/// A board's firmware: its identity, 2 LEDs, ClockHigh 200 MHz.
pub(crate) fn firmware(
    id: Identity,
    modules: Vec<ModuleSpec>,
    pins: Vec<PinDescriptor>,
) -> FirmwareSpec {
    let mut board_name = [b' '; 8];
    let n = id.idrom_name.len().min(8);
    board_name[..n].copy_from_slice(&id.idrom_name.as_bytes()[..n]);
    FirmwareSpec {
        board: id.board.into(),
        board_name,
        fpga_part: id.fpga_part.into(),
        fpga_size: id.fpga_size,
        fpga_pins: id.fpga_pins,
        connectors: id.connectors.iter().map(|c| c.to_string()).collect(),
        port_width: id.port_width,
        leds: 2,
        clock_low: id.clock_low,
        clock_high: 200_000_000,
        modules,
        pins,
        remotes: Vec::new(),
    }
}

/// 5i25 with a 7i76-style firmware.
fn five_i25() -> FirmwareSpec {
    let mut pins = Vec::new();
    for conn in 0..2u8 {
        for k in 0..5u8 {
            pins.push(pd(gtag::STEPGEN, 5 * conn + k, 0x81));
            pins.push(pd(gtag::STEPGEN, 5 * conn + k, 0x82));
        }
        for f in 1..=3 {
            pins.push(pd(gtag::ENCODER, conn, f));
        }
        pins.extend(std::iter::repeat_n(gpio(), 4));
    }
    firmware(
        FIVE_I25,
        vec![
            ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
            ModuleSpec::standard(gtag::IOPORT, 0, 2),
            ModuleSpec::standard(gtag::ENCODER, 2, 2),
            ModuleSpec::standard(gtag::STEPGEN, 2, 10),
            ModuleSpec::standard(gtag::LED, 0, 1),
        ],
        pins,
    )
}

/// 6i25 with a servo firmware.
fn six_i25() -> FirmwareSpec {
    let mut pins = Vec::new();
    for k in 0..4u8 {
        for f in 1..=3 {
            pins.push(pd(gtag::ENCODER, k, f));
        }
    }
    pins.extend(std::iter::repeat_n(gpio(), 5));
    for k in 0..4u8 {
        for f in 0x81..=0x83 {
            pins.push(pd(gtag::PWMGEN, k, f));
        }
    }
    pins.extend(std::iter::repeat_n(gpio(), 5));
    firmware(
        Identity {
            board: "6i25",
            idrom_name: "MESA6I25",
            fpga_part: "6slx9tqg144",
            fpga_size: 9,
            fpga_pins: 144,
            connectors: &["P3", "P2"],
            port_width: 17,
            clock_low: 66_666_667,
        },
        vec![
            ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
            ModuleSpec::standard(gtag::IOPORT, 0, 2),
            ModuleSpec::standard(gtag::ENCODER, 0x83, 4),
            ModuleSpec::standard(gtag::PWMGEN, 1, 4),
            ModuleSpec::standard(gtag::LED, 0, 1),
        ],
        pins,
    )
}

/// 5i24 with 8 encoders, 8 PWM generators, 8 step generators.
fn five_i24() -> FirmwareSpec {
    let mut pins = Vec::new();
    for k in 0..8u8 {
        for f in 1..=3 {
            pins.push(pd(gtag::ENCODER, k, f));
        }
    }
    for k in 0..8u8 {
        for f in 0x81..=0x83 {
            pins.push(pd(gtag::PWMGEN, k, f));
        }
    }
    for k in 0..8u8 {
        pins.push(pd(gtag::STEPGEN, k, 0x81));
        pins.push(pd(gtag::STEPGEN, k, 0x82));
    }
    pins.extend(std::iter::repeat_n(gpio(), 8));
    firmware(
        Identity {
            board: "5i24",
            idrom_name: "MESA5I24",
            fpga_part: "6slx16ftg256",
            fpga_size: 16,
            fpga_pins: 256,
            connectors: &["P4", "P3", "P2"],
            port_width: 24,
            clock_low: 100_000_000,
        },
        vec![
            ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
            ModuleSpec::standard(gtag::IOPORT, 0, 3),
            ModuleSpec::standard(gtag::ENCODER, 3, 8),
            ModuleSpec::standard(gtag::STEPGEN, 0xC2, 8),
            ModuleSpec::standard(gtag::PWMGEN, 1, 8),
            ModuleSpec::standard(gtag::LED, 0, 1),
        ],
        pins,
    )
}
