//! For tests of real kernel interfaces in the VM rig
//! (`../shared/tools/vmrig`): finding the rig's ivshmem PCI device, and
//! the host-side peer that plays a board's registers in the same memory.
//!
//! The rig boots a VM with an `ivshmem-plain` device (1af4:1110) whose
//! BAR 2 is backed by a host file (`vmrig run --bar-file FILE`). Inside
//! the VM the test finds it with [`ivshmem`] and maps BAR 2 through
//! [`crate::pci`] like any board; on the host a peer process maps FILE
//! (with [`MmapWindow::open`](crate::bus::MmapWindow::open)) and sees the
//! same words. `.ci/run` runs one rig test binary per VM boot; for a
//! binary marked `peer` it first starts the same binary on the host with
//! [`PEER_BAR_ENV`] set and the filter `host_peer`, so that test plays
//! the board while the rest run in the VM.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::pci::{PciMatch, Sysfs};

/// The rig's ivshmem device.
pub const IVSHMEM: PciMatch = PciMatch::new(0x1af4, 0x1110, "ivshmem");
/// Its BAR holding the shared memory.
pub const IVSHMEM_SHARED_BAR: usize = 2;
/// The variable naming the BAR file a host-side peer maps.
pub const PEER_BAR_ENV: &str = "HAL_PEER_BAR_FILE";

/// The rig's ivshmem device, as the rig describes it.
#[derive(Debug, Clone)]
pub struct Ivshmem {
    /// The device's bus address (`VMRIG_IVSHMEM_PCI`).
    pub address: String,
    /// The sysfs directory listing it.
    pub sysfs: Sysfs,
    /// Its BAR 2 resource file (`VMRIG_IVSHMEM_BAR`).
    pub bar_path: PathBuf,
    /// The host file behind the BAR (`VMRIG_IVSHMEM_HOSTFILE`).
    pub host_file: Option<PathBuf>,
}

/// The ivshmem device when running inside the rig; otherwise None, after
/// printing why the caller skips (`SKIPPED: ...` on stderr).
pub fn ivshmem() -> Option<Ivshmem> {
    let bar = std::env::var_os("VMRIG_IVSHMEM_BAR").map(PathBuf::from);
    let Some(bar_path) = bar.filter(|p| p.exists()) else {
        eprintln!(
            "SKIPPED: no VM rig ivshmem device (VMRIG_IVSHMEM_BAR unset or missing); \
             run this binary through ../shared/tools/vmrig to test a real PCI BAR"
        );
        return None;
    };
    let dev_dir = bar_path.parent().unwrap_or(Path::new("/"));
    let address = std::env::var("VMRIG_IVSHMEM_PCI").unwrap_or_else(|_| {
        dev_dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    });
    Some(Ivshmem {
        address,
        sysfs: Sysfs::at(dev_dir.parent().unwrap_or(Path::new("/"))),
        bar_path: bar_path.clone(),
        host_file: std::env::var_os("VMRIG_IVSHMEM_HOSTFILE").map(PathBuf::from),
    })
}

/// The BAR file a host-side peer should map, when this process is one;
/// otherwise None, after printing that the peer test is skipped.
pub fn peer_bar_file() -> Option<PathBuf> {
    let f = std::env::var_os(PEER_BAR_ENV).map(PathBuf::from);
    if f.is_none() {
        eprintln!("SKIPPED: not the host-side peer ({PEER_BAR_ENV} unset)");
    }
    f
}

/// Polls `cond` every millisecond until it holds or `timeout` passes;
/// whether it held. For waiting on the other side of the shared memory.
pub fn wait_until(timeout: Duration, mut cond: impl FnMut() -> bool) -> bool {
    let end = Instant::now() + timeout;
    loop {
        if cond() {
            return true;
        }
        if Instant::now() >= end {
            return false;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}
