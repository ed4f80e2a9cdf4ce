//! The raw backend: `inb`/`outb` on the port's I/O addresses, through the
//! driver layer's [`IopermPorts`], opened for the port's two register
//! windows and nothing else.
//!
//! `ioperm` grants access to the calling thread only, and the realtime
//! functions run in the HAL threads, not in the thread that loads the
//! module: `IopermPorts` takes the permission on the first access in each
//! thread, and probes it once in the loading thread, so a missing
//! capability (`EPERM`), kernel lockdown, or a kernel without port I/O
//! (`ENOSYS`) is a load error instead of a silent failure later.
//!
//! When the kernel's parport driver owns the port (a `/dev/parportN` with
//! the same base exists), the port is also claimed through ppdev, as
//! LinuxCNC does, so no other program uses it meanwhile.

use hal_driver::bus::{IopermPorts, PortBus};
use hal_driver::DriverError;

use super::ppdev::PpdevPort;
use super::{PortAt, PortError, PortIo};

/// A parallel port reached by raw port I/O.
#[derive(Debug)]
pub struct RawPort {
    at: PortAt,
    ports: IopermPorts,
    claim_via: Option<PpdevPort>,
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
        let at = PortAt { base, base_hi };
        let ranges = at.ranges().map_err(|_| {
            PortError::NotFound(format!(
                "address {base:#x}: the register window runs past 0xffff"
            ))
        })?;
        let ports = IopermPorts::open(&ranges).map_err(|e| match e {
            DriverError::Unsupported { .. } => PortError::Unsupported(format!(
                "raw port I/O at {base:#x} exists only on x86-64; use the ppdev backend"
            )),
            // Not a permission matter: no grant would help (a VM or a
            // kernel built without port I/O).
            DriverError::PortIo { ref source, .. }
                if source.raw_os_error() == Some(libc::ENOSYS) =>
            {
                PortError::NoPortIo {
                    addr: base,
                    source: e,
                }
            }
            e => PortError::NoPermission {
                addr: base,
                reason: format!("{e}; or use the ppdev backend"),
            },
        })?;
        Ok(RawPort {
            at,
            ports,
            claim_via,
        })
    }
}

impl PortIo for RawPort {
    #[inline]
    fn read_data(&self) -> u8 {
        self.at.read_data(&self.ports)
    }
    #[inline]
    fn write_data(&self, v: u8) {
        self.at.write_data(&self.ports, v)
    }
    #[inline]
    fn read_status(&self) -> u8 {
        self.at.read_status(&self.ports)
    }
    #[inline]
    fn read_control(&self) -> u8 {
        self.at.read_control(&self.ports)
    }
    #[inline]
    fn write_control(&self, v: u8) {
        self.at.write_control(&self.ports, v)
    }
    fn has_ecr(&self) -> bool {
        self.at.base_hi.is_some()
    }
    fn write_ecr(&self, v: u8) -> Result<(), PortError> {
        if self.at.write_ecr(&self.ports, v) {
            Ok(())
        } else {
            Err(PortError::Unsupported(format!(
                "port {:#x} has no known ECR address",
                self.at.base
            )))
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
            Some(p) => format!(
                "raw I/O at {:#x} (claimed through {})",
                self.at.base,
                p.path()
            ),
            None => format!("raw I/O at {:#x}", self.at.base),
        }
    }
    fn errors(&self) -> u64 {
        self.ports.errors()
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
            Err(PortError::NoPortIo { addr, source }) => {
                // ENOSYS: the kernel has none, and the message says so
                // rather than asking for a permission.
                assert_eq!(addr, 0x378);
                assert!(source.to_string().contains("ioperm"), "{source}");
            }
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
