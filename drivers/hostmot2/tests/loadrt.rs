//! `loadrt hostmot2`, `hm2_pci` (simulated boards and a fake sysfs PCI
//! tree) and `hm2_test`: what loads, what is refused with which words, and
//! that a refused load leaves nothing behind.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use hal_core::module::ModuleArgs;
use hal_core::{Host, HostConfig, Value};
use hal_driver::pci::fake::{FakeBar, FakeSysfs};
use hal_driver::pci::PciIds;
use hal_driver::sim as layer_sim;
use hostmot2::hal::{self, HM2_PCI_MODULE, HM2_TEST_MODULE, HOSTMOT2_MODULE};
use hostmot2::pci::BOARDS;
use hostmot2::sim::{boards, SimHm2};
use hostmot2::test_patterns;

fn host(tag: &str) -> Host {
    Host::create(HostConfig::for_tests(tag)).unwrap()
}

fn with_core(tag: &str) -> Host {
    let h = host(tag);
    h.loadrt(&HOSTMOT2_MODULE, &[] as &[&str]).unwrap();
    h
}

fn history(h: &Host) -> Vec<String> {
    h.flush_rt_log();
    h.rt_log().history().into_iter().map(|(_, t)| t).collect()
}

#[test]
fn board_drivers_need_hostmot2() {
    let h = host("hm2-nocore");
    let e = h.loadrt(&HM2_PCI_MODULE, &["sim=5i25"]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "hm2_pci: the hostmot2 driver is not loaded (loadrt hostmot2 first)"
    );
    let e = h.loadrt(&HM2_TEST_MODULE, &["test_pattern=0"]).unwrap_err();
    assert!(e.to_string().contains("loadrt hostmot2 first"));
    assert!(h.loaded_components().is_empty());
}

#[test]
fn simulated_boards_load_with_linuxcncs_names() {
    let h = with_core("hm2-simload");
    h.loadrt(
        &HM2_PCI_MODULE,
        &[
            "config=num_encoders=1 num_pwmgens=2,num_stepgens=4",
            "sim=6i25,5i25",
        ],
    )
    .unwrap();
    assert_eq!(h.loaded_components(), ["hostmot2", "hm2_pci"]);
    let inst = h.instance();
    let functs: Vec<String> = inst.functs().unwrap().into_iter().map(|f| f.name).collect();
    for f in [
        "hm2_6i25.0.read",
        "hm2_6i25.0.write",
        "hm2_6i25.0.read_gpio",
        "hm2_6i25.0.write_gpio",
        "hm2_6i25.0.pet_watchdog",
        "hm2_5i25.0.read",
        "hm2_5i25.0.write",
    ] {
        assert!(functs.iter().any(|n| n == f), "{f} in {functs:?}");
    }
    for pin in [
        "hm2_6i25.0.encoder.00.position",
        "hm2_6i25.0.encoder.00.probe-enable",
        "hm2_6i25.0.pwmgen.01.value",
        "hm2_6i25.0.gpio.012.in_not",
        "hm2_6i25.0.watchdog.has_bit",
        "hm2_6i25.0.led.CR02",
        "hm2_5i25.0.stepgen.03.position-fb",
        "hm2_5i25.0.gpio.008.in",
    ] {
        assert!(inst.pin(pin).unwrap().is_some(), "{pin}");
    }
    for param in [
        "hm2_6i25.0.io_error",
        "hm2_6i25.0.watchdog.timeout_ns",
        "hm2_6i25.0.pwmgen.pwm_frequency",
        "hm2_6i25.0.pwmgen.00.output-type",
        "hm2_6i25.0.pwmgen.01.out0.invert_output",
        "hm2_5i25.0.stepgen.00.step_type",
        "hm2_5i25.0.gpio.008.is_output",
    ] {
        assert!(inst.param(param).unwrap().is_some(), "{param}");
    }
    assert!(inst
        .pin("hm2_6i25.0.encoder.01.position")
        .unwrap()
        .is_none());
    assert!(inst
        .pin("hm2_5i25.0.stepgen.04.position-fb")
        .unwrap()
        .is_none());
    assert_eq!(
        inst.param_value("hm2_6i25.0.watchdog.timeout_ns").unwrap(),
        Value::U32(5_000_000)
    );
    // Unloading bites the watchdog: every output released.
    let board = layer_sim::find::<SimHm2>(inst.name(), "hm2_5i25.0").unwrap();
    board.with(|m| m.write32(0x1100, 0x3FF));
    h.unloadrt("hm2_pci").unwrap();
    assert_eq!(board.with(|m| m.read32(0x1100)), 0);
    assert!(layer_sim::find::<SimHm2>(h.instance().name(), "hm2_6i25.0").is_none());
}

