//! The GPIO character device's uAPI v2 as this driver uses it
//! (`linux/gpio.h`, hardware.md 7.1): the driver's "register map".
//!
//! A line request holds at most [`LINES_MAX`] lines; bit k of a request's
//! value words is the k-th requested offset in ascending order (gpiocdev
//! sorts the offsets before it asks the kernel). Values are *logical*:
//! with [`flags::ACTIVE_LOW`] a 1 is electrically low.

/// `GPIO_V2_LINES_MAX`: lines in one request.
pub const LINES_MAX: usize = 64;

/// `GPIO_MAX_NAME_SIZE`: bytes of a chip or line name, consumer or label,
/// including the terminating NUL.
pub const NAME_SIZE: usize = 32;

/// The consumer name this driver's requests carry (what `gpioinfo` shows
/// beside a line in use).
pub const CONSUMER: &str = "hal_gpio";

/// `enum gpio_v2_line_flag`: a line's configuration as the kernel reports
/// it in line info and takes it in a request.
pub mod flags {
    /// The line is requested (line info only).
    pub const USED: u64 = 1 << 0;
    /// Logical 1 is electrically low.
    pub const ACTIVE_LOW: u64 = 1 << 1;
    /// Input.
    pub const INPUT: u64 = 1 << 2;
    /// Output.
    pub const OUTPUT: u64 = 1 << 3;
    /// Open drain: drives low, floats high (outputs only).
    pub const OPEN_DRAIN: u64 = 1 << 6;
    /// Open source: drives high, floats low (outputs only).
    pub const OPEN_SOURCE: u64 = 1 << 7;
    /// Internal pull-up.
    pub const BIAS_PULL_UP: u64 = 1 << 8;
    /// Internal pull-down.
    pub const BIAS_PULL_DOWN: u64 = 1 << 9;
    /// Bias explicitly disabled.
    pub const BIAS_DISABLED: u64 = 1 << 10;
}

/// The mask of the first `n` request bits (n ≤ [`LINES_MAX`]).
#[inline]
pub const fn low_bits(n: usize) -> u64 {
    if n >= 64 {
        u64::MAX
    } else {
        (1u64 << n) - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks() {
        assert_eq!(low_bits(0), 0);
        assert_eq!(low_bits(3), 0b111);
        assert_eq!(low_bits(64), u64::MAX);
    }

    #[test]
    fn flags_match_the_uapi_crate() {
        use gpiocdev_uapi::v2::LineFlags as F;
        assert_eq!(flags::USED, F::USED.bits());
        assert_eq!(flags::ACTIVE_LOW, F::ACTIVE_LOW.bits());
        assert_eq!(flags::INPUT, F::INPUT.bits());
        assert_eq!(flags::OUTPUT, F::OUTPUT.bits());
        assert_eq!(flags::OPEN_DRAIN, F::OPEN_DRAIN.bits());
        assert_eq!(flags::OPEN_SOURCE, F::OPEN_SOURCE.bits());
        assert_eq!(flags::BIAS_PULL_UP, F::BIAS_PULL_UP.bits());
        assert_eq!(flags::BIAS_PULL_DOWN, F::BIAS_PULL_DOWN.bits());
        assert_eq!(flags::BIAS_DISABLED, F::BIAS_DISABLED.bits());
        assert_eq!(LINES_MAX, gpiocdev_uapi::NUM_LINES_MAX);
    }
}
