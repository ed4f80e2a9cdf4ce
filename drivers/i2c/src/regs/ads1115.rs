//! TI ADS1115: 16-bit delta-sigma ADC, four inputs through a multiplexer,
//! programmable gain.
//!
//! A write's first byte sets the pointer register; 16-bit registers are
//! sent **most significant byte first**, the opposite of SMBus word
//! transfers, so the driver swaps the bytes of every word it moves.

/// 7-bit addresses the ADDR pin selects (GND, VDD, SDA, SCL).
pub const ADDRESSES: std::ops::RangeInclusive<u8> = 0x48..=0x4B;

/// Conversion result (signed, read-only).
pub const CONVERSION: u8 = 0x00;
/// Configuration.
pub const CONFIG: u8 = 0x01;
/// Comparator low threshold.
pub const LO_THRESH: u8 = 0x02;
/// Comparator high threshold.
pub const HI_THRESH: u8 = 0x03;

/// CONFIG at power-up.
pub const CONFIG_RESET: u16 = 0x8583;
/// LO_THRESH at power-up.
pub const LO_THRESH_RESET: u16 = 0x8000;
/// HI_THRESH at power-up.
pub const HI_THRESH_RESET: u16 = 0x7FFF;

/// CONFIG: write 1 to start a single conversion; reads 0 while
/// converting, 1 when idle.
pub const OS: u16 = 1 << 15;
/// CONFIG: multiplexer field shift (3 bits).
pub const MUX_SHIFT: u16 = 12;
/// CONFIG: gain field shift (3 bits).
pub const PGA_SHIFT: u16 = 9;
/// CONFIG: single-shot mode (else continuous).
pub const MODE_SINGLE: u16 = 1 << 8;
/// CONFIG: data rate field shift (3 bits).
pub const DR_SHIFT: u16 = 5;
/// CONFIG: comparator off (COMP_QUE = 11).
pub const COMP_QUE_OFF: u16 = 0b11;

/// MUX codes 4..7: AINn against GND.
pub const MUX_SINGLE_0: u16 = 0b100;
/// MUX code: AIN0 − AIN1.
pub const MUX_DIFF_0_1: u16 = 0b000;
/// MUX code: AIN2 − AIN3.
pub const MUX_DIFF_2_3: u16 = 0b011;

/// Full-scale volts by PGA code (codes 5..7 are all ±0.256 V).
pub const FULL_SCALE: [f64; 8] = [6.144, 4.096, 2.048, 1.024, 0.512, 0.256, 0.256, 0.256];

/// Samples per second by DR code.
pub const RATES: [u32; 8] = [8, 16, 32, 64, 128, 250, 475, 860];

/// The PGA code for a full-scale range in millivolts, if the chip has it.
pub fn pga_for_mv(mv: i64) -> Option<u16> {
    FULL_SCALE[..6]
        .iter()
        .position(|fs| (fs * 1000.0).round() as i64 == mv)
        .map(|p| p as u16)
}

/// The DR code for a rate in samples per second, if the chip has it.
pub fn dr_for_sps(sps: i64) -> Option<u16> {
    RATES
        .iter()
        .position(|&r| r as i64 == sps)
        .map(|p| p as u16)
}

/// Volts per count at PGA code `pga`.
pub fn lsb_volts(pga: u16) -> f64 {
    FULL_SCALE[(pga & 7) as usize] / 32768.0
}

/// The nominal conversion time at DR code `dr`, ns.
pub fn conversion_ns(dr: u16) -> u64 {
    1_000_000_000 / RATES[(dr & 7) as usize] as u64
}

/// The code for `volts` at full scale `fs`: round(V / FS × 32768),
/// clipped to the register's range.
pub fn code_for(volts: f64, fs: f64) -> i16 {
    let c = (volts / fs * 32768.0).round();
    if c.is_nan() {
        0
    } else {
        c.clamp(-32768.0, 32767.0) as i16
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables() {
        assert_eq!(pga_for_mv(4096), Some(1));
        assert_eq!(pga_for_mv(256), Some(5));
        assert_eq!(pga_for_mv(5000), None);
        assert_eq!(dr_for_sps(860), Some(7));
        assert_eq!(dr_for_sps(100), None);
        assert_eq!(conversion_ns(4), 7_812_500);
        assert_eq!(lsb_volts(2), 2.048 / 32768.0);
        assert_eq!(code_for(1.024, 2.048), 16384);
        assert_eq!(code_for(3.0, 2.048), 32767);
        assert_eq!(code_for(-3.0, 2.048), -32768);
        assert_eq!(code_for(f64::NAN, 2.048), 0);
        assert_eq!((CONFIG_RESET >> PGA_SHIFT) & 7, 2, "±2.048 V at power-up");
    }
}
