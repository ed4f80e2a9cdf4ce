//! The IDROM loader on the simulated boards' images and on hm2_test's
//! broken images: every check of hardware.md 5.7, in LinuxCNC's words.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use hostmot2::config::{self, Config};
use hostmot2::firmware::{self, Debug};
use hostmot2::image::{pd, FirmwareSpec, ImageTransport, ModuleSpec};
use hostmot2::log::{Level, MessageLog};
use hostmot2::pins::PinOwner;
use hostmot2::regs::gtag;
use hostmot2::sim::boards;
use hostmot2::test_patterns;
use hostmot2::Hm2Error;

fn load(spec: &FirmwareSpec, cfg: &str) -> (Result<firmware::Firmware, Hm2Error>, MessageLog) {
    let mut t = ImageTransport::new(spec.image(), "test");
    let mut log = MessageLog::default();
    let config = config::parse(cfg).unwrap();
    let r = firmware::load(&spec.llio(0), &config, Debug::default(), &mut t, &mut log);
    (r, log)
}

/// Loads `img` as a board described by `llio`, without config.
fn load_image(
    llio: &hostmot2::llio::Llio,
    img: Vec<u32>,
) -> (Result<firmware::Firmware, Hm2Error>, MessageLog) {
    let mut t = ImageTransport::new(img, "test");
    let mut log = MessageLog::default();
    let r = firmware::load(llio, &Config::default(), Debug::default(), &mut t, &mut log);
    (r, log)
}

#[test]
fn every_simulated_board_loads() {
    for name in boards::PRESETS.iter().chain(boards::ETH_PRESETS) {
        let spec = boards::preset(name).unwrap();
        let (fw, log) = load(&spec, "");
        let fw = fw.unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(
            fw.idrom.board_name(),
            std::str::from_utf8(&spec.board_name).unwrap()
        );
        assert_eq!(fw.pins.len(), spec.pins.len());
        assert!(
            log.messages().iter().all(|m| m.level >= Level::Info),
            "{log:?}"
        );
        // (A firmware image without its Smart Serial processor behind
        // it finds no card first.)
        let lines = log.lines("", Level::Info);
        let used = format!("{} I/O Pins used:", spec.pins.len());
        assert!(lines.contains(&used), "{name}: {lines:?}");
    }
    let (fw, _) = load(&boards::preset("5i25").unwrap(), "");
    let fw = fw.unwrap();
    assert_eq!(fw.stepgen.unwrap().instances, 10);
    assert_eq!(fw.encoder.unwrap().instances, 2);
    assert!(fw.pwmgen.is_none());
    assert_eq!(fw.led.unwrap().instances, 2);
}

#[test]
fn config_counts_choose_instances_and_free_pins() {
    let spec = boards::preset("5i25").unwrap();
    let (fw, log) = load(&spec, "num_stepgens=3 num_encoders=0 num_leds=5");
    let fw = fw.unwrap();
    assert_eq!(fw.stepgen.unwrap().instances, 3);
    assert!(fw.encoder.is_none());
    assert_eq!(fw.led.unwrap().instances, 2, "clamped");
    assert!(log
        .lines("", Level::Warn)
        .iter()
        .any(|l| l.contains("only 2 LEDs")));
    // Stepgens 3, 4 (pins 6..9) and the encoder (10..12) are GPIO now.
    let module = |io: usize| fw.pins[io].owner != PinOwner::Gpio;
    assert!((0..6).all(module));
    assert!(!(6..17).any(module));
    let usage: Vec<&str> = log
        .messages()
        .iter()
        .filter(|m| m.level == Level::Info)
        .map(|m| m.text.as_str())
        .collect();
    assert_eq!(
        usage[1],
        "    IO Pin 000 (P3-01): StepGen #0, pin Step (Output)"
    );
    assert_eq!(
        usage[2],
        "    IO Pin 001 (P3-14): StepGen #0, pin Direction (Output)"
    );
    assert_eq!(usage[18], "    IO Pin 017 (P2-01): IOPort");
    let (r, _) = load(&spec, "num_stepgens=11");
    assert_eq!(
        r.unwrap_err().to_string(),
        "config.num_stepgens=11, but only 10 are available, not loading driver"
    );
}

#[test]
fn stepgen_width_masks_table_pins() {
    let mut spec = boards::preset("5i25").unwrap();
    spec.pins[13] = pd(gtag::STEPGEN, 0, 0x83);
    let (fw, _) = load(&spec, "");
    assert_eq!(fw.unwrap().pins[13].owner, PinOwner::Gpio);
    let (fw, _) = load(&spec, "stepgen_width=3");
    assert_ne!(fw.unwrap().pins[13].owner, PinOwner::Gpio);
}

#[test]
fn hm2_test_patterns_fail_with_linuxcncs_words() {
    for n in test_patterns::PATTERNS {
        let (llio, img) = test_patterns::pattern(n).unwrap();
        let (err, log) = load_image(&llio, img);
        let err = err.expect_err("every pattern fails").to_string();
        let want = test_patterns::expected_message(n).unwrap();
        let logged = log.lines("", Level::Err);
        assert!(
            err.lines().next() == Some(want) || logged.first().map(String::as_str) == Some(want),
            "pattern {n}: {err} / {logged:?}"
        );
    }
    assert!(test_patterns::pattern(15).is_none());
    let (llio, img) = test_patterns::pattern(0).unwrap();
    let (e, _log) = load_image(&llio, img);
    let e = e.unwrap_err().to_string();
    assert_eq!(
        e.lines().nth(1),
        Some("FPGA failed to initialize, or unexpected firmware?")
    );
}

