//! The register map of the Pico Systems boards on the EPP bus.
//!
//! The bus has 256 byte addresses in 16 slots of 16. A board answers in
//! the slot its address switches select; the last byte of that slot
//! ([`ID_OFFSET`]) reads its ID: the kind in the high nibble
//! ([`id`]), the firmware revision in the low one. The USC, the UPC and
//! revision 4 and later encoder boards decode two slots (32 bytes), so
//! the next board sits two slots on. Offsets below are from the board's
//! first byte; a register that reads and writes different things is
//! listed under both names.

/// Slots on one EPP bus.
pub const SLOTS: usize = 16;
/// Bytes per slot.
pub const SLOT_SIZE: u8 = 16;
/// The ID byte's offset in a slot.
pub const ID_OFFSET: u8 = 15;
/// The bytes one board may decode (two slots).
pub const SPAN: usize = 32;

/// Board kinds: the ID byte's high nibble.
pub mod id {
    /// PPMC encoder board: four 24-bit counters.
    pub const ENCODER: u8 = 0x10;
    /// PPMC DAC board: four 16-bit DACs.
    pub const DAC: u8 = 0x20;
    /// PPMC digital I/O board: 16 inputs, 8 outputs, the estop circuit.
    pub const DIO: u8 = 0x30;
    /// Universal Stepper Controller: 4 step generators, 4 counters, 16
    /// inputs, 8 outputs, the 8-bit extra port.
    pub const USC: u8 = 0x40;
    /// Universal PWM Controller: 4 PWM generators, 4 counters, 16
    /// inputs, 8 outputs, the extra port.
    pub const UPC: u8 = 0x50;
}

/// Encoder counters (encoder board, USC, UPC).
pub mod enc {
    /// Counter 0's low byte; each counter is 3 bytes, little-endian.
    pub const COUNT0: u8 = 0x00;
    /// Bytes per counter.
    pub const COUNT_BYTES: u8 = 3;
    /// Write: the preset loaded into the counters by [`CTRL`] (3 bytes).
    pub const LOAD: u8 = 0x00;
    /// Write: control; [`CTRL_RESET_ALL`] loads every counter from [`LOAD`].
    pub const CTRL: u8 = 0x03;
    /// Write: latch control; [`RATE_MASTER`] makes this board drive the
    /// bus's latch strobe, [`RATE_STROBE`] is the strobe.
    pub const RATE: u8 = 0x04;
    /// Write (encoder board rev 4+): the input filter clock, [`CLOCKS`].
    pub const CLOCK: u8 = 0x05;
    /// Read: index seen since the last read, one bit per counter.
    pub const ISR: u8 = 0x0C;
    /// Write: clear the counter at its next index, one bit per counter.
    pub const INDEX: u8 = 0x0D;
    /// Read (rev 4+, with timestamps): counter 0's timestamp, 2 bytes per
    /// counter: the 1 MHz timebase when it last counted.
    pub const TS0: u8 = 0x10;
    /// Read: the timebase at the latch strobe (2 bytes).
    pub const TB: u8 = 0x18;
    /// [`CTRL`] value that loads all four counters.
    pub const CTRL_RESET_ALL: u8 = 0xF0;
    /// [`RATE`] bit: this board makes the latch strobe.
    pub const RATE_MASTER: u8 = 0x10;
    /// [`RATE`] bit: the strobe itself.
    pub const RATE_STROBE: u8 = 0x20;
    /// Timebase ticks per second.
    pub const TIMEBASE_HZ: f64 = 1e6;
    /// Filter clock choices in MHz (as `enc_clock` names them: 1, 2 for
    /// 2.5, 5, 10) and the [`CLOCK`] code of each.
    pub const CLOCKS: [(u8, u8); 4] = [(1, 0), (2, 1), (5, 2), (10, 3)];
}

/// PPMC DAC board.
pub mod dac {
    /// DAC 0's low byte; 2 bytes per DAC, little-endian.
    pub const DAC0: u8 = 0x00;
    /// The code of 0 V (0x0000 is -10 V, 0xFFFF +10 V).
    pub const ZERO: u16 = 0x8000;
    /// Full scale in volts.
    pub const FULL_SCALE_V: f64 = 10.0;
}

/// USC step generators.
pub mod stepgen {
    /// Generator 0's divisor, 3 bytes per generator, little-endian.
    pub const RATE0: u8 = 0x10;
    /// Run and direction bits, two per generator (generator 0 in bits 0..1).
    pub const CTRL: u8 = 0x1C;
    /// Step setup time, as 256 minus 100 ns ticks.
    pub const SETUP: u8 = 0x1D;
    /// Step pulse width, as 256 minus 100 ns ticks.
    pub const WIDTH: u8 = 0x1E;
    /// The generators' clock.
    pub const CLOCK_HZ: f64 = 10e6;
    /// The divisor the hardware adds to the one written.
    pub const DIVISOR_OFFSET: u32 = 4;
    /// The largest divisor (24 bits).
    pub const MAX_DIVISOR: u32 = 0xFF_FFFF;
}

