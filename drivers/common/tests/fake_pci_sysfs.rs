//! PCI discovery over a fake sysfs tree in a temp dir: match, no match,
//! permission denied, BARs missing, of the wrong kind or too small,
//! enable and disable, and register words reaching the mapped file.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use hal_driver::bus::{PortBus, RegWindow};
use hal_driver::pci::fake::{FakeBar, FakeSysfs};
use hal_driver::pci::{self, PciIds, PciMatch};
use hal_driver::DriverError;

const MESA: &[PciMatch] = &[
    PciMatch::new(0x2718, 0x5125, "5i25").subsystem(0x2718, 0x5125),
    PciMatch::new(0x10b5, 0x9030, "5i20").subsystem(0x10b5, 0x3131),
];

fn ids(vendor: u16, device: u16, subvendor: u16, subdevice: u16) -> PciIds {
    PciIds {
        vendor,
        device,
        subvendor,
        subdevice,
    }
}

/// A tree with a 5i25 (BAR 0: 64 KiB), a 5i20 behind a PLX 9030 (BAR 1
/// I/O, BAR 5 memory), a PLX 9030 of someone else (other subsystem) and
/// an unrelated device, listed out of bus order.
fn tree(tag: &str) -> FakeSysfs {
    let t = FakeSysfs::new(tag).unwrap();
    t.add_device(
        "0000:03:00.0",
        ids(0x2718, 0x5125, 0x2718, 0x5125),
        &[FakeBar::Mem {
            start: 0xfea0_0000,
            len: 0x10000,
        }],
    )
    .unwrap();
    t.add_device(
        "0000:02:01.0",
        ids(0x10b5, 0x9030, 0x10b5, 0x3131),
        &[
            FakeBar::Mem {
                start: 0xfeb0_0000,
                len: 0x80,
            },
            FakeBar::Io {
                start: 0xe000,
                len: 0x80,
            },
            FakeBar::Io {
                start: 0xe080,
                len: 0x20,
            },
            FakeBar::Unused,
            FakeBar::Unused,
            FakeBar::Mem {
                start: 0xfeb1_0000,
                len: 0x10000,
            },
        ],
    )
    .unwrap();
    t.add_device("0000:02:02.0", ids(0x10b5, 0x9030, 0x1234, 0x0001), &[])
        .unwrap();
    t.add_device("0000:00:1f.0", ids(0x8086, 0x2918, 0x8086, 0x0000), &[])
        .unwrap();
    t
}

#[test]
fn matching_devices_come_in_bus_order_with_their_names() {
    let t = tree("match");
    let found = pci::scan(&t.sysfs(), MESA).unwrap();
    let got: Vec<(&str, &str)> = found
        .iter()
        .map(|d| (d.address.as_str(), d.name()))
        .collect();
    assert_eq!(
        got,
        vec![("0000:02:01.0", "5i20"), ("0000:03:00.0", "5i25")]
    );
    assert_eq!(found[1].ids, ids(0x2718, 0x5125, 0x2718, 0x5125));
    assert_eq!(found[1].path, t.dir().join("0000:03:00.0"));
    // Without the subsystem the other PLX card matches too.
    let any_plx = [PciMatch::new(0x10b5, 0x9030, "plx")];
    assert_eq!(pci::scan(&t.sysfs(), &any_plx).unwrap().len(), 2);
}

#[test]
fn no_match_names_what_and_where() {
    let t = tree("nomatch");
    let table = [PciMatch::new(0x2718, 0x6125, "6i25")];
    assert!(pci::scan(&t.sysfs(), &table).unwrap().is_empty());
    let e = pci::find(&t.sysfs(), &table).unwrap_err();
    assert!(matches!(e, DriverError::PciNotFound { .. }));
    let m = e.to_string();
    assert!(m.contains("no 6i25 (2718:6125) found"), "{m}");
    assert!(m.contains(&t.dir().display().to_string()), "{m}");
    let e = pci::scan(&pci::Sysfs::at(t.dir().join("absent")), MESA).unwrap_err();
    assert!(e.to_string().contains("listing PCI devices"), "{e}");
}

#[test]
fn a_malformed_id_file_is_named() {
    let t = tree("badid");
    std::fs::write(t.dir().join("0000:03:00.0/device"), "5125\n").unwrap();
    let e = pci::scan(&t.sysfs(), MESA).unwrap_err().to_string();
    assert!(
        e.contains("0000:03:00.0/device") && e.contains("'5125'"),
        "{e}"
    );
}

#[test]
fn enable_writes_one_and_the_guard_writes_zero() {
    let t = tree("enable");
    let dev = pci::find(&t.sysfs(), &MESA[..1]).unwrap().remove(0);
    let enable = dev.path.join("enable");
    {
        let g = dev.enable().unwrap();
        assert_eq!(g.path(), enable);
        assert_eq!(std::fs::read_to_string(&enable).unwrap(), "1");
    }
    assert_eq!(std::fs::read_to_string(&enable).unwrap(), "0");
    // Older kernels call the file `enabled`.
    std::fs::remove_file(&enable).unwrap();
    std::fs::write(dev.path.join("enabled"), "0").unwrap();
    let g = dev.enable().unwrap();
    assert_eq!(
        std::fs::read_to_string(dev.path.join("enabled")).unwrap(),
        "1"
    );
    drop(g);
    assert!(!enable.exists());
}

