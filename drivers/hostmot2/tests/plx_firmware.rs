//! FPGA loading on the PLX-bridged cards, end to end: `loadrt hm2_pci
//! config="firmware=..."` with a simulated 5i20, 5i22, ... (the bitfile
//! parsed, checked and clocked through the simulated bridge; the card
//! then runs that firmware's modules), with bitfiles of a test's own
//! firmware directory, and through a fake sysfs PLX card's I/O BARs.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;
use common::{has_pin, with_core};

use std::path::Path;

use hal_core::module::ModuleArgs;
use hal_driver::pci::fake::{FakeBar, FakeSysfs};
use hal_driver::pci::PciIds;
use hostmot2::fpga::bitfile;
use hostmot2::hal::{self, HM2_PCI_MODULE};
use hostmot2::pci::BOARDS;
use hostmot2::sim::plx;

#[test]
fn a_simulated_5i20_runs_the_firmware_its_config_names() {
    let h = with_core("plx-5i20");
    h.loadrt(
        &HM2_PCI_MODULE,
        &[
            "config=firmware=hm2/5i20/SVST8_4.BIT num_encoders=3 num_pwmgens=3 num_stepgens=1",
            "sim=5i20",
        ],
    )
    .unwrap();
    for pin in [
        "hm2_5i20.0.encoder.02.position",
        "hm2_5i20.0.pwmgen.02.value",
        "hm2_5i20.0.stepgen.00.position-cmd",
        "hm2_5i20.0.led.CR08",
        "hm2_5i20.0.gpio.025.in_not",
        "hm2_5i20.0.gpio.050.in",
    ] {
        assert!(has_pin(&h, pin), "{pin}");
    }
    for pin in [
        "hm2_5i20.0.encoder.03.position",
        "hm2_5i20.0.stepgen.01.position-cmd",
        // Stepgen 0's step and direction pins are the module's.
        "hm2_5i20.0.gpio.048.out",
    ] {
        assert!(!has_pin(&h, pin), "{pin}");
    }
    let functs: Vec<String> = h
        .instance()
        .functs()
        .unwrap()
        .into_iter()
        .map(|f| f.name)
        .collect();
    assert!(functs.iter().any(|f| f == "hm2_5i20.0.read"), "{functs:?}");
    h.unloadrt("hm2_pci").unwrap();
}

#[test]
fn every_plx_card_takes_all_its_firmwares_modules() {
    // Two loads of three: six cards' pins fill a test segment.
    for (tag, config, sims, pins) in [
        (
            "plx-all-a",
            "config=firmware=hm2/5i22-1/SVST8_8.BIT,firmware=hm2/5i23/SV12.BIT,\
             firmware=hm2/3x20-1/SVST16_24.BIT",
            "sim=5i22,5i23,3x20",
            &[
                "hm2_5i22.0.stepgen.07.position-fb",
                "hm2_5i22.0.encoder.07.position",
                "hm2_5i23.0.pwmgen.11.value",
                "hm2_3x20.0.stepgen.23.position-fb",
                "hm2_3x20.0.encoder.15.position",
            ][..],
        ),
        (
            "plx-all-b",
            "config=firmware=hm2/4i65/SVST8_4.BIT,firmware=hm2/4i68/SVST8_4.BIT,\
             firmware=hm2/5i22-1.5/SV16.BIT",
            "sim=4i65,4i68,5i22-1.5",
            &[
                "hm2_4i65.0.stepgen.03.position-fb",
                "hm2_4i68.0.led.CR04",
                "hm2_5i22.0.encoder.15.position",
            ][..],
        ),
    ] {
        let h = with_core(tag);
        h.loadrt(&HM2_PCI_MODULE, &[config, sims]).unwrap();
        for pin in pins {
            assert!(has_pin(&h, pin), "{pin}");
        }
    }
}

/// Loads hm2_pci with `args`, expecting a refusal containing every `want`.
fn refused(tag: &str, args: &[&str], want: &[&str]) {
    let h = with_core(tag);
    let e = h.loadrt(&HM2_PCI_MODULE, args).unwrap_err().to_string();
    for w in want {
        assert!(e.contains(w), "{args:?}: {e}");
    }
    assert_eq!(h.loaded_components(), ["hostmot2"], "{args:?}");
}

#[test]
fn simulated_cards_without_flash_need_firmware_they_know() {
    refused(
        "plx-nofw",
        &["sim=5i20"],
        &[
            "the simulated 5i20 has no flash",
            "firmware=hm2/5i20/SVST8_4.BIT",
        ],
    );
    refused(
        "plx-unknownfw",
        &["config=firmware=hm2/5i20/7I77X2.BIT", "sim=5i20"],
        &[
            "hm2_5i20.0 fails HM2 registration",
            "does not know the firmware '7I77X2'",
        ],
    );
    refused(
        "plx-toobig",
        &["config=firmware=hm2/5i20/SV24.BIT", "sim=5i20"],
        &["24 servo channels need 6 connectors"],
    );
    refused(
        "plx-escape",
        &[
            "config=firmware=../hm2/SV12.BIT",
            "sim=5i20",
            "firmware_dir=/nonexistent",
        ],
        &["'..' would leave the firmware directory"],
    );
}

fn fw_dir(files: &[(&str, Vec<u8>)]) -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    for (name, bytes) in files {
        let p = d.path().join(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, bytes).unwrap();
    }
    d
}