#[test]
fn pattern_12_reports_every_pin() {
    let (llio, img) = test_patterns::pattern(12).unwrap();
    let (e, log) = load_image(&llio, img);
    let e = e.unwrap_err().to_string();
    let lines = log.lines("", Level::Err);
    assert_eq!(lines.len(), 48);
    assert_eq!(lines[46], "hm2_set_pin_source: invalid pin number 23");
    assert_eq!(
        lines[47],
        "hm2_set_pin_direction_immediate: invalid pin number 23"
    );
    assert!(e.to_string().contains("no IOPort Module Descriptor"), "{e}");
}

fn with_module(m: ModuleSpec) -> FirmwareSpec {
    let mut spec = boards::preset("6i25").unwrap();
    spec.modules.push(m);
    spec
}

#[test]
fn module_descriptor_checks() {
    let cases: Vec<(FirmwareSpec, &str)> = vec![
        (with_module(ModuleSpec::standard(gtag::ENCODER, 3, 1)), "found duplicate Module Descriptor for Encoder (inconsistent firmware), not loading driver"),
        (with_module(ModuleSpec { version: 1, ..ModuleSpec::standard(gtag::IOPORT, 0, 2) }), "inconsistent Module Descriptor for IOPort, not loading driver"),
        (with_module(ModuleSpec { num_registers: 4, ..ModuleSpec::standard(gtag::WATCHDOG, 0, 1) }), "inconsistent Module Descriptor for Watchdog"),
        (with_module(ModuleSpec { version: 7, ..ModuleSpec::standard(gtag::STEPGEN, 2, 1) }), "unknown stepgen MD:"),
        (with_module(ModuleSpec { version: 2, ..ModuleSpec::standard(gtag::LED, 0, 1) }), "inconsistent Module Descriptor for LED"),
    ];
    for (spec, want) in cases {
        let (r, _) = load(&spec, "");
        let e = r.unwrap_err().to_string();
        assert!(e.starts_with(want), "{e}");
    }
    // A wrong PWM version, after the duplicate check of others.
    let mut spec = boards::preset("6i25").unwrap();
    spec.modules[3].version = 2;
    assert!(load(&spec, "")
        .0
        .unwrap_err()
        .to_string()
        .starts_with("Unsupported PWM firmware version 2"));
    // IOPort instances must match IOPorts.
    let mut spec = boards::preset("6i25").unwrap();
    spec.modules[1].instances = 3;
    assert_eq!(
        load(&spec, "").0.unwrap_err().to_string(),
        "IDROM IOPorts is 2 but MD IOPort NumInstances is 3, inconsistent firmware, aborting driver load"
    );
    // Unknown and unsupported modules are ignored with a warning.
    let spec = with_module(ModuleSpec::standard(0x55, 0, 1));
    let (r, log) = load(&spec, "");
    r.unwrap();
    let warns = log.lines("", Level::Warn);
    assert_eq!(warns[0], "Firmware contains unknown function (gtag-85)");
    assert_eq!(warns[1], "MD 5: 1x (unknown-gtag-85) v0: ignored");
}

#[test]
fn descriptor_stride_and_clock_checks() {
    let spec = boards::preset("5i25").unwrap();
    let md1 = (hostmot2::image::IDROM_ADDR + hostmot2::image::MD_OFFSET + 12) as usize / 4;
    for (word, value, want) in [
        (
            0,
            0x0203_0003u32,
            "Module Descriptor 1 (at 0x044c) has invalid ClockTag 3",
        ),
        (
            1,
            0x0205_1000,
            "Module Descriptor 1 (at 0x044c) has invalid RegisterStride 2",
        ),
        (
            1,
            0x3005_1000,
            "Module Descriptor 1 (at 0x044c) has invalid InstanceStride 3",
        ),
    ] {
        let mut img = spec.image();
        img[md1 + word] = value;
        let (e, _log) = load_image(&spec.llio(0), img);
        let e = e.unwrap_err().to_string();
        assert_eq!(e.to_string(), want);
    }
    // A pin whose primary tag is not IOPort.
    let mut img = spec.image();
    img[(hostmot2::image::IDROM_ADDR + hostmot2::image::PD_OFFSET) as usize / 4 + 3] = 0x0400_0000;
    let (e, _log) = load_image(&spec.llio(0), img);
    let e = e.unwrap_err().to_string();
    assert_eq!(
        e.to_string(),
        "pin 3 primary tag is 4 (Encoder), not IOPort!"
    );
}

#[test]
fn debug_switches_log_the_descriptors() {
    let spec = boards::preset("5i25").unwrap();
    let mut t = ImageTransport::new(spec.image(), "t");
    let mut log = MessageLog::default();
    let all = Debug {
        idrom: true,
        module_descriptors: true,
        pin_descriptors: true,
        modules: true,
        ..Debug::default()
    };
    firmware::load(&spec.llio(0), &Config::default(), all, &mut t, &mut log).unwrap();
    let dbg = log.lines("", Level::Dbg);
    assert!(dbg.iter().any(|l| l == "    Board Name: MESA5I25"));
    assert!(dbg
        .iter()
        .any(|l| l.starts_with("Module Descriptor 3 at 0x0464")));
    assert!(dbg
        .iter()
        .any(|l| l.starts_with("pin 33: Primary Tag 0x03")));
    assert!(dbg.iter().any(|l| l.starts_with("StepGen: using 10 of 10")));
}
