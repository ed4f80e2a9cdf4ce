//! Speed and character format of a line, and the RTU times that follow
//! from them.

use std::time::Duration;

/// Parity bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Parity {
    /// No parity bit.
    None,
    /// Even parity.
    Even,
    /// Odd parity.
    Odd,
}

impl Parity {
    /// LinuxCNC's spelling.
    pub fn name(self) -> &'static str {
        match self {
            Parity::None => "none",
            Parity::Even => "even",
            Parity::Odd => "odd",
        }
    }
}

/// Baud rate and character format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineSettings {
    /// Bits per second.
    pub baud: u32,
    /// Data bits per character, 5..=8.
    pub data_bits: u8,
    /// Parity.
    pub parity: Parity,
    /// Stop bits, 1 or 2.
    pub stop_bits: u8,
}

/// Above this speed Modbus fixes the inter-frame silence instead of
/// counting characters.
const FIXED_TIMING_ABOVE_BAUD: u32 = 19_200;
/// The fixed 3.5-character silence above 19 200 baud.
const FIXED_T35: Duration = Duration::from_micros(1750);

impl LineSettings {
    /// `baud` with 8 data bits, `parity` and 1 stop bit.
    pub fn new(baud: u32, parity: Parity) -> LineSettings {
        LineSettings {
            baud,
            data_bits: 8,
            parity,
            stop_bits: 1,
        }
    }

    /// Bits on the wire per character: start, data, parity, stop.
    pub fn bits_per_char(&self) -> u32 {
        1 + u32::from(self.data_bits)
            + u32::from(self.parity != Parity::None)
            + u32::from(self.stop_bits)
    }

    /// How long one character takes on the wire.
    pub fn char_time(&self) -> Duration {
        let baud = u64::from(self.baud.max(1));
        Duration::from_nanos(u64::from(self.bits_per_char()) * 1_000_000_000 / baud)
    }

    /// How long `n` characters take on the wire.
    pub fn transmit_time(&self, n: usize) -> Duration {
        self.char_time() * n as u32
    }

    /// A silence of `chars` character times, as Modbus counts it: above
    /// 19 200 baud the 3.5-character silence is a fixed 1.75 ms and other
    /// silences scale with it.
    pub fn silence(&self, chars: f64) -> Duration {
        if self.baud > FIXED_TIMING_ABOVE_BAUD {
            FIXED_T35.mul_f64(chars / 3.5)
        } else {
            self.char_time().mul_f64(chars)
        }
    }
}

impl std::fmt::Display for LineSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = match self.parity {
            Parity::None => 'N',
            Parity::Even => 'E',
            Parity::Odd => 'O',
        };
        write!(
            f,
            "{} baud {}{}{}",
            self.baud, self.data_bits, p, self.stop_bits
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn character_and_frame_times() {
        let s = LineSettings::new(19_200, Parity::Even);
        assert_eq!(s.bits_per_char(), 11);
        assert_eq!(s.char_time(), Duration::from_nanos(572_916));
        // 3.5 characters at 19 200 baud 8E1: about 2 ms.
        assert_eq!(s.silence(3.5), Duration::from_nanos(2_005_206));
        let fast = LineSettings::new(38_400, Parity::None);
        assert_eq!(fast.bits_per_char(), 10);
        assert_eq!(fast.silence(3.5), Duration::from_micros(1750));
        assert_eq!(fast.silence(1.5), Duration::from_micros(750));
        assert_eq!(fast.to_string(), "38400 baud 8N1");
    }
}
