//! [`IopermPorts`]: x86 `in`/`out` instructions after `ioperm`.
//!
//! `ioperm` grants access to the calling thread only, and the realtime
//! functions run in the HAL threads, not in the thread that loads the
//! module. So the permission is taken lazily: each access looks up this
//! bus in a small thread-local table and calls `ioperm` on the first
//! access in a thread (a refusal is remembered, so a thread without the
//! permission does not make a system call per access). `open` probes
//! `ioperm` once in the loading thread, so a missing `CAP_SYS_RAWIO`,
//! kernel lockdown or a kernel without port I/O is a load error, never a
//! silent failure later.

use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use super::ranges::{self, PortRange};
use super::{PortBus, ALL_ONES};
use crate::error::{DriverError, Result};

/// How many buses one thread remembers; past that, the oldest entry is
/// forgotten and its bus calls `ioperm` again (it is idempotent).
const GRANT_SLOTS: usize = 8;
const UNKNOWN: u8 = 0;
const GRANTED: u8 = 1;
const REFUSED: u8 = 2;

#[derive(Clone, Copy)]
struct Grants {
    ids: [u64; GRANT_SLOTS],
    state: [u8; GRANT_SLOTS],
    next: usize,
}

thread_local! {
    static GRANTS: Cell<Grants> = const {
        Cell::new(Grants { ids: [0; GRANT_SLOTS], state: [UNKNOWN; GRANT_SLOTS], next: 0 })
    };
}

/// Gives every bus an id for the thread-local table (0 is never used).
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// I/O ports reached with `in`/`out` after `ioperm`, limited to the
/// declared ranges.
#[derive(Debug)]
pub struct IopermPorts {
    id: u64,
    ranges: Box<[PortRange]>,
    errors: AtomicU64,
}

/// Calls `ioperm(from, num, 1)`.
#[cfg(target_arch = "x86_64")]
fn ioperm(r: &PortRange) -> std::io::Result<()> {
    // SAFETY: ioperm changes only this thread's I/O permission bitmap.
    let rc = unsafe { libc::ioperm(r.base as libc::c_ulong, r.len as libc::c_ulong, 1) };
    if rc == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

/// No `ioperm` outside x86 (`open` refuses before calling it).
#[cfg(not(target_arch = "x86_64"))]
fn ioperm(_: &PortRange) -> std::io::Result<()> {
    Err(std::io::Error::from_raw_os_error(libc::ENOSYS))
}

/// Why `ioperm` failed, as an error an integrator can act on.
fn explain(what: String, e: std::io::Error) -> DriverError {
    let hint = match e.raw_os_error() {
        Some(libc::ENOSYS) => "this kernel has no port I/O support",
        Some(libc::EPERM) if crate::lockdown::active() => {
            return DriverError::Lockdown { what };
        }
        Some(libc::EPERM) => {
            "needs CAP_SYS_RAWIO: setcap cap_sys_rawio+ep on the HAL host binary; \
             kernel lockdown under Secure Boot refuses it always"
        }
        _ => "ioperm refused the range",
    };
    DriverError::PortIo {
        what,
        source: e,
        hint,
    }
}

impl IopermPorts {
    /// Opens the port `ranges` (at least one), probing the permission in
    /// this thread. Other ports are never touched.
    pub fn open(ranges: &[PortRange]) -> Result<IopermPorts> {
        let what = format!("ioperm for ports {}", ranges::describe(ranges));
        if !cfg!(target_arch = "x86_64") {
            return Err(DriverError::Unsupported {
                what,
                reason: "port I/O is x86 only".into(),
            });
        }
        if ranges.is_empty() {
            return Err(DriverError::Unsupported {
                what,
                reason: "no port range given".into(),
            });
        }
        let bus = IopermPorts {
            id: NEXT_ID.fetch_add(1, Relaxed),
            ranges: ranges.into(),
            errors: AtomicU64::new(0),
        };
        bus.grant().map_err(|e| explain(what, e))?;
        bus.remember(GRANTED);
        Ok(bus)
    }

    /// The declared ranges.
    pub fn ranges(&self) -> &[PortRange] {
        &self.ranges
    }

    fn grant(&self) -> std::io::Result<()> {
        self.ranges.iter().try_for_each(ioperm)
    }

    fn remember(&self, state: u8) {
        let mut g = GRANTS.get();
        let slot = match g.ids.iter().position(|&i| i == self.id) {
            Some(s) => s,
            None => {
                let s = g.next;
                g.next = (g.next + 1) % GRANT_SLOTS;
                s
            }
        };
        g.ids[slot] = self.id;
        g.state[slot] = state;
        GRANTS.set(g);
    }

    /// Whether this thread may make the access: inside the ranges and
    /// permitted. Counts an error if not.
    #[inline]
    fn allowed(&self, port: u16, width: u16) -> bool {
        if !ranges::allowed(&self.ranges, port, width) {
            self.errors.fetch_add(1, Relaxed);
            return false;
        }
        let g = GRANTS.get();
        let state = g
            .ids
            .iter()
            .position(|&i| i == self.id)
            .map_or(UNKNOWN, |s| g.state[s]);
        let ok = match state {
            GRANTED => true,
            REFUSED => false,
            _ => {
                let ok = self.grant().is_ok();
                self.remember(if ok { GRANTED } else { REFUSED });
                ok
            }
        };
        if !ok {
            self.errors.fetch_add(1, Relaxed);
        }
        ok
    }
}

impl PortBus for IopermPorts {
    #[inline]
    fn inb(&self, port: u16) -> u8 {
        if self.allowed(port, 1) {
            // SAFETY: this thread has ioperm access to `port`.
            unsafe { asm::inb(port) }
        } else {
            ALL_ONES as u8
        }
    }
    #[inline]
    fn outb(&self, port: u16, value: u8) {
        if self.allowed(port, 1) {
            // SAFETY: this thread has ioperm access to `port`.
            unsafe { asm::outb(port, value) }
        }
    }
    #[inline]
    fn inw(&self, port: u16) -> u16 {
        if self.allowed(port, 2) {
            // SAFETY: this thread has ioperm access to `port..port+2`.
            unsafe { asm::inw(port) }
        } else {
            ALL_ONES as u16
        }
    }
    #[inline]
    fn outw(&self, port: u16, value: u16) {
        if self.allowed(port, 2) {
            // SAFETY: this thread has ioperm access to `port..port+2`.
            unsafe { asm::outw(port, value) }
        }
    }
    #[inline]
    fn inl(&self, port: u16) -> u32 {
        if self.allowed(port, 4) {
            // SAFETY: this thread has ioperm access to `port..port+4`.
            unsafe { asm::inl(port) }
        } else {
            ALL_ONES
        }
    }
    #[inline]
    fn outl(&self, port: u16, value: u32) {
        if self.allowed(port, 4) {
            // SAFETY: this thread has ioperm access to `port..port+4`.
            unsafe { asm::outl(port, value) }
        }
    }
    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }
    fn describe(&self) -> String {
        format!("raw I/O at {}", ranges::describe(&self.ranges))
    }
}

