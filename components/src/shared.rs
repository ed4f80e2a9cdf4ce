//! State that two functions of one component share. They may run in
//! different threads that preempt each other, so what they share lives in
//! atomics (relaxed: each value is read and written whole, and the
//! functions of one instance never need more ordering than that).

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// An `f64` stored in an atomic word.
#[derive(Debug, Default)]
pub struct AtomicF64(AtomicU64);

impl AtomicF64 {
    /// A cell holding `v`.
    pub fn new(v: f64) -> AtomicF64 {
        AtomicF64(AtomicU64::new(v.to_bits()))
    }

    /// The value.
    #[inline(always)]
    pub fn get(&self) -> f64 {
        f64::from_bits(self.0.load(Relaxed))
    }

    /// Replaces the value.
    #[inline(always)]
    pub fn set(&self, v: f64) {
        self.0.store(v.to_bits(), Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_every_bit_of_the_value() {
        let c = AtomicF64::new(-0.0);
        assert!(c.get().is_sign_negative());
        c.set(f64::MIN_POSITIVE);
        assert_eq!(c.get(), f64::MIN_POSITIVE);
        assert_eq!(AtomicF64::default().get(), 0.0);
    }
}
