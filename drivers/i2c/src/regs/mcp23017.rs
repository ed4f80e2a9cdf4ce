//! Microchip MCP23017: 16-bit I/O expander, ports A (GPA0..7) and B
//! (GPB0..7).
//!
//! Addresses are those of IOCON.BANK = 0 (the power-up map), where the A
//! and B registers of each kind are neighbours, so with sequential
//! addressing (IOCON.SEQOP = 0) one 16-bit transfer at the A register
//! covers both ports, A in the first byte: what an SMBus word transfer
//! (low byte first) carries as bits 0..7 = port A, 8..15 = port B.

/// 7-bit addresses the A2..A0 straps select.
pub const ADDRESSES: std::ops::RangeInclusive<u8> = 0x20..=0x27;

/// Direction, port A (1 = input).
pub const IODIRA: u8 = 0x00;
/// Direction, port B.
pub const IODIRB: u8 = 0x01;
/// Input polarity, port A.
pub const IPOLA: u8 = 0x02;
/// Input polarity, port B.
pub const IPOLB: u8 = 0x03;
/// Interrupt-on-change enable, port A.
pub const GPINTENA: u8 = 0x04;
/// Interrupt-on-change enable, port B.
pub const GPINTENB: u8 = 0x05;
/// Interrupt compare value, port A.
pub const DEFVALA: u8 = 0x06;
/// Interrupt compare value, port B.
pub const DEFVALB: u8 = 0x07;
/// Interrupt control (1 = compare with DEFVAL), port A.
pub const INTCONA: u8 = 0x08;
/// Interrupt control, port B.
pub const INTCONB: u8 = 0x09;
/// Configuration (shared by both addresses).
pub const IOCON: u8 = 0x0A;
/// Configuration, its second address.
pub const IOCON_B: u8 = 0x0B;
/// 100 kΩ pull-ups, port A.
pub const GPPUA: u8 = 0x0C;
/// Pull-ups, port B.
pub const GPPUB: u8 = 0x0D;
/// Interrupt flags, port A (read-only).
pub const INTFA: u8 = 0x0E;
/// Interrupt flags, port B.
pub const INTFB: u8 = 0x0F;
/// Port value captured at the interrupt, port A (read-only).
pub const INTCAPA: u8 = 0x10;
/// Captured value, port B.
pub const INTCAPB: u8 = 0x11;
/// Pins, port A (a write goes to OLATA).
pub const GPIOA: u8 = 0x12;
/// Pins, port B.
pub const GPIOB: u8 = 0x13;
/// Output latches, port A.
pub const OLATA: u8 = 0x14;
/// Output latches, port B.
pub const OLATB: u8 = 0x15;
/// Registers in the BANK = 0 map.
pub const REGISTERS: u8 = 0x16;

/// IOCON: registers grouped by port.
pub const IOCON_BANK: u8 = 1 << 7;
/// IOCON: INTA and INTB tied together.
pub const IOCON_MIRROR: u8 = 1 << 6;
/// IOCON: no address auto-increment.
pub const IOCON_SEQOP: u8 = 1 << 5;
/// IOCON: slew rate control of SDA off.
pub const IOCON_DISSLW: u8 = 1 << 4;
/// IOCON: hardware address enable (SPI variant only).
pub const IOCON_HAEN: u8 = 1 << 3;
/// IOCON: open-drain interrupt output.
pub const IOCON_ODR: u8 = 1 << 2;
/// IOCON: interrupt output active high.
pub const IOCON_INTPOL: u8 = 1 << 1;

/// The address that is IOCON under BANK = 1 and GPINTENB under BANK = 0:
/// writing 0 there leaves a chip in either map in BANK = 0 without
/// touching anything that matters (see [`crate::chips::mcp23017`]).
pub const IOCON_IN_BANK1: u8 = 0x05;

/// GPA7 and GPB7: output-only on current silicon (newer data sheet
/// revisions withdrew their input function).
pub const OUTPUT_ONLY_PINS: u16 = 1 << 7 | 1 << 15;

/// Register address of kind `a_reg` (the port A register in the BANK = 0
/// map) for port `port` (0 = A, 1 = B) under `bank` (IOCON.BANK).
pub const fn address(a_reg: u8, port: u8, bank: bool) -> u8 {
    if bank {
        (a_reg / 2) + 0x10 * port
    } else {
        a_reg + port
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bank1_map() {
        assert_eq!(address(IODIRA, 0, true), 0x00);
        assert_eq!(address(IODIRA, 1, true), 0x10);
        assert_eq!(address(IOCON, 0, true), IOCON_IN_BANK1);
        assert_eq!(address(IOCON, 1, true), 0x15);
        assert_eq!(address(GPIOA, 1, true), 0x19);
        assert_eq!(address(OLATA, 0, true), 0x0A);
        assert_eq!(address(GPPUA, 1, false), GPPUB);
    }
}
