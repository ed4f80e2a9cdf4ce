//! The PCI path on a real kernel: the VM rig's ivshmem device (1af4:1110)
//! found through sysfs, enabled, BAR 2 mapped, and words exchanged with a
//! host-side peer that maps the same memory and plays a board.
//!
//! One binary, two roles. In the VM (`vmrig run --bar-file FILE --env
//! HAL_PEER_EXPECTED=1 -- <this binary>`) `ivshmem_bar_through_the_pci_layer`
//! runs; on the host, `HAL_PEER_BAR_FILE=FILE <this binary> --exact
//! host_peer` plays the board in FILE. `.ci/run` starts both. Outside the
//! rig both are ignored, with the reason; run there on purpose they fail.
//!
//! The peer's registers (byte offsets in BAR 2):
//!
//! | offset | who writes | meaning |
//! |---|---|---|
//! | 0x000 | peer | `MAGIC` once it is serving |
//! | 0x004 | peer | heartbeat, +1 every millisecond |
//! | 0x008 | guest | doorbell: request number n (1, 2, ...) |
//! | 0x00C | peer | acknowledge: n once request n is answered |
//! | 0x010 | guest | `DONE`: the peer may exit |
//! | 0x100..0x140 | guest | 16 request words |
//! | 0x200..0x240 | peer | 16 replies: `reply(i, request[i])` |
//! | last word | peer | `LAST`: the whole BAR is mapped |

use std::time::Duration;

use hal_driver::bus::{MmapWindow, RegWindow};
use hal_driver::pci;
use hal_driver::vmrig::{self, IVSHMEM, IVSHMEM_SHARED_BAR};
use hal_driver::DriverError;

const MAGIC_AT: usize = 0x000;
const HEARTBEAT: usize = 0x004;
const DOORBELL: usize = 0x008;
const ACK: usize = 0x00C;
const DONE_AT: usize = 0x010;
const REQUEST: usize = 0x100;
const REPLY: usize = 0x200;
const WORDS: usize = 16;
const SCRATCH: usize = 0x300;

const MAGIC: u32 = 0x4841_4C50; // "HALP"
const DONE: u32 = 0x600D_D0E5;
const LAST: u32 = 0x1A57_0B0D;

/// What the peer answers to request word `i`.
fn reply(i: usize, word: u32) -> u32 {
    word.rotate_left(i as u32) ^ 0xA5A5_A5A5
}