fn dir_arg(d: &Path) -> String {
    format!("firmware_dir={}", d.display())
}

#[test]
fn bitfiles_from_the_firmware_directory_are_checked_and_loaded() {
    let good = plx::bitfile("SV12", "2s200pq208");
    let wrong_part = plx::bitfile("SV12", "3s400pq208");
    let stream = plx::bitstream("SV12", "2s200pq208");
    let cut = bitfile::build(
        "sv12.ncd",
        "2s200pq208",
        "",
        "",
        &stream[..stream.len() - 64],
    );
    let mut bad_crc = stream.clone();
    let n = bad_crc.len();
    bad_crc[n - 1] ^= 0xFF;
    let bad_crc = bitfile::build("sv12.ncd", "2s200pq208", "", "", &bad_crc);
    let mut short_header = good.clone();
    short_header.truncate(40);
    let d = fw_dir(&[
        ("hm2/5i20/SV12.BIT", good),
        ("hm2/5i20/WRONG.BIT", wrong_part),
        ("hm2/5i20/CUT.BIT", cut),
        ("hm2/5i20/CRC.BIT", bad_crc),
        ("hm2/5i20/SHORT.BIT", short_header),
    ]);
    let dir = dir_arg(d.path());
    let h = with_core("plx-dir-ok");
    h.loadrt(
        &HM2_PCI_MODULE,
        &[
            "config=firmware=hm2/5i20/SV12.BIT",
            "sim=5i20",
            dir.as_str(),
        ],
    )
    .unwrap();
    assert!(has_pin(&h, "hm2_5i20.0.encoder.11.position"));
    assert!(!has_pin(&h, "hm2_5i20.0.stepgen.00.position-fb"));
    for (tag, file, want) in [
        (
            "plx-dir-missing",
            "NONE.BIT",
            &["cannot read the bitfile", "NONE.BIT"][..],
        ),
        (
            "plx-dir-part",
            "WRONG.BIT",
            &["bitfile is for the FPGA part '3s400pq208', but this board has a '2s200pq208'"],
        ),
        (
            "plx-dir-cut",
            "CUT.BIT",
            &[
                "FPGA programming failed at the DONE check step",
                "DONE did not rise",
            ],
        ),
        (
            "plx-dir-crc",
            "CRC.BIT",
            &[
                "FPGA programming failed at the DONE check step",
                "CRC error",
            ],
        ),
        ("plx-dir-short", "SHORT.BIT", &["bitfile cut short"]),
    ] {
        let config = format!("config=firmware=hm2/5i20/{file}");
        refused(tag, &[config.as_str(), "sim=5i20", dir.as_str()], want);
    }
}

#[test]
fn flash_boards_ignore_firmware() {
    let h = with_core("plx-flash");
    h.loadrt(
        &HM2_PCI_MODULE,
        &["config=firmware=hm2/5i25/7i76x2.bit", "sim=5i25"],
    )
    .unwrap();
    assert!(has_pin(&h, "hm2_5i25.0.stepgen.00.position-fb"));
}

/// A fake 5i20 on a fake sysfs tree: its bridge BARs are plain files, so
/// the FPGA never answers the loader.
#[test]
fn a_pci_5i20_is_programmed_through_its_io_bars() {
    let fake = FakeSysfs::new("plx-pci").unwrap();
    let ids = PciIds {
        vendor: 0x10B5,
        device: 0x9030,
        subvendor: 0x10B5,
        subdevice: 0x3131,
    };
    let bars = [
        FakeBar::Unused,
        FakeBar::Io {
            start: 0xD000,
            len: 0x80,
        },
        FakeBar::Io {
            start: 0xD400,
            len: 0x10,
        },
        FakeBar::Unused,
        FakeBar::Unused,
        FakeBar::Mem {
            start: 0xFE00_0000,
            len: 0x1_0000,
        },
    ];
    let dev = fake.add_device("0000:06:00.0", ids, &bars).unwrap();
    let d = fw_dir(&[(
        "hm2/5i20/SVST8_4.BIT",
        plx::bitfile("SVST8_4", "2s200pq208"),
    )]);
    let h = with_core("plx-pci");
    let args = ModuleArgs::parse(
        "hm2_pci",
        HM2_PCI_MODULE.params,
        &[
            "config=firmware=hm2/5i20/SVST8_4.BIT",
            dir_arg(d.path()).as_str(),
        ],
    )
    .unwrap();
    let e = hal::load_pci(&h, &args, &fake.sysfs(), BOARDS)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("hm2_pci: board at 0000:06:00.0 fails HM2 registration")
            && e.contains("FPGA programming failed at the waiting for /INIT step"),
        "{e}"
    );
    // The loader fixed the local bus descriptors' READY# bits and left
    // /PROGRAM released, /WRITE and /LED high.
    let regs = std::fs::read(dev.join("resource1")).unwrap();
    let word = |a: usize| u32::from_le_bytes(regs[a..a + 4].try_into().unwrap());
    for a in [0x28, 0x2C, 0x30, 0x34] {
        assert_eq!(word(a) & 2, 2, "LAS BRD at {a:#x}");
    }
    assert_eq!(word(0x54) >> 23 & 0b1001, 0b1001, "{:#x}", word(0x54));
}
