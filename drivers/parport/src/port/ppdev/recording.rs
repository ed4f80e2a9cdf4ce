//! [`RecordingIoctl`]: a fake `/dev/parportN` for tests (feature
//! `testing`), recording the ioctl sequence a driver issues.

use std::sync::atomic::{AtomicU32, AtomicU8, Ordering::Relaxed};
use std::sync::{Arc, Mutex};

use super::{PpIoctl, MODE_PCSPP};
use crate::regs;

/// One ioctl as [`RecordingIoctl`] saw it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ioctl {
    /// `PPCLAIM`.
    Claim,
    /// `PPRELEASE`.
    Release,
    /// `PPGETMODES`.
    GetModes,
    /// `PPRDATA`.
    ReadData,
    /// `PPWDATA` with its byte.
    WriteData(u8),
    /// `PPRSTATUS`.
    ReadStatus,
    /// `PPRCONTROL`.
    ReadControl,
    /// `PPWCONTROL` with its byte.
    WriteControl(u8),
    /// `PPDATADIR` (true = input).
    DataDir(bool),
}

/// A fake `/dev/parportN` handle that records every ioctl and answers
/// as ppdev does. Handles opened on one port ([`open_again`]) share its
/// registers and its owner:
///
/// * `PPCLAIM` takes the port. On a port another handle holds, the real
///   ioctl blocks until that handle releases it, so a driver that claims
///   one port twice hangs; the fake answers `EDEADLK` instead ("this
///   would hang"), so such a test fails with that error rather than
///   hangs. `PPCLAIM` on a handle that already holds the port answers
///   `EINVAL`, as ppdev does.
/// * Register ioctls and `PPRELEASE` on a handle that does not hold the
///   port answer `EINVAL` ("claim the port first").
/// * Dropping the handle (closing the file) releases the port.
///
/// The registers: data and control read back what was written (control:
/// its low four bits, as parport_pc's cache does), status is a fixed
/// value set with [`set_status`].
///
/// [`open_again`]: RecordingIoctl::open_again
/// [`set_status`]: RecordingIoctl::set_status
#[derive(Debug)]
pub struct RecordingIoctl {
    calls: Mutex<Vec<Ioctl>>,
    port: Arc<FakePort>,
    /// This handle's id on the port (non-zero).
    id: u32,
    /// The errno `PPCLAIM` answers, for a port that cannot be claimed.
    claim_errno: Option<i32>,
}

/// The kernel side of a fake port, shared by its handles.
#[derive(Debug)]
struct FakePort {
    modes: u32,
    status: AtomicU8,
    data: AtomicU8,
    control: AtomicU8,
    /// The id of the handle holding the port, 0 when free.
    holder: AtomicU32,
    /// The last handle id given out.
    handles: AtomicU32,
}

impl RecordingIoctl {
    /// A handle on a new fake port with capability bits `modes`.
    pub fn new(modes: u32) -> RecordingIoctl {
        let port = Arc::new(FakePort {
            modes,
            status: 0x78.into(),
            data: 0.into(),
            control: 0.into(),
            holder: 0.into(),
            handles: 0.into(),
        });
        RecordingIoctl::on(port, None)
    }

    /// A handle on a port whose driver has gone away (parport_pc unloaded
    /// after the node was opened): `PPCLAIM` cannot register with the
    /// port and answers `ENXIO`, as ppdev does.
    pub fn unregistered() -> RecordingIoctl {
        let mut r = RecordingIoctl::new(MODE_PCSPP);
        r.claim_errno = Some(libc::ENXIO);
        r
    }

    /// Another handle on the same port, as a second `open()` of the
    /// device node gives; it records its own calls.
    pub fn open_again(&self) -> RecordingIoctl {
        RecordingIoctl::on(self.port.clone(), self.claim_errno)
    }

    fn on(port: Arc<FakePort>, claim_errno: Option<i32>) -> RecordingIoctl {
        let id = port.handles.fetch_add(1, Relaxed) + 1;
        RecordingIoctl {
            calls: Mutex::new(Vec::new()),
            port,
            id,
            claim_errno,
        }
    }

    /// Sets what `PPRSTATUS` returns.
    pub fn set_status(&self, v: u8) {
        self.port.status.store(v, Relaxed);
    }

    /// The calls so far.
    pub fn calls(&self) -> Vec<Ioctl> {
        self.calls.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// Forgets the calls so far.
    pub fn clear(&self) {
        self.calls.lock().unwrap_or_else(|e| e.into_inner()).clear();
    }

    /// Records `c`, then answers `EINVAL` unless this handle holds the
    /// port, as ppdev does for everything but the claim.
    fn rec(&self, c: Ioctl) -> std::io::Result<()> {
        self.calls.lock().unwrap_or_else(|e| e.into_inner()).push(c);
        if self.port.holder.load(Relaxed) == self.id {
            Ok(())
        } else {
            Err(std::io::Error::from_raw_os_error(libc::EINVAL))
        }
    }
}

impl Drop for RecordingIoctl {
    /// Closing the file releases the port if this handle holds it.
    fn drop(&mut self) {
        let _ = self
            .port
            .holder
            .compare_exchange(self.id, 0, Relaxed, Relaxed);
    }
}

impl PpIoctl for RecordingIoctl {
    fn claim(&self) -> std::io::Result<()> {
        self.calls
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(Ioctl::Claim);
        if let Some(errno) = self.claim_errno {
            return Err(std::io::Error::from_raw_os_error(errno));
        }
        match self
            .port
            .holder
            .compare_exchange(0, self.id, Relaxed, Relaxed)
        {
            Ok(_) => Ok(()),
            Err(h) if h == self.id => Err(std::io::Error::from_raw_os_error(libc::EINVAL)),
            // Another handle holds the port: the real ioctl would block
            // until it is released, which in a test is a hang.
            Err(_) => Err(std::io::Error::from_raw_os_error(libc::EDEADLK)),
        }
    }
    fn release(&self) -> std::io::Result<()> {
        self.rec(Ioctl::Release)?;
        self.port.holder.store(0, Relaxed);
        Ok(())
    }
    fn get_modes(&self) -> std::io::Result<u32> {
        // PPGETMODES is answered whether or not the port is claimed.
        let _ = self.rec(Ioctl::GetModes);
        Ok(self.port.modes)
    }
    fn read_data(&self) -> std::io::Result<u8> {
        self.rec(Ioctl::ReadData)?;
        Ok(self.port.data.load(Relaxed))
    }
    fn write_data(&self, v: u8) -> std::io::Result<()> {
        self.rec(Ioctl::WriteData(v))?;
        self.port.data.store(v, Relaxed);
        Ok(())
    }
    fn read_status(&self) -> std::io::Result<u8> {
        self.rec(Ioctl::ReadStatus)?;
        Ok(self.port.status.load(Relaxed))
    }
    fn read_control(&self) -> std::io::Result<u8> {
        self.rec(Ioctl::ReadControl)?;
        Ok(self.port.control.load(Relaxed))
    }
    fn write_control(&self, v: u8) -> std::io::Result<()> {
        self.rec(Ioctl::WriteControl(v))?;
        self.port.control.store(v & regs::CONTROL_LINES, Relaxed);
        Ok(())
    }
    fn data_dir(&self, input: bool) -> std::io::Result<()> {
        self.rec(Ioctl::DataDir(input))
    }
}
