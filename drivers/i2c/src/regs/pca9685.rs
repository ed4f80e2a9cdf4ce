//! NXP PCA9685: 16-channel 12-bit PWM (LED) driver.
//!
//! Channel n's four registers start at [`led_on_l`]`(n)`: ON_L, ON_H,
//! OFF_L, OFF_H, 12-bit counts of a 4096-tick cycle; bit 4 of ON_H is
//! "full on", bit 4 of OFF_H "full off" (full off wins). With
//! [`MODE1_AI`] set a write or read moves through the registers, so one
//! block transfer covers a channel (or several).

/// 7-bit addresses the A5..A0 straps select.
pub const ADDRESSES: std::ops::RangeInclusive<u8> = 0x40..=0x7F;

/// Mode register 1.
pub const MODE1: u8 = 0x00;
/// Mode register 2.
pub const MODE2: u8 = 0x01;
/// First I2C sub-address.
pub const SUBADR1: u8 = 0x02;
/// Second I2C sub-address.
pub const SUBADR2: u8 = 0x03;
/// Third I2C sub-address.
pub const SUBADR3: u8 = 0x04;
/// LED all-call address.
pub const ALLCALLADR: u8 = 0x05;
/// Channel 0's ON_L; channel n is 4n further.
pub const LED0_ON_L: u8 = 0x06;
/// All channels' ON_L at once (write-only).
pub const ALL_LED_ON_L: u8 = 0xFA;
/// All channels' ON_H at once.
pub const ALL_LED_ON_H: u8 = 0xFB;
/// All channels' OFF_L at once.
pub const ALL_LED_OFF_L: u8 = 0xFC;
/// All channels' OFF_H at once.
pub const ALL_LED_OFF_H: u8 = 0xFD;
/// Prescaler for the PWM frequency (writable only while asleep).
pub const PRE_SCALE: u8 = 0xFE;
/// Test mode: never written.
pub const TESTMODE: u8 = 0xFF;

/// MODE1: restart the PWM after a sleep.
pub const MODE1_RESTART: u8 = 1 << 7;
/// MODE1: external clock.
pub const MODE1_EXTCLK: u8 = 1 << 6;
/// MODE1: register auto-increment.
pub const MODE1_AI: u8 = 1 << 5;
/// MODE1: low-power mode, oscillator off.
pub const MODE1_SLEEP: u8 = 1 << 4;
/// MODE1: answers the all-call address.
pub const MODE1_ALLCALL: u8 = 1 << 0;
/// MODE1 at power-up: asleep, all-call on.
pub const MODE1_RESET: u8 = 0x11;

/// MODE2: invert the outputs.
pub const MODE2_INVRT: u8 = 1 << 4;
/// MODE2: outputs change on ACK (else on STOP).
pub const MODE2_OCH: u8 = 1 << 3;
/// MODE2: totem-pole outputs (else open drain).
pub const MODE2_OUTDRV: u8 = 1 << 2;
/// MODE2 at power-up: totem pole.
pub const MODE2_RESET: u8 = 0x04;

/// ON_H/OFF_H: the channel is fully on / fully off.
pub const FULL: u8 = 1 << 4;

/// Ticks in one PWM cycle.
pub const TICKS: u16 = 4096;
/// The internal oscillator, Hz.
pub const OSC_HZ: f64 = 25_000_000.0;
/// Smallest and largest PRE_SCALE values.
pub const PRE_SCALE_RANGE: std::ops::RangeInclusive<u8> = 3..=255;
/// PRE_SCALE at power-up (about 200 Hz).
pub const PRE_SCALE_RESET: u8 = 0x1E;
/// Time the oscillator needs after SLEEP is cleared, ns.
pub const WAKE_NS: u64 = 500_000;

/// Channels.
pub const CHANNELS: usize = 16;

/// Channel `n`'s ON_L register.
pub const fn led_on_l(n: usize) -> u8 {
    LED0_ON_L + 4 * n as u8
}

/// The PRE_SCALE value for `hz`: round(25 MHz / (4096 × hz)) − 1, or
/// None when `hz` is outside what the chip can do (about 24..1526 Hz).
pub fn prescale_for(hz: f64) -> Option<u8> {
    if !hz.is_finite() || hz <= 0.0 {
        return None;
    }
    let p = (OSC_HZ / (TICKS as f64 * hz)).round() - 1.0;
    if p < *PRE_SCALE_RANGE.start() as f64 || p > *PRE_SCALE_RANGE.end() as f64 {
        return None;
    }
    Some(p as u8)
}

/// The PWM frequency a PRE_SCALE value gives, Hz.
pub fn frequency(prescale: u8) -> f64 {
    OSC_HZ / (TICKS as f64 * (prescale as f64 + 1.0))
}

/// The four channel registers for an output `counts` ticks of 4096 on:
/// 0 is full off, 4096 (or more) full on, else on at tick 0 and off at
/// tick `counts`.
pub fn channel_bytes(counts: u16) -> [u8; 4] {
    match counts {
        0 => [0, 0, 0, FULL],
        c if c >= TICKS => [0, FULL, 0, 0],
        c => [0, 0, (c & 0xFF) as u8, (c >> 8) as u8],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prescale_from_the_data_sheet_formula() {
        assert_eq!(prescale_for(200.0), Some(0x1E));
        assert_eq!(prescale_for(1526.0), Some(3));
        assert_eq!(prescale_for(24.0), Some(253));
        assert_eq!(prescale_for(50.0), Some(121));
        assert_eq!(prescale_for(2000.0), None);
        assert_eq!(prescale_for(20.0), None);
        assert_eq!(prescale_for(f64::NAN), None);
        assert!((frequency(121) - 50.0).abs() < 0.2);
    }

    #[test]
    fn channel_registers() {
        assert_eq!(led_on_l(0), 0x06);
        assert_eq!(led_on_l(15), 0x42);
        assert_eq!(channel_bytes(0), [0, 0, 0, 0x10]);
        assert_eq!(channel_bytes(4096), [0, 0x10, 0, 0]);
        assert_eq!(channel_bytes(2048), [0, 0, 0x00, 0x08]);
        assert_eq!(channel_bytes(1), [0, 0, 1, 0]);
        assert_eq!(channel_bytes(4095), [0, 0, 0xFF, 0x0F]);
    }
}
