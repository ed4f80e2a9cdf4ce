//! A process-shared robust mutex living in the segment header.

use std::cell::UnsafeCell;

/// Outcome of taking the lock.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum Acquired {
    /// The lock was free or released normally.
    Clean,
    /// The previous holder died while holding it: its change must be undone
    /// before anything else reads the structure.
    OwnerDied,
}

/// A `pthread_mutex_t` set up as process-shared, robust and error-checking.
#[repr(C, align(64))]
pub(crate) struct RobustMutex {
    raw: UnsafeCell<libc::pthread_mutex_t>,
}

// SAFETY: the pthread mutex is designed to be shared between threads and,
// being process-shared, between processes; all access goes through the
// pthread API.
unsafe impl Sync for RobustMutex {}

impl RobustMutex {
    /// Initialises the mutex in place. Only the host calls this, on a fresh
    /// segment that no other process has mapped yet.
    pub(crate) fn init(&self) -> Result<(), nix::Error> {
        // SAFETY: attr is initialised by pthread_mutexattr_init before use and
        // destroyed afterwards; self.raw points to memory inside the mapping
        // which no other process uses yet.
        unsafe {
            let mut attr: libc::pthread_mutexattr_t = std::mem::zeroed();
            check(libc::pthread_mutexattr_init(&mut attr))?;
            let result = (|| {
                check(libc::pthread_mutexattr_setpshared(
                    &mut attr,
                    libc::PTHREAD_PROCESS_SHARED,
                ))?;
                check(libc::pthread_mutexattr_setrobust(
                    &mut attr,
                    libc::PTHREAD_MUTEX_ROBUST,
                ))?;
                check(libc::pthread_mutexattr_settype(
                    &mut attr,
                    libc::PTHREAD_MUTEX_ERRORCHECK,
                ))?;
                check(libc::pthread_mutex_init(self.raw.get(), &attr))
            })();
            libc::pthread_mutexattr_destroy(&mut attr);
            result
        }
    }

    /// Takes the lock, reporting whether the previous holder died.
    pub(crate) fn lock(&self) -> Result<Acquired, nix::Error> {
        // SAFETY: the mutex was initialised by the host before the segment's
        // magic was published; attach refuses segments without it.
        let rc = unsafe { libc::pthread_mutex_lock(self.raw.get()) };
        match rc {
            0 => Ok(Acquired::Clean),
            libc::EOWNERDEAD => Ok(Acquired::OwnerDied),
            e => Err(nix::Error::from_raw(e)),
        }
    }

    /// Marks a lock taken with [`Acquired::OwnerDied`] as consistent again.
    pub(crate) fn make_consistent(&self) -> Result<(), nix::Error> {
        // SAFETY: called by the current holder after it repaired the state.
        check(unsafe { libc::pthread_mutex_consistent(self.raw.get()) })
    }

    /// Releases the lock.
    pub(crate) fn unlock(&self) {
        // SAFETY: only called by the holder (the transaction guard).
        unsafe {
            libc::pthread_mutex_unlock(self.raw.get());
        }
    }
}

fn check(rc: libc::c_int) -> Result<(), nix::Error> {
    if rc == 0 {
        Ok(())
    } else {
        Err(nix::Error::from_raw(rc))
    }
}