#[test]
fn refused_loads_leave_nothing_behind() {
    let h = with_core("hm2-refused");
    for (args, want) in [
        (
            &["config=bogus", "sim=5i25"][..],
            "invalid token in config string: \"bogus\"",
        ),
        (
            &["config=num_stepgens=11", "sim=5i25"][..],
            "config.num_stepgens=11, but only 10 are available",
        ),
        (
            &["config=firmware=hm2/5i20/x.bit", "sim=5i20"][..],
            "the simulator does not know the firmware 'x'",
        ),
        (
            &["config=,num_encoders=9", "sim=5i25,6i25"][..],
            "config.num_encoders=9, but only 4",
        ),
        (&["sim=7i99"][..], "hm2_pci: parameter 'sim'"),
    ] {
        let e = h.loadrt(&HM2_PCI_MODULE, args).unwrap_err().to_string();
        assert!(e.contains(want), "{args:?}: {e}");
        assert_eq!(h.loaded_components(), ["hostmot2"], "{args:?}");
        assert!(h
            .instance()
            .pin("hm2_5i25.0.gpio.000.in")
            .unwrap()
            .is_none());
    }
    let said = history(&h);
    assert!(
        said.iter()
            .any(|l| l == "hm2/hm2_5i25.0: invalid token in config string: \"bogus\""),
        "{said:?}"
    );
    assert!(said
        .iter()
        .any(|l| l == "hm2_pci: simulated board hm2_5i25.0 fails HM2 registration"));
    // After all that, a good load works.
    h.loadrt(&HM2_PCI_MODULE, &["sim=5i25"]).unwrap();
}

#[test]
fn hm2_test_patterns_fail_as_in_linuxcnc() {
    for n in test_patterns::PATTERNS {
        let h = with_core(&format!("hm2-test-{n}"));
        let arg = format!("test_pattern={n}");
        let e = h.loadrt(&HM2_TEST_MODULE, &[arg.as_str()]).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("hm2_test: hm2_test.0: hm2_test fails HM2 registration"),
            "{n}: {e}"
        );
        assert_eq!(h.loaded_components(), ["hostmot2"], "pattern {n}");
        assert!(!h.loaded_modules().contains(&"hm2_test"));
        let said = history(&h);
        let want = format!(
            "hm2/hm2_test.0: {}",
            test_patterns::expected_message(n).unwrap()
        );
        assert!(said.contains(&want), "pattern {n}: {said:?}");
        assert_eq!(
            said.last().map(String::as_str),
            Some("hm2_test.0: hm2_test fails HM2 registration")
        );
    }
    let h = with_core("hm2-test-unknown");
    let e = h
        .loadrt(&HM2_TEST_MODULE, &["test_pattern=15"])
        .unwrap_err();
    assert_eq!(e.to_string(), "hm2_test: unknown test pattern 15");
    assert!(history(&h).contains(&"hm2_test: unknown test pattern 15".to_string()));
}

fn pci_args(args: &[&str]) -> ModuleArgs {
    ModuleArgs::parse("hm2_pci", HM2_PCI_MODULE.params, args).unwrap()
}

