//! The PCI path over a fake sysfs tree: discovery by IDs, enable, BAR 2
//! mapped from its `resource2` file, identification from the register
//! words in that file, initialisation and functions writing into it.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use common::*;
use hal_core::module::ModuleArgs;
use hal_core::{Host, Value};
use hal_driver::pci::fake::{FakeBar, FakeSysfs};
use hal_driver::pci::PciIds;
use hal_motenc::hal::{load_from, NAME, PARAMS};
use hal_motenc::regs;

const IDS: PciIds = PciIds {
    vendor: regs::PCI_VENDOR,
    device: regs::PCI_DEVICE,
    subvendor: 0x10B5,
    subdevice: 0x9030,
};

/// Adds a MOTENC at `address` whose BAR 2 is `bar_len` bytes, with
/// boardVersion `version` and ID jumpers `jumpers`; returns its
/// directory.
fn add_board(fake: &FakeSysfs, address: &str, bar_len: u64, version: u32, jumpers: u32) -> PathBuf {
    let dir = fake
        .add_device(
            address,
            IDS,
            &[
                FakeBar::Mem {
                    start: 0xfebf_0000,
                    len: 0x80,
                },
                FakeBar::Io {
                    start: 0xe000,
                    len: 0x80,
                },
                FakeBar::Mem {
                    start: 0xfebe_0000,
                    len: bar_len,
                },
            ],
        )
        .unwrap();
    if bar_len >= 0x20 {
        poke(&dir, regs::BOARD_VERSION, version);
        poke(&dir, regs::status_control(0), jumpers << 16 | 0xFFFF);
    }
    dir
}

fn poke(dir: &Path, offset: usize, value: u32) {
    let f = std::fs::OpenOptions::new()
        .write(true)
        .open(dir.join("resource2"))
        .unwrap();
    f.write_all_at(&value.to_le_bytes(), offset as u64).unwrap();
}

fn peek(dir: &Path, offset: usize) -> u32 {
    let f = std::fs::File::open(dir.join("resource2")).unwrap();
    let mut b = [0u8; 4];
    f.read_exact_at(&mut b, offset as u64).unwrap();
    u32::from_le_bytes(b)
}

fn enabled(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("enable"))
        .unwrap()
        .trim()
        .to_string()
}

fn load(host: &Host, fake: &FakeSysfs) -> hal_core::Result<()> {
    let args = ModuleArgs::parse(NAME, PARAMS, &[] as &[&str]).unwrap();
    load_from(host, &args, &fake.sysfs(), regs::PCI_TABLE)
}