#[test]
fn words_written_through_the_bar_reach_the_resource_file() {
    let t = tree("map");
    let dev = pci::find(&t.sysfs(), &MESA[..1]).unwrap().remove(0);
    let r = dev.resources().unwrap();
    assert_eq!((r[0].start, r[0].len()), (0xfea0_0000, 0x10000));
    assert!(r[0].is_mem() && !r[1].is_present());
    let w = dev.map_bar(0).unwrap();
    assert_eq!(w.len(), 0x10000);
    w.write32(0x100, 0x55AA_CAFE);
    w.write_burst(0x104, &[0x5453_4F48, 0x3254_4F4D]);
    let bytes = std::fs::read(dev.resource_path(0)).unwrap();
    assert_eq!(&bytes[0x100..0x10C], b"\xFE\xCA\xAA\x55HOSTMOT2");
    assert_eq!(w.read32(0x100), 0x55AA_CAFE);
    assert_eq!(w.errors(), 0);
    let small = dev.map_bar_window(0, 0x1000).unwrap();
    assert_eq!(small.len(), 0x1000);
    assert_eq!(small.read32(0x104), 0x5453_4F48);
}

#[test]
fn bars_missing_of_the_wrong_kind_or_too_small_are_refused() {
    let t = tree("bars");
    let devs = pci::find(&t.sysfs(), MESA).unwrap();
    let (plx, mesa) = (&devs[0], &devs[1]);
    let e = mesa.map_bar(2).unwrap_err();
    assert!(matches!(e, DriverError::BarMissing { bar: 2, .. }), "{e}");
    assert_eq!(
        e.to_string(),
        "PCI device 0000:03:00.0: BAR 2 is not present"
    );
    assert!(matches!(
        mesa.map_bar(9).unwrap_err(),
        DriverError::BarMissing { bar: 9, .. }
    ));
    let e = plx.map_bar(1).unwrap_err().to_string();
    assert_eq!(
        e,
        "PCI device 0000:02:01.0: BAR 1 is an I/O BAR, the driver needs a memory BAR"
    );
    let e = plx.io_bar(5).unwrap_err().to_string();
    assert!(
        e.contains("BAR 5 is a memory BAR, the driver needs an I/O BAR"),
        "{e}"
    );
    let e = plx.map_bar_window(0, 0x10000).unwrap_err();
    assert!(
        matches!(
            e,
            DriverError::BarTooSmall {
                bar: 0,
                size: 0x80,
                needed: 0x10000,
                ..
            }
        ),
        "{e}"
    );
    assert!(e
        .to_string()
        .contains("BAR 0 is 0x80 bytes, the driver needs at least 0x10000"));
    // A resource file shorter than its BAR (a broken tree) is refused
    // before mapping: touching past its end would be SIGBUS.
    std::fs::File::options()
        .write(true)
        .open(mesa.resource_path(0))
        .unwrap()
        .set_len(0x100)
        .unwrap();
    let e = mesa.map_bar(0).unwrap_err();
    assert!(
        matches!(
            e,
            DriverError::BarTooSmall {
                size: 0x100,
                needed: 0x10000,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn an_io_bar_is_addressed_by_port() {
    let t = tree("io");
    let plx = pci::find(&t.sysfs(), &MESA[1..]).unwrap().remove(0);
    let io = plx.io_bar(1).unwrap();
    assert_eq!((io.range().base, io.range().len), (0xe000, 0x80));
    io.outl(0xe054, 0x0400_0000);
    io.outb(0xe07f, 0x5A);
    assert_eq!(io.inl(0xe054), 0x0400_0000);
    assert_eq!(io.inw(0xe056), 0x0400);
    let bytes = std::fs::read(plx.resource_path(1)).unwrap();
    assert_eq!(&bytes[0x54..0x58], &[0, 0, 0, 4]);
    assert_eq!(bytes[0x7f], 0x5A);
    assert_eq!(io.errors(), 0);
    assert_eq!(io.inl(0xe07e), u32::MAX, "runs past the BAR");
    assert_eq!(io.inb(0xdfff), 0xFF);
    assert_eq!(io.errors(), 2);
}

/// Runs `f` in a thread without file-permission override: as root, that
/// thread's filesystem uid becomes `nobody`, which drops its
/// CAP_DAC_OVERRIDE (fsuid and capabilities are per thread; the rest of
/// the process keeps root).
fn unprivileged<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    std::thread::scope(|s| {
        s.spawn(|| {
            // SAFETY: geteuid and setfsuid have no memory-safety
            // preconditions; setfsuid changes only the calling thread.
            unsafe {
                if libc::geteuid() == 0 {
                    libc::setfsuid(65534);
                }
            }
            f()
        })
        .join()
        .unwrap()
    })
}

#[test]
fn permission_denied_names_the_file_and_the_udev_rule() {
    use std::os::unix::fs::PermissionsExt;
    let t = tree("perm");
    let dev = pci::find(&t.sysfs(), &MESA[..1]).unwrap().remove(0);
    let res = dev.resource_path(0);
    let enable = dev.path.join("enable");
    for f in [&res, &enable] {
        std::fs::set_permissions(f, std::fs::Permissions::from_mode(0o444)).unwrap();
    }
    let (map_err, enable_err) =
        unprivileged(|| (dev.map_bar(0).unwrap_err(), dev.enable().unwrap_err()));
    assert!(
        matches!(map_err, DriverError::Permission { .. }),
        "{map_err}"
    );
    let m = map_err.to_string();
    assert!(m.contains(&res.display().to_string()), "{m}");
    assert!(
        m.contains("udev/60-hal-suite.rules") && m.contains("'hal'"),
        "{m}"
    );
    assert!(
        matches!(enable_err, DriverError::Permission { .. }),
        "{enable_err}"
    );
    assert!(
        enable_err
            .to_string()
            .contains(&enable.display().to_string()),
        "{enable_err}"
    );
}