fn add_board(fake: &FakeSysfs, address: &str, id: u16, image: Option<Vec<u32>>) {
    let ids = PciIds {
        vendor: 0x2718,
        device: id,
        subvendor: 0x2718,
        subdevice: id,
    };
    let bar = FakeBar::Mem {
        start: 0xfe00_0000,
        len: 0x1_0000,
    };
    let dir = fake.add_device(address, ids, &[bar]).unwrap();
    if let Some(img) = image {
        let bytes: Vec<u8> = img.iter().flat_map(|w| w.to_le_bytes()).collect();
        std::fs::write(dir.join("resource0"), bytes).unwrap();
    }
}

#[test]
fn pci_boards_over_a_fake_sysfs_tree() {
    let fake = FakeSysfs::new("hm2-pci").unwrap();
    let img = |name| boards::preset(name).unwrap().image();
    add_board(&fake, "0000:03:00.0", 0x5125, Some(img("5i25")));
    add_board(&fake, "0000:02:00.0", 0x5125, Some(img("5i25")));
    add_board(&fake, "0000:04:00.0", 0x6125, Some(img("6i25")));
    let h = with_core("hm2-pcifake");
    hal::load_pci(
        &h,
        &pci_args(&["config=num_stepgens=1,num_stepgens=2"]),
        &fake.sysfs(),
        BOARDS,
    )
    .unwrap();
    let inst = h.instance();
    // Bus order: 02:00.0 is hm2_5i25.0 and takes config item 0.
    assert!(inst
        .pin("hm2_5i25.0.stepgen.00.position-fb")
        .unwrap()
        .is_some());
    assert!(inst
        .pin("hm2_5i25.0.stepgen.01.position-fb")
        .unwrap()
        .is_none());
    assert!(inst
        .pin("hm2_5i25.1.stepgen.01.position-fb")
        .unwrap()
        .is_some());
    assert!(inst.pin("hm2_6i25.0.pwmgen.03.value").unwrap().is_some());
    let enable = |a: &str| std::fs::read_to_string(fake.dir().join(a).join("enable")).unwrap();
    assert_eq!(enable("0000:02:00.0").trim(), "1");
    // The registration wrote the configuration into the BAR: stepgen
    // pins of hm2_5i25.0 to their module (AltSource at 0x1200).
    let bar = std::fs::read(fake.dir().join("0000:02:00.0/resource0")).unwrap();
    let word = |b: &[u8], a: usize| u32::from_le_bytes(b[a..a + 4].try_into().unwrap());
    assert_eq!(word(&bar, 0x1200) & 0x3, 0x3);
    h.unload("hm2_pci").unwrap();
    assert_eq!(enable("0000:02:00.0").trim(), "0", "disabled at unload");
}

#[test]
fn pci_refusals_name_the_board_and_the_reason() {
    let h = with_core("hm2-pcibad");
    let fake = FakeSysfs::new("hm2-pcibad").unwrap();
    let e = hal::load_pci(&h, &pci_args(&[]), &fake.sysfs(), BOARDS).unwrap_err();
    assert!(e.to_string().starts_with("hm2_pci: "), "{e}");
    assert!(e.to_string().contains("5i25 (2718:5125"), "{e}");
    // A board whose FPGA is not configured: an all-zero window.
    add_board(&fake, "0000:05:00.0", 0x5124, None);
    let e = hal::load_pci(&h, &pci_args(&[]), &fake.sysfs(), BOARDS).unwrap_err();
    assert!(
        e.to_string()
            .contains("hm2_pci: board at 0000:05:00.0 fails HM2 registration: invalid cookie"),
        "{e}"
    );
    assert_eq!(h.loaded_components(), ["hostmot2"]);
    let said = history(&h);
    assert!(said.contains(
        &"hm2/hm2_5i24.0: invalid cookie, got 0x00000000, expected 0x55AACAFE".to_string()
    ));
}