#[test]
fn boards_are_found_enabled_mapped_identified_and_initialised() {
    let fake = FakeSysfs::new("motenc-found").unwrap();
    let lite = add_board(&fake, "0000:03:00.0", 0x200, regs::VERSION_LITE, 2);
    let full = add_board(&fake, "0000:04:00.0", 0x200, regs::VERSION_100, 2);
    // A device of another vendor is not touched.
    let other = fake
        .add_device(
            "0000:02:00.0",
            PciIds {
                vendor: 0x8086,
                ..IDS
            },
            &[],
        )
        .unwrap();
    let host = host("pci-found");
    load(&host, &fake).unwrap();
    assert_eq!(enabled(&lite), "1");
    assert_eq!(enabled(&full), "1");
    assert_eq!(enabled(&other), "0");
    let inst = host.instance();
    // Bus order: the Lite at 03 keeps its jumper ID 2, the 100 at 04
    // gets the lowest free one.
    inst.pin_value("motenc.2.enc-03-count").unwrap();
    assert!(inst.pin_value("motenc.2.enc-04-count").is_err());
    inst.pin_value("motenc.0.enc-07-count").unwrap();
    inst.pin_value("motenc.0.in-67").unwrap();
    // LinuxCNC's initialisation, in the BAR.
    for dir in [&lite, &full] {
        assert_eq!(peek(dir, regs::digital_io(0)), 0x0000_FFFF, "outputs off");
        assert_eq!(peek(dir, regs::status_control(0)), 0x0F, "counters reset");
        for n in 0..8 {
            assert_eq!(peek(dir, regs::dac(n)), regs::DAC_ZERO);
        }
        assert_eq!(peek(dir, regs::TIMER_IRQ_DISABLE), 1);
        assert_eq!(peek(dir, regs::WATCHDOG_CONTROL), 0);
    }
    assert_eq!(peek(&full, regs::digital_io(1)), 0x0000_FFFF);
    assert_eq!(
        peek(&lite, regs::digital_io(1)),
        0,
        "the Lite has no FPGA 1"
    );

    // Functions write into the BAR.
    set(&host, "motenc.0.dac-01-value", Value::Float(-10.0));
    set(&host, "motenc.2.out-04", Value::Bit(true));
    run(&host, &["motenc.0.dac-write", "motenc.2.digital-out-write"]);
    wait("DAC 1 of board 0", || peek(&full, regs::dac(1)) == 0x1FFF);
    wait("output 4 of board 2", || {
        peek(&lite, regs::digital_io(0)) == !(1u32 << 4)
    });
    host.stop();
    // Unloading puts them in the safe state and disables the devices.
    host.shutdown();
    assert_eq!(peek(&full, regs::dac(1)), regs::DAC_ZERO);
    assert_eq!(peek(&lite, regs::digital_io(0)), 0xFFFF_FFFF);
    assert_eq!(enabled(&lite), "0");
    assert_eq!(enabled(&full), "0");
}

#[test]
fn bad_boards_fail_the_load_naming_the_board_and_leave_nothing() {
    let host = host("pci-bad");
    let fake = FakeSysfs::new("motenc-none").unwrap();
    let e = load(&host, &fake).unwrap_err().to_string();
    assert!(
        e.starts_with("hal_motenc: no MOTENC (10b5:3001) found on the PCI bus (searched "),
        "{e}"
    );

    let fake = FakeSysfs::new("motenc-version").unwrap();
    let good = add_board(&fake, "0000:03:00.0", 0x200, regs::VERSION_100, 0);
    let bad = add_board(&fake, "0000:05:00.0", 0x200, 7, 0);
    let e = load(&host, &fake).unwrap_err().to_string();
    assert_eq!(
        e,
        "hal_motenc: PCI 0000:05:00.0: boardVersion is 0x7, expected 0 (MOTENC-100) or 1 \
         (MOTENC-Lite)"
    );
    assert!(host.loaded_components().is_empty());
    assert_eq!(enabled(&good), "0", "enabled again is disabled again");
    assert_eq!(enabled(&bad), "0");
    assert_eq!(peek(&good, regs::WATCHDOG_CONTROL), 0, "nothing written");

    let fake = FakeSysfs::new("motenc-ones").unwrap();
    let dir = add_board(&fake, "0000:03:00.0", 0x200, u32::MAX, 0);
    poke(&dir, regs::status_control(0), u32::MAX);
    let e = load(&host, &fake).unwrap_err().to_string();
    assert_eq!(
        e,
        "hal_motenc: PCI 0000:03:00.0: nothing answers (boardVersion and statusControl read \
         0xffffffff)"
    );

    let fake = FakeSysfs::new("motenc-small").unwrap();
    add_board(&fake, "0000:03:00.0", 0x80, 0, 0);
    let e = load(&host, &fake).unwrap_err().to_string();
    assert_eq!(
        e,
        "hal_motenc: PCI device 0000:03:00.0: BAR 2 is 0x80 bytes, the driver needs at least 0xa4"
    );

    let fake = FakeSysfs::new("motenc-five").unwrap();
    for i in 0..5 {
        add_board(&fake, &format!("0000:0{i}:00.0"), 0x200, 0, 0);
    }
    let e = load(&host, &fake).unwrap_err().to_string();
    assert_eq!(
        e,
        "hal_motenc: 5 MOTENC boards found; at most 4 can be used (board IDs 0..3)"
    );
    assert!(host.loaded_components().is_empty());
}