/// The port instructions.
///
/// # Safety (every function)
///
/// The calling thread must hold I/O permission for the ports touched
/// (granted by `ioperm`; without it the CPU raises a general protection
/// fault and the process dies with SIGSEGV), and they must belong to the
/// device this bus was opened for: an access elsewhere can clear another
/// device's status latch or reprogram it. [`IopermPorts`] checks both
/// (declared ranges, per-thread grant) before every call.
#[cfg(target_arch = "x86_64")]
mod asm {
    use core::arch::asm;

    /// `in al, dx`.
    #[inline(always)]
    pub unsafe fn inb(port: u16) -> u8 {
        let v: u8;
        // SAFETY: the caller guarantees the thread may access `port`.
        unsafe {
            asm!("in al, dx", out("al") v, in("dx") port, options(nomem, nostack, preserves_flags))
        };
        v
    }
    /// `out dx, al`.
    #[inline(always)]
    pub unsafe fn outb(port: u16, v: u8) {
        // SAFETY: the caller guarantees the thread may access `port`.
        unsafe {
            asm!("out dx, al", in("dx") port, in("al") v, options(nomem, nostack, preserves_flags))
        };
    }
    /// `in ax, dx`.
    #[inline(always)]
    pub unsafe fn inw(port: u16) -> u16 {
        let v: u16;
        // SAFETY: the caller guarantees the thread may access `port..port+2`.
        unsafe {
            asm!("in ax, dx", out("ax") v, in("dx") port, options(nomem, nostack, preserves_flags))
        };
        v
    }
    /// `out dx, ax`.
    #[inline(always)]
    pub unsafe fn outw(port: u16, v: u16) {
        // SAFETY: the caller guarantees the thread may access `port..port+2`.
        unsafe {
            asm!("out dx, ax", in("dx") port, in("ax") v, options(nomem, nostack, preserves_flags))
        };
    }
    /// `in eax, dx`.
    #[inline(always)]
    pub unsafe fn inl(port: u16) -> u32 {
        let v: u32;
        // SAFETY: the caller guarantees the thread may access `port..port+4`.
        unsafe {
            asm!("in eax, dx", out("eax") v, in("dx") port, options(nomem, nostack, preserves_flags))
        };
        v
    }
    /// `out dx, eax`.
    #[inline(always)]
    pub unsafe fn outl(port: u16, v: u32) {
        // SAFETY: the caller guarantees the thread may access `port..port+4`.
        unsafe {
            asm!("out dx, eax", in("dx") port, in("eax") v, options(nomem, nostack, preserves_flags))
        };
    }
}

/// Other architectures have no port instructions; `open` refuses them,
/// so these are never reached, and they read all ones if they were.
#[cfg(not(target_arch = "x86_64"))]
mod asm {
    pub unsafe fn inb(_: u16) -> u8 {
        0xFF
    }
    pub unsafe fn outb(_: u16, _: u8) {}
    pub unsafe fn inw(_: u16) -> u16 {
        0xFFFF
    }
    pub unsafe fn outw(_: u16, _: u16) {}
    pub unsafe fn inl(_: u16) -> u32 {
        u32::MAX
    }
    pub unsafe fn outl(_: u16, _: u32) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probe_failure_is_a_clear_error_or_access_works() {
        // Here ioperm answers ENOSYS (no port I/O in this kernel) or EPERM
        // (no CAP_SYS_RAWIO); in the VM rig, as root, it works.
        let r = [PortRange::new(0x378, 8).unwrap()];
        match IopermPorts::open(&r) {
            Ok(p) => {
                assert_eq!(p.describe(), "raw I/O at 0x378..0x37f");
                // Outside the declared range: refused without touching it.
                assert_eq!(p.inb(0x3f8), 0xFF);
                assert_eq!(p.errors(), 1);
            }
            Err(e) => {
                let m = e.to_string();
                assert!(m.contains("ioperm for ports 0x378..0x37f"), "{m}");
            }
        }
        assert!(IopermPorts::open(&[]).is_err());
    }
}