#[test]
#[ignore = "needs the VM rig's ivshmem device: runs in ../shared/tools/vmrig (scripts/test-all)"]
fn ivshmem_bar_through_the_pci_layer() {
    let iv = vmrig::ivshmem().expect(
        "no VM rig ivshmem device (VMRIG_IVSHMEM_BAR unset or missing): \
         run this binary through ../shared/tools/vmrig",
    );
    // Discovery: the device by its IDs, in a table as a driver has one.
    let found = pci::find(&iv.sysfs, &[IVSHMEM]).expect("ivshmem found by the PCI layer");
    let dev = found
        .iter()
        .find(|d| d.address == iv.address)
        .unwrap_or_else(|| panic!("{} not among {found:?}", iv.address));
    assert_eq!((dev.ids.vendor, dev.ids.device), (0x1af4, 0x1110));
    assert_eq!(dev.name(), "ivshmem");

    // The real resource file: BAR 0 = 256 bytes of registers, BAR 2 = the
    // shared memory, both memory BARs.
    let bar0 = dev.bar(0).unwrap();
    let bar2 = dev.bar(IVSHMEM_SHARED_BAR).unwrap();
    assert!(bar0.is_mem() && bar2.is_mem(), "{bar0:?} {bar2:?}");
    assert_eq!(bar0.len(), 256);
    let bar_file_len = std::fs::metadata(&iv.bar_path).unwrap().len();
    assert_eq!(bar2.len(), bar_file_len, "resource2's size is the BAR's");
    eprintln!(
        "{} at {}: BAR 2 {:#x} bytes at {:#x}",
        dev.name(),
        dev.address,
        bar2.len(),
        bar2.start
    );

    // Clear errors from the real kernel.
    let e = dev.map_bar_window(0, 0x1000).unwrap_err();
    assert!(
        matches!(
            e,
            DriverError::BarTooSmall {
                bar: 0,
                size: 256,
                ..
            }
        ),
        "{e}"
    );
    let e = dev.io_bar(IVSHMEM_SHARED_BAR).unwrap_err();
    assert!(matches!(e, DriverError::BarKind { .. }), "{e}");
    assert!(matches!(
        dev.map_bar(1).unwrap_err(),
        DriverError::BarMissing { bar: 1, .. }
    ));

    // Enable and map BAR 2. The kernel counts enables (reading `enable`
    // gives the count; the rig's init made one), and the guard undoes
    // exactly this one.
    let enable_count = || -> u32 {
        let text = std::fs::read_to_string(dev.path.join("enable")).unwrap();
        text.trim().parse().unwrap()
    };
    let before = enable_count();
    let enabled = dev.enable().expect("enable");
    assert_eq!(enable_count(), before + 1);
    drop(enabled);
    assert_eq!(enable_count(), before);
    let _enabled = dev.enable().expect("enable");
    let bar = dev.map_bar(IVSHMEM_SHARED_BAR).expect("map BAR 2");
    assert_eq!(bar.len() as u64, bar2.len());
    bar.write32(SCRATCH, 0x1234_5678);
    assert_eq!(bar.read32(SCRATCH), 0x1234_5678);

    if std::env::var_os("HAL_PEER_EXPECTED").is_none() {
        eprintln!("SKIPPED the peer exchange: HAL_PEER_EXPECTED unset (no host-side peer)");
        return;
    }
    assert!(
        vmrig::wait_until(Duration::from_secs(120), || bar.read32(MAGIC_AT) == MAGIC),
        "the host-side peer never showed its magic word"
    );
    assert_eq!(
        bar.read32(bar.len() - 4),
        LAST,
        "the last word is the peer's"
    );
    let beat = bar.read32(HEARTBEAT);
    assert!(
        vmrig::wait_until(Duration::from_secs(30), || bar.read32(HEARTBEAT) != beat),
        "the peer's heartbeat does not move: reads do not see live memory"
    );
    for n in 1..=3u32 {
        let request: Vec<u32> = (0..WORDS as u32)
            .map(|i| n.wrapping_mul(0x0101_0101) ^ (i << 24) ^ 0x00C0_FFEE)
            .collect();
        bar.write_burst(REQUEST, &request);
        bar.write32(DOORBELL, n);
        assert!(
            vmrig::wait_until(Duration::from_secs(60), || bar.read32(ACK) == n),
            "request {n} not acknowledged"
        );
        let mut got = [0u32; WORDS];
        bar.read_burst(REPLY, &mut got);
        let want: Vec<u32> = request
            .iter()
            .enumerate()
            .map(|(i, w)| reply(i, *w))
            .collect();
        assert_eq!(got.to_vec(), want, "request {n}");
    }
    bar.write32(DONE_AT, DONE);
    assert_eq!(bar.errors(), 0);
    eprintln!("exchanged 3 requests of {WORDS} words with the host-side peer");
}

#[test]
#[ignore = "the host-side peer of a VM rig run: scripts/test-all starts it beside the VM"]
fn host_peer() {
    let path = vmrig::peer_bar_file()
        .expect("not the host-side peer: HAL_PEER_BAR_FILE unset (scripts/test-all sets it)");
    let secs: u64 = std::env::var("HAL_PEER_TIMEOUT_S")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let bar = MmapWindow::open(&path).expect("peer maps the BAR file");
    bar.write_burst(0, &[0; 0x400]);
    bar.write32(bar.len() - 4, LAST);
    bar.write32(MAGIC_AT, MAGIC);
    eprintln!("host-peer: serving {}", bar.describe());
    let (mut served, mut beat) = (0u32, 0u32);
    let done = vmrig::wait_until(Duration::from_secs(secs), || {
        beat = beat.wrapping_add(1);
        bar.write32(HEARTBEAT, beat);
        let n = bar.read32(DOORBELL);
        if n != 0 && n != bar.read32(ACK) {
            let mut request = [0u32; WORDS];
            bar.read_burst(REQUEST, &mut request);
            let answer: Vec<u32> = request
                .iter()
                .enumerate()
                .map(|(i, w)| reply(i, *w))
                .collect();
            bar.write_burst(REPLY, &answer);
            bar.write32(ACK, n);
            served += 1;
        }
        bar.read32(DONE_AT) == DONE
    });
    eprintln!("host-peer: served {served} requests, guest done: {done}");
    assert!(done, "the guest never finished within {secs} s");
    assert_eq!(served, 3);
    assert_eq!(bar.errors(), 0);
}
