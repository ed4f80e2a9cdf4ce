//! The raw backend: `inb`/`outb` on the port's I/O addresses after
//! `ioperm`.
//!
//! `ioperm` grants access to the calling thread only, and the realtime
//! functions run in the HAL threads, not in the thread that loads the
//! module. So the permission is taken lazily: each access checks a
//! thread-local list of granted ports and calls `ioperm` on the first
//! access in a thread. `open` probes `ioperm` once in the loading thread,
//! so a missing capability (`EPERM`), kernel lockdown, or a kernel without
//! port I/O (`ENOSYS`) is a load error instead of a silent failure later.
//!
//! When the kernel's parport driver owns the port (a `/dev/parportN` with
//! the same base exists), the port is also claimed through ppdev, as
//! LinuxCNC does, so no other program uses it meanwhile.

use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use super::ppdev::PpdevPort;
use super::{PortError, PortIo};
use crate::regs;

/// How many distinct ports one thread remembers as granted; past that,
/// `ioperm` is simply called again (it is idempotent).
const GRANT_SLOTS: usize = 8;

#[derive(Clone, Copy)]
struct Grants {
    bases: [u16; GRANT_SLOTS],
    next: usize,
    /// ioperm was refused in this thread: do not ask again on every access.
    refused: bool,
}

thread_local! {
    static GRANTED: Cell<Grants> = const {
        Cell::new(Grants {
                        bases: [0; GRANT_SLOTS],
            next: 0,
            refused: false,
        })
    };
}

/// A parallel port reached by raw port I/O.
#[derive(Debug)]
pub struct RawPort {
    base: u16,
    base_hi: Option<u16>,
    errors: AtomicU64,
    claim_via: Option<PpdevPort>,
}

/// Calls `ioperm(from, num, 1)`.
fn ioperm(from: u16, num: u16) -> Result<(), std::io::Error> {
    // SAFETY: ioperm only changes this thread's I/O permission bitmap.
    let rc = unsafe { libc::ioperm(from as libc::c_ulong, num as libc::c_ulong, 1) };
    if rc == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

/// Why an ioperm failure happened, in words an integrator can act on.
fn explain(e: &std::io::Error) -> String {
    match e.raw_os_error() {
        Some(libc::ENOSYS) => {
            format!("ioperm: {e} (this kernel has no port I/O support; use the ppdev backend)")
        }
        Some(libc::EPERM) => format!(
            "ioperm: {e} (needs CAP_SYS_RAWIO: setcap cap_sys_rawio+ep on the HAL host binary; \
             kernel lockdown under Secure Boot refuses it always; or use the ppdev backend)"
        ),
        _ => format!("ioperm: {e}"),
    }
}

impl RawPort {
    /// Opens the port at `base` (and `base_hi` for the ECR), probing the
    /// permission in this thread. `claim_via` is the ppdev handle of the
    /// same port, if the kernel knows it.
    pub fn open(
        base: u16,
        base_hi: Option<u16>,
        claim_via: Option<PpdevPort>,
    ) -> Result<RawPort, PortError> {
        if !cfg!(target_arch = "x86_64") {
            return Err(PortError::Unsupported(format!(
                "raw port I/O at {base:#x} exists only on x86-64; use the ppdev backend"
            )));
        }
        if base.checked_add(regs::BASE_SPAN - 1).is_none()
            || base_hi.is_some_and(|h| h.checked_add(regs::HI_SPAN - 1).is_none())
        {
            return Err(PortError::NotFound(format!(
                "address {base:#x}: the register window runs past 0xffff"
            )));
        }
        let p = RawPort {
            base,
            base_hi,
            errors: AtomicU64::new(0),
            claim_via,
        };
        p.grant().map_err(|e| PortError::NoPermission {
            addr: base,
            reason: explain(&e),
        })?;
        Ok(p)
    }

    fn grant(&self) -> Result<(), std::io::Error> {
        ioperm(self.base, regs::BASE_SPAN)?;
        if let Some(hi) = self.base_hi {
            ioperm(hi, regs::HI_SPAN)?;
        }
        Ok(())
    }

    /// Makes sure this thread may access the port; false if it may not.
    #[inline]
    fn allowed(&self) -> bool {
        let mut g = GRANTED.get();
        if g.bases.contains(&self.base) {
            return true;
        }
        if g.refused {
            self.errors.fetch_add(1, Relaxed);
            return false;
        }
        if self.grant().is_err() {
            self.errors.fetch_add(1, Relaxed);
            g.refused = true;
            GRANTED.set(g);
            return false;
        }
        g.bases[g.next] = self.base;
        g.next = (g.next + 1) % GRANT_SLOTS;
        GRANTED.set(g);
        true
    }

    #[inline]
    fn inb(&self, addr: u16) -> u8 {
        if self.allowed() {
            // SAFETY: `allowed` just made sure this thread has ioperm
            // access to the port's window, and every caller passes an
            // address inside it (base + a register offset of regs).
            unsafe { port_in(addr) }
        } else {
            0xFF
        }
    }

    #[inline]
    fn outb(&self, addr: u16, v: u8) {
        if self.allowed() {
            // SAFETY: `allowed` just made sure this thread has ioperm
            // access to the port's window, and every caller passes an
            // address inside it (base + a register offset of regs).
            unsafe { port_out(addr, v) }
        }
    }
}

/// Reads one byte from I/O port `addr` (`inb`).
///
/// # Safety
///
/// The calling thread must hold I/O permission for `addr` (granted by
/// `ioperm`; without it the CPU raises a general protection fault and the
/// process dies with SIGSEGV), and `addr` must be a register of the port
/// this backend owns: a read from another device's register can have side
/// effects on it (clearing a status latch, popping a FIFO).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn port_in(addr: u16) -> u8 {
    let v: u8;
    // SAFETY: the caller guarantees I/O permission for `addr` and that it
    // is this port's register; the instruction touches no memory.
    unsafe {
        core::arch::asm!("in al, dx", out("al") v, in("dx") addr,
            options(nomem, nostack, preserves_flags));
    }
    v
}

