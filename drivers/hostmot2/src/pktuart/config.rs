//! A line configuration and the register words it becomes: the bit-rate
//! word (baud x 2^24 / clock, 24 bits from v2; 20 bits before) and the
//! mode words, with the inter-frame delay scaled by 4 past 255 bit times
//! on v3+ and clamped to 255 before.

use crate::regs::pktuart::{rx, tx};

/// One direction's settings, as `hm2_pktuart_config` takes them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineConfig {
    /// Baud rate.
    pub baud: u32,
    /// Parity: 0 none, 1 odd, 2 even.
    pub parity: u8,
    /// Two stop bits (v3+ only; ignored before).
    pub stop_bits2: bool,
    /// Inter-frame delay in bit times (0..=1020).
    pub if_delay: u32,
    /// TX: driver-enable to data delay (0..=15).
    pub drive_delay: u32,
    /// RX: enables the receiver; masks its input while sending (half
    /// duplex) when `rx_mask` is set too.
    pub rx_enable: bool,
    /// RX: masks the input while the transmitter sends.
    pub rx_mask: bool,
}

/// The words to write for one direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModeWords {
    /// The bit-rate register.
    pub bitrate: u32,
    /// The mode register.
    pub mode: u32,
}

/// The bit-rate word for `baud` at `clock_hz` on module `version`.
pub fn bitrate_word(baud: u32, clock_hz: u32, version: u8) -> u32 {
    let clock = u64::from(clock_hz.max(1));
    if version >= 2 {
        ((u64::from(baud) << 24) / clock).clamp(1, 0x00FF_FFFF) as u32
    } else {
        ((u64::from(baud) << 20) / clock).min(0x000F_FFFF) as u32
    }
}

/// The baud a bit-rate word gives (the simulator's reading of it).
pub fn baud_of(bitrate: u32, clock_hz: u32, version: u8) -> u32 {
    let shift = if version >= 2 { 24 } else { 20 };
    let mask = if version >= 2 {
        0x00FF_FFFF
    } else {
        0x000F_FFFF
    };
    ((u64::from(bitrate & mask) * u64::from(clock_hz)) >> shift) as u32
}

/// The inter-frame delay field and whether it is scaled by 4.
fn if_delay_field(delay: u32, version: u8, round_up: bool) -> (u32, bool) {
    if delay <= 0xFF {
        (delay, false)
    } else if version >= 3 {
        let q = if round_up {
            delay.div_ceil(4)
        } else {
            delay / 4
        };
        (q.min(0xFF), true)
    } else {
        (0xFF, false)
    }
}

/// Parity bits common to both directions.
fn parity_bits(c: &LineConfig, en: u32, odd: u32) -> u32 {
    match c.parity {
        0 => 0,
        1 => en | odd,
        _ => en,
    }
}

/// The transmitter's words: the driver always enabled automatically.
pub fn tx_words(c: &LineConfig, clock_hz: u32, version: u8) -> ModeWords {
    let (delay, scaled) = if_delay_field(c.if_delay, version, true);
    let mut mode = delay << tx::IF_DELAY_SHIFT
        | (c.drive_delay & tx::DRIVE_DELAY_MASK)
        | tx::DRIVE_AUTO
        | tx::DRIVE_EN
        | parity_bits(c, tx::PARITY_EN, tx::PARITY_ODD);
    if scaled {
        mode |= tx::IF_SCALE;
    }
    if c.stop_bits2 && version >= 3 {
        mode |= tx::STOP_BITS2;
    }
    ModeWords {
        bitrate: bitrate_word(c.baud, clock_hz, version),
        mode,
    }
}

/// The receiver's words: the input filter at half a bit time.
pub fn rx_words(c: &LineConfig, clock_hz: u32, version: u8) -> ModeWords {
    let filter = clock_hz / c.baud.saturating_mul(2).max(1);
    let mut bitrate = bitrate_word(c.baud, clock_hz, version);
    let filter = if version >= 2 {
        let f = filter.min(0xFFFF);
        bitrate |= (f & 0xFF00) << 16;
        f & 0xFF
    } else {
        filter.min(0xFF)
    };
    let (delay, scaled) = if_delay_field(c.if_delay, version, false);
    let mut mode = filter << rx::FILTER_SHIFT
        | delay << rx::IF_DELAY_SHIFT
        | parity_bits(c, rx::PARITY_EN, rx::PARITY_ODD);
    if c.rx_enable {
        mode |= rx::RX_EN;
    }
    if c.rx_mask {
        mode |= rx::RX_MASK_EN;
    }
    if scaled {
        mode |= rx::IF_SCALE;
    }
    if c.stop_bits2 && version >= 3 {
        mode |= rx::STOP_BITS2;
    }
    ModeWords { bitrate, mode }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(baud: u32, if_delay: u32) -> LineConfig {
        LineConfig {
            baud,
            parity: 2,
            stop_bits2: false,
            if_delay,
            drive_delay: 1,
            rx_enable: true,
            rx_mask: true,
        }
    }

    #[test]
    fn bitrate_round_trips_at_common_rates() {
        for baud in [9600, 19200, 115_200] {
            let w = bitrate_word(baud, 100_000_000, 3);
            let back = baud_of(w, 100_000_000, 3);
            assert!(back.abs_diff(baud) <= baud / 1000 + 1, "{baud} -> {back}");
        }
        assert_eq!(bitrate_word(9600, 100_000_000, 3), 1610);
    }

    #[test]
    fn long_delays_scale_on_v3_and_clamp_before() {
        let w = tx_words(&line(9600, 600), 100_000_000, 3);
        assert_eq!((w.mode >> 8) & 0xFF, 150);
        assert_ne!(w.mode & tx::IF_SCALE, 0);
        let w = tx_words(&line(9600, 600), 100_000_000, 2);
        assert_eq!((w.mode >> 8) & 0xFF, 255);
        assert_eq!(w.mode & tx::IF_SCALE, 0);
    }

    #[test]
    fn even_parity_sets_enable_only() {
        let w = rx_words(&line(9600, 40), 100_000_000, 3);
        assert_ne!(w.mode & rx::PARITY_EN, 0);
        assert_eq!(w.mode & rx::PARITY_ODD, 0);
        assert_ne!(w.mode & rx::RX_EN, 0);
        assert_ne!(w.mode & rx::RX_MASK_EN, 0);
        // 100 MHz / 19200 = 5208 = 0x1458: low byte in the mode, high
        // byte in the bit-rate word.
        assert_eq!((w.mode >> rx::FILTER_SHIFT) & 0xFF, 0x58);
        assert_eq!(w.bitrate >> 24, 0x14);
    }
}
