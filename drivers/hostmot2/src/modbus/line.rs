//! The line settings an mbccb file asks for, with LinuxCNC's automatic
//! values: inter-frame delays of 3.5 characters up to 19200 baud and
//! 1750 us above (the receiver one bit time shorter, the transmitter one
//! longer), an inter-character limit of 1.5 characters (750 us above
//! 19200 baud, v3+ receivers only), and a driver delay of one.

use crate::pktuart::LineConfig;

/// What the `hm2_modbus.N.*` parameters show and the PktUART is set to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Line {
    /// Baud rate.
    pub baud: u32,
    /// 0 none, 1 odd, 2 even.
    pub parity: u32,
    /// 1 or 2.
    pub stop_bits: u32,
    /// Receive inter-frame delay, bit times.
    pub rxdelay: u32,
    /// Transmit inter-frame delay, bit times.
    pub txdelay: u32,
    /// Driver delay.
    pub drvdelay: u32,
    /// Inter-character limit, bit times (0: not checked).
    pub icdelay: u32,
    /// Full duplex: the receiver is not masked while sending.
    pub full_duplex: bool,
}

/// The 3.5-character inter-frame delay in bit times.
pub fn if_delay(baud: u32, parity: u32, stop_bits: u32) -> u32 {
    if baud > 582_000 {
        return 1020;
    }
    if baud > 19_200 {
        return (175 * u64::from(baud)).div_ceil(100_000) as u32;
    }
    let bits = 1 + 8 + u32::from(parity != 0) + if stop_bits > 1 { 2 } else { 1 };
    (bits * 35).div_ceil(10)
}

/// The 1.5-character inter-character limit in bit times.
pub fn ic_delay(baud: u32, parity: u32, stop_bits: u32) -> u32 {
    if baud <= 19_200 {
        let bits = 8 + u32::from(parity != 0) + stop_bits;
        (15 * bits + 14) / 10
    } else {
        ((75 * u64::from(baud)).div_ceil(100_000) as u32).min(255)
    }
}

/// Version limits of the PktUART halves applied to a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Versions {
    /// Receiver version.
    pub rx: u8,
    /// Transmitter version.
    pub tx: u8,
}

impl Line {
    /// The settings from the values given (0 meaning automatic), within
    /// what the PktUART versions can do.
    pub fn new(baud: u32, parity: u32, stop_bits: u32, manual: [u32; 4], v: Versions) -> Line {
        let [rxd, txd, drv, ic] = manual;
        let stop_bits = if v.rx < 3 || v.tx < 3 { 1 } else { stop_bits };
        let auto = if_delay(baud, parity, stop_bits);
        let mut rxdelay = if rxd == 0 {
            auto.saturating_sub(1)
        } else {
            rxd
        };
        let mut txdelay = if txd == 0 { auto + 1 } else { txd };
        if v.rx < 3 {
            rxdelay = rxdelay.min(255);
        }
        if v.tx < 3 {
            txdelay = txdelay.min(255);
        }
        let icdelay = match (v.rx >= 3, ic) {
            (false, _) => 0,
            (true, 0) => ic_delay(baud, parity, stop_bits),
            (true, m) => m,
        };
        Line {
            baud,
            parity,
            stop_bits,
            rxdelay,
            txdelay,
            drvdelay: if drv == 0 { 1 } else { drv },
            icdelay,
            full_duplex: false,
        }
    }

    /// The receiver's and the transmitter's configuration.
    pub fn configs(&self) -> (LineConfig, LineConfig) {
        let base = LineConfig {
            baud: self.baud,
            parity: self.parity as u8,
            stop_bits2: self.stop_bits > 1,
            if_delay: self.rxdelay,
            drive_delay: 0,
            rx_enable: true,
            rx_mask: !self.full_duplex,
        };
        let tx = LineConfig {
            if_delay: self.txdelay,
            drive_delay: self.drvdelay,
            rx_enable: false,
            rx_mask: false,
            ..base
        };
        (base, tx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn automatic_delays_follow_the_modbus_timings() {
        // 8E1 at 9600: 11 bits a character, 3.5 characters = 38.5 -> 39.
        assert_eq!(if_delay(9600, 2, 1), 39);
        // Above 19200: 1750 us; 115200 baud -> 201.6 -> 202 bit times.
        assert_eq!(if_delay(115_200, 2, 1), 202);
        assert_eq!(ic_delay(9600, 2, 1), 16);
        let v3 = Versions { rx: 3, tx: 3 };
        let l = Line::new(9600, 2, 1, [0; 4], v3);
        assert_eq!(
            (l.rxdelay, l.txdelay, l.drvdelay, l.icdelay),
            (38, 40, 1, 16)
        );
        let v2 = Versions { rx: 2, tx: 2 };
        let l = Line::new(1_000_000, 0, 2, [0; 4], v2);
        assert_eq!(
            (l.rxdelay, l.txdelay, l.stop_bits, l.icdelay),
            (255, 255, 1, 0)
        );
    }
}
