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

/// State two functions of one component both change, when atomics per
/// value would be clumsy. Access never waits: [`Exclusive::try_with`]
/// takes the state only if the other function is not in the middle of
/// using it, which can only happen when the two run in different threads
/// and one preempted the other. Nobody ever blocks on the inner mutex, so
/// taking and releasing it is one atomic operation each, with no system
/// call.
#[derive(Debug, Default)]
pub struct Exclusive<T> {
    inner: std::sync::Mutex<T>,
    missed: std::sync::atomic::AtomicU32,
}

impl<T> Exclusive<T> {
    /// Wraps `v`.
    pub fn new(v: T) -> Exclusive<T> {
        Exclusive {
            inner: std::sync::Mutex::new(v),
            missed: std::sync::atomic::AtomicU32::new(0),
        }
    }

    /// Runs `f` on the state, or returns `None` (and counts a missed
    /// call) if the other function holds it right now.
    pub fn try_with<R>(&self, f: impl FnOnce(&mut T) -> R) -> Option<R> {
        match self.inner.try_lock() {
            Ok(mut g) => Some(f(&mut g)),
            Err(std::sync::TryLockError::Poisoned(p)) => Some(f(&mut p.into_inner())),
            Err(std::sync::TryLockError::WouldBlock) => {
                self.missed.fetch_add(1, Relaxed);
                None
            }
        }
    }

    /// How many calls found the state busy.
    pub fn missed(&self) -> u32 {
        self.missed.load(Relaxed)
    }
}

#[cfg(test)]
mod exclusive_tests {
    use super::*;

    #[test]
    fn a_busy_state_is_skipped_not_waited_for() {
        let e = Exclusive::new(1);
        assert_eq!(e.try_with(|v| *v + 1), Some(2));
        let nested = e.try_with(|_| e.try_with(|v| *v));
        assert_eq!(nested, Some(None));
        assert_eq!(e.missed(), 1);
    }
}
