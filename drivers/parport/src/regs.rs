//! The register map of a PC parallel port (SPP registers, EPP window, ECP
//! extended control register) and the DB-25 pin assignment hal_parport
//! uses.
//!
//! Offsets are from the port's base address, except [`ECR`], which is an
//! offset from `base_hi` (normally `base + 0x400`).

/// Data register: bits 0..7 are DB-25 pins 2..9 (no inversion).
pub const DATA: u16 = 0;
/// Status register (read-only): pins 15, 13, 12, 10, 11 on bits 3..7.
pub const STATUS: u16 = 1;
/// Control register: pins 1, 14, 16, 17 on bits 0..3, IRQ enable, data
/// direction.
pub const CONTROL: u16 = 2;
/// EPP address register.
pub const EPP_ADDR: u16 = 3;
/// EPP data register (four bytes, `base+4..base+7`).
pub const EPP_DATA: u16 = 4;
/// Size of the register window at `base`.
pub const BASE_SPAN: u16 = 8;

/// Usual distance of `base_hi` (the ECP registers) from `base`.
pub const HI_OFFSET: u16 = 0x400;
/// Extended control register, an offset from `base_hi`.
pub const ECR: u16 = 2;
/// Size of the register window at `base_hi`.
pub const HI_SPAN: u16 = 3;

/// ECR value hal_parport writes in `epp` mode: mode field (bits 7..5) =
/// 100 (EPP), interrupts and DMA off.
pub const ECR_EPP_MODE: u8 = 0x94;

/// Status bits the hardware inverts (bit 7, pin 11 Busy).
pub const STATUS_INVERTED: u8 = 0x80;
/// Control bits the hardware inverts (bits 0, 1, 3: pins 1, 14, 17).
pub const CONTROL_INVERTED: u8 = 0x0B;
/// Unused status bits (0..2); a simulator reads them as 1.
pub const STATUS_UNUSED: u8 = 0x07;

/// Control bit 4: IRQ enable (the driver always writes 0).
pub const CONTROL_IRQ: u8 = 0x10;
/// Control bit 5: data direction, 1 = data lines are inputs.
pub const CONTROL_DIR_IN: u8 = 0x20;
/// Control bits 0..3, the four signal lines.
pub const CONTROL_LINES: u8 = 0x0F;

/// Status bits 3..7 in bit order: DB-25 pins 15, 13, 12, 10, 11.
pub const STATUS_PINS: [u8; 5] = [15, 13, 12, 10, 11];
/// Bit number of the first status pin.
pub const STATUS_FIRST_BIT: u32 = 3;
/// Data bits 0..7 in bit order: DB-25 pins 2..9.
pub const DATA_PINS: [u8; 8] = [2, 3, 4, 5, 6, 7, 8, 9];
/// Control bits 0..3 in bit order: DB-25 pins 1, 14, 16, 17.
pub const CONTROL_PINS: [u8; 4] = [1, 14, 16, 17];

/// Where a DB-25 signal pin lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PinReg {
    /// Data register bit.
    Data(u8),
    /// Status register bit.
    Status(u8),
    /// Control register bit.
    Control(u8),
}

/// The register bit of DB-25 pin `pin` (1..17), `None` for ground pins
/// (18..25) and numbers outside the connector.
pub fn pin_reg(pin: u8) -> Option<PinReg> {
    if let Some(b) = DATA_PINS.iter().position(|&p| p == pin) {
        return Some(PinReg::Data(b as u8));
    }
    if let Some(b) = STATUS_PINS.iter().position(|&p| p == pin) {
        return Some(PinReg::Status(b as u8 + STATUS_FIRST_BIT as u8));
    }
    CONTROL_PINS
        .iter()
        .position(|&p| p == pin)
        .map(|b| PinReg::Control(b as u8))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pin_map_covers_the_17_signal_pins_once() {
        let mut seen = 0u32;
        for pin in 1..=25u8 {
            match pin_reg(pin) {
                Some(_) => {
                    assert!(pin <= 17, "pin {pin}");
                    seen |= 1 << pin;
                }
                None => assert!(pin >= 18, "pin {pin}"),
            }
        }
        assert_eq!(seen.count_ones(), 17);
        assert_eq!(pin_reg(11), Some(PinReg::Status(7)));
        assert_eq!(pin_reg(15), Some(PinReg::Status(3)));
        assert_eq!(pin_reg(17), Some(PinReg::Control(3)));
        assert_eq!(pin_reg(0), None);
    }

    #[test]
    fn inverted_lines_match_the_xor_masks() {
        // The pins whose line the hardware inverts between the register
        // bit and the connector.
        let inverted = |pin| match pin_reg(pin) {
            Some(PinReg::Status(b)) => STATUS_INVERTED & (1 << b) != 0,
            Some(PinReg::Control(b)) => CONTROL_INVERTED & (1 << b) != 0,
            _ => false,
        };
        let inv: Vec<u8> = (1..=17).filter(|&p| inverted(p)).collect();
        assert_eq!(inv, vec![1, 11, 14, 17]);
    }
}