/// Writes one byte to I/O port `addr` (`outb`).
///
/// # Safety
///
/// The calling thread must hold I/O permission for `addr` (granted by
/// `ioperm`; without it the CPU raises a general protection fault and the
/// process dies with SIGSEGV), and `addr` must be a register of the port
/// this backend owns: a write elsewhere reprograms whatever device sits
/// there.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn port_out(addr: u16, v: u8) {
    // SAFETY: the caller guarantees I/O permission for `addr` and that it
    // is this port's register; the instruction touches no memory.
    unsafe {
        core::arch::asm!("out dx, al", in("dx") addr, in("al") v,
            options(nomem, nostack, preserves_flags));
    }
}

/// Stands in for `inb` where there is no port I/O: reads as a floating
/// bus (all ones). `open` refuses the raw backend on such targets, so it
/// is never called.
///
/// # Safety
///
/// None needed; it is `unsafe` only to keep the x86-64 signature.
#[cfg(not(target_arch = "x86_64"))]
unsafe fn port_in(_addr: u16) -> u8 {
    0xFF
}

/// Stands in for `outb` where there is no port I/O: does nothing.
/// `open` refuses the raw backend on such targets, so it is never called.
///
/// # Safety
///
/// None needed; it is `unsafe` only to keep the x86-64 signature.
#[cfg(not(target_arch = "x86_64"))]
unsafe fn port_out(_addr: u16, _v: u8) {}

impl PortIo for RawPort {
    #[inline]
    fn read_data(&self) -> u8 {
        self.inb(self.base + regs::DATA)
    }
    #[inline]
    fn write_data(&self, v: u8) {
        self.outb(self.base + regs::DATA, v)
    }
    #[inline]
    fn read_status(&self) -> u8 {
        self.inb(self.base + regs::STATUS)
    }
    #[inline]
    fn read_control(&self) -> u8 {
        self.inb(self.base + regs::CONTROL)
    }
    #[inline]
    fn write_control(&self, v: u8) {
        self.outb(self.base + regs::CONTROL, v)
    }
    fn has_ecr(&self) -> bool {
        self.base_hi.is_some()
    }
    fn write_ecr(&self, v: u8) -> Result<(), PortError> {
        match self.base_hi {
            Some(hi) => {
                self.outb(hi + regs::ECR, v);
                Ok(())
            }
            None => Err(PortError::Unsupported(format!(
                "port {:#x} has no known ECR address",
                self.base
            ))),
        }
    }
    fn claim(&self) -> Result<(), PortError> {
        match &self.claim_via {
            Some(p) => p.claim(),
            None => Ok(()),
        }
    }
    fn release(&self) {
        if let Some(p) = &self.claim_via {
            p.release();
        }
    }
    fn describe(&self) -> String {
        match &self.claim_via {
            Some(p) => format!("raw I/O at {:#x} (claimed through {})", self.base, p.path()),
            None => format!("raw I/O at {:#x}", self.base),
        }
    }
    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probe_failure_is_a_clear_load_error_or_access_works() {
        // On this VM ioperm answers ENOSYS; as an unprivileged user EPERM.
        // Where it works (root in the VM rig), the port opens.
        match RawPort::open(0x378, Some(0x778), None) {
            Ok(p) => assert_eq!(p.describe(), "raw I/O at 0x378"),
            Err(e) => {
                let m = e.to_string();
                assert!(m.contains("no permission for raw port I/O at 0x378"), "{m}");
                assert!(m.contains("ioperm"), "{m}");
            }
        }
    }

    #[test]
    fn window_past_the_end_of_the_io_space_is_refused() {
        let e = RawPort::open(0xFFFC, None, None).unwrap_err();
        assert!(e.to_string().contains("runs past 0xffff"), "{e}");
    }
}