/// UPC PWM generators.
pub mod pwm {
    /// Generator 0's stop count, 2 bytes per generator, little-endian.
    pub const GEN0: u8 = 0x10;
    /// Enable and direction bits, two per generator.
    pub const CTRL: u8 = 0x1C;
    /// The period counter's start value, low byte (65536 - period).
    pub const FREQ_LO: u8 = 0x1D;
    /// Its high byte.
    pub const FREQ_HI: u8 = 0x1E;
    /// The PWM clock of firmware revisions before 3.
    pub const CLOCK_OLD_HZ: f64 = 10e6;
    /// The PWM clock from revision 3 on.
    pub const CLOCK_HZ: f64 = 40e6;
    /// The highest carrier frequency.
    pub const MAX_FREQ_HZ: f64 = 500e3;
}

/// The run and direction bits of a USC or UPC control byte: generator
/// `n`'s pair is bits `2n` (forward) and `2n + 1` (run).
pub mod ctrl {
    /// Forward (the direction output for positive commands).
    pub const FORWARD: u8 = 0x01;
    /// Running / enabled.
    pub const RUN: u8 = 0x02;
}

/// USC and UPC digital I/O.
pub mod uxc {
    /// Read: inputs 0..7.
    pub const DIN_A: u8 = 0x0D;
    /// Read: inputs 8..15; bit 7 is the estop input, which reads 1 only
    /// while the estop output is on and the safety chain is closed.
    pub const DIN_B: u8 = 0x0E;
    /// Write: the 8-bit extra port (spindle DAC or 8 outputs).
    pub const EXTRA: u8 = 0x0F;
    /// Write: outputs 0..7; bit 7 is the estop output.
    pub const DOUT: u8 = 0x1F;
    /// Write: 1 makes a second USC/UPC a slave of the first's estop.
    pub const SLAVE: u8 = 0x06;
    /// Bit of the estop in [`DIN_B`] and [`DOUT`].
    pub const ESTOP_BIT: u8 = 0x80;
}

/// PPMC digital I/O board.
pub mod dio {
    /// Read: inputs 0..7.
    pub const DIN_A: u8 = 0x00;
    /// Read: inputs 8..15.
    pub const DIN_B: u8 = 0x01;
    /// Read: bit 0 the estop input (1: the board is in estop), bit 1 the
    /// fault input.
    pub const ESTOP_IN: u8 = 0x02;
    /// Write: outputs 0..7.
    pub const DOUT: u8 = 0x00;
    /// Write: bit 0 the estop output; [`SLAVE`] makes a further DIO board
    /// a slave of the first.
    pub const ESTOP_OUT: u8 = 0x02;
    /// [`ESTOP_OUT`] value of a slave board.
    pub const SLAVE: u8 = 0x02;
}

/// The 16-bit DAC code of `volts` (clamped to ±10 V; NaN gives 0 V).
pub fn dac16_code(volts: f64) -> u16 {
    if volts.is_nan() {
        return dac::ZERO;
    }
    let code = (volts / dac::FULL_SCALE_V) * 32767.0 + 32768.0;
    code.clamp(0.0, 65535.0) as u16
}

/// The extra port's 8-bit DAC code of `volts`: magnitude only, 0..10 V.
pub fn dac8_code(volts: f64) -> u8 {
    if volts.is_nan() {
        return 0;
    }
    ((volts.abs() / dac::FULL_SCALE_V) * 255.0).clamp(0.0, 255.0) as u8
}

/// Places `v`'s low `n` bytes little-endian at `at` in `buf`.
#[inline]
pub fn put_le(buf: &mut [u8; SPAN], at: u8, v: u32, n: u8) {
    for i in 0..n {
        buf[(at + i) as usize & (SPAN - 1)] = (v >> (8 * i)) as u8;
    }
}

/// Reads `n` bytes little-endian at `at` from `buf`.
#[inline]
pub fn get_le(buf: &[u8; SPAN], at: u8, n: u8) -> u32 {
    (0..n).fold(0, |v, i| {
        v | (buf[(at + i) as usize & (SPAN - 1)] as u32) << (8 * i)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dac_codes() {
        assert_eq!(dac16_code(0.0), 0x8000);
        assert_eq!(dac16_code(10.0), 0xFFFF);
        assert_eq!(dac16_code(-10.0), 0x0001);
        assert_eq!(dac16_code(-20.0), 0x0000);
        assert_eq!(dac16_code(f64::NAN), 0x8000);
        assert_eq!(dac8_code(-10.0), 255);
        assert_eq!(dac8_code(5.0), 127);
        assert_eq!(dac8_code(f64::NAN), 0);
    }

    #[test]
    fn little_endian_fields() {
        let mut b = [0u8; SPAN];
        put_le(&mut b, 0x10, 0x0A0B0C, 3);
        assert_eq!(&b[0x10..0x13], &[0x0C, 0x0B, 0x0A]);
        assert_eq!(get_le(&b, 0x10, 3), 0x0A0B0C);
    }
}
