//! [`RtCell`]: state that a driver's `read` and `write` functions share,
//! handed to one of them at a time without a lock (canservo's engine,
//! lcec's masters).
//!
//! Both functions normally run in the same HAL thread, one after the
//! other, and never overlap. If a configuration puts them in two threads
//! that preempt each other, they could; a mutex would then make the
//! faster thread wait for the slower one, which a realtime function must
//! not do. Instead a function that finds the cell busy skips its work
//! this cycle (counted in [`RtCell::collisions`]); nothing waits, and
//! the state is never touched by two at once.

use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::*};

/// Exclusive, non-blocking access to a `T`.
#[derive(Debug)]
pub struct RtCell<T> {
    busy: AtomicBool,
    collisions: AtomicU64,
    value: UnsafeCell<T>,
}

// SAFETY: the value is only reached through `try_with`, which hands out
// the `&mut T` to one caller at a time (the `busy` flag, taken with an
// acquire compare-exchange and released with a release store, orders the
// accesses); `T: Send` lets it move between the threads that take turns.
unsafe impl<T: Send> Sync for RtCell<T> {}

impl<T> RtCell<T> {
    /// A cell holding `value`.
    pub fn new(value: T) -> RtCell<T> {
        RtCell {
            busy: AtomicBool::new(false),
            collisions: AtomicU64::new(0),
            value: UnsafeCell::new(value),
        }
    }

    /// Runs `f` on the value unless another caller has it now; None then.
    #[inline]
    pub fn try_with<R>(&self, f: impl FnOnce(&mut T) -> R) -> Option<R> {
        if self
            .busy
            .compare_exchange(false, true, Acquire, Relaxed)
            .is_err()
        {
            self.collisions.fetch_add(1, Relaxed);
            return None;
        }
        /// Clears the flag even if `f` panics.
        struct Done<'a>(&'a AtomicBool);
        impl Drop for Done<'_> {
            fn drop(&mut self) {
                self.0.store(false, Release);
            }
        }
        let _release = Done(&self.busy);
        // SAFETY: we hold the flag, so no other `&mut` to the value
        // exists until `_release` drops it.
        Some(f(unsafe { &mut *self.value.get() }))
    }

    /// How many times a caller found the cell busy.
    pub fn collisions(&self) -> u64 {
        self.collisions.load(Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_caller_at_a_time() {
        let c = RtCell::new(5);
        let r = c.try_with(|v| {
            *v += 1;
            c.try_with(|_| ()).is_none()
        });
        assert_eq!(r, Some(true), "nested access is refused");
        assert_eq!(c.try_with(|v| *v), Some(6));
        assert_eq!(c.collisions(), 1);
        let threads: Vec<_> = (0..4)
            .map(|_| {
                let c = &c;
                move || {
                    for _ in 0..1000 {
                        while c.try_with(|v| *v += 1).is_none() {}
                    }
                }
            })
            .collect();
        std::thread::scope(|s| {
            for t in threads {
                s.spawn(t);
            }
        });
        assert_eq!(c.try_with(|v| *v), Some(4006));
    }
}
