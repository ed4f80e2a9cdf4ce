//! A process-shared robust mutex living in the segment header.
//!
//! The kernel recovers the lock when its holder dies (robust futex: the
//! next locker gets `EOWNERDEAD`). It cannot help when the lock word names
//! a holder that never existed: a stray write into the segment (the group
//! may write it) leaves a word whose owner thread is dead, impossible or
//! unrelated, and every locker would wait forever. So a locker waits in
//! short slices; when the word has stayed the same for [`STALE_AFTER`] and
//! its owner is judged impossible ([`StaleOwner`]), it marks the word
//! "owner died" as the kernel would, wakes the waiters, and the next
//! locker gets `EOWNERDEAD` and rolls back whatever the journal holds.

use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// Bits of the futex word of a robust mutex (linux/futex.h).
const FUTEX_WAITERS: u32 = 0x8000_0000;
const FUTEX_OWNER_DIED: u32 = 0x4000_0000;
const FUTEX_TID_MASK: u32 = 0x3fff_ffff;

/// How long a locker waits before it looks at the owner again.
const CHECK_EVERY: Duration = Duration::from_millis(100);
/// How long the word must stay unchanged, naming an impossible owner,
/// before the lock is taken from it. Structural changes take
/// microseconds; a second is far beyond any real holder.
pub(crate) const STALE_AFTER: Duration = Duration::from_secs(1);

/// Outcome of taking the lock.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum Acquired {
    /// The lock was free or released normally.
    Clean,
    /// The previous holder died while holding it: its change must be undone
    /// before anything else reads the structure.
    OwnerDied,
}

/// Judges the owner a lock word names.
pub(crate) trait StaleOwner {
    /// Why thread `tid` cannot be holding the lock (it does not exist, is
    /// a kernel thread, has not mapped the segment), or None if it may be.
    fn impossible(&self, tid: u32) -> Option<String>;
    /// Says that the lock was taken from `tid`, and why.
    fn recovered(&self, tid: u32, why: &str);
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

    /// Takes the lock, reporting whether the previous holder died. A lock
    /// word naming an owner that `judge` finds impossible, unchanged for
    /// [`STALE_AFTER`], is recovered (see the module documentation).
    pub(crate) fn lock(&self, judge: &dyn StaleOwner) -> Result<Acquired, nix::Error> {
        let mut suspect: Option<(u32, Instant)> = None;
        loop {
            match self.lock_for(CHECK_EVERY) {
                Err(nix::Error::ETIMEDOUT) => {}
                other => return other,
            }
            let word = self.word().load(Ordering::Relaxed);
            let owner = word & FUTEX_TID_MASK;
            if owner == 0 || word & FUTEX_OWNER_DIED != 0 {
                suspect = None;
                continue;
            }
            let Some(why) = judge.impossible(owner) else {
                suspect = None;
                continue;
            };
            match suspect {
                Some((w, since)) if w == word && since.elapsed() >= STALE_AFTER => {
                    if self.mark_owner_died(word) {
                        judge.recovered(owner, &why);
                    }
                    suspect = None;
                }
                Some((w, _)) if w == word => {}
                _ => suspect = Some((word, Instant::now())),
            }
        }
    }

    /// Waits up to `limit` for the lock.
    fn lock_for(&self, limit: Duration) -> Result<Acquired, nix::Error> {
        let now = nix::time::clock_gettime(nix::time::ClockId::CLOCK_REALTIME)
            .map_err(|_| nix::Error::EINVAL)?;
        let deadline = now + nix::sys::time::TimeSpec::from_duration(limit);
        // SAFETY: the mutex was initialised by the host before the segment's
        // magic was published; attach refuses segments without it. The
        // deadline is a valid timespec on the stack.
        let rc = unsafe { libc::pthread_mutex_timedlock(self.raw.get(), deadline.as_ref()) };
        match rc {
            0 => Ok(Acquired::Clean),
            libc::EOWNERDEAD => Ok(Acquired::OwnerDied),
            e => Err(nix::Error::from_raw(e)),
        }
    }

    /// The futex word: the first field of glibc's `pthread_mutex_t`.
    fn word(&self) -> &AtomicU32 {
        // SAFETY: glibc keeps the lock word (`__data.__lock`, an int) at
        // offset 0 of the mutex, which is 64-byte aligned; the kernel and
        // glibc access it atomically, so an atomic view is sound.
        unsafe { &*(self.raw.get() as *const AtomicU32) }
    }

    /// Marks the lock's owner dead if the word still is `seen`, keeping
    /// the waiters bit, and wakes every waiter; the next locker then gets
    /// `EOWNERDEAD`, as after a holder's real death. False if the word
    /// changed meanwhile (the owner was real after all, or another locker
    /// recovered it first).
    fn mark_owner_died(&self, seen: u32) -> bool {
        let died = FUTEX_OWNER_DIED | (seen & FUTEX_WAITERS);
        if self
            .word()
            .compare_exchange(seen, died, Ordering::SeqCst, Ordering::SeqCst)
            .is_err()
        {
            return false;
        }
        // SAFETY: FUTEX_WAKE on a word inside our mapping of the shared
        // segment; it only wakes threads waiting on that word.
        unsafe {
            libc::syscall(
                libc::SYS_futex,
                self.word().as_ptr(),
                libc::FUTEX_WAKE,
                i32::MAX,
                std::ptr::null::<libc::timespec>(),
                std::ptr::null::<u32>(),
                0u32,
            );
        }
        true
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
